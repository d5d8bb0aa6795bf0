"""The HTTP resources, one package each: ``routes`` (one APIRouter), ``schemas`` (request
and response models), ``convert`` (request -> solver problem, result -> response) and
``render`` (SVG pictures), only those a resource needs.

A route parses its request, builds one problem object, calls one solver entry point with
it and the request's budget, and converts the result back. The packages are independent
of each other (import-linter contract ``api-independent``); what several share is in
:mod:`service.common`.
"""

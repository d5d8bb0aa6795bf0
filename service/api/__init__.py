"""The HTTP resources, one package each: ``routes`` (one APIRouter), ``schemas`` (request
and response models), ``convert`` (request -> solver problem, result -> response) and
``render`` (SVG pictures), only those a resource needs.

A route parses its request, builds one problem object, calls one solver entry point with
it and the request's budget, and converts the result back. The packages are independent
of each other (import-linter contract ``api-independent``); what several share is in
:mod:`service.common`.
"""

RESOURCES = ("health", "locus", "motion", "particle", "push", "sketch", "spiral", "feeder", "scenes", "jobs")
"""Every resource, in the order the app includes their routers: the one list of them
(``tests/service/test_resources.py`` checks it against the folders)."""

ROUTE_MODULES = tuple(f"service.api.{name}.routes" for name in RESOURCES)
"""Their route modules: what the app includes and what a solver worker imports before it
forks (their jobs and, through them, the solver stack)."""

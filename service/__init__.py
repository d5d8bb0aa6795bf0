"""HTTP layer of the planning service (FastAPI + pydantic).

The service turns JSON requests into domain objects of :mod:`models` (and later
:mod:`solver`), calls them, and turns the results back into JSON or SVG. It holds no
mechanics of its own.
"""

__version__ = "0.1.0"

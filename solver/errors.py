"""The project's own errors for the optimisation layer."""

from __future__ import annotations

from models.errors import ModelError


class SolverError(ModelError):
    """An optimisation back end failed or returned an unusable status."""

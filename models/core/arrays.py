"""Type aliases of the pure layer (for annotations only)."""

from __future__ import annotations

import numpy as np

Real = float | np.ndarray
"""A real number or an array of them: vectorised formulas take and return either."""

"""The numbers the compiled kernels and their callers share (solver/kernels/forward.py,
solver/kernels/fence.py, solver/kernels/disk.py): their algorithms' constants, the codes of their answers and the
columns of their arrays. Plain Python: importing it loads no compiler, so the layers above
read these without loading the kernels (a web process never does)."""

from __future__ import annotations

import math
import sys

# ---------------------------------------------------------------------------------------
# The forward solve (solver/kernels/forward.py, and its reference solver/motion/newton.py)

TINY = 1e-300
ARMIJO = 1e-4
"""Sufficient decrease of the Newton line search."""
MAX_HALVINGS = 40
ROUNDOFF = 1e-13
"""A predicted decrease below this fraction of f cannot be verified by comparing powers in
floating point: in that (quadratic) region the full Newton step is taken."""
VERTEX_FIRST_MAX_K = 16
"""Supports with more points than this are solved Newton-first."""
NEAREST = 3
"""Support points tested where a Newton-first solve stalled."""
ESCAPE_ROUNDS = 3
ESCAPE_HALVINGS = 60
LINE_GROWTH = 200
EPS = sys.float_info.epsilon

MODE_FRICTIONLESS, MODE_STICKING, MODE_SLIPPING_UP, MODE_SLIPPING_DOWN = 0, 1, 2, 3
"""Indices into solver.motion.forward.MODES."""


# ---------------------------------------------------------------------------------------
# The batch of supports (solver.kernels.forward.solve_supports)

BAD_VALUES, BAD_TOTAL, BAD_CENTROID, BAD_LENGTH = range(4)
"""What :func:`solve_supports` found wrong with a support first (the index of ``bad``):
a point or weight not finite or a weight negative, no positive total weight, the weighted
centroid off the CM, every point and the contact at the CM (L = 0)."""

# Columns of solve_supports' real outputs per row
(O_VX, O_VY, O_OMEGA, O_FX, O_FY, O_KKT, O_COR_X, O_COR_Y, O_POWER, O_SLIP, O_GAP) = range(11)
# and of its integer outputs per row
(I_VERTEX, I_ITERS, I_MODE, I_CONSISTENT, I_FAILED) = range(5)


# ---------------------------------------------------------------------------------------
# The fence simulator (solver/kernels/fence.py)

# Run statuses (solver/feeder/simulate.py's words, in this order)
LEFT, MISSED, JAMMED, STEP_LIMIT, STALLED, OVERLAP, GRAZING_PUSH, REFERENCE = range(8)
STATUSES = ("left", "missed", "jammed", "step_limit", "stalled", "overlap", "grazing", "reference")

# Contacts (solver.feeder.simulate.Contact)
VERTEX, END, FLUSH, ALONG, JAM = range(5)

# Events: what happened at a push (its detail is the caller's words, from the code, the index
# and the value)
(EV_FIRST_CONTACT, EV_CONTACT_AGAIN, EV_VERTEX, EV_END, EV_FLUSH, EV_VERTEX_CORNER, EV_END_CORNER, EV_LEFT,
 EV_MISSED, EV_ALONG, EV_JAM, EV_STALLED, EV_OVERLAP) = range(13)

D0, D1 = 0.0, 1.0
"""The belt's motion relative to the fences is -D; in the belt's frame the fence pushes along +D."""
PUSH_ANGLE = 0.5 * math.pi
GRAZING = 1e-9
"""|sin| below which an edge under E lies along the belt (solver.feeder.simulate.GRAZING)."""
E_ON_EDGE = 2.0
TRANSLATION_TURN = 1e-14
"""A turn at most this is taken as a translation (solver.sim.kinematics.TRANSLATION_TURN)."""
GRAZING_SIN = 1e-9
"""The push scene's grazing test (models.core.tolerances.Tolerances.grazing_sin)."""
MODE_COUNT = 4
COUNT_SIDE = 4 + MODE_COUNT
"""In a run's counts: the side of the cone its last forward solve slipped on (0: it did not),
tried first by the next solve (solver.kernels.forward.solve_modes)."""

# Columns of a run's summary (floats): its status, steps, push, the start and end pose,
# whether an edge came flush, the largest |x| of the hull over its poses, what its forward
# solves did (solves, not optimal, largest KKT residual and force angle, the solves of each
# mode), and where its events and path lie in the batch's buffers
(S_STATUS, S_STEPS, S_PUSH, S_START_X, S_START_Y, S_START_THETA, S_CM_X, S_CM_Y, S_THETA, S_FLUSHED, S_MAX_X,
 S_SOLVES, S_NOT_OPTIMAL, S_MAX_KKT, S_MAX_ANGLE, S_EVENTS_FROM, S_EVENTS_TO, S_PATH_FROM, S_PATH_TO,
 S_MODES) = range(20)
SUMMARY = S_MODES + MODE_COUNT


# ---------------------------------------------------------------------------------------
# The disk loci (solver/kernels/disk.py)

SPAN_NONE, SPAN_FOUND, SPAN_REFERENCE = 0, 1, 2
"""What the sticking sweep found at a force angle: no sticking point (or a translation), a
span, or a scene or boundary the reference must answer (it says why)."""

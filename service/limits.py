"""Input limits and service-level tolerances, in one place.

Every limit here is enforced by the request schemas (``service/api/*/schemas.py``), shows up
in the OpenAPI document as ``minimum``/``maximum``/``minItems``/``maxItems``, and is
listed in docs/api.md. A request outside them is answered with HTTP 422 naming the field.
Lengths are in whatever unit the client uses consistently; angles are radians.
"""

from __future__ import annotations

MAX_ABS_COORDINATE = 1e9
"""Largest |x| or |y| of any point (contact, centre of mass, workpiece vertex)."""

MAX_DISK_RADIUS = 1e9
"""disk_radius must lie in (0, MAX_DISK_RADIUS]."""

MAX_ABS_ANGLE = 1e6
"""Largest |edge_angle| and |push_direction| in radians (beyond this an angle carries
less than ~1e-10 rad of precision)."""

MIN_N_POINTS = 8
MAX_N_POINTS = 20_000
DEFAULT_N_POINTS = 256
"""Number of boundary points of the COR locus polygon (odd counts are rounded up to even
by the model, because the locus is mirror symmetric)."""

MIN_POLYGON_VERTICES = 3
MAX_POLYGON_VERTICES = 1000
"""Vertex count of a workpiece polygon."""

CONTACT_ON_OUTLINE_REL = 1e-9
"""A contact point farther than CONTACT_ON_OUTLINE_REL * a from the workpiece outline
(a = disk radius used) is reported in ``warnings`` as not on the outline."""

CONTACT_IN_DISK_REL = 1e-9
"""A contact point farther than (1 + CONTACT_IN_DISK_REL) * a from the centre of mass lies
outside the bounding disk; this is reported in ``warnings`` (the book assumes the disk
bounds the whole workpiece, contact included)."""

# ---------------------------------------------------------------------------------------
# The minimum-power engine (issue 3): sizes that bound the work of one request. Measured
# on one core (docs/api.md): a Newton solve of 25 000 points takes ~10 ms, a batch of
# 10 000 tripods ~0.1 s; Clarabel (cvxpy) ~0.05 s and IPOPT (casadi) ~0.2 s for 256
# points, plus a one-off compilation per new support size.
# ---------------------------------------------------------------------------------------

MAX_MU_C = 1e6
"""Largest pusher friction coefficient mu_c (beyond it the friction cone is a half
plane to within 1e-12 rad)."""

MAX_WEIGHT = 1e12
"""Largest single support weight (weights are normalised; the cap keeps their sum finite)."""

MAX_SUPPORT_POINTS = 25_000
"""Points of one support with method "newton" (also the cells of a uniform pressure)."""

MAX_SUPPORT_POINTS_SLOW = 256
"""Points of one support with methods "cvxpy" and "casadi" (conic / interior-point
solvers, compiled per support size)."""

MAX_BATCH = 10_000
"""Supports in one batch (``supports``) with method "newton"."""

MAX_BATCH_SLOW = 16
"""Supports in one batch with methods "cvxpy" and "casadi" (solved one by one)."""

MAX_BATCH_POINTS = 200_000
"""Total points over all supports of one batch."""

MAX_COLUMN_POINTS = 400_000
"""Total points of one columnar batch (``batch``: 100,000 tripods or quadpods)."""

DEFAULT_PRESSURE_RESOLUTION = 32
MAX_PRESSURE_RESOLUTION = 64
"""Rings of the uniform disk discretisation (6 n^2 cells) or subdivisions per triangle of a
polygon (n^2 cells per triangle); the cell count must also stay within the method's
support-point limit."""

MAX_PRESSURE_FOOTPRINT_VERTICES = 64
"""Vertices of a uniform-pressure polygon footprint (its triangulation is O(n^3))."""

SUPPORT_IN_DISK_REL = 1e-9
"""An explicit disk_radius must be at least (1 - SUPPORT_IN_DISK_REL) times the largest
distance of a support point from the centre of mass."""

MIN_CERTIFIED_POINTS = 4
MAX_CERTIFIED_POINTS = 256
DEFAULT_CERTIFIED_POINTS = 64
"""Boundary points (disk) or rays (polygon) of a certified COR locus. Each costs two or
more membership queries: ~25 ms per disk point, ~0.25 s per polygon ray (measured)."""

SKETCH_DEFAULT_RAYS = 32
"""Rays per traced elementary locus of a certified polygon sketch (two loci: ~2-4 s with
the exact sticking locus, measured on rectangles)."""

DEFAULT_TIME_LIMIT_S = 10.0
"""time_limit_s of certificate searches (membership, certified loci) by default."""
MAX_TIME_LIMIT_S = 30.0
"""The default cap of every time limit (PESHKIN_MAX_TIME_LIMIT_S): a deployment sets its
own, up to TIME_LIMIT_HARD_MAX_S; the request schemas accept up to that, the runner refuses
(422 at time_limit_s) what exceeds the deployment's cap, and the OpenAPI document the
service serves states its cap as the maximum."""
TIME_LIMIT_HARD_MAX_S = 3600.0
"""The largest cap a deployment may set."""
TIME_LIMIT_CAP_TEXT = (f"at most the deployment's cap, PESHKIN_MAX_TIME_LIMIT_S ({MAX_TIME_LIMIT_S:g} s by default; "
                       "the `maximum` of this field in the service's /openapi.json); a default above the cap is "
                       "lowered to it")
"""How every time_limit_s field describes its cap."""

PARTICLE_MIN_MAGNITUDE = 1e-6
PARTICLE_MAX_MAGNITUDE = 1e6
"""Range of v_x, mg and eta of the particle example (book 2.5). Within it (and n <= 10)
every quantity of the answer is a finite float."""

PARTICLE_MAX_EXPONENT = 10.0
"""Largest exponent n of the dissipative force eta |v|^n of the particle example."""

AGREEMENT_REL = 1e-9
"""Newton's and the minimum-power answer of the particle example are reported as agreeing
when their relative difference is at most this."""

MAX_TRIPODS = 100_000
"""Random tripods of one tripod-statistics request."""

MAX_TRIPOD_CORS = 20_000
"""Largest sample whose CORs are returned one by one (``include_cors`` with layout
"rows"); as columns, all of them (up to MAX_TRIPODS)."""

MIN_FOOTPRINT_FILL = 0.01
"""Smallest area / bounding-box area of a tripod-statistics footprint: tripods are drawn
by rejection from the bounding box, whose cost grows like 1 / fill (100 000 tripods in a
1 % triangle take ~3 s; a 0.05 % sliver 13 s for only 1000)."""

SAMPLING_MIN_SIZE = 1e-100
SAMPLING_MIN_SIZE_REL = 1e-9
"""Tripod statistics: the disk radius (or the footprint's circumradius) must be at least
SAMPLING_MIN_SIZE and SAMPLING_MIN_SIZE_REL times the largest |coordinate| of the centre
of mass; below that random points coincide in floating point and no tripod is balanced."""

MAX_HISTOGRAM_BINS = 1000

# ---------------------------------------------------------------------------------------
# Quasi-static validity (book 6.8): POST /v1/push/quasistatic. Within these ranges every
# speed, ratio and coasting error of the answer is a finite float (checked by the tests).
# ---------------------------------------------------------------------------------------

QS_MAX_SPEED = 1e12
"""Largest push speed, in the client's length unit per second."""

QS_MIN_MU_S = 1e-6
QS_MAX_MU_S = 1e3
"""Range of the part-table friction coefficient mu_s."""

QS_MIN_GRAVITY = 1e-12
QS_MAX_GRAVITY = 1e12
"""Range of an explicit g, in the client's length unit per s^2 (9.81 m/s^2 is 9.81e-3 km/s^2
and 9.81e9 nm/s^2)."""

QS_MIN_LENGTH = 1e-100
"""Smallest disk_radius and translational_error (the largest is MAX_DISK_RADIUS)."""

QS_MAX_ANGULAR_ERROR = 6.283185307179586
"""Largest permissible angular error, radians (one full turn, 2 pi)."""

# ---------------------------------------------------------------------------------------
# The COR sketch with pusher friction (book 4.1): POST /v1/cor/sketch. One sketch costs
# about 100 locus evaluations of max(n_points, 1024) boundary points (the sticking-locus
# sweep), measured ~0.2-0.5 s up to n_points 1024, ~1 s at 4096 (one core).
# ---------------------------------------------------------------------------------------

SKETCH_DEFAULT_N_POINTS = 512
SKETCH_MAX_N_POINTS = 4096
"""Boundary points of each elementary locus of a COR sketch (minimum MIN_N_POINTS, as for
the COR locus; the smaller maximum bounds one request to about a second)."""

SKETCH_MIN_LENGTH = 1e-100
"""Smallest disk radius (or polygon circumradius) of a COR sketch: the sense of rotation
(models.core.mpp.mason_sense) squares lengths, which underflow below about 1e-154 and turn every
push into a translation."""

# ---------------------------------------------------------------------------------------
# Gross motions (book 3.4, 4.3, 4.4): POST /v1/push/align and POST /v1/push/disk-encounter.
# An exact bound (models.push.gross_bounds) builds one COR sketch per Gauss node at n_nodes and
# at n_nodes // 2 nodes (the error estimate). The cost model of the sketches is
# solver.push.bounds.SKETCH_COST; a request whose predicted cost exceeds its time_limit_s is
# refused (422 at time_limit_s) before any work, and one that runs out on the way is answered
# 504 with the stages it finished.
# ---------------------------------------------------------------------------------------

GROSS_MIN_N_NODES = 4
GROSS_MAX_N_NODES = 64
"""Gauss-Legendre nodes of an exact gross-motion bound (models.push.gross_bounds needs >= 4)."""

ALIGN_DEFAULT_N_NODES = 8
ENCOUNTER_DEFAULT_N_NODES = 16
"""Default nodes: the fence push's integrand is smooth (8 nodes: error estimate ~2e-4 of
the book example); the encounter's has a kink where sketch i begins (16 nodes: ~6e-4)."""

GROSS_DEFAULT_N_POINTS = 256
"""Boundary points of each elementary locus of the sketches of an exact bound (and of its
sticking sweep); MIN_N_POINTS..SKETCH_MAX_N_POINTS."""

GROSS_MIN_LENGTH = 1e-100
"""Smallest disk radius (or footprint circumradius) of a gross-motion request: the closed
forms square lengths and the sketches' sense of rotation underflows below ~1e-154."""

# ---------------------------------------------------------------------------------------
# Spiral localization (book 4.5): POST /v1/spiral/critical-radius and /v1/spiral/schedule

SPIRAL_MIN_LENGTH = 1e-100
"""Smallest disk radius (squared lengths must not underflow)."""

SPIRAL_MIN_BETA = 1e-3
"""Smallest collision parameter (rad): r* ~ 2a/beta, beyond 2000 a below it."""

SPIRAL_MAX_BETAS = 256
"""Most collision parameters (or radii) in one request."""

SPIRAL_MAX_RADIUS_REL = 1e4
"""Largest start radius / max_radius, in units of a (the table's grid reaches beta ~ 2a / r)."""

SPIRAL_SWEEP_MARGIN_REL = 1e-3
"""Default safety margin (units of a) added to the sweep's r* before planning: the sweep
differs from the certified r* by at most 1.1e-4 a (docs/benchmarks.md)."""

SPIRAL_MIN_RESOLUTION = 2
SPIRAL_MAX_RESOLUTION = 256
SPIRAL_DEFAULT_RESOLUTION = 16
"""Grid radii per safe step of the OR-Tools graph."""

SPIRAL_MIN_POINTS_PER_REVOLUTION = 8
SPIRAL_MAX_POINTS_PER_REVOLUTION = 720
SPIRAL_DEFAULT_POINTS_PER_REVOLUTION = 64

SPIRAL_MAX_PATH_POINTS = 200_000
"""Points of a returned path at most: points_per_revolution is lowered for long schedules."""

SPIRAL_MAX_SIMULATED = 64
"""Random supports of one simulation check at most."""

SPIRAL_DEFAULT_TIME_LIMIT_S = 30.0
"""A first table for a new mu_c takes ~10-20 s by the sweep (then it is cached)."""

SPIRAL_SWEEP_POINTS = 512
"""Boundary points of the loci of the sweep method (error ~1e-5 a)."""

SPIRAL_MAX_NODES = 50_000
SPIRAL_MAX_ARCS = 1_500_000
"""Largest OR-Tools graph of one schedule request (radii, safe revolutions): ~2 s to build
and solve. Larger grids are refused (422 at `resolution`)."""

SPIRAL_MAX_REVOLUTIONS = 20_000
"""Most revolutions of a schedule request (the recursion stops there; a target that needs
more, e.g. within 1e-4 a of b_inf, or a tiny max_step, is refused with 422)."""


# Echoes of invalid input in a 422 (service.errors.echo): bounded whatever was sent
ECHO_MAX_ITEMS = 16
"""Arrays and objects with more items are echoed by their size only."""
ECHO_MAX_DEPTH = 4
"""Nesting echoed at most (deeper parts by their size only)."""
ECHO_MAX_CHARS = 200
"""Strings echoed at most this long."""
ECHO_MAX_ERRORS = 32
"""Validation errors listed at most in one 422."""

FEEDER_MAX_FENCES = 20
"""Fences in one feeder request (maps or simulation)."""
FEEDER_MAX_RESOLUTION = 1440
"""Cells of the circle in a configuration map's boolean matrix (1440: a quarter degree)."""
FEEDER_MAX_VERTICES = 64
"""Vertices of a feeder part's outline (each hull edge costs extreme-B integrations)."""
FEEDER_MAX_SUPPORT_POINTS = 64
"""Support points of a simulated part (one forward solve per step)."""
FEEDER_MAX_STEPS = 20_000
"""Steps of one part through one fence."""
FEEDER_MAX_TRAJECTORY_POINTS = 2000
"""Trajectory samples returned per fence."""
FEEDER_MAX_FENCE_LENGTH_RADII = 1e4
"""fence_length, in part radii."""
FEEDER_MAX_WORLD_RADII = 1e5
"""Placed fences' ends and the part's start: distance from the origin, in part radii
(rounding there stays far below the simulator's contact tolerance)."""
FEEDER_MAX_PART_CONTACTS = 33
"""Contact positions per edge of the part's own bound (each a dipod sweep and traced rays)."""
FEEDER_MAX_RAYS_PER_AIM = 40
"""Certified rays of one climb of the part's own bound (each a few tenths of a second)."""
FEEDER_PART_DEFAULT_TIME_LIMIT_S = 120.0
"""time_limit_s of a feeder map bounded by the part's own loci by default (a fence takes
seconds to minutes: docs/benchmarks.md), within the deployment's cap."""
FEEDER_MAX_CANDIDATES = 180
"""Candidate fences of one design (both sides together: a map each)."""
FEEDER_MAX_DESIGN_DEPTH = 20
"""Fences in a design (the book searched one part to depth 20, 5.4.1)."""
FEEDER_MAX_VALIDATION_PARTS = 10_000
"""Simulated parts that validate a design (each runs through every fence; 10,000 make a
yield worth quoting to 0.1 %, a few tenths of a second on the compiled simulator:
docs/benchmarks.md)."""


SCENE_MAX_QUESTIONS = 12
"""Questions of one scene analysis (``POST /v1/scenes/analyze``)."""

SCENE_DEFAULT_TIME_LIMIT_S = 30.0
"""time_limit_s of a scene analysis by default (all its questions together)."""

FEEDER_MAX_CATALOGUE_PARTS = 500
"""Parts of one feeder catalogue (``POST /v1/feeder/catalogue``)."""

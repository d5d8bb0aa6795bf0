"""Print the source files of every module the service imports, one per line: the
service's app (every route and the solver stack), the modules its routes import lazily
(OR-Tools' CP-SAT and min cost flow, cvxpy, CasADi, Ray), and what a first solve with each
back end and an SVG picture import. Run from the service's source tree in the image
build (scripts/image/slim-venv.sh keeps the bytecode of these files only)."""

from __future__ import annotations

import importlib.util
import os
import sys
import tempfile

os.environ.setdefault("PESHKIN_JOBS_PATH", os.path.join(tempfile.mkdtemp(), "jobs.sqlite3"))
os.environ.setdefault("MPLBACKEND", "Agg")

# the back ends the routes import inside functions (solver/feeder/design_cpsat.py,
# solver/spiral/schedule.py, solver/motion/forward.py); then the app (every route module
# and what they import), the server (gunicorn and the uvicorn worker: service.server) and
# what a solver worker runs
import casadi as ca
import cvxpy as cp
import numpy as np
from ortools.graph.python import min_cost_flow
from ortools.sat.python import cp_model

import service.__main__
import service.app
import service.runtime.jobs  # noqa: F401

if importlib.util.find_spec("ray") is not None:  # not in an image built WITH_RAY=false
    import ray
    import ray._private.worker  # noqa: F401

# a first solve with each back end imports more of each library
v = cp.Variable(2)
cp.Problem(cp.Minimize(cp.sum(v)), [cp.SOC(cp.Constant(1.0), v)]).solve(solver=cp.CLARABEL)
p = cp.Parameter(2, value=np.ones(2))
cp.Problem(cp.Minimize(cp.sum_squares(v - p)), [v >= 0]).solve(solver=cp.CLARABEL)
x = ca.MX.sym("x", 2)
ca.nlpsol("s", "ipopt", {"x": x, "f": ca.sumsqr(x - 1)}, {"print_time": False, "ipopt.print_level": 0})(x0=[0, 0])
m = cp_model.CpModel()
a = m.new_int_var(0, 4, "a")
m.maximize(a)
cp_model.CpSolver().solve(m)
f = min_cost_flow.SimpleMinCostFlow()
f.add_arc_with_capacity_and_unit_cost(0, 1, 1, 1)
f.set_node_supply(0, 1)
f.set_node_supply(1, -1)
f.solve()

import io

from matplotlib.backends.backend_svg import FigureCanvasSVG
from matplotlib.figure import Figure

fig = Figure()
fig.add_subplot().plot(np.arange(3), np.arange(3), label="x")
fig.axes[0].legend()
FigureCanvasSVG(fig).print_svg(io.StringIO())

for module in list(sys.modules.values()):
    path = getattr(module, "__file__", None)
    if path and path.endswith(".py"):
        print(os.path.realpath(path))

# the running server imports more of its own stack than the app does (anyio's asyncio
# backend and streams, uvicorn's lifespan and loop, gunicorn's logging): every module of
# these small packages (a few MB of bytecode)
import importlib

for name in ("anyio", "uvicorn", "uvicorn_worker", "gunicorn", "fastapi", "starlette", "h11", "httptools"):
    root = os.path.dirname(importlib.import_module(name).__file__)
    for folder, _, files in os.walk(root):
        for file in files:
            if file.endswith(".py"):
                print(os.path.realpath(os.path.join(folder, file)))

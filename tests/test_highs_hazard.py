"""Guard against the HiGHS shared-library clash.

The full ``cvxpy`` distribution pulls in ``highspy``, whose bundled
libhighs.so crashes the interpreter when it is loaded next to the HiGHS
copies inside OR-Tools and CasADi.  The project therefore depends on
``cvxpy-base`` only.  These tests load cvxpy, OR-Tools, CasADi and numba (with
its own LLVM, for the compiled kernels) into one fresh interpreter, in both
import orders, and solve a small problem with each solver we rely on; a
segfault shows up as a non-zero exit code.
"""

from __future__ import annotations

import importlib.metadata
import importlib.util
import json
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[1]

# Each snippet imports one library and appends its results to `out`.
_IMPORTS = {
    "cvxpy": "import cvxpy as cp",
    "ortools": "from ortools.linear_solver import pywraplp\nfrom ortools.sat.python import cp_model",
    "casadi": "import casadi as ca",
    # numba bundles LLVM (llvmlite): the compiled kernels load beside the three
    "numba": "import numba\nfrom solver.kernels import codes\nfrom solver.kernels import forward as kernels",
}

_SOLVES = textwrap.dedent(
    """
    import numpy as np

    # cvxpy: tiny SOCP  min x + y  s.t. ||(x, y)||_2 <= 1   ->  -sqrt(2)
    for solver in ("CLARABEL", "SCS"):
        v = cp.Variable(2)
        prob = cp.Problem(cp.Minimize(cp.sum(v)), [cp.SOC(cp.Constant(1.0), v)])
        kwargs = {"eps": 1e-7} if solver == "SCS" else {}
        prob.solve(solver=solver, **kwargs)
        out["cvxpy_" + solver] = {"status": prob.status, "value": float(prob.value)}

    # OR-Tools GLOP: max 3x + 2y  s.t. x + y <= 4, x + 3y <= 6, x <= 3  ->  11
    lp = pywraplp.Solver.CreateSolver("GLOP")
    x = lp.NumVar(0, lp.infinity(), "x")
    y = lp.NumVar(0, lp.infinity(), "y")
    lp.Add(x + y <= 4)
    lp.Add(x + 3 * y <= 6)
    lp.Add(x <= 3)
    lp.Maximize(3 * x + 2 * y)
    status = lp.Solve()
    out["glop"] = {"optimal": status == pywraplp.Solver.OPTIMAL,
                   "value": lp.Objective().Value()}

    # OR-Tools CP-SAT: max x + 2y  s.t. x + y <= 5, 2x >= y, x, y in 0..4  ->  8 (x=2, y=3)
    m = cp_model.CpModel()
    a = m.NewIntVar(0, 4, "a")
    b = m.NewIntVar(0, 4, "b")
    m.Add(a + b <= 5)
    m.Add(2 * a >= b)
    m.Maximize(a + 2 * b)
    sat = cp_model.CpSolver()
    sat.parameters.num_workers = 1
    st = sat.Solve(m)
    out["cpsat"] = {"optimal": st == cp_model.OPTIMAL, "value": sat.ObjectiveValue()}

    # CasADi + IPOPT: Rosenbrock  min (1-x)^2 + 100 (y - x^2)^2  ->  0 at (1, 1)
    z = ca.SX.sym("z", 2)
    f = (1 - z[0]) ** 2 + 100 * (z[1] - z[0] ** 2) ** 2
    nlp = ca.nlpsol("nlp", "ipopt", {"x": z, "f": f},
                    {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes"})
    sol = nlp(x0=[-1.2, 1.0])
    out["ipopt"] = {"success": bool(nlp.stats()["success"]),
                    "value": float(sol["f"]), "x": [float(t) for t in np.array(sol["x"]).ravel()]}

    # numba: the compiled forward solve of one tripod, frictionless (solver/kernels/forward.py)
    w = np.array([[[0.5, 0.0], [-0.25, 0.4], [-0.25, -0.4]]])
    two = lambda v: np.array([v], dtype=float)
    real, ints, _ = kernels.solve_supports(w, np.full((1, 3), 1 / 3), two([0.0, 0.0]), two([-0.9, 0.1]),
                                           two([1.0, 0.0]), two([0.0, 1.0]), two([1.0, 0.0]), np.ones(1), 0.0,
                                           np.array([1e-10, 1e-10, 80, 1e-12, 1e-9]))
    out["numba"] = {"kkt": float(real[0, codes.O_KKT]), "failed": bool(ints[0, codes.I_FAILED])}

    # SciPy's own (statically linked) HiGHS: min -x - 2y  s.t. x + y <= 4, x, y >= 0  ->  -8
    from scipy.optimize import linprog
    res = linprog([-1, -2], A_ub=[[1, 1]], b_ub=[4], bounds=[(0, None)] * 2, method="highs")
    out["scipy_highs"] = {"success": bool(res.success), "value": float(res.fun)}
    """
)


def _script(order: tuple[str, ...]) -> str:
    imports = "\n".join(_IMPORTS[name] for name in order)
    return (
        "import json, sys\n"
        + imports
        + "\nout = {}\n"
        + _SOLVES
        + "\nout['loaded_highspy'] = 'highspy' in sys.modules\n"
        + "print('RESULT ' + json.dumps(out))\n"
    )


ORDERS = [("cvxpy", "ortools", "casadi", "numba"), ("numba", "casadi", "ortools", "cvxpy")]


@pytest.mark.slow
@pytest.mark.parametrize("order", ORDERS, ids=["->".join(o) for o in ORDERS])
def test_solver_stack_coexists(order: tuple[str, ...]) -> None:
    proc = subprocess.run(
        [sys.executable, "-c", _script(order)],
        cwd=REPO_ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, (
        f"interpreter died (exit {proc.returncode}) with import order {order}\n"
        f"--- stdout ---\n{proc.stdout[-4000:]}\n--- stderr ---\n{proc.stderr[-4000:]}"
    )
    match = re.search(r"^RESULT (.*)$", proc.stdout, flags=re.MULTILINE)
    assert match, proc.stdout
    out = json.loads(match.group(1))

    for solver, tol in (("CLARABEL", 1e-6), ("SCS", 1e-4)):
        r = out["cvxpy_" + solver]
        assert r["status"] == "optimal", r
        assert r["value"] == pytest.approx(-(2**0.5), abs=tol)
    assert out["glop"]["optimal"] and out["glop"]["value"] == pytest.approx(11.0, abs=1e-9)
    assert out["cpsat"]["optimal"] and out["cpsat"]["value"] == pytest.approx(8.0)
    assert out["ipopt"]["success"] and out["ipopt"]["value"] == pytest.approx(0.0, abs=1e-10)
    assert out["ipopt"]["x"] == pytest.approx([1.0, 1.0], abs=1e-6)
    assert out["scipy_highs"]["success"] and out["scipy_highs"]["value"] == pytest.approx(-8.0)
    assert out["numba"]["kkt"] <= 1e-10 and not out["numba"]["failed"]
    assert out["loaded_highspy"] is False


def test_highspy_not_installed() -> None:
    assert importlib.util.find_spec("highspy") is None, "highspy is importable"
    with pytest.raises(importlib.metadata.PackageNotFoundError):
        importlib.metadata.distribution("highspy")


def test_full_cvxpy_distribution_not_installed() -> None:
    # cvxpy-base provides the `cvxpy` module; the `cvxpy` *distribution* must be absent.
    importlib.metadata.distribution("cvxpy-base")
    with pytest.raises(importlib.metadata.PackageNotFoundError):
        importlib.metadata.distribution("cvxpy")


@pytest.mark.parametrize("name", ["requirements.txt", "requirements-dev.txt"])
def test_requirements_never_pull_full_cvxpy(name: str) -> None:
    path = REPO_ROOT / name
    if not path.is_file():
        pytest.skip(f"{name} not present")
    for raw in path.read_text().splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line or line.startswith("-"):
            continue
        dist = re.split(r"[<>=!~\[; ]", line, maxsplit=1)[0].strip().lower().replace("_", "-")
        assert dist not in {"cvxpy", "highspy"}, f"{name}: {raw!r}"

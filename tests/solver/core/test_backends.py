"""The ledger of time per numerical back end (solver/core/backends.py): a certified
membership query spends its time in Clarabel, a CasADi forward solve in IPOPT, a spiral
schedule in OR-Tools; nothing is recorded without an open ledger, nor on another thread."""

from __future__ import annotations

import math
import threading

import numpy as np

from models.core.scene import PushScene
from models.core.support import Support
from solver import close_ledger, open_ledger
from solver.core.backends import in_backend
from solver.locus.membership import membership
from solver.motion.forward import solve_forward


def test_each_back_end_is_timed_while_a_ledger_is_open():
    scene = PushScene.create(1.0, [-0.5, -0.3], math.pi / 2, 0.0)
    support = Support.create(np.array([[0.8, 0.0], [-0.4, 0.6], [-0.4, -0.6]]), np.ones(3) / 3, np.zeros(2))
    open_ledger()
    try:
        res = membership(scene, np.array([0.0, 4.0]))  # outside: a dual certificate (3.3)
        solve_forward(scene, support, method="casadi")
    finally:
        spent = close_ledger()
    assert res.status == "outside"
    assert spent["clarabel"] > 0.0 and spent["casadi"] > 0.0 and "ortools" not in spent


def test_nothing_is_recorded_without_a_ledger_or_on_another_thread():
    assert close_ledger() == {}
    with in_backend("clarabel"):
        pass
    open_ledger()
    other: dict = {}

    def elsewhere():
        with in_backend("ortools"):
            other["done"] = True

    t = threading.Thread(target=elsewhere)
    t.start()
    t.join()
    with in_backend("ortools"):
        pass
    spent = close_ledger()
    assert other["done"] and set(spent) == {"ortools"} and spent["ortools"] >= 0.0
    assert close_ledger() == {}

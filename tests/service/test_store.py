"""The result store (service/store.py) and the r* rows it keeps (solver/spiral/
critical_radius.py, 4.5.3): a second identical table computes nothing, a table cut by a
work limit is kept and the next request extends it, two processes writing at once do not
corrupt the file, a version change makes old rows unreachable, a broken file is
survived."""

from __future__ import annotations

import multiprocessing
import sqlite3
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from service import store as store_module
from service.store import SqliteStore
from solver.spiral import critical_radius as cr
from tests.budgets import checks_budget
from tests.service.runtime.conftest import TestClient, hold_a_slot, pool_app
from tests.service.store_openers import open_and_put

BETAS = (0.3, 0.6, 0.9, 1.2, 1.45)


def test_values_round_trip_and_the_cap_holds(tmp_path):
    s = SqliteStore(tmp_path / "r.sqlite3", max_rows=3)
    assert s.get("ns", "k") is None
    for i in range(5):
        s.put("ns", f"k{i}", {"i": i, "x": [1.5, None]})
    assert s.get("ns", "k4") == {"i": 4, "x": [1.5, None]} and s.count() == 3 and s.get("ns", "k0") is None
    s.put("ns", "bad", {"x": float("nan")})  # not JSON: not kept
    assert s.get("ns", "bad") is None


def test_a_second_table_computes_nothing(tmp_path, monkeypatch):
    s = SqliteStore(tmp_path / "r.sqlite3")
    first = cr.critical_radius_table(1.0, 0.25, "sweep", betas=BETAS, find_kink=False, store=s)

    def no_more(*args, **kwargs):
        raise AssertionError("r* computed again")

    monkeypatch.setattr(cr, "critical_radius", no_more)
    again = cr.critical_radius_table(2.5, 0.25, "sweep", betas=BETAS, find_kink=False, store=s)  # another a: scaled
    assert np.array_equal(again.radii, 2.5 * first.radii) and again.complete


def test_a_table_cut_short_is_kept_and_extended(tmp_path, monkeypatch):
    s = SqliteStore(tmp_path / "r.sqlite3")
    cut = cr.critical_radius_table(1.0, 0.25, "sweep", betas=BETAS, find_kink=False, store=s, budget=checks_budget(3))
    assert cut.time_limited and 0 < cut.n_done < len(BETAS)
    computed = []
    real = cr.critical_radius

    def counting(a, beta, *args, **kwargs):
        computed.append(beta)
        return real(a, beta, *args, **kwargs)

    monkeypatch.setattr(cr, "critical_radius", counting)
    whole = cr.critical_radius_table(1.0, 0.25, "sweep", betas=BETAS, find_kink=False, store=s)
    assert whole.complete and len(computed) == len(BETAS) - cut.n_done  # only what the cut table lacked
    reference = cr.critical_radius_table(1.0, 0.25, "sweep", betas=BETAS, find_kink=False)
    assert np.array_equal(whole.radii, reference.radii)


def test_a_new_version_does_not_read_old_rows(tmp_path, monkeypatch):
    s = SqliteStore(tmp_path / "r.sqlite3")
    cr.critical_radius_table(1.0, 0.25, "sweep", betas=BETAS[:2], find_kink=False, store=s)
    monkeypatch.setattr(cr, "STORE_VERSION", cr.STORE_VERSION + 1)
    computed = []
    real = cr.critical_radius
    monkeypatch.setattr(cr, "critical_radius", lambda a, b, *x, **k: computed.append(b) or real(a, b, *x, **k))
    cr.critical_radius_table(1.0, 0.25, "sweep", betas=BETAS[:2], find_kink=False, store=s)
    assert len(computed) == 2


def _writer(path: str, offset: int) -> None:
    s = SqliteStore(path)
    for i in range(300):
        s.put("ns", f"{offset + i}", {"i": offset + i})


@pytest.mark.slow  # 7 s: the heaviest of the everyday tier
def test_two_processes_writing_at_once_leave_a_whole_file(tmp_path):
    path = str(tmp_path / "r.sqlite3")
    ctx = multiprocessing.get_context("spawn")
    procs = [ctx.Process(target=_writer, args=(path, k * 1000)) for k in range(2)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(60)
    assert [p.exitcode for p in procs] == [0, 0]
    s = SqliteStore(path)
    assert s.count() == 600 and s.get("ns", "1299") == {"i": 1299}
    assert sqlite3.connect(path).execute("PRAGMA integrity_check").fetchone()[0] == "ok"


OPENING_TRIALS = 12
"""New files opened by four processes at once; before the fix about one opening in four lost
its store ("database is locked" switching to WAL), so twelve trials miss it with chance
0.75**48 ~ 1e-6."""


def test_processes_opening_a_new_file_at_once_all_keep_their_store(tmp_path):
    paths = [str(tmp_path / f"r{i}.sqlite3") for i in range(OPENING_TRIALS)]
    ctx = multiprocessing.get_context("spawn")
    barrier, faults = ctx.Barrier(4), ctx.Queue()
    procs = [ctx.Process(target=open_and_put, args=(paths, barrier, faults)) for _ in range(4)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(120)
    assert [p.exitcode for p in procs] == [0] * 4
    seen = []
    while not faults.empty():
        seen.append(faults.get())
    assert not seen, seen


def test_a_broken_file_is_survived(tmp_path, caplog):
    bad = tmp_path / "r.sqlite3"
    bad.write_bytes(b"this is not a database" * 100)
    s = SqliteStore(bad)
    s.put("ns", "k", {"x": 1})
    assert s.get("ns", "k") is None
    assert "goes on without it" in caplog.text


def test_the_process_store_follows_the_setting(tmp_path, monkeypatch):
    monkeypatch.setattr(store_module, "_PROCESS_STORE", {})
    monkeypatch.setenv("PESHKIN_STORE_PATH", "")
    assert store_module.result_store() is None
    monkeypatch.setenv("PESHKIN_STORE_PATH", str(tmp_path / "x.sqlite3"))
    s = store_module.result_store()
    assert isinstance(s, SqliteStore) and store_module.result_store() is s


pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")


def test_a_certified_locus_is_kept_and_answered_again_without_work(tmp_path, monkeypatch, client):
    """A complete certified locus is kept (per request, all but its time limit): the same
    request again is answered from the store (from_store), identical but for the timing,
    with no solver call; an analytic request never touches the store."""
    from service.api.locus import routes

    monkeypatch.setattr(store_module, "_PROCESS_STORE", {})
    monkeypatch.setenv("PESHKIN_STORE_PATH", str(tmp_path / "r.sqlite3"))
    body = {"footprint": [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]], "contact_point": [-1, -0.3],
            "edge_angle": 1.5707963267948966, "method": "certified", "n_certified": 8, "time_limit_s": 30,
            "outputs": []}
    first = client.post("/v1/cor/locus", json=body).json()
    assert first["certified"]["complete"] and first["from_store"] is False

    def no_more(*args, **kwargs):
        raise AssertionError("computed again")

    monkeypatch.setattr(routes, "locus_of", no_more)
    again = client.post("/v1/cor/locus", json={**body, "time_limit_s": 5}).json()
    assert again["from_store"] is True
    assert again["certified"] == first["certified"] and again["tip"] == first["tip"]
    other = client.post("/v1/cor/locus", json={**body, "n_certified": 9})  # another request computes: here, fails
    assert other.status_code == 500


@pytest.mark.slow
def test_a_kept_locus_is_answered_while_every_solver_slot_is_busy(tmp_path, monkeypatch, client):
    """Issue 25 (found in the container): a flood of one certified request was refused 503
    by its predicted wait although its answer was in the store. The store is read before
    the request queues for a slot: with the only slot held by a 2 s job, the kept answer
    comes at once."""
    monkeypatch.setattr(store_module, "_PROCESS_STORE", {})
    monkeypatch.setenv("PESHKIN_STORE_PATH", str(tmp_path / "r.sqlite3"))
    body = {"footprint": [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]], "contact_point": [-1, -0.3],
            "edge_angle": 1.5707963267948966, "method": "certified", "n_certified": 8, "time_limit_s": 30,
            "outputs": []}
    # kept by this process (a solver worker's forkserver may have started before the
    # store path was set, with another store)
    assert client.post("/v1/cor/locus", json=body).json()["certified"]["complete"]
    with TestClient(pool_app(solver_workers=1), raise_server_exceptions=False) as c:
        with ThreadPoolExecutor(1) as ex:
            busy = hold_a_slot(c, ex, 2.0)
            t0 = time.monotonic()
            again = c.post("/v1/cor/locus", json={**body, "time_limit_s": 3})
            took = time.monotonic() - t0
            assert busy.result().status_code == 200
    assert again.status_code == 200 and again.json()["from_store"] is True and took < 1.0

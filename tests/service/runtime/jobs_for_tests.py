"""Top-level jobs for the runtime tests (a solver worker imports them by name)."""

from __future__ import annotations

import ctypes
import os
import signal
import time

from starlette.responses import JSONResponse

from models.core.errors import InvalidInput
from service.runtime.deadline import Deadline
from solver import TimeLimitReached


def pid_job(deadline: Deadline) -> JSONResponse:
    return JSONResponse({"pid": os.getpid(), "solver_s": deadline.solver_s(), "limit_s": deadline.limit_s})


def sleep_job(seconds: float, deadline: Deadline) -> JSONResponse:
    """Works for ``seconds`` without looking at the deadline (a runaway)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        time.sleep(0.01)
    return JSONResponse({"pid": os.getpid(), "slept": seconds})


def budgeted_job(deadline: Deadline) -> JSONResponse:
    """Works until its budget ends, then stops with what it did (a well-behaved solver)."""
    budget = deadline.budget()
    done = 0
    while True:
        budget.checkpoint(f"step {done + 1}", partial={"steps": done})
        time.sleep(0.01)
        done += 1


def invalid_job(deadline: Deadline) -> JSONResponse:
    raise InvalidInput("disk_radius", "must be positive")


def limit_job(deadline: Deadline) -> JSONResponse:
    raise TimeLimitReached("the second stage", deadline.limit_s, 1.0, None)


def bug_job(deadline: Deadline) -> JSONResponse:
    raise KeyError("a bug")


def crash_job(deadline: Deadline) -> JSONResponse:
    """Dies as a native library would: a segmentation fault."""
    ctypes.string_at(0)
    return JSONResponse({})


def killed_job(deadline: Deadline) -> JSONResponse:
    """Is stopped from outside, as by the out-of-memory killer: SIGKILL."""
    os.kill(os.getpid(), signal.SIGKILL)
    return JSONResponse({})

"""Runtime settings from the environment (service/settings.py)."""

from __future__ import annotations

import pytest

from service.settings import Settings


def test_settings_defaults_and_env():
    assert Settings.from_env({}) == Settings("127.0.0.1", 8000, "info")
    s = Settings.from_env({"PESHKIN_HOST": "0.0.0.0", "PESHKIN_PORT": "9001", "PESHKIN_LOG_LEVEL": "DEBUG"})
    assert s == Settings("0.0.0.0", 9001, "debug")
    for bad in ({"PESHKIN_PORT": "http"}, {"PESHKIN_PORT": "70000"}, {"PESHKIN_LOG_LEVEL": "loud"}):
        with pytest.raises(ValueError):
            Settings.from_env(bad)


def test_runtime_settings_are_read_and_checked():
    s = Settings.from_env({"PESHKIN_WEB_WORKERS": "3", "PESHKIN_SOLVER_WORKERS": "0", "PESHKIN_SOLVER_QUEUE": "5",
                           "PESHKIN_MAX_TIME_LIMIT_S": "12.5", "PESHKIN_HEADER_TIMEOUT_S": "2"})
    assert (s.web_workers, s.solver_workers, s.solver_queue, s.max_time_limit_s, s.header_timeout_s) == (3, 0, 5, 12.5, 2.0)
    for bad in ({"PESHKIN_WEB_WORKERS": "0"}, {"PESHKIN_SOLVER_WORKERS": "-2"}, {"PESHKIN_MAX_TIME_LIMIT_S": "nan"},
                {"PESHKIN_HEADER_TIMEOUT_S": "0"}, {"PESHKIN_DEADLINE_GRACE_S": "soon"}, {"PESHKIN_RETRY_AFTER_S": "1.5"}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            Settings.from_env(bad)


def test_solver_workers_auto_are_the_usable_cpus_for_the_whole_server():
    """One slot per CPU the process may use, shared by the web processes (so not divided
    among them: service/runtime/slots.py)."""
    auto = Settings.from_env({"PESHKIN_SOLVER_WORKERS": "auto", "PESHKIN_WEB_WORKERS": "2"})
    assert auto.solver_processes(cpus=2) == 2 and auto.solver_processes(cpus=8) == 8
    assert auto.solver_processes(cpus=0) == 1  # at least one
    assert Settings(solver_workers=3).solver_processes(cpus=64) == 3

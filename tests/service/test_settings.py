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

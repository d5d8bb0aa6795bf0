"""The supervisor's configuration (service/server.py): gunicorn's control socket is this
instance's own or none (issue 25: two instances shared gunicorn's default path in the
user's home, and in the image every start logged a Permission denied ERROR for it)."""

from __future__ import annotations

from service.server import Server
from service.settings import Settings


def test_the_control_socket_is_off_unless_a_path_of_its_own_is_given(tmp_path):
    off = Server(Settings()).cfg
    assert off.control_socket_disable is True
    path = str(tmp_path / "peshkin.ctl")
    own = Server(Settings.from_env({"PESHKIN_CONTROL_SOCKET": path})).cfg
    assert own.control_socket_disable is False and own.control_socket == path
    assert Settings.from_env({"PESHKIN_CONTROL_SOCKET": ""}).control_socket == ""

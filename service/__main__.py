"""``python -m service``: the server (gunicorn supervising uvicorn web processes,
:mod:`service.server`), configured by :mod:`service.settings`."""

from __future__ import annotations

from service.server import Server
from service.settings import Settings


def main() -> None:
    Server(Settings.from_env()).run()


if __name__ == "__main__":
    main()

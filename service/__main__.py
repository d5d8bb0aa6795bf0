"""``python -m service``: run the API with uvicorn, configured by :mod:`service.settings`."""

from __future__ import annotations

import uvicorn

from service.settings import Settings


def main() -> None:
    settings = Settings.from_env()
    uvicorn.run("service.app:app", host=settings.host, port=settings.port, log_level=settings.log_level)


if __name__ == "__main__":
    main()

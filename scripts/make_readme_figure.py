"""Regenerate docs/img/cor_locus.svg, the README's picture, through the public API."""

from __future__ import annotations

import sys
from pathlib import Path

from fastapi.testclient import TestClient

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from service.app import app

# The book's five-sided part (figure 3-3 style): pushed at a corner by a fence at 70 degrees.
REQUEST = {
    "workpiece": [[-1.0, -0.6], [0.9, -0.8], [1.1, 0.3], [0.2, 1.0], [-0.9, 0.6]],
    "contact_point": [-0.9, 0.6],
    "edge_angle": 1.2217304763960306,
    "push_direction": 0.0,
    "n_points": 512,
}


def main() -> None:
    with TestClient(app) as client:
        response = client.post("/v1/cor/locus?format=svg", json=REQUEST)
        response.raise_for_status()
    out = ROOT / "docs" / "img" / "cor_locus.svg"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_bytes(response.content)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()

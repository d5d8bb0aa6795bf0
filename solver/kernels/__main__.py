"""``python -m solver.kernels``: load every compiled kernel, compiling (and caching) those the
cache lacks, and say which (scripts/serve.sh and scripts/test.sh run it after an install,
the image's build runs it, so that no request pays for a compile)."""

from __future__ import annotations

import sys


def main() -> int:
    from solver.kernels import compiled, ensure_cache

    loaded, built = compiled()
    where = ensure_cache()
    where = "next to the sources" if where is None else str(where)
    print(f"solver.kernels: {loaded} entry points loaded from the cache, {built} compiled (cache {where})")
    return 0


if __name__ == "__main__":
    sys.exit(main())

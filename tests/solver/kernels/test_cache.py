"""Where the compiled kernels are kept (solver/kernels/__init__.py): compiled code of older
sources is dropped whole (numba keys a function's cache by its own module's source only,
and the fence loop compiles the forward solve into itself), and a read-only cache (the
image) is copied to a writable folder that numba then reads."""

from __future__ import annotations

import tempfile

from numba.core import config

import solver.kernels as kernels


def test_compiled_code_of_older_sources_is_dropped_whole(tmp_path):
    for name in ("forward.f-10.py311.nbi", "forward.f-10.py311.1.nbc", "fence.g-3.py311.nbi"):
        (tmp_path / name).write_bytes(b"old")
    (tmp_path / kernels.STAMP_FILE).write_text("sources of yesterday")
    kernels.drop_if_stale(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == [kernels.STAMP_FILE]
    assert (tmp_path / kernels.STAMP_FILE).read_text() == kernels.sources_stamp()
    (tmp_path / "fence.g-3.py311.nbi").write_bytes(b"new")
    kernels.drop_if_stale(tmp_path)  # the same sources: kept
    assert (tmp_path / "fence.g-3.py311.nbi").read_bytes() == b"new"


def test_the_stamp_covers_every_kernel_module():
    names = {p.name for p in kernels.HERE.glob("*.py")}
    assert {"forward.py", "fence.py", "__init__.py"} <= names
    assert len(kernels.sources_stamp()) == 64


def test_a_read_only_cache_is_copied_to_a_writable_folder(tmp_path, monkeypatch):
    """The sources' folder not writable (the image): its compiled code and stamp are copied
    into the temporary directory, and numba is pointed there."""
    monkeypatch.setattr(kernels, "writable", lambda folder: False)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setattr(config, "CACHE_DIR", config.CACHE_DIR)
    root = kernels.prepare_cache()
    assert root is not None and root.parent == tmp_path
    (target,) = [p for p in root.iterdir() if p.is_dir()]
    in_tree = {p.name for p in (kernels.HERE / "__pycache__").glob("*.nb?")}
    assert in_tree and in_tree <= {p.name for p in target.iterdir()}
    assert (target / kernels.STAMP_FILE).read_text() == kernels.sources_stamp()
    assert config.CACHE_DIR == str(root)

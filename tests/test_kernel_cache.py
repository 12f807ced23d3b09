"""numba's kernel cache is keyed by the package's compiled code (clutchlab._kernel_cache_dir)."""

import shutil
from pathlib import Path

import clutchlab

PACKAGE = Path(clutchlab.__file__).parent


def _copy(tmp_path):
    dst = tmp_path / "clutchlab"
    shutil.copytree(PACKAGE, dst, ignore=shutil.ignore_patterns("__pycache__"))
    return dst


def test_an_edit_to_a_module_a_kernel_calls_moves_the_cache(tmp_path, monkeypatch):
    """numba alone keeps a cached kernel when a function it calls from another module changes
    (here the engagement's Dormand-Prince stepper, called by the driver's kernel)."""
    monkeypatch.delenv("CLUTCHLAB_NUMBA_CACHE_BASE", raising=False)
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    root = _copy(tmp_path)
    before = clutchlab._kernel_cache_dir(root)
    assert before.parent == tmp_path / "cache"  # the user's folder is the base
    stepper = root / "engagement" / "_dopri.py"
    stepper.write_text(stepper.read_text() + "\n# an edit\n")
    assert clutchlab._kernel_cache_dir(root) != before
    status = root / "status.py"  # module-level constants the kernels read
    status.write_text(status.read_text() + "\n# an edit\n")
    assert len({before, clutchlab._kernel_cache_dir(root)}) == 2


def test_the_report_and_benchmarks_do_not_move_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    root = _copy(tmp_path)
    before = clutchlab._kernel_cache_dir(root)
    for rel in ("report/__init__.py", "bench/__init__.py"):
        (root / rel).write_text((root / rel).read_text() + "\n# an edit\n")
    assert clutchlab._kernel_cache_dir(root) == before


def test_numba_uses_the_folder_of_this_source():
    import os

    import numba

    assert numba.config.CACHE_DIR == os.environ["NUMBA_CACHE_DIR"]
    assert Path(numba.config.CACHE_DIR) == clutchlab._kernel_cache_dir()

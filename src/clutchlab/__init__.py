"""clutchlab: batch parameter studies of helicopter and UAV drivetrain clutches.

Physics modules are pure, vectorised numpy functions in SI units; studies turn a design of
experiments into a labelled :class:`xarray.Dataset`; :mod:`clutchlab.store` writes and reads
those Datasets as HDF5 (h5netcdf engine).
"""

import hashlib
import os
import sys
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

try:
    __version__ = version("clutchlab")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"

__all__ = ["__version__", "source_hash"]


def source_hash(root=None) -> str:
    """SHA-256 (first 16 hex digits) of the package's source: every .py and .yaml file below
    ``root`` (default: this package), by relative path and content. The workflow passes it to
    every physics rule as a param, so that a change to the code reruns what it affects (a version
    number would not change for an edit), and stores it in every result."""
    root = Path(root) if root is not None else Path(__file__).parent
    h = hashlib.sha256()
    for path in sorted(_source_files(root, (".py", ".yaml"))):
        h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:16]


def _source_files(root: Path, suffixes) -> list[Path]:
    """The files below ``root`` ending in one of ``suffixes``, outside ``__pycache__`` folders
    (not walked: numba's kernel cache holds thousands of files)."""
    out = []
    for folder, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        out += [Path(folder) / f for f in files if f.endswith(suffixes)]
    return out


def _kernel_cache_dir(root=None) -> Path:
    """The folder of numba's compiled-kernel cache for this source: a subfolder named by the hash
    of the package's compiled code (every module outside ``report`` and ``bench``) below the
    user's ``NUMBA_CACHE_DIR`` if set, else below the package's ``__pycache__`` (the user's cache
    folder where the package's is not writable).

    numba invalidates a cached kernel when the file that defines it changes, not when a function
    it calls from another module or a module-level constant it reads does: the kernels are split
    over many modules, so a cache keyed by the whole source keeps an edit from running stale
    machine code."""
    h = hashlib.sha256()
    root = Path(root) if root is not None else Path(__file__).parent
    for path in sorted(_source_files(root, (".py",))):
        rel = path.relative_to(root)
        if rel.parts[0] not in ("report", "bench"):
            h.update(rel.as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    base = os.environ.get("CLUTCHLAB_NUMBA_CACHE_BASE") or os.environ.get("NUMBA_CACHE_DIR")
    if not base:
        base = root / "__pycache__" / "numba"
        try:
            base.mkdir(parents=True, exist_ok=True)
            writable = os.access(base, os.W_OK)
        except OSError:
            writable = False
        if not writable:
            cache_home = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
            base = Path(cache_home) / "clutchlab" / "numba"
    return Path(base) / f"kernels-{h.hexdigest()[:16]}"


def _use_kernel_cache_dir() -> None:
    """Point numba's cache at :func:`_kernel_cache_dir` (inherited by the workflow's jobs through
    the environment; the user's own ``NUMBA_CACHE_DIR`` stays the base folder)."""
    folder = _kernel_cache_dir()
    os.environ.setdefault("CLUTCHLAB_NUMBA_CACHE_BASE", str(folder.parent))
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    if "numba" in sys.modules:  # numba read its environment on import: set its config too
        sys.modules["numba"].config.CACHE_DIR = str(folder)


_use_kernel_cache_dir()

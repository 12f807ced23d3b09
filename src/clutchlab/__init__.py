"""clutchlab: batch parameter studies of helicopter and UAV drivetrain clutches.

Physics modules are pure, vectorised numpy functions in SI units; studies turn a design of
experiments into a labelled :class:`xarray.Dataset`; :mod:`clutchlab.store` writes and reads
those Datasets as HDF5 (h5netcdf engine).
"""

from importlib.metadata import PackageNotFoundError, version

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
    import hashlib
    from pathlib import Path

    root = Path(root) if root is not None else Path(__file__).parent
    h = hashlib.sha256()
    for path in sorted(
        p for p in root.rglob("*") if p.suffix in (".py", ".yaml") and "__pycache__" not in p.parts
    ):
        h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:16]

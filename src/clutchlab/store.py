"""xarray Dataset <-> HDF5 (netCDF4 flavour, h5netcdf engine).

* every variable and coordinate must carry ``units`` and ``long_name`` (checked on write);
* floating and integer arrays are gzip-compressed;
* files are written to a temporary name in the target folder and renamed, so a reader (or an
  interrupted Snakemake run) never sees a partial file; the file's mode follows the umask like any
  tool's (``tempfile.mkstemp`` would leave it 0600); temporary files that a killed process left
  beside the target are removed by the next write of that target;
* :func:`checksum` digests a Dataset's data, so a chunk file changed or cut after it was written
  is found by the merge (``clutchlab_checksum`` attribute).
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import socket
import time
from pathlib import Path

import numpy as np
import xarray as xr

__all__ = ["MissingMetadata", "check_metadata", "write", "open", "load", "atomic", "checksum", "CorruptChunk",
           "load_verified"]

ENGINE = "h5netcdf"


class MissingMetadata(ValueError):
    """A variable or coordinate lacks ``units`` or ``long_name``."""


def check_metadata(ds: xr.Dataset) -> None:
    """Raise :class:`MissingMetadata` naming every variable without ``units``/``long_name``."""
    missing = [
        f"{name} ({key})"
        for name, var in {**ds.coords, **ds.data_vars}.items()
        for key in ("units", "long_name")
        if key not in var.attrs
    ]
    if missing:
        raise MissingMetadata("missing CF attributes: " + ", ".join(missing))


def _encoding(ds: xr.Dataset, complevel: int) -> dict:
    enc = {}
    for name, var in {**ds.coords, **ds.data_vars}.items():
        if var.ndim == 0 or var.dtype.kind not in "fiub" or var.size < 64:
            continue
        enc[name] = {"compression": "gzip", "compression_opts": complevel, "shuffle": True}
    return enc


STALE_AFTER_S = 7 * 86400  # a temporary file this old is stale whoever wrote it (e.g. another host)


def _remove_stale_temporaries(path: Path) -> None:
    host = socket.gethostname()
    for old in path.parent.glob(f".{path.name}.*.tmp"):
        try:
            tmp_host, pid, _, _ = old.name[len(path.name) + 2:].rsplit(".", 3)
            mine = tmp_host == host
            alive = mine and _pid_alive(int(pid))
            if (mine and not alive) or time.time() - old.stat().st_mtime > STALE_AFTER_S:
                old.unlink(missing_ok=True)
        except (ValueError, OSError):
            continue


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


@contextlib.contextmanager
def atomic(path):
    """Yield a temporary path beside ``path``; on success rename it to ``path``, on error remove it.

    The temporary name ``.NAME.HOST.PID.RANDOM.tmp`` tells the next writer of ``path`` whether the
    process that left it is gone (same host, dead pid), so stale files of killed runs are removed.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    _remove_stale_temporaries(path)
    tmp = path.parent / f".{path.name}.{socket.gethostname()}.{os.getpid()}.{os.urandom(4).hex()}.tmp"
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def checksum(ds: xr.Dataset) -> str:
    """SHA-256 of every variable's name, shape and values (numbers as float64, text as UTF-8), so a
    file whose data changed after it was written, or that was cut short, no longer matches."""
    h = hashlib.sha256()
    for name in sorted(ds.variables):
        v = ds.variables[name].values
        h.update(f"{name}{v.shape}".encode())
        if v.dtype.kind in "biuf":
            h.update(np.ascontiguousarray(v, dtype="<f8").tobytes())
        else:
            h.update("\x00".join(map(str, v.ravel())).encode())
    return h.hexdigest()


class CorruptChunk(RuntimeError):
    """A chunk file cannot be read or its data do not match its checksum (the message names it)."""


def load_verified(path) -> xr.Dataset:
    """Load a file written with a ``clutchlab_checksum`` attribute and check its data against it.

    A file that cannot be read or does not match is removed, and :class:`CorruptChunk` says which it
    was: the next ``snakemake`` run recomputes it.
    """
    path = Path(path)
    try:
        ds = load(path)
        stored = ds.attrs.pop("clutchlab_checksum", None)
        problem = None if stored == checksum(ds) else (
            "has no checksum" if stored is None else "does not match its checksum (changed after it was written)")
    except Exception as exc:  # h5py/netCDF raise several types for a cut or damaged file
        problem = f"cannot be read ({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
    if problem:
        path.unlink(missing_ok=True)
        raise CorruptChunk(f"{path} {problem}; it has been removed, run snakemake again to recompute it")
    return ds


def write(ds: xr.Dataset, path, *, complevel: int = 4, with_checksum: bool = False) -> Path:
    """Write ``ds`` atomically to ``path`` (HDF5 via h5netcdf) and return the path.

    ``with_checksum`` stores :func:`checksum` of the data as the ``clutchlab_checksum`` attribute
    (chunk files; :func:`load_verified` checks it).
    """
    check_metadata(ds)
    if with_checksum:
        ds = ds.assign_attrs(clutchlab_checksum=checksum(ds))
    with atomic(path) as tmp:
        ds.to_netcdf(tmp, engine=ENGINE, encoding=_encoding(ds, complevel))
    return Path(path)


def open(path) -> xr.Dataset:  # noqa: A001 - mirrors xr.open_dataset
    """Open a stored study lazily (``xr.open_dataset(path, engine="h5netcdf")``)."""
    return xr.open_dataset(path, engine=ENGINE)


def load(path) -> xr.Dataset:
    """Read a stored study fully into memory and close the file."""
    with open(path) as ds:
        return ds.load()


def flag_meanings(ds: xr.Dataset, var: str = "status") -> xr.DataArray:
    """The ``status`` codes of ``ds`` as meaning strings (for notebooks)."""
    v = ds[var]
    table = dict(zip(np.atleast_1d(v.attrs["flag_values"]).tolist(), v.attrs["flag_meanings"].split()))
    return xr.apply_ufunc(np.vectorize(lambda c: table.get(int(c), "unknown"), otypes=[object]), v)

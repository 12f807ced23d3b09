"""xarray Dataset <-> HDF5 (netCDF4 flavour, h5netcdf engine).

* every variable and coordinate must carry ``units`` and ``long_name`` (checked on write);
* floating and integer arrays are gzip-compressed;
* files are written to a temporary name in the target folder and renamed, so a reader (or an
  interrupted Snakemake run) never sees a partial file.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

__all__ = ["MissingMetadata", "check_metadata", "write", "open", "load"]

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


def write(ds: xr.Dataset, path, *, complevel: int = 4) -> Path:
    """Write ``ds`` atomically to ``path`` (HDF5 via h5netcdf) and return the path."""
    check_metadata(ds)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine=ENGINE, encoding=_encoding(ds, complevel))
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


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

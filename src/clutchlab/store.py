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

__all__ = [
    "MissingMetadata",
    "check_metadata",
    "write",
    "open",
    "load",
    "atomic",
    "checksum",
    "CorruptChunk",
    "load_verified",
    "StreamWriter",
]

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


_FILTER_KEYS = (
    "compression",
    "compression_opts",
    "shuffle",
    "chunksizes",
    "zlib",
    "complevel",
    "contiguous",
    "fletcher32",
    "szip_coding",
    "szip_pixels_per_block",
    "blosc_shuffle",
)


def _encoding(ds: xr.Dataset, complevel: int) -> dict:
    """HDF5 filters per variable (issue 16 item 5, measured on a 2^20-scenario roller result of 25
    float columns, 195 MB raw): gzip 4 + shuffle saved a third (130 MB) but took 3.2 s to write
    and 28 ms to read one column (lzf: 143 MB, 1.3 s, 17 ms); uncompressed and contiguous took
    0.5 s and 1.2 ms. Physics outputs are floats with noisy mantissas, so floats are stored
    uncompressed and contiguous (reading one variable over every scenario is a single read);
    integers and flags (status, model, counts) compress tenfold and stay gzip + shuffle.
    ``complevel`` 0 compresses nothing (chunk files: written once, read once by the merge)."""
    enc = {}
    for name, var in {**ds.coords, **ds.data_vars}.items():
        for key in _FILTER_KEYS:  # a variable read from a file brings that file's filters
            var.encoding.pop(key, None)
        if complevel == 0 or var.ndim == 0 or var.dtype.kind not in "iub" or var.size < 64:
            continue
        enc[name] = {"compression": "gzip", "compression_opts": complevel, "shuffle": True}
    return enc


STALE_AFTER_S = 7 * 86400  # a temporary file this old is stale whoever wrote it (e.g. another host)


def _remove_stale_temporaries(path: Path) -> None:
    host = socket.gethostname()
    for old in path.parent.glob(f".{path.name}.*.tmp"):
        try:
            tmp_host, pid, _, _ = old.name[len(path.name) + 2 :].rsplit(".", 3)
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
    tmp = (
        path.parent / f".{path.name}.{socket.gethostname()}.{os.getpid()}.{os.urandom(4).hex()}.tmp"
    )
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
        problem = (
            None
            if stored == checksum(ds)
            else (
                "has no checksum"
                if stored is None
                else "does not match its checksum (changed after it was written)"
            )
        )
    except Exception as exc:  # h5py/netCDF raise several types for a cut or damaged file
        problem = (
            f"cannot be read ({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
        )
    if problem:
        path.unlink(missing_ok=True)
        raise CorruptChunk(
            f"{path} {problem}; it has been removed, run snakemake again to recompute it"
        )
    return ds


def write(ds: xr.Dataset, path, *, complevel: int = 4, with_checksum: bool = False) -> Path:
    """Write ``ds`` atomically to ``path`` (HDF5 via h5netcdf) and return the path.

    ``with_checksum`` stores :func:`checksum` of the data as the ``clutchlab_checksum`` attribute
    (chunk files; :func:`load_verified` checks it).
    """
    check_metadata(ds)
    if with_checksum:
        ds = ds.assign_attrs(clutchlab_checksum=checksum(ds))
    ds = ds.copy()  # _encoding clears the filters a loaded variable brings, on this copy only
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
    table = dict(
        zip(np.atleast_1d(v.attrs["flag_values"]).tolist(), v.attrs["flag_meanings"].split())
    )
    return xr.apply_ufunc(np.vectorize(lambda c: table.get(int(c), "unknown"), otypes=[object]), v)


def _flat_blocks(start: int, stop: int, shape: tuple) -> list[tuple[tuple, int, int]]:
    """The flat C-order index range [start, stop) of an array of ``shape`` as rectangular blocks:
    [(index tuple of slices, flat start, flat stop)], at most 2·ndim of them."""
    if start >= stop:
        return []
    if len(shape) <= 1:
        return [((slice(start, stop),), start, stop)]
    inner = int(np.prod(shape[1:], dtype=np.int64))
    i0, r0 = divmod(start, inner)
    i1, r1 = divmod(stop, inner)
    if i0 == i1:
        return [
            ((i0,) + s, i0 * inner + a, i0 * inner + b)
            for s, a, b in _flat_blocks(r0, r1, shape[1:])
        ]
    out = []
    if r0:
        out += [
            ((i0,) + s, i0 * inner + a, i0 * inner + b)
            for s, a, b in _flat_blocks(r0, inner, shape[1:])
        ]
        i0 += 1
    if i1 > i0:
        out.append(
            ((slice(i0, i1),) + tuple(slice(None) for _ in shape[1:]), i0 * inner, i1 * inner)
        )
    if r1:
        out += [
            ((i1,) + s, i1 * inner + a, i1 * inner + b)
            for s, a, b in _flat_blocks(0, r1, shape[1:])
        ]
    return out


class StreamWriter:
    """Write a study result scenario range by scenario range into a pre-sized HDF5 file, so that
    no process holds more than one range (issue 16).

    Every range is a Dataset on ``run`` (a chunk's result); ``grid`` maps the flat scenario index
    onto the factor dimensions of a factorial design ({factor: coordinate DataArray}, in order),
    or is None to keep ``run``. The file is created from the first range with xarray's own CF
    encoding and HDF5 store (same variables, attributes, fill values and compression as
    :func:`write`); variables without ``run`` are written from the first range. Use as a
    context manager around :func:`atomic`'s temporary path.
    """

    def __init__(
        self, path, n: int, grid: dict | None = None, complevel: int = 4, curve_stride: int = 1
    ):
        from xarray.backends import H5NetCDFStore

        self.path, self.n, self.grid = Path(path), int(n), grid
        self.curve_stride = int(
            curve_stride
        )  # curves stored for every curve_stride-th scenario (curve_run)
        self.complevel = complevel
        self.shape = tuple(c.size for c in grid.values()) if grid else (self.n,)
        self.store = H5NetCDFStore.open(str(self.path), mode="w")
        self.created = False

    def _encode(self, ds: xr.Dataset) -> dict:
        from xarray import conventions

        ds = ds.copy()
        for name, enc in _encoding(ds, self.complevel).items():
            ds[name].encoding.update(enc)
        variables, attrs = conventions.encode_dataset_coordinates(ds)
        variables, _ = self.store.encode(variables, attrs)
        return variables

    def _final_dims(self, dims: tuple) -> tuple:
        return tuple(self.grid) + dims[1:] if self.grid and dims and dims[0] == "run" else dims

    def _create(self, ds: xr.Dataset, variables: dict) -> None:
        sizes = {d: s for d, s in ds.sizes.items() if d != "run"}
        sizes.update(dict(zip(self.grid, self.shape)) if self.grid else {"run": self.n})
        if "curve_run" in sizes:
            sizes["curve_run"] = -(-self.n // self.curve_stride)
        for dim, size in sizes.items():
            self.store.set_dimension(dim, size)
        if self.grid:  # the factors become dimension coordinates
            for name, var in self._encode(xr.Dataset(coords=self.grid)).items():
                target, data = self.store.prepare_variable(name, var)
                self.store.ds[name][...] = np.asarray(data)
        for name, var in variables.items():
            if self.grid and name in ("run", *self.grid):
                continue
            if "run" in var.dims:
                var = var.transpose("run", ...)
            attrs = dict(var.attrs)
            if (
                self.grid and "coordinates" in attrs
            ):  # factors and run are no longer auxiliary coordinates
                kept = [c for c in attrs["coordinates"].split() if c not in ("run", *self.grid)]
                attrs.pop("coordinates")
                if kept:
                    attrs["coordinates"] = " ".join(kept)
            dims = self._final_dims(
                var.dims
            )  # the file's variable is sized by the dimensions set above
            final = xr.Variable(
                dims, np.empty((1,) * len(dims), dtype=var.dtype), attrs, var.encoding
            )
            self.store.prepare_variable(name, final)
            if "run" not in var.dims and "curve_run" not in var.dims:
                self.store.ds[name][...] = np.asarray(var.data)
        self.created = True

    def write(self, ds: xr.Dataset, start: int) -> None:
        """Write the range ds (a Dataset on ``run`` of scenarios start, start + 1, ...)."""
        check_metadata(ds)
        k = int(ds.sizes.get("run", 0))
        if k == 0:
            return
        variables = self._encode(ds)
        if not self.created:
            self._create(ds, variables)
        for name, var in variables.items():
            if (
                "curve_run" in var.dims
            ):  # the stored curves: their own slice, after the earlier chunks'
                data = np.asarray(var.transpose("curve_run", ...).data)
                if data.shape[0] == 0:
                    continue
                first = -(-start // self.curve_stride)
                self.store.ds[name][first : first + data.shape[0]] = data
                continue
            if "run" not in var.dims or (self.grid and name in ("run", *self.grid)):
                continue
            data = np.asarray(var.transpose("run", ...).data)
            target = self.store.ds[name]
            for index, a, b in _flat_blocks(start, start + k, self.shape):
                block = data[a - start : b - start]
                shape = tuple(
                    len(range(*s.indices(n)))
                    for s, n in zip(index, self.shape)
                    if isinstance(s, slice)
                )
                target[index] = block.reshape(shape + data.shape[1:])

    def set_attrs(self, attrs: dict) -> None:
        """Replace the file's global attributes (e.g. those every range agreed on)."""
        for key in list(self.store.ds.attrs):
            del self.store.ds.attrs[key]
        for key, value in attrs.items():
            self.store.set_attribute(key, value)

    def close(self) -> None:
        self.store.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

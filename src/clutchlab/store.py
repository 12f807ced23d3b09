"""xarray Dataset <-> HDF5 (netCDF4 flavour, h5netcdf engine).

* every variable and coordinate must carry ``units`` and ``long_name`` (checked on write);
* floating and integer arrays are gzip-compressed;
* files are written to a temporary name in the target folder and renamed, so a reader (or an
  interrupted Snakemake run) never sees a partial file; the file's mode follows the umask like any
  tool's (``tempfile.mkstemp`` would leave it 0600); temporary files that a killed process left
  beside the target are removed by the next write of that target;
* :func:`checksum` digests a Dataset's values and attributes (every variable's and the global
  ones), block by block, so a file changed or cut after it was written is found: by the merge for
  a chunk file, by :mod:`clutchlab.verify` and a study's pages job for a result
  (``clutchlab_checksum`` attribute).
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
    "checksums",
    "checksum_attrs",
    "checksum_problem",
    "stored_checksum",
    "file_checksum_problem",
    "seal",
    "CorruptChunk",
    "ForeignChunk",
    "load_verified",
    "StreamWriter",
]

ENGINE = "h5netcdf"


class MissingMetadata(ValueError):
    """A variable or coordinate lacks ``units`` or ``long_name``."""


def check_metadata(ds: xr.Dataset) -> None:
    """Raise :class:`MissingMetadata` naming every variable without ``units``/``long_name``.

    Parameters
    ----------
    ds : xarray.Dataset
        A study result.

    Raises
    ------
    MissingMetadata
        Naming every variable and coordinate that lacks ``units`` or ``long_name``.
    """
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
    """HDF5 filters per variable (measured on a 2^20-scenario roller result of 25
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

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write.

    Yields
    ------
    pathlib.Path
        The temporary path to write to.
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


# global attributes of a sealed file: the SHA-256 of its values and attributes, and per variable
# the digests of its attributes and of its values (to say what changed)
CHECKSUM = "clutchlab_checksum"
CHECKSUM_VARIABLES = "clutchlab_checksum_variables"
_CHECKSUM_KEYS = (CHECKSUM, CHECKSUM_VARIABLES)
# values hashed per block (2 MB as float64): a stored file is read a block at a time (a smaller
# block costs more in reading than in hashing: 1 << 16 took 1.8 times the CPU of 1 << 18)
BLOCK_VALUES = 1 << 18


def _frame(text: str) -> bytes:
    b = str(text).encode("utf-8", "surrogatepass")
    return len(b).to_bytes(8, "little") + b


_NAN_BITS = np.array(np.nan, "<f8").view("<u8")  # the one NaN that stands for every NaN


def _canonical(a: np.ndarray):
    """The bytes (a bytes-like object) that stand for an array's values: numbers as little-endian
    float64 with one NaN bit pattern (a file's fill value reads back as numpy's NaN), text as
    length-prefixed UTF-8."""
    kind = a.dtype.kind
    if kind in "mM":
        a = a.view("<i8")
        kind = "i"
    if kind in "biuf":
        f = np.ascontiguousarray(a, dtype="<f8")
        if kind == "f":
            nan = np.isnan(f)
            if nan.any() and np.any(f.view("<u8")[nan] != _NAN_BITS):
                f = np.where(nan, np.nan, f)
        return memoryview(f).cast("B")
    return b"".join(
        _frame(x.decode("utf-8", "surrogateescape") if isinstance(x, bytes) else x)
        for x in a.ravel()
    )


def _canonical_attr(value) -> bytes:
    """An attribute as bytes: a scalar, a one-element list and a 1-element array are one value
    (a netCDF file reads them back either way); numbers as float64, text as UTF-8."""
    if isinstance(value, bytes):
        value = value.decode("utf-8", "surrogateescape")
    a = np.asarray(value).ravel()
    tag = b"n" if a.dtype.kind in "biufmM" else b"t"
    return tag + a.size.to_bytes(8, "little") + bytes(_canonical(a))


def _blocks(var: xr.Variable):
    """A variable's values in C order, a block of leading-axis rows at a time (a variable of a
    lazily opened file reads only that block)."""
    if var.ndim == 0:
        yield np.asarray(var.values)
        return
    rows = max(1, BLOCK_VALUES // max(1, int(np.prod(var.shape[1:], dtype=np.int64))))
    for i in range(0, var.shape[0], rows):
        yield np.asarray(var[i : i + rows].values)


def _variable_digests(name: str, var: xr.Variable, is_coord: bool) -> tuple[str, str]:
    """(digest of the variable's kind, dims, shape and attributes; digest of its values)."""
    meta = hashlib.sha256()
    meta.update(_frame(name) + (b"c" if is_coord else b"d"))
    meta.update(b"n" if var.dtype.kind in "biufmM" else b"t")
    meta.update(_frame(" ".join(map(str, var.dims))) + _frame(" ".join(map(str, var.shape))))
    for key in sorted(var.attrs):
        meta.update(_frame(key) + _canonical_attr(var.attrs[key]))
    values = hashlib.sha256()
    for block in _blocks(var):
        values.update(_canonical(block))
    return meta.hexdigest(), values.hexdigest()


def checksums(ds: xr.Dataset) -> tuple[str, dict[str, tuple[str, str]]]:
    """The checksum of a Dataset and the digests it is made of.

    Every variable and coordinate, in name order, gives a digest of its name, dimensions, shape
    and attributes and one of its values (numbers as float64, text as UTF-8, hashed a block of
    rows at a time in C order, so a lazily opened file is hashed without reading it whole); the
    checksum is the SHA-256 of the global attributes (but the checksum's own) and those digests.

    Parameters
    ----------
    ds : xarray.Dataset
        In memory or opened lazily (:func:`open`).

    Returns
    -------
    checksum : str
        64 hex digits.
    variables : dict
        Variable name -> (attributes digest, values digest), 64 hex digits each.
    """
    coords = set(ds.coords)
    digests = {
        name: _variable_digests(name, ds.variables[name], name in coords)
        for name in sorted(ds.variables)
    }
    h = hashlib.sha256()
    for key in sorted(k for k in ds.attrs if k not in _CHECKSUM_KEYS):
        h.update(_frame(key) + _canonical_attr(ds.attrs[key]))
    h.update(b"\0variables")
    for name, (meta, values) in digests.items():
        h.update(_frame(name) + meta.encode() + values.encode())
    return h.hexdigest(), digests


def checksum(ds: xr.Dataset) -> str:
    """SHA-256 of a Dataset's values and attributes.

    Of every variable and coordinate (name, dimensions, shape, attributes, values) and of the
    global attributes except the stored checksum itself (:func:`checksums`). A file whose data or
    attributes changed after it was written, or that was cut short, no longer matches.

    Parameters
    ----------
    ds : xarray.Dataset
        In memory or opened lazily (:func:`open`).

    Returns
    -------
    str
        64 hex digits.
    """
    return checksums(ds)[0]


_DIGEST_CHARS = 16  # per-variable digests are stored shortened (they locate a change; the
# checksum of the whole, all 64 digits, decides whether there is one)


def _variables_text(digests: dict) -> str:
    return "\n".join(
        f"{name} attributes:{meta[:_DIGEST_CHARS]} values:{values[:_DIGEST_CHARS]}"
        for name, (meta, values) in digests.items()
    )


def checksum_attrs(ds: xr.Dataset) -> dict:
    """The attributes that seal ``ds``.

    Parameters
    ----------
    ds : xarray.Dataset
        In memory or opened lazily (:func:`open`).

    Returns
    -------
    dict
        ``clutchlab_checksum`` (:func:`checksum`) and ``clutchlab_checksum_variables`` (each
        variable's digests, to say what changed).
    """
    whole, digests = checksums(ds)
    return {CHECKSUM: whole, CHECKSUM_VARIABLES: _variables_text(digests)}


def _parse_variables(text: str) -> dict:
    out = {}
    for line in str(text).splitlines():
        name, *parts = line.split(" ")
        fields = dict(p.split(":", 1) for p in parts if ":" in p)
        out[name] = (fields.get("attributes", ""), fields.get("values", ""))
    return out


def checksum_problem(ds: xr.Dataset) -> str | None:
    """What is wrong with ``ds`` against its stored checksum, if anything.

    Parameters
    ----------
    ds : xarray.Dataset
        In memory or opened lazily (:func:`open`).

    Returns
    -------
    str or None
        None if ``ds`` matches its stored checksum, else what is wrong: no checksum, or which
        variables' values or attributes (or the global attributes) changed.
    """
    stored = ds.attrs.get(CHECKSUM)
    if stored is None:
        return "has no checksum"
    whole, digests = checksums(ds)
    if stored == whole:
        return None
    before = _parse_variables(ds.attrs.get(CHECKSUM_VARIABLES, ""))
    n = _DIGEST_CHARS
    changed = [f"variable {v} missing" for v in before if v not in digests]
    changed += [f"new variable {v}" for v in digests if before and v not in before]
    for name, (meta, values) in digests.items():
        if name in before:
            was = before[name]
            changed += [f"{name} attributes"] if was[0] != meta[:n] else []
            changed += [f"{name} values"] if was[1] != values[:n] else []
    if before and not changed:
        changed = ["global attributes"]
    return "does not match its checksum (changed after it was written" + (
        ": " + ", ".join(changed[:8]) + (", ..." if len(changed) > 8 else "") + ")"
        if changed
        else ")"
    )


def file_checksum_problem(path) -> str | None:
    """:func:`checksum_problem` of a stored file, read a block at a time.

    A result of a million scenarios is hashed without holding it in memory.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    str or None
        None if the file matches its stored checksum, else what is wrong (a file that cannot be
        read says so).
    """
    if not Path(path).exists():
        return "does not exist"
    try:
        with open(path, indexes=False) as ds:
            return checksum_problem(ds)
    except Exception as exc:  # h5py/netCDF raise several types for a cut or damaged file
        return _unreadable(exc)


def _unreadable(exc: Exception) -> str:
    first = str(exc).splitlines()[0] if str(exc) else ""
    return f"cannot be read ({type(exc).__name__}: {first})"


def seal(path) -> str:
    """Checksum a stored file a block at a time and store it in the file's global attributes.

    With the per-variable digests. For a file written piecewise
    (:func:`clutchlab.pipeline.merge_to_file`) before it is renamed into place.

    Parameters
    ----------
    path : str or pathlib.Path
        The file, rewritten in place (its attributes only).

    Returns
    -------
    str
        The checksum.
    """
    import h5netcdf

    with open(path, indexes=False) as ds:
        attrs = checksum_attrs(ds)
    with h5netcdf.File(str(path), "a") as f:
        for key, value in attrs.items():
            f.attrs[key] = value
    return attrs[CHECKSUM]


def stored_checksum(path) -> str:
    """The checksum a stored file carries (its ``clutchlab_checksum`` attribute, :func:`seal`),
    read without its data (not checked: :func:`file_checksum_problem` does that); "" if none.

    Parameters
    ----------
    path : str or pathlib.Path
        The HDF5 file.

    Returns
    -------
    str
        The stored checksum, or "".
    """
    import h5py

    with h5py.File(path, "r") as f:
        value = f.attrs.get(CHECKSUM, "")
    return value.decode() if isinstance(value, bytes) else str(value)


class CorruptChunk(RuntimeError):
    """A chunk file cannot be read, its data do not match its checksum, or it does not belong to
    the study being merged (the message names it and says what differs)."""


class ForeignChunk(CorruptChunk):
    """A chunk file that was not computed from the design, config or source it is merged with
    (another config's chunk, an older source's, a chunk of another split; see
    :mod:`clutchlab.verify`)."""


def load_verified(path) -> xr.Dataset:
    """Load a file written with a ``clutchlab_checksum`` attribute and check it against it.

    A file that cannot be read or does not match is removed, and :class:`CorruptChunk` says which
    it was (and which variables changed): the next ``snakemake`` run recomputes it.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    xarray.Dataset
        The Dataset in memory, without the checksum attributes.

    Raises
    ------
    CorruptChunk
        If the file does not exist, cannot be read or does not match its checksum (it is removed).
    """
    path = Path(path)
    if not path.exists():
        raise CorruptChunk(f"{path} does not exist; run snakemake again to compute it")
    try:
        ds = load(path)
        problem = checksum_problem(ds)
    except Exception as exc:  # h5py/netCDF raise several types for a cut or damaged file
        problem = _unreadable(exc)
    if problem:
        path.unlink(missing_ok=True)
        raise CorruptChunk(
            f"{path} {problem}; it has been removed, run snakemake again to recompute it"
        )
    for key in _CHECKSUM_KEYS:
        ds.attrs.pop(key, None)
    return ds


def write(ds: xr.Dataset, path, *, complevel: int = 4, with_checksum: bool = False) -> Path:
    """Write ``ds`` atomically to ``path`` (HDF5 via h5netcdf) and return the path.

    ``with_checksum`` stores :func:`checksum` of the values and attributes, computed in memory
    before writing, as the ``clutchlab_checksum`` attribute (with the per-variable digests,
    :func:`checksum_attrs`); :func:`load_verified` and :mod:`clutchlab.verify` check it.

    Parameters
    ----------
    ds : xarray.Dataset
        The Dataset (every variable with ``units`` and ``long_name``: :func:`check_metadata`).
    path : str or pathlib.Path
        The file to write; its directory is created.
    complevel : int
        zlib compression level of the variables.
    with_checksum : bool
        Whether to store the checksum attributes.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    check_metadata(ds)
    if with_checksum:
        ds = ds.assign_attrs(checksum_attrs(ds))
    ds = ds.copy()  # _encoding clears the filters a loaded variable brings, on this copy only
    with atomic(path) as tmp:
        ds.to_netcdf(tmp, engine=ENGINE, encoding=_encoding(ds, complevel))
    return Path(path)


def open(path, *, indexes: bool = True) -> xr.Dataset:  # noqa: A001 - mirrors xr.open_dataset
    """Open a stored study lazily (``xr.open_dataset(path, engine="h5netcdf")``).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    indexes : bool
        False: without pandas indexes (xarray would otherwise read every dimension coordinate,
        e.g. a million-scenario ``run``, to build one).

    Returns
    -------
    xarray.Dataset
        The lazily opened Dataset (close it, or use it in a ``with`` block).
    """
    return xr.open_dataset(path, engine=ENGINE, create_default_indexes=indexes)


def load(path) -> xr.Dataset:
    """Read a stored study fully into memory and close the file.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    xarray.Dataset
        The Dataset, in memory.
    """
    with open(path) as ds:
        return ds.load()


def flag_meanings(ds: xr.Dataset, var: str = "status") -> xr.DataArray:
    """The ``status`` codes of ``ds`` as meaning strings (for notebooks)."""
    v = ds[var]
    table = dict(
        zip(
            np.atleast_1d(v.attrs["flag_values"]).tolist(),
            v.attrs["flag_meanings"].split(),
            strict=False,
        )
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
    no process holds more than one range.

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
        sizes.update(
            dict(zip(self.grid, self.shape, strict=False)) if self.grid else {"run": self.n}
        )
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
                    for s, n in zip(index, self.shape, strict=False)
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

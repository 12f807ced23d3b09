"""Running a design: split it into chunks, compute a chunk, merge the chunks (in memory or
streamed into one HDF5 file), or a whole study in memory for notebooks and tests.

A design comes from :func:`clutchlab.doe.build_design`; a chunk is computed by the study's pure
``compute`` (:mod:`clutchlab.studies`); the Snakemake job scripts call :func:`run_chunk` and
:func:`merge_to_file`.
"""

from __future__ import annotations

import contextlib
import hashlib
import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

from . import studies
from .doe import build_design, option_factors

__all__ = [
    "n_scenarios",
    "chunk_slice",
    "chunk_inputs",
    "run_chunk",
    "merge",
    "merge_to_file",
    "traces_to_file",
    "run_study",
]


def _factors(design: xr.Dataset) -> list[str]:
    return design.attrs["factors"].split()


def _gridded(design: xr.Dataset) -> bool:
    """A design whose scenarios are a grid of its factors' dimensions: a factorial design, or a
    robust study's crossed design (design points × conditions × noise draws)."""
    return design.attrs["design"] == "factorial" or "noise" in design.dims


def n_scenarios(design: xr.Dataset) -> int:
    """Number of scenarios in a design."""
    if _gridded(design):
        return math.prod(int(design.sizes[f]) for f in _factors(design))
    return int(design.sizes["run"])


def chunk_slice(n: int, chunks: int, i: int) -> slice:
    """Scenarios [start, stop) of chunk ``i`` of ``chunks`` (sizes differ by at most one)."""
    if not 0 <= i < chunks:
        raise IndexError(f"chunk {i} out of range 0..{chunks - 1}")
    bounds = np.linspace(0, n, chunks + 1).round().astype(np.int64)
    return slice(int(bounds[i]), int(bounds[i + 1]))


def chunk_inputs(design: xr.Dataset, chunks: int, i: int) -> tuple[np.ndarray, dict]:
    """Global scenario indices of chunk ``i`` and its inputs (flat arrays / scalars, SI)."""
    sl = chunk_slice(n_scenarios(design), chunks, i)
    idx = np.arange(sl.start, sl.stop)
    factors = _factors(design)
    inputs = {}
    if _gridded(design):
        shape = tuple(design.sizes[f] for f in factors)
        sub = np.unravel_index(idx, shape) if factors else ()
        for f, s in zip(factors, sub, strict=True):
            inputs[f] = design[f].values[s]
        at = dict(zip(factors, sub, strict=True))
    else:
        for f in factors:
            inputs[f] = design[f].values[sl]
    for name, var in design.data_vars.items():
        if var.ndim == 0:
            inputs[name] = float(var.values)
        elif var.dims == ("point",):  # a crossed design's sampled design points
            inputs[name] = var.values[at["point"]]
    return idx, inputs  # (a robust design's noise draws are applied by run_chunk)


def _with_noise(design: xr.Dataset, inputs: dict) -> dict:
    """A chunk's inputs for its study: a robust design's noise draws applied
    (:func:`clutchlab.robust.apply_noise`), the draw index left out."""
    from . import robust as rb

    if rb.NOISE_DIM not in design.dims:
        return inputs
    inputs = dict(inputs)
    inputs.pop("point", None)  # (the index of a sampled design point)
    index = np.asarray(inputs.pop(rb.NOISE_DIM), dtype=np.int64)
    names = [v[: -len("_noise")] for v in design.data_vars if v.endswith("_noise")]
    draws = {n: design[rb.noise_variable(n)].values for n in names}
    relative = {n: bool(design[rb.noise_variable(n)].attrs["relative"]) for n in names}
    return rb.apply_noise(inputs, draws, relative, index)


# a chunk of more than PROGRESS_MIN scenarios runs as PROGRESS_BATCHES batches with a progress line
# after each (scenarios are independent, so the numbers are those of one batch)
PROGRESS_MIN = 20_000
PROGRESS_BATCHES = 10


def run_chunk(design: xr.Dataset, options: dict, chunks: int, i: int, progress=None) -> xr.Dataset:
    """Compute chunk ``i``: a Dataset on ``run`` with every factor as a 1-D coordinate.
    ``progress``: a callable given one line of text (scenarios done, rate, time left) after each
    batch of a large chunk and at the end."""
    study = studies.get(design.attrs["study"])
    idx, inputs = chunk_inputs(design, chunks, i)
    choices = option_factors(design)
    codes = {o: inputs.pop(o) for o in choices}
    start, cpu = time.perf_counter(), time.process_time()
    n = idx.size

    physical = _with_noise(design, inputs)
    stride = int(design.attrs.get("curve_stride", 1))

    def compute(sel):
        part = {k: (v[sel] if np.ndim(v) else v) for k, v in physical.items()}
        if not any(np.ndim(v) for v in part.values()) and not len(range(n)[sel]):
            # a grid of no factor: its one scenario is in one chunk (scalars, as fixed inputs are
            # everywhere), the other chunks hold none (empty arrays)
            part = {k: np.full(0, v) for k, v in part.items()}
        if choices:
            out = _compute_by_choice(
                study, part, options, choices, {o: c[sel] for o, c in codes.items()}
            )
        else:
            out = study.compute(part, options)
        # the stored subset of the curves, taken batch by batch: the full curves of a large
        # chunk are never joined (joining them cost seconds of page faults a chunk)
        return _curve_subset(out, idx[sel], stride)

    if n:
        with _kernel_lock(study.name):  # the first call compiles (or loads from numba's cache)
            compute(slice(0, 1))  # the kernels this chunk uses: one job of a study at a time, so
            # that parallel jobs of a first run do not compile the same kernel twice (the jobs of
            # other studies, with other kernels, compile theirs meanwhile)
    if n <= PROGRESS_MIN:
        ds = compute(slice(None))
    else:
        bounds = np.linspace(0, n, PROGRESS_BATCHES + 1).round().astype(np.int64)
        parts = []
        for b in range(PROGRESS_BATCHES):
            parts.append(compute(slice(int(bounds[b]), int(bounds[b + 1]))))
            if progress is not None and b < PROGRESS_BATCHES - 1:
                done, spent = int(bounds[b + 1]), time.perf_counter() - start
                progress(
                    f"{study.name} chunk {i + 1} of {chunks}: {done} of {n} scenarios ({100 * done / n:.0f} %), "
                    f"{done / spent:,.0f} per second, about {spent * (n - done) / done:.0f} s left"
                )
        ds = _join_batches(parts)
    if progress is not None:
        spent = time.perf_counter() - start
        progress(
            f"{study.name} chunk {i + 1} of {chunks}: {n} scenarios computed in {spent:.1f} s"
            + (f" ({n / spent:,.0f} per second)" if n and spent > 0 else "")
        )
    # (the traces of the design the pages show are computed after the merge: clutchlab.traces)
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    coords = {"run": ("run", idx, {"long_name": "scenario index", "units": "1"})}
    for f in _factors(design):
        coords[f] = (
            "run",
            np.asarray(codes[f] if f in codes else inputs[f]),
            dict(design[f].attrs),
        )
    ds = ds.assign_coords(coords)
    ds.attrs.update(design.attrs)
    ds.attrs.update(_provenance(design, chunks, i))
    ds.attrs["chunk"] = f"{i + 1} of {chunks}"
    ds.attrs["compute_seconds"] = seconds  # the physics' own time (benchmark_million); not merged
    ds.attrs["compute_cpu_seconds"] = cpu  # (its CPU time: the machine may be shared)
    return ds


@contextlib.contextmanager
def _kernel_lock(study: str):
    """An exclusive lock (``fcntl.flock``) held by one process at a time of this user, this numba
    cache (``NUMBA_CACHE_DIR``, else the installed package's: the cache lives beside its source)
    and this study; none where the platform or the temporary folder does not allow one."""
    try:
        import fcntl
    except ImportError:  # not a POSIX system
        yield
        return
    cache = os.environ.get("NUMBA_CACHE_DIR") or str(Path(__file__).resolve().parent)
    key = hashlib.sha256(cache.encode()).hexdigest()[:12]
    name = f"clutchlab-{os.getuid()}-{key}-{study}.lock"
    try:
        fh = open(Path(tempfile.gettempdir()) / name, "a")  # noqa: SIM115 (closed below)
    except OSError:
        yield
        return
    with fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX)
        except OSError:
            pass
        yield  # closing the file releases the lock


def _provenance(design: xr.Dataset, chunks: int, i: int) -> dict:
    """What produced a chunk (:mod:`clutchlab.verify`): the design's config text (with the design's
    attributes), the design's hash, the source that computed it, which chunk of how many."""
    from . import source_hash, store

    return {
        "clutchlab_source": source_hash(),
        "clutchlab_design_hash": store.checksum(design),
        "chunk_index": int(i),
        "chunk_count": int(chunks),
    }


def _join_batches(parts) -> xr.Dataset:
    """Batches of one chunk, in order, as one Dataset (each batch's stored curves, on
    ``curve_run``, after each other); an attribute the batches disagree on (the models that ran,
    "; "-separated) is the union of their parts."""
    join = dict(data_vars="minimal", coords="minimal", compat="override", combine_attrs="override")
    ds = xr.concat(
        [p.drop_dims("curve_run", errors="ignore") for p in parts], dim="run", join="outer", **join
    )
    if "curve_run" in parts[0].dims:  # the curves' stored subset, along its own dimension
        curves = [n for n, v in parts[0].data_vars.items() if "curve_run" in v.dims]
        ds = ds.assign(xr.concat([p[curves] for p in parts], dim="curve_run", **join))
    ds.attrs = {}
    for k in dict.fromkeys(k for p in parts for k in p.attrs):
        vals = [p.attrs[k] for p in parts if k in p.attrs]
        if len(vals) == len(parts) and all(_same(v, vals[0]) for v in vals):
            ds.attrs[k] = vals[0]
        elif all(isinstance(v, str) for v in vals):
            ds.attrs[k] = "; ".join(
                dict.fromkeys(seg for v in vals for seg in v.split("; ") if seg)
            )
    return ds


def _compute_by_choice(study, inputs, options, choices, codes) -> xr.Dataset:
    """A chunk whose scenarios draw categorical options: one compute per combination of choices
    present, each on its own scenarios (a batch of its own), put back in scenario order. An
    attribute the groups disagree on (model_used) lists each group's value with its choices."""
    names = list(choices)
    n = len(next(iter(codes.values())))
    key = np.stack([np.asarray(codes[o]) for o in names], axis=1)
    combos, group = (
        np.unique(key, axis=0, return_inverse=True) if n else (np.zeros((1, len(names)), int), None)
    )
    parts, where = [], []
    for g, combo in enumerate(combos):
        sel = np.flatnonzero(group.reshape(-1) == g) if n else np.zeros(0, np.int64)
        chosen = {o: choices[o][int(c)] for o, c in zip(names, combo, strict=False)}
        part = study.compute(
            {k: (v[sel] if np.ndim(v) else v) for k, v in inputs.items()}, {**options, **chosen}
        )
        label = ", ".join(f"{o} {c}" for o, c in chosen.items())
        parts.append((label, part))
        where.append(sel)
    ds = xr.concat(
        [p for _, p in parts],
        dim="run",
        data_vars="minimal",
        coords="minimal",
        compat="override",
        join="outer",
        combine_attrs="override",
    )  # variables' attributes: the first group's
    ds = ds.isel(run=np.argsort(np.concatenate(where), kind="stable"))
    ds.attrs = {}
    # attributes: one that differs between choices (the model text) lists every combination of the
    # design's choices (from an empty batch each, so it is the same in every chunk); one the groups
    # present disagree on otherwise (which models ran) is left out, as the merge does
    import itertools

    empty = {k: (v[:0] if np.ndim(v) else v) for k, v in inputs.items()}
    every = {
        ", ".join(f"{o} {c}" for o, c in zip(names, combo, strict=False)): study.compute(
            empty, {**options, **dict(zip(names, combo, strict=False))}
        ).attrs
        for combo in itertools.product(*choices.values())
    }
    labels = list(every)
    for k in dict.fromkeys(k for _, p in parts for k in p.attrs):
        if not all(k in a and _same(a[k], every[labels[0]].get(k)) for a in every.values()):
            ds.attrs[k] = "; ".join(f"[{label}] {every[label].get(k, '')}" for label in labels)
        elif all(k in p.attrs and _same(p.attrs[k], parts[0][1].attrs[k]) for _, p in parts):
            ds.attrs[k] = parts[0][1].attrs[k]
    return ds


# attributes of one chunk file that a merged result does not carry (its checksum: the merged
# result is sealed with its own)
CHUNK_ATTRS = (
    "chunk",
    "chunk_index",
    "chunk_count",
    "compute_seconds",
    "compute_cpu_seconds",
    "clutchlab_checksum",
    "clutchlab_checksum_variables",
)


def _curve_subset(ds: xr.Dataset, idx, stride: int) -> xr.Dataset:
    """Keep the per-scenario curves (variables on ``run`` and another dimension) of every
    ``stride``-th scenario only, on dimension ``curve_run`` whose coordinate is their scenario
    index (a million spring curves are not stored unasked)."""
    if stride <= 1:
        return ds
    curves = [n for n, v in ds.data_vars.items() if "run" in v.dims and v.ndim > 1]
    if not curves:
        return ds
    keep = np.flatnonzero(idx % stride == 0)
    sub = ds[curves].isel(run=keep).rename(run="curve_run")
    out = ds.drop_vars(curves).assign({n: sub[n] for n in curves})
    return out.assign_coords(
        curve_run=(
            "curve_run",
            idx[keep],
            {
                "long_name": f"scenario index of the stored curves (every {stride}th scenario)",
                "units": "1",
            },
        )
    )


def _design_hash(design: xr.Dataset, config=None, source=None) -> str:
    """The design's hash (:func:`clutchlab.store.checksum`), after checking that the design was
    built from ``config`` (a study config text; None: not checked) and by ``source`` (None: the
    current :func:`clutchlab.source_hash`); :class:`clutchlab.verify.ProvenanceError` otherwise."""
    from . import source_hash, store, verify

    problems = verify.provenance_problems(
        design.attrs,
        config=config,
        source=source if source is not None else source_hash(),
        required=("config", "clutchlab_source"),
    )
    if problems:
        raise verify.ProvenanceError("the design " + "; ".join(problems))
    return store.checksum(design)


def _check_chunk(attrs, design, design_hash, config, source, position, count, where) -> None:
    """A chunk must come from this design, config and source (else
    :class:`clutchlab.store.ForeignChunk`) and be chunk ``position`` of ``count`` (else
    ValueError: chunks missing, duplicated or out of order)."""
    from . import store, verify

    problems = verify.chunk_problems(
        attrs, design, config=config, source=source, design_hash=design_hash
    )
    if problems:
        raise store.ForeignChunk(f"{where} {'; '.join(problems)}")
    index, total = int(np.ravel(attrs["chunk_index"])[0]), int(np.ravel(attrs["chunk_count"])[0])
    if (index, total) != (position, count):
        raise ValueError(
            f"{where} is chunk {index + 1} of {total}, given as chunk {position + 1} of {count}"
            " (missing or duplicated chunks, or out of order)"
        )


def merge(
    design: xr.Dataset, parts: list[xr.Dataset], *, config: str | None = None, source=None
) -> xr.Dataset:
    """Merge chunk results into one study Dataset shaped like the design.

    Factorial designs get their factors back as dimensions; sampled designs keep ``run``. The
    design's fixed values are stored as 0-d input variables. Each part must come from this design
    (its ``clutchlab_design_hash``), its config (``config``: the current study config text, by
    default the design's) and ``source`` (default: the current :func:`clutchlab.source_hash`), and
    be chunk k of ``len(parts)`` in order (:mod:`clutchlab.verify`).

    Parameters
    ----------
    design : xarray.Dataset
        The study's design (:func:`clutchlab.doe.build_design`).
    parts : list of xarray.Dataset
        Every chunk (:func:`run_chunk`), in chunk order.
    config : str or None
        The study config text the design and chunks must come from
        (:func:`clutchlab.config.study_config_text`); None: the design's.
    source : str or None
        The package source hash that must have computed them; None: the current one.

    Raises
    ------
    clutchlab.store.ForeignChunk
        A part from another design, config or source (the message says what differs).
    clutchlab.verify.ProvenanceError
        The design is not from ``config`` or ``source``.
    ValueError
        Parts missing, duplicated or out of order.
    """
    design_hash = _design_hash(design, config, source)
    for k, p in enumerate(parts):
        where = f"chunk {k + 1} of the {len(parts)} given"
        _check_chunk(p.attrs, design, design_hash, config, source, k, len(parts), where)
    curves = [n for n, v in parts[0].data_vars.items() if "curve_run" in v.dims]
    # variables without a run dimension (if a study gives any) come from the chunk of scenario 0
    first = next((p for p in parts if p.sizes.get("run", 0) and int(p["run"][0]) == 0), parts[0])
    seed = [
        n for n, v in first.data_vars.items() if "run" not in v.dims and "curve_run" not in v.dims
    ]
    ds = xr.concat(
        [
            p.drop_vars(curves + (["curve_run"] if curves else []) + [n for n in seed if n in p])
            for p in parts
        ],
        dim="run",
        data_vars="minimal",
        coords="minimal",
        compat="override",
        join="outer",
        combine_attrs="drop_conflicts",
    ).sortby("run")
    ds = ds.assign(first[seed].drop_dims(["run", "curve_run"], errors="ignore"))
    if curves:  # the stored subset of the curves, along its own dimension
        ds = ds.assign(
            xr.concat([p[curves] for p in parts], dim="curve_run", combine_attrs="drop_conflicts")
        )
    n = n_scenarios(design)
    if ds.sizes["run"] != n or not np.array_equal(ds["run"].values, np.arange(n)):
        raise ValueError(
            f"chunks cover {ds.sizes['run']} scenarios, the design has {n} (missing or duplicated)"
        )
    for key in CHUNK_ATTRS:
        ds.attrs.pop(key, None)
    factors = _factors(design)
    if _gridded(design):
        shape = tuple(design.sizes[f] for f in factors)
        out = {}
        for name, var in ds.data_vars.items():
            if "run" in var.dims:
                var = var.transpose("run", ...)
                rest = var.dims[1:]
                out[name] = (
                    tuple(factors) + rest,
                    var.values.reshape(shape + var.shape[1:]),
                    var.attrs,
                )
            else:
                out[name] = var
        other = {c: v for c, v in ds.coords.items() if "run" not in v.dims}
        ds = xr.Dataset(out, coords={**{f: design[f] for f in factors}, **other}, attrs=ds.attrs)
    for name, var in design.data_vars.items():
        ds[name] = var
    return ds


def merge_to_file(
    design: xr.Dataset,
    chunk_paths,
    path,
    objectives=(),
    constraints=None,
    sensitivity_path=None,
    *,
    config: str | None = None,
    source: str | None = None,
    robust_path=None,
) -> None:
    """Merge chunk files into the study's result file without holding the study in memory.

    Each chunk is read and checked: against its checksum (values and attributes,
    :func:`clutchlab.store.load_verified`) and its provenance (:mod:`clutchlab.verify`): it must
    come from this design (``clutchlab_design_hash``), from ``config`` (the current study config
    text; default: the design's, which must be ``config`` too), from ``source`` (default: the
    current :func:`clutchlab.source_hash`), and be chunk k of ``len(chunk_paths)`` in order. A chunk
    that fails is removed and named (:class:`clutchlab.store.CorruptChunk`, ``ForeignChunk``), so
    the next run recomputes it; a design that fails raises
    :class:`clutchlab.verify.ProvenanceError`. Each chunk is written into its region of a
    pre-sized HDF5 file (:class:`clutchlab.store.StreamWriter`): a factorial design's flat
    scenario range as blocks of its grid, a sampled design's as a slice of ``run``; global
    attributes are those every chunk agrees on (as :func:`merge`). The design answers
    (:func:`clutchlab.explore.annotate`) are then computed from the objectives, constraints and
    status alone, read back from the file, and appended; the file is sealed with its checksum of
    everything (:func:`clutchlab.store.seal`, read back a block at a time); the sensitivity
    indices likewise (``sensitivity_path``, with its checksum). Peak memory: one chunk plus a few
    per-scenario columns. The same values as :func:`merge` followed by
    :func:`~clutchlab.explore.annotate` (tested).

    Parameters
    ----------
    design : xarray.Dataset
        The study's design.
    chunk_paths : list of path
        Every chunk file, in chunk order.
    path : path
        The result file (written atomically).
    objectives, constraints
        The study's (:func:`clutchlab.explore.annotate`).
    sensitivity_path : path or None
        Where to write the sensitivity indices (factorial and saltelli designs).
    config : str or None
        The current study config text (:func:`clutchlab.config.study_config_text`); None: the
        design's.
    source : str or None
        The current package source hash; None: :func:`clutchlab.source_hash`.
    robust_path : path or None
        Where a robust (crossed) study writes its robust answers (:func:`clutchlab.explore.robust`,
        sealed with its checksum), read from the few columns they need of the sealed result.
    """
    from . import explore, store

    constraints = dict(constraints or {})
    design_hash = _design_hash(design, config, source)
    factorial = _gridded(design)
    grid = {f: design[f] for f in _factors(design)} if factorial else None
    with store.atomic(path) as tmp:
        with store.StreamWriter(
            tmp,
            n_scenarios(design),
            grid,
            curve_stride=int(design.attrs.get("curve_stride", 1)),
        ) as out:
            checked = (design_hash, config, source)
            out.set_attrs(_stream_chunks(out, design, list(chunk_paths), checked))
        needed = ["status"] + [o.split(":")[0] for o in objectives] + list(constraints)
        with xr.open_dataset(tmp, engine=store.ENGINE) as lazy:
            columns = lazy[list(dict.fromkeys(needed))].load()
        answers = explore.annotate(columns, list(objectives), constraints)
        new = answers[[v for v in ("feasible", "constraint_margin", "pareto_rank") if v in answers]]
        new.to_netcdf(tmp, mode="a", engine=store.ENGINE, encoding=store._encoding(new, 4))
        store.seal(tmp)  # the checksum of everything, after the design answers are written
    if sensitivity_path is not None:
        outputs = [o.split(":")[0] for o in objectives] + list(constraints)
        store.write(explore.sensitivity(columns, outputs), sensitivity_path, with_checksum=True)
    if robust_path is not None:
        with xr.open_dataset(path, engine=store.ENGINE) as lazy:
            answers = explore.robust(lazy, list(objectives), constraints)
        store.write(answers, robust_path, with_checksum=True)


# attributes of a merged result that its traces file carries (what it was computed from)
TRACES_ATTRS = (
    "study",
    "config",
    "clutchlab_version",
    "clutchlab_source",
    "clutchlab_design_hash",
)


def traces_to_file(result_path, options: dict, path) -> None:
    """Write the traces of the design a study's pages show (:func:`clutchlab.traces.compute`),
    chosen from the merged result at ``result_path`` (only the columns the choice needs are
    read), with the result's provenance attributes and its own checksum."""
    from . import store, traces

    with store.open(result_path) as lazy:
        ds = lazy[traces.needed(lazy)].load()
        ds.attrs = dict(lazy.attrs)
    out = traces.compute(ds, dict(options))
    out.attrs.update({k: ds.attrs[k] for k in TRACES_ATTRS if k in ds.attrs})
    store.write(out, path, with_checksum=True)


def _load_chunk(p, design, position: int, count: int, checked: tuple) -> xr.Dataset:
    """Chunk file ``p`` checked against its checksum and its provenance (``checked``: the design's
    hash, the config text, the source), without its chunk attributes; a chunk that fails is
    removed (CorruptChunk, ForeignChunk)."""
    from . import store

    chunk = store.load_verified(p)
    design_hash, config, source = checked
    try:
        _check_chunk(chunk.attrs, design, design_hash, config, source, position, count, p)
    except store.ForeignChunk as exc:
        Path(p).unlink(missing_ok=True)
        raise store.ForeignChunk(
            f"{exc}; it has been removed, run snakemake again to recompute it"
        ) from None
    for key in CHUNK_ATTRS:
        chunk.attrs.pop(key, None)
    return chunk


def _stream_chunks(out, design: xr.Dataset, chunk_paths: list, checked: tuple) -> dict:
    """Write every chunk (checked, :func:`_load_chunk`) into its region of ``out`` (a
    :class:`clutchlab.store.StreamWriter`); return the global attributes every chunk agrees on."""
    n = n_scenarios(design)
    attrs, bounds = None, []
    for position, p in enumerate(chunk_paths):
        chunk = _load_chunk(p, design, position, len(chunk_paths), checked)
        attrs = (
            dict(chunk.attrs)
            if attrs is None
            else {k: v for k, v in attrs.items() if k in chunk.attrs and _same(chunk.attrs[k], v)}
        )
        if chunk.sizes.get("run", 0) == 0:
            continue
        idx = chunk["run"].values
        start = int(idx[0])
        if not np.array_equal(idx, np.arange(start, start + idx.size)):
            raise ValueError(f"{p}: scenarios are not one contiguous range")
        bounds.append((start, start + idx.size))
        for name, var in design.data_vars.items():
            chunk[name] = var
        out.write(chunk, start)
    covered = sorted(bounds)
    if [a for a, _ in covered] != [0] + [b for _, b in covered[:-1]] or covered[-1][1] != n:
        raise ValueError(
            f"chunks cover {covered}, the design has {n} scenarios (missing or duplicated)"
        )
    return attrs


def _same(a, b) -> bool:
    try:
        return bool(np.all(a == b)) and np.shape(a) == np.shape(b)
    except ValueError:
        return False


def run_study(resolved_study: dict) -> xr.Dataset:
    """Design, compute and merge a whole study in memory (one chunk), with its design answers
    (:func:`clutchlab.explore.annotate`) and the traces of the design its pages show
    (:func:`clutchlab.traces.compute`); for notebooks and tests."""
    from . import traces
    from .explore import annotate

    design = build_design(resolved_study)
    ds = merge(design, [run_chunk(design, resolved_study["options"], 1, 0)])
    ds = annotate(ds, resolved_study.get("objectives", []), resolved_study.get("constraints", {}))
    return traces.attach(ds, traces.compute(ds, resolved_study["options"]))

"""Design of experiments: build a design, split it into chunks, run a chunk, merge the chunks.

Design kinds (``design`` key of a study section):

* ``factorial`` — full factorial over every factor; each factor is a real dimension of the
  design and of the merged result (``ds.clamp_load.sel(sheet_thickness=...)`` works).
* ``lhs`` / ``sobol`` — Latin hypercube / scrambled Sobol' samples from
  :mod:`scipy.stats.qmc`, seeded and reproducible, on a ``run`` dimension with every factor
  as a 1-D coordinate; a discrete factor (a ``values`` list, or a count's whole numbers between
  ``min`` and ``max``) takes each of its values on an equal share of the unit interval.
* ``saltelli`` — the samples Sobol' indices need (:func:`saltelli_unit`).
* ``refine`` — samples near the Pareto fronts of a stored result (:func:`refine_samples`), on
  ``run`` like the sampled kinds.

Parameters that are not factors are fixed and stored as 0-d variables.
"""
from __future__ import annotations

import time

import numpy as np
import xarray as xr

from . import __version__, source_hash, studies
from .config import study_config_text

__all__ = ["build_design", "n_scenarios", "chunk_slice", "chunk_inputs", "run_chunk", "merge", "merge_to_file",
           "run_study"]


def _param_attrs(param) -> dict:
    return {"long_name": param.long_name, "units": param.units}


def saltelli_unit(n, d, rng) -> np.ndarray:
    """Saltelli's design for first-order and total Sobol indices, in the unit cube: base matrices
    A, B (the two halves of a scrambled Sobol sequence in 2d dimensions, n points) and, per base
    point j, the block A_j, AB_j^(1), ..., AB_j^(d), B_j (AB^(i): A with column i from B) —
    n·(d + 2) rows, the order SALib's ``sobol.analyze`` (calc_second_order=False) reads."""
    from scipy.stats import qmc

    u = qmc.Sobol(d=2 * d, scramble=True, rng=rng).random(n)
    a, b = u[:, :d], u[:, d:]
    blocks = [a[:, None, :]]
    for i in range(d):
        ab = a.copy()
        ab[:, i] = b[:, i]
        blocks.append(ab[:, None, :])
    blocks.append(b[:, None, :])
    return np.concatenate(blocks, axis=1).reshape(n * (d + 2), d)


def build_design(resolved_study: dict) -> xr.Dataset:
    """The design Dataset of a resolved study section (see :func:`clutchlab.config.resolve`)."""
    study = studies.get(resolved_study["name"])
    kind = resolved_study["design"]
    factors = resolved_study["factors"]
    choices = resolved_study.get("option_factors", {})  # categorical options drawn per scenario
    coords, data = {}, {}
    if kind == "factorial":
        for name, spec in factors.items():
            coords[name] = (name, np.asarray(spec["values"], dtype=float), _param_attrs(study.parameter(name)))
    elif kind == "refine":
        from . import store

        first = store.load(resolved_study["refine"]["from"])
        values, halfwidth = refine_samples(first, resolved_study, np.random.default_rng(resolved_study["seed"]))
        coords["run"] = ("run", np.arange(resolved_study["samples"]), {"long_name": "scenario index", "units": "1"})
        for name in factors:
            attrs = {**_param_attrs(study.parameter(name)), "refine_halfwidth": halfwidth[name]}
            coords[name] = ("run", values[name], attrs)
        for name, labels in choices.items():  # kept at the front design's choice
            coords[name] = ("run", values[name], option_attrs(name, labels))
    else:
        n = resolved_study["samples"]
        d = len(factors) + len(choices)
        rng = np.random.default_rng(resolved_study["seed"])
        if d:
            from scipy.stats import qmc

            if kind == "lhs":
                unit = qmc.LatinHypercube(d=d, rng=rng).random(n)
            elif kind == "sobol":
                unit = qmc.Sobol(d=d, scramble=True, rng=rng).random(n)
            elif kind == "saltelli":
                unit = saltelli_unit(n, d, rng)
            else:
                raise ValueError(f"unknown design kind {kind!r}")
            n = unit.shape[0]
        coords["run"] = ("run", np.arange(n), {"long_name": "scenario index", "units": "1"})
        for j, (name, spec) in enumerate(factors.items()):
            u = unit[:, j]
            if "values" in spec:  # a discrete factor (a count, a list): each value on an equal share of [0, 1)
                values = np.asarray(spec["values"], dtype=float)
                vals = values[np.minimum((u * values.size).astype(np.int64), values.size - 1)]
                coords[name] = ("run", vals, _param_attrs(study.parameter(name)))
                continue
            lo, hi = spec["min"], spec["max"]
            vals = np.exp(np.log(lo) + u * np.log(hi / lo)) if spec["scale"] == "log" else lo + u * (hi - lo)
            coords[name] = ("run", vals, _param_attrs(study.parameter(name)))
        for j, (name, labels) in enumerate(choices.items(), start=len(factors)):  # each on an equal share
            codes = np.minimum((unit[:, j] * len(labels)).astype(np.int64), len(labels) - 1).astype(np.int8)
            coords[name] = ("run", codes, option_attrs(name, labels))
    for name, value in resolved_study["fixed"].items():
        data[name] = ((), float(value), _param_attrs(study.parameter(name)))
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(_provenance(resolved_study))
    ds.attrs["factors"] = " ".join([*factors, *choices])
    ds.attrs["option_factors"] = " ".join(choices)
    ds.attrs["curve_stride"] = int(resolved_study.get("curve_stride", 1))
    if kind == "refine":
        ds.attrs["refine_from"] = resolved_study["refine"]["from"]
        ds.attrs["refine_within"] = first["pareto_rank"].attrs.get("ranked_within", "")
    return ds


def option_attrs(name: str, labels) -> dict:
    """Attributes of a categorical option drawn per scenario: an int8 code, CF flags naming the choices."""
    return {"long_name": f"option {name} (code; the choices are its flag_meanings)", "units": "1",
            "flag_values": np.arange(len(labels), dtype=np.int8), "flag_meanings": " ".join(labels)}


def option_factors(design: xr.Dataset) -> dict:
    """{option: [choices]} of the options a design draws per scenario (codes index the choices)."""
    return {o: design[o].attrs["flag_meanings"].split() for o in design.attrs.get("option_factors", "").split()}


def _unit_map(spec):
    """(to unit interval, from unit interval) of a resolved factor spec (min/max/scale or values)."""
    if "values" in spec:
        lo, hi, log = min(spec["values"]), max(spec["values"]), False
    else:
        lo, hi, log = spec["min"], spec["max"], spec["scale"] == "log"
    if hi == lo:
        return (lambda x: np.zeros_like(x)), (lambda u: np.full_like(u, lo))
    if log:
        return (lambda x: np.log(x / lo) / np.log(hi / lo)), (lambda u: lo * np.exp(u * np.log(hi / lo)))
    return (lambda x: (x - lo) / (hi - lo)), (lambda u: lo + u * (hi - lo))


def refine_samples(first: xr.Dataset, resolved_study: dict, rng) -> tuple[dict, dict]:
    """New designs near the Pareto fronts of a stored result ``first``.

    Each sample belongs to one front design (round robin; when there are more front designs than
    samples, to as many spread along the front) and is drawn by Latin hypercube in a box around
    it: ± h of each factor's range, h = ``shrink`` × the first stage's spacing (a factorial grid's
    step 1/(levels − 1), N^(-1/d) for N sampled designs, a refined design's own h), reflected at
    the range's ends (the range of the first stage, never left). Operating conditions (designs are
    ranked within them), counts, choices and the discrete factors of a sampled first stage stay at
    the front design's values, so a front moves only along what the engineer chooses. Returns ({factor: values}, {factor: h}).
    """
    from . import explore

    study = studies.get(resolved_study["name"])
    factors = resolved_study["factors"]
    n, shrink = resolved_study["samples"], resolved_study["refine"]["shrink"]
    front = explore.spread(explore.front_order(first), n)
    owner = front[np.arange(n) % front.size]
    kept = set(study.conditions)
    sampled_first = first.attrs["design"] != "factorial"
    halfwidth, values = {}, {}
    u = qmc_lhs(len(factors), n, rng)
    for j, (name, spec) in enumerate(factors.items()):
        param = study.parameter(name)
        centre = explore.flat(first, name)[owner]
        discrete = "values" in spec and resolved_study["refine"]["origin_design"] != "factorial"
        if name in kept or param.integer or param.choices is not None or discrete:
            halfwidth[name], values[name] = 0.0, centre.astype(float)
            continue
        if first.attrs["design"] == "refine":
            spacing = float(first[name].attrs["refine_halfwidth"])
        elif sampled_first:
            spacing = first.sizes["run"] ** (-1.0 / len(factors))
        else:
            spacing = 1.0 / (len(spec["values"]) - 1) if len(spec["values"]) > 1 else 0.0
        h = shrink * spacing
        to_unit, from_unit = _unit_map(spec)
        x = to_unit(centre) + (2.0 * u[:, j] - 1.0) * h
        x = np.abs(x)  # reflected at 0 and at 1
        x = np.where(x > 1.0, 2.0 - x, x)
        halfwidth[name], values[name] = h, from_unit(np.clip(x, 0.0, 1.0))
    for name in resolved_study.get("option_factors", {}):  # a choice stays the front design's
        values[name] = explore.flat(first, name)[owner].astype(np.int8)
    return values, halfwidth


def qmc_lhs(d, n, rng) -> np.ndarray:
    """n Latin hypercube points in the unit cube of dimension d (shape (n, d); d may be 0)."""
    from scipy.stats import qmc

    return qmc.LatinHypercube(d=d, rng=rng).random(n) if d else np.zeros((n, 0))


def _provenance(resolved_study: dict) -> dict:
    study = studies.get(resolved_study["name"])
    return {
        "Conventions": "CF-1.10",
        "title": study.description,
        "study": study.name,
        "design": resolved_study["design"],
        "model": study.model,
        "clutchlab_version": __version__,
        "clutchlab_source": source_hash(),
        "config": study_config_text(resolved_study),
        "source": "clutchlab",
    }


def _factors(design: xr.Dataset) -> list[str]:
    return design.attrs["factors"].split()


def n_scenarios(design: xr.Dataset) -> int:
    """Number of scenarios in a design."""
    if design.attrs["design"] == "factorial":
        return int(np.prod([design.sizes[f] for f in _factors(design)], dtype=np.int64))
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
    if design.attrs["design"] == "factorial":
        shape = tuple(design.sizes[f] for f in factors)
        sub = np.unravel_index(idx, shape) if factors else ()
        for f, s in zip(factors, sub):
            inputs[f] = design[f].values[s]
    else:
        for f in factors:
            inputs[f] = design[f].values[sl]
    for name, var in design.data_vars.items():
        inputs[name] = float(var.values)
    return idx, inputs


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
    start = time.perf_counter()
    n = idx.size

    def compute(sel):
        part = {k: (v[sel] if np.ndim(v) else v) for k, v in inputs.items()}
        if choices:
            return _compute_by_choice(study, part, options, choices, {o: c[sel] for o, c in codes.items()})
        return study.compute(part, options)

    if n <= PROGRESS_MIN:
        ds = compute(slice(None))
    else:
        bounds = np.linspace(0, n, PROGRESS_BATCHES + 1).round().astype(np.int64)
        parts = []
        for b in range(PROGRESS_BATCHES):
            parts.append(compute(slice(int(bounds[b]), int(bounds[b + 1]))))
            if progress is not None and b < PROGRESS_BATCHES - 1:
                done, spent = int(bounds[b + 1]), time.perf_counter() - start
                progress(f"{study.name} chunk {i + 1} of {chunks}: {done} of {n} scenarios ({100 * done / n:.0f} %), "
                         f"{done / spent:,.0f} per second, about {spent * (n - done) / done:.0f} s left")
        ds = _join_batches(parts)
    if progress is not None:
        spent = time.perf_counter() - start
        progress(f"{study.name} chunk {i + 1} of {chunks}: {n} scenarios computed in {spent:.1f} s"
                 + (f" ({n / spent:,.0f} per second)" if n and spent > 0 else ""))
    ds = _curve_subset(ds, idx, int(design.attrs.get("curve_stride", 1)))
    if idx.size and idx[0] == 0 and study.traces is not None:  # the seed design's traces: once per study,
        # by the chunk holding scenario 0 (with more chunks than scenarios, chunk 0 may be empty)
        ds = ds.merge(study.traces(inputs, study.full_options(options)))
    seconds = time.perf_counter() - start
    coords = {"run": ("run", idx, {"long_name": "scenario index", "units": "1"})}
    for f in _factors(design):
        coords[f] = ("run", np.asarray(codes[f] if f in codes else inputs[f]), dict(design[f].attrs))
    ds = ds.assign_coords(coords)
    ds.attrs.update(design.attrs)
    ds.attrs["chunk"] = f"{i + 1} of {chunks}"
    ds.attrs["compute_seconds"] = seconds  # the physics' own time (benchmark_million); not merged
    return ds


def _join_batches(parts) -> xr.Dataset:
    """Batches of one chunk, in order, as one Dataset; an attribute the batches disagree on (the
    models that ran, "; "-separated) is the union of their parts."""
    ds = xr.concat(parts, dim="run", data_vars="minimal", coords="minimal", compat="override", join="outer",
                   combine_attrs="override")
    ds.attrs = {}
    for k in dict.fromkeys(k for p in parts for k in p.attrs):
        vals = [p.attrs[k] for p in parts if k in p.attrs]
        if len(vals) == len(parts) and all(_same(v, vals[0]) for v in vals):
            ds.attrs[k] = vals[0]
        elif all(isinstance(v, str) for v in vals):
            ds.attrs[k] = "; ".join(dict.fromkeys(seg for v in vals for seg in v.split("; ") if seg))
    return ds


def _compute_by_choice(study, inputs, options, choices, codes) -> xr.Dataset:
    """A chunk whose scenarios draw categorical options: one compute per combination of choices
    present, each on its own scenarios (a batch of its own), put back in scenario order. An
    attribute the groups disagree on (model_used) lists each group's value with its choices."""
    names = list(choices)
    n = len(next(iter(codes.values())))
    key = np.stack([np.asarray(codes[o]) for o in names], axis=1)
    combos, group = np.unique(key, axis=0, return_inverse=True) if n else (np.zeros((1, len(names)), int), None)
    parts, where = [], []
    for g, combo in enumerate(combos):
        sel = np.flatnonzero(group.reshape(-1) == g) if n else np.zeros(0, np.int64)
        chosen = {o: choices[o][int(c)] for o, c in zip(names, combo)}
        part = study.compute({k: (v[sel] if np.ndim(v) else v) for k, v in inputs.items()}, {**options, **chosen})
        label = ", ".join(f"{o} {c}" for o, c in chosen.items())
        parts.append((label, part))
        where.append(sel)
    ds = xr.concat([p for _, p in parts], dim="run", data_vars="minimal", coords="minimal", compat="override",
                   join="outer", combine_attrs="override")  # variables' attributes: the first group's
    ds = ds.isel(run=np.argsort(np.concatenate(where), kind="stable"))
    ds.attrs = {}
    # attributes: one that differs between choices (the model text) lists every combination of the
    # design's choices (from an empty batch each, so it is the same in every chunk); one the groups
    # present disagree on otherwise (which models ran) is left out, as the merge does
    import itertools

    empty = {k: (v[:0] if np.ndim(v) else v) for k, v in inputs.items()}
    every = {", ".join(f"{o} {c}" for o, c in zip(names, combo)):
             study.compute(empty, {**options, **dict(zip(names, combo))}).attrs
             for combo in itertools.product(*choices.values())}
    labels = list(every)
    for k in dict.fromkeys(k for _, p in parts for k in p.attrs):
        if not all(k in a and _same(a[k], every[labels[0]].get(k)) for a in every.values()):
            ds.attrs[k] = "; ".join(f"[{label}] {every[label].get(k, '')}" for label in labels)
        elif all(k in p.attrs and _same(p.attrs[k], parts[0][1].attrs[k]) for _, p in parts):
            ds.attrs[k] = parts[0][1].attrs[k]
    return ds


# attributes of one chunk file that a merged result does not carry
CHUNK_ATTRS = ("chunk", "compute_seconds")


def _curve_subset(ds: xr.Dataset, idx, stride: int) -> xr.Dataset:
    """Keep the per-scenario curves (variables on ``run`` and another dimension) of every
    ``stride``-th scenario only, on dimension ``curve_run`` whose coordinate is their scenario
    index (issue 16 item 5: a million spring curves are not stored unasked)."""
    if stride <= 1:
        return ds
    curves = [n for n, v in ds.data_vars.items() if "run" in v.dims and v.ndim > 1]
    if not curves:
        return ds
    keep = np.flatnonzero(idx % stride == 0)
    sub = ds[curves].isel(run=keep).rename(run="curve_run")
    out = ds.drop_vars(curves).assign({n: sub[n] for n in curves})
    return out.assign_coords(curve_run=("curve_run", idx[keep], {
        "long_name": f"scenario index of the stored curves (every {stride}th scenario)", "units": "1"}))


def merge(design: xr.Dataset, parts: list[xr.Dataset]) -> xr.Dataset:
    """Merge chunk results into one study Dataset shaped like the design.

    Factorial designs get their factors back as dimensions; sampled designs keep ``run``. The
    design's fixed values are stored as 0-d input variables.
    """
    curves = [n for n, v in parts[0].data_vars.items() if "curve_run" in v.dims]
    # the seed design's traces (no run dimension) come from the chunk holding scenario 0 (run_chunk)
    first = next((p for p in parts if p.sizes.get("run", 0) and int(p["run"][0]) == 0), parts[0])
    seed = [n for n, v in first.data_vars.items() if "run" not in v.dims and "curve_run" not in v.dims]
    ds = xr.concat([p.drop_vars(curves + (["curve_run"] if curves else []) + [n for n in seed if n in p])
                    for p in parts], dim="run", data_vars="minimal", coords="minimal", compat="override",
                   join="outer", combine_attrs="drop_conflicts").sortby("run")
    ds = ds.assign(first[seed].drop_dims(["run", "curve_run"], errors="ignore"))
    if curves:  # the stored subset of the curves, along its own dimension
        ds = ds.assign(xr.concat([p[curves] for p in parts], dim="curve_run", combine_attrs="drop_conflicts"))
    n = n_scenarios(design)
    if ds.sizes["run"] != n or not np.array_equal(ds["run"].values, np.arange(n)):
        raise ValueError(f"chunks cover {ds.sizes['run']} scenarios, the design has {n} (missing or duplicated)")
    for key in CHUNK_ATTRS:
        ds.attrs.pop(key, None)
    factors = _factors(design)
    if design.attrs["design"] == "factorial":
        shape = tuple(design.sizes[f] for f in factors)
        out = {}
        for name, var in ds.data_vars.items():
            if "run" in var.dims:
                var = var.transpose("run", ...)
                rest = var.dims[1:]
                out[name] = (tuple(factors) + rest, var.values.reshape(shape + var.shape[1:]), var.attrs)
            else:
                out[name] = var
        other = {c: v for c, v in ds.coords.items() if "run" not in v.dims}
        ds = xr.Dataset(out, coords={**{f: design[f] for f in factors}, **other}, attrs=ds.attrs)
    for name, var in design.data_vars.items():
        ds[name] = var
    return ds


def merge_to_file(design: xr.Dataset, chunk_paths, path, objectives=(), constraints=None,
                  sensitivity_path=None) -> None:
    """Merge chunk files into the study's result file without holding the study in memory.

    Each chunk is read (checked against its checksum, :func:`clutchlab.store.load_verified`) and
    written into its region of a pre-sized HDF5 file (:class:`clutchlab.store.StreamWriter`): a
    factorial design's flat scenario range as blocks of its grid, a sampled design's as a slice of
    ``run``; global attributes are those every chunk agrees on (as :func:`merge`). The design
    answers (:func:`clutchlab.explore.annotate`) are then computed from the objectives,
    constraints and status alone, read back from the file, and appended; the sensitivity indices
    likewise (``sensitivity_path``). Peak memory: one chunk plus a few per-scenario columns. The
    same values as :func:`merge` followed by :func:`~clutchlab.explore.annotate` (tested)."""
    from . import explore, store

    constraints = dict(constraints or {})
    factors = _factors(design)
    factorial = design.attrs["design"] == "factorial"
    n = n_scenarios(design)
    grid = {f: design[f] for f in factors} if factorial else None
    attrs, bounds = None, []
    with store.atomic(path) as tmp:
        with store.StreamWriter(tmp, n, grid, curve_stride=int(design.attrs.get("curve_stride", 1))) as out:
            for p in chunk_paths:
                chunk = store.load_verified(p)
                for key in CHUNK_ATTRS:
                    chunk.attrs.pop(key, None)
                attrs = dict(chunk.attrs) if attrs is None else {
                    k: v for k, v in attrs.items() if k in chunk.attrs and _same(chunk.attrs[k], v)}
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
                raise ValueError(f"chunks cover {covered}, the design has {n} scenarios (missing or duplicated)")
            out.set_attrs(attrs)
        needed = ["status"] + [o.split(":")[0] for o in objectives] + list(constraints)
        with xr.open_dataset(tmp, engine=store.ENGINE) as lazy:
            columns = lazy[list(dict.fromkeys(needed))].load()
        answers = explore.annotate(columns, list(objectives), constraints)
        new = answers[[v for v in ("feasible", "constraint_margin", "pareto_rank") if v in answers]]
        new.to_netcdf(tmp, mode="a", engine=store.ENGINE, encoding=store._encoding(new, 4))
    if sensitivity_path is not None:
        outputs = [o.split(":")[0] for o in objectives] + list(constraints)
        store.write(explore.sensitivity(columns, outputs), sensitivity_path)


def _same(a, b) -> bool:
    try:
        return bool(np.all(a == b)) and np.shape(a) == np.shape(b)
    except ValueError:
        return False


def run_study(resolved_study: dict) -> xr.Dataset:
    """Design, compute and merge a whole study in memory (one chunk), with its design answers
    (:func:`clutchlab.explore.annotate`); for notebooks and tests."""
    from .explore import annotate

    design = build_design(resolved_study)
    ds = merge(design, [run_chunk(design, resolved_study["options"], 1, 0)])
    return annotate(ds, resolved_study.get("objectives", []), resolved_study.get("constraints", {}))

"""Design of experiments: build a design (running and merging its chunks: :mod:`clutchlab.pipeline`).

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

import numpy as np
import xarray as xr

from . import __version__, source_hash, studies
from .config import study_config_text

__all__ = ["build_design", "saltelli_unit", "refine_samples", "option_factors", "option_attrs"]


def _param_attrs(param) -> dict:
    return param.attrs()


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
    if _sampled_robust(resolved_study):
        return _crossed_points(study, resolved_study)
    return _design(study, resolved_study)


def _design(study, resolved_study: dict) -> xr.Dataset:
    """A factorial grid (crossed with its noise draws for a robust study) or samples on run."""
    kind = resolved_study["design"]
    factors = resolved_study["factors"]
    choices = resolved_study.get("option_factors", {})  # categorical options drawn per scenario
    coords, data = {}, {}
    if kind == "factorial":
        for name, spec in factors.items():
            coords[name] = (
                name,
                np.asarray(spec["values"], dtype=float),
                _param_attrs(study.parameter(name)),
            )
    elif kind == "refine":
        from . import store

        first = store.load(resolved_study["refine"]["from"])
        values, halfwidth = refine_samples(
            first, resolved_study, np.random.default_rng(resolved_study["seed"])
        )
        coords["run"] = (
            "run",
            np.arange(resolved_study["samples"]),
            {"long_name": "scenario index", "units": "1"},
        )
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
            coords[name] = ("run", _from_unit(spec, u), _param_attrs(study.parameter(name)))
        for j, (name, labels) in enumerate(
            choices.items(), start=len(factors)
        ):  # each on an equal share
            codes = np.minimum((unit[:, j] * len(labels)).astype(np.int64), len(labels) - 1).astype(
                np.int8
            )
            coords[name] = ("run", codes, option_attrs(name, labels))
    for name, value in resolved_study["fixed"].items():
        data[name] = ((), float(value), _param_attrs(study.parameter(name)))
    crossed = _crossed(study, resolved_study, coords, data)
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(_provenance(resolved_study))
    ds.attrs["factors"] = " ".join([*factors, *choices, *crossed])
    if crossed:  # the operating conditions every design must work at (robust answers)
        ds.attrs["conditions"] = " ".join(resolved_study["robust"]["conditions"])
    ds.attrs["option_factors"] = " ".join(choices)
    ds.attrs["curve_stride"] = int(resolved_study.get("curve_stride", 1))
    if kind == "refine":
        ds.attrs["refine_from"] = resolved_study["refine"]["from"]
        ds.attrs["refine_within"] = first["pareto_rank"].attrs.get("ranked_within", "")
    return ds


def _from_unit(spec: dict, u) -> np.ndarray:
    """A sampled factor's values at the unit interval's points ``u``: a discrete factor (a count,
    a list) takes each value on an equal share of [0, 1); a range maps linearly or by log."""
    if "values" in spec:
        values = np.asarray(spec["values"], dtype=float)
        return values[np.minimum((u * values.size).astype(np.int64), values.size - 1)]
    lo, hi = spec["min"], spec["max"]
    if spec["scale"] == "log":
        return np.exp(np.log(lo) + u * np.log(hi / lo))
    return lo + u * (hi - lo)


def _sampled_robust(resolved_study: dict) -> bool:
    """A robust study whose design points are sampled or refined (not a factorial grid)."""
    return bool(resolved_study.get("robust")) and resolved_study["design"] != "factorial"


POINT_DIM = "point"  # the design points of a crossed sampled design (a grid dimension of indices)


def _crossed_points(study, rs: dict) -> xr.Dataset:
    """The design of a robust study whose design points are sampled (lhs, sobol) or refined:
    dimensions ``point`` (the design points, each factor a variable on it), its conditions' grid
    and ``noise``; a refined design keeps the first stage's conditions and noise draws."""
    from . import robust as rb

    conds = rs["robust"]["conditions"]
    own = {k: v for k, v in rs["factors"].items() if k not in conds}
    rng = np.random.default_rng(rs["seed"])
    n = rs["samples"]
    coords = {POINT_DIM: (POINT_DIM, np.arange(n), {"long_name": "design point", "units": "1"})}
    data = {}
    for c in conds:
        coords[c] = (
            c,
            np.asarray(rs["factors"][c]["values"], float),
            _param_attrs(study.parameter(c)),
        )
    if rs["design"] == "refine":
        from . import store

        first = store.load(rs["refine"]["from"])
        values, halfwidth = refine_samples(front_view(first), {**rs, "factors": own}, rng)
        for name in own:
            attrs = {**_param_attrs(study.parameter(name)), "refine_halfwidth": halfwidth[name]}
            data[name] = (POINT_DIM, values[name], attrs)
        coords[rb.NOISE_DIM] = first[rb.NOISE_DIM]
        for v in first.data_vars:
            if first[v].dims == (rb.NOISE_DIM,):
                data[v] = first[v].variable
        crossed = [rb.NOISE_DIM]
    else:
        from scipy.stats import qmc

        d = len(own)
        gen = (
            qmc.LatinHypercube(d=d, rng=rng)
            if rs["design"] == "lhs"
            else qmc.Sobol(d=d, scramble=True, rng=rng)
        )
        unit = gen.random(n)
        for j, (name, spec) in enumerate(own.items()):
            data[name] = (
                POINT_DIM,
                _from_unit(spec, unit[:, j]),
                _param_attrs(study.parameter(name)),
            )
        crossed = _crossed(study, rs, coords, data)
    for name, value in rs["fixed"].items():
        data[name] = ((), float(value), _param_attrs(study.parameter(name)))
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(_provenance(rs))
    ds.attrs["factors"] = " ".join([POINT_DIM, *conds, *crossed])
    ds.attrs["design_factors"] = " ".join(own)
    ds.attrs["option_factors"] = ""
    ds.attrs["curve_stride"] = int(rs.get("curve_stride", 1))
    ds.attrs["conditions"] = " ".join(conds)
    if rs["design"] == "refine":
        ds.attrs["refine_from"] = rs["refine"]["from"]
        ds.attrs["refine_within"] = ""
    return ds


def front_view(first: xr.Dataset) -> xr.Dataset:
    """A stored result as :func:`refine_samples` reads it: itself, or for a robust (crossed)
    result its robust answers over the design factors (the robust front as ``pareto_rank``, the
    robust objectives as the objectives, design points on ``run``)."""
    from . import explore
    from . import robust as rb

    if rb.NOISE_DIM not in first.dims:
        return first
    answers = explore.robust(first)
    which = answers["robust_rank"].attrs["robust_objectives"]
    objectives = answers["robust_rank"].attrs["objectives"].split()
    rank = answers["robust_rank"]
    view = xr.Dataset(
        {
            "status": xr.zeros_like(rank, dtype=np.int8),
            "pareto_rank": rank.assign_attrs(objectives=" ".join(objectives), ranked_within=""),
            **{o.split(":")[0]: answers[f"{which}_{o.split(':')[0]}"] for o in objectives},
        },
        attrs=dict(first.attrs),
    )
    if POINT_DIM in view.dims:
        view = view.swap_dims({POINT_DIM: "run"}).drop_vars(POINT_DIM, errors="ignore")
    return view


def _crossed(study, resolved_study: dict, coords: dict, data: dict) -> list[str]:
    """A robust study's ``noise`` dimension (the last of its grid): its draws' index, each noise
    parameter's draws and the draws' weights (:func:`clutchlab.robust.noise_draws`); [] for a
    study that is not robust."""
    from . import robust as rb

    spec = resolved_study.get("robust")
    if not spec:
        return []
    draws, weight = rb.noise_draws(spec, resolved_study["seed"])
    coords[rb.NOISE_DIM] = (
        rb.NOISE_DIM,
        np.arange(weight.size),
        {
            "long_name": "noise draw (the corners of the noise box first, then samples)",
            "units": "1",
        },
    )
    data["noise_weight"] = (
        rb.NOISE_DIM,
        weight,
        {"long_name": "weight of the draw in probabilities (0: a corner)", "units": "1"},
    )
    for name, values in draws.items():
        param = study.parameter(name)
        relative = spec["noise"][name]["relative"]
        attrs = (
            {"long_name": f"relative deviation of the {param.long_name} (noise)", "units": "1"}
            if relative
            else {**_param_attrs(param), "long_name": f"{param.long_name} (noise)"}
        )
        attrs["relative"] = int(relative)
        data[rb.noise_variable(name)] = (rb.NOISE_DIM, np.asarray(values, float), attrs)
    return [rb.NOISE_DIM]


def option_attrs(name: str, labels) -> dict:
    """Attributes of a categorical option drawn per scenario: an int8 code, CF flags naming the choices."""
    return {
        "long_name": f"option {name} (code; the choices are its flag_meanings)",
        "units": "1",
        "flag_values": np.arange(len(labels), dtype=np.int8),
        "flag_meanings": " ".join(labels),
    }


def option_factors(design: xr.Dataset) -> dict:
    """{option: [choices]} of the options a design draws per scenario (codes index the choices)."""
    return {
        o: design[o].attrs["flag_meanings"].split()
        for o in design.attrs.get("option_factors", "").split()
    }


def _unit_map(spec):
    """(to unit interval, from unit interval) of a resolved factor spec (min/max/scale or values)."""
    if "values" in spec:
        lo, hi, log = min(spec["values"]), max(spec["values"]), False
    else:
        lo, hi, log = spec["min"], spec["max"], spec["scale"] == "log"
    if hi == lo:
        return (lambda x: np.zeros_like(x)), (lambda u: np.full_like(u, lo))
    if log:
        return (lambda x: np.log(x / lo) / np.log(hi / lo)), (
            lambda u: lo * np.exp(u * np.log(hi / lo))
        )
    return (lambda x: (x - lo) / (hi - lo)), (lambda u: lo + u * (hi - lo))


def refine_samples(first: xr.Dataset, resolved_study: dict, rng) -> tuple[dict, dict]:
    """New designs near the Pareto fronts of a stored result ``first``.

    Each sample belongs to one front design (round robin; when there are more front designs than
    samples, to as many spread along the front) and is drawn by Latin hypercube in a box around
    it: ± h of each factor's range, h = ``shrink`` × the first stage's spacing (a factorial grid's
    step 1/(levels − 1), N^(-1/d) for N sampled designs, a refined design's own h), reflected at
    the range's ends (the range of the first stage, never left). Operating conditions (designs are
    ranked within them), counts, choices and the discrete factors of a sampled first stage stay at
    the front design's values, so a front moves only along what the engineer chooses. Returns
    ({factor: values}, {factor: h}).
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

"""Robust designs: noise draws of a crossed design, and the robust answers over conditions and
noise.

A robust study (config keys ``robust``, ``noise``, ``noise_samples``, ``role: condition``;
:func:`clutchlab.config.resolve`) crosses its factorial grid of designs with the grid of its
operating conditions and with ``noise`` draws of its uncertain parameters: the scenario grid has
the design factors, the condition factors and a ``noise`` dimension. The noise draws
(:func:`noise_draws`) are the 2^k corners of the box of the k noise parameters first (weight 0:
they count in the worst case only, so a worst case monotone in the noise is exact), then
``noise_samples`` scrambled Sobol' points (weight 1/N each) mapped through each parameter's
distribution; the same draws for every design, so designs are compared on the same draws.

:func:`answers` turns the per-scenario objectives, constraint outputs and status into a Dataset
over the design factors only: per objective its worst case, mean and quantile; per constraint
its worst margin and, per condition, the probability of violation over the noise with a Wilson
interval (a failed status is a violation); ``robust_feasible`` and ``robust_rank``; the
condition and noise values where each worst case occurs. The merge writes it beside the study's
result (``results/<study>/robust.h5``); :func:`clutchlab.explore.robust` asks it of any stored
crossed result.
"""

from __future__ import annotations

import itertools

import numpy as np
import xarray as xr

from . import status as st

__all__ = [
    "noise_draws",
    "apply_noise",
    "wilson_interval",
    "answers",
    "front_view",
    "NOISE_DIM",
    "CONFIDENCE",
]

NOISE_DIM = "noise"
CONFIDENCE = 0.95  # of the violation probability's interval (Wilson score)


def _ppf(u, spec) -> np.ndarray:
    """Values of a noise of ``spec`` (resolved, :func:`clutchlab.config.resolve`) at the unit
    interval's points ``u``: the inverse of its distribution function."""
    from scipy import stats

    lo, hi, c = spec["min"], spec["max"], spec["centre"]
    if spec["dist"] == "uniform":
        return lo + u * (hi - lo)
    if spec["dist"] == "triangular":
        return stats.triang.ppf(u, (c - lo) / (hi - lo), loc=lo, scale=hi - lo)
    sd = spec["sd"]
    return stats.truncnorm.ppf(u, (lo - c) / sd, (hi - c) / sd, loc=c, scale=sd)


def noise_draws(robust: dict, seed: int) -> tuple[dict, np.ndarray]:
    """The noise draws of a resolved robust section (:func:`clutchlab.config.resolve`).

    Parameters
    ----------
    robust : dict
        The resolved ``robust`` section: ``noise`` {parameter: spec} and ``noise_samples`` N (a
        power of 2).
    seed : int
        The study's ``seed`` of the scrambled Sobol' sequence.

    Returns
    -------
    ({parameter: numpy.ndarray}, numpy.ndarray)
        Each noise parameter's draws (relative deviations [1] or absolute values [SI], as its
        spec says), 2^k corners first then the N samples; and each draw's weight [1] (0 for a
        corner, 1/N for a sample; 1 for the one nominal draw of a study without noise).
    """
    from scipy.stats import qmc

    names = list(robust["noise"])
    if not names:
        return {}, np.ones(1)
    k, n = len(names), int(robust["noise_samples"])
    corners = np.array(list(itertools.product((0.0, 1.0), repeat=k)), dtype=float)
    u = qmc.Sobol(d=k, scramble=True, rng=np.random.default_rng(seed)).random_base2(int(np.log2(n)))
    values = {}
    for j, name in enumerate(names):
        spec = robust["noise"][name]
        at_corner = np.where(corners[:, j] > 0, spec["max"], spec["min"])
        values[name] = np.concatenate([at_corner, _ppf(u[:, j], spec)])
    weight = np.concatenate([np.zeros(2**k), np.full(n, 1.0 / n)])
    return values, weight


def apply_noise(inputs: dict, draws: dict, relative: dict, index) -> dict:
    """A chunk's inputs with its noise applied: each noise parameter at draw ``index`` (per
    scenario), times (1 + the draw) of the design's value where ``relative``, else the draw.

    Parameters
    ----------
    inputs : dict
        Parameter -> value [SI] (scalars or flat arrays of the chunk's scenarios).
    draws : dict
        Parameter -> its draws (:func:`noise_draws`).
    relative : dict
        Parameter -> True where its draws are relative deviations [1].
    index : numpy.ndarray of int
        The noise draw of each scenario of the chunk.

    Returns
    -------
    dict
        ``inputs`` with each noise parameter replaced by its per-scenario value [SI].
    """
    out = dict(inputs)
    for name, values in draws.items():
        d = np.asarray(values)[index]
        out[name] = np.asarray(inputs[name], dtype=float) * (1.0 + d) if relative[name] else d
    return out


def wilson_interval(k, n, confidence=CONFIDENCE) -> tuple[np.ndarray, np.ndarray]:
    """Wilson score interval of a probability from ``k`` events in ``n`` trials.

    Parameters
    ----------
    k, n : array_like
        Events and trials [1] (n > 0).
    confidence : float
        Two-sided confidence level [1].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Lower and upper bounds [1] (Wilson 1927, J. Am. Stat. Assoc. 22, 209-212).
    """
    from scipy.stats import norm

    k, n = np.asarray(k, dtype=float), np.asarray(n, dtype=float)
    z = norm.ppf(0.5 + confidence / 2.0)
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    lo = np.where(k == 0, 0.0, np.clip(centre - half, 0.0, 1.0))  # (exact at the ends: round-off)
    hi = np.where(k == n, 1.0, np.clip(centre + half, 0.0, 1.0))
    return lo, hi


def _layout(ds, robust):
    """(design dims, condition dims, the scenario array order) of a crossed result."""
    dims = list(ds["status"].dims)
    conditions = [c for c in robust["conditions"] if c in dims]
    design = [d for d in dims if d not in conditions and d != NOISE_DIM]
    return design, conditions, design + conditions + [NOISE_DIM]


def _cube(ds, name, order, ndesign) -> np.ndarray:
    """Variable ``name`` as (designs, conditions, noise draws)."""
    a = ds[name].broadcast_like(ds["status"]).transpose(*order).values
    return a.reshape(int(np.prod(a.shape[:ndesign], dtype=np.int64)), -1, a.shape[-1])


def _stats(v, weight, q):
    """Worst case (all draws), mean and worst-condition q-quantile (samples) of v (designs,
    conditions, draws), every objective minimised (NaN wherever a scenario failed)."""
    bad = np.isnan(v).any(axis=(1, 2))
    samples = v[:, :, weight > 0]
    with np.errstate(invalid="ignore"):
        worst = np.where(bad, np.nan, np.nanmax(np.where(np.isnan(v), -np.inf, v), axis=(1, 2)))
        mean = np.where(bad, np.nan, (samples * weight[weight > 0]).sum(axis=2).mean(axis=1))
        quant = np.quantile(samples, q, axis=2, method="inverted_cdf").max(axis=1)
    return worst, mean, np.where(bad, np.nan, quant)


def _argworst(v) -> np.ndarray:
    """Flat (condition, draw) index of each design's worst value of v (a NaN, a failure, first)."""
    flat = v.reshape(v.shape[0], -1)
    return np.argmax(np.where(np.isnan(flat), np.inf, flat), axis=1)


def noise_variable(name: str) -> str:
    """Name of the stored draws of noise parameter ``name`` (on dimension ``noise``)."""
    return f"{name}_noise"


def _attrs(ds, name) -> dict:
    a = ds[name].attrs
    return {k: a[k] for k in ("units", "long_name", "units_metadata") if k in a}


def answers(ds, objectives, constraints, robust) -> xr.Dataset:
    """The robust answers of a crossed study result, over its design factors only.

    Parameters
    ----------
    ds : xarray.Dataset
        A merged crossed result: ``status``, the objective and constrained outputs, the condition
        and ``noise`` dimensions and the draws' ``noise_weight``.
    objectives : list of str
        "name:min" / "name:max".
    constraints : dict
        Output -> ("max" or "min", limit [SI]).
    robust : dict
        The resolved robust section (``conditions``, ``quantile``, ``max_failure_probability``,
        ``objectives``: "worst" or "quantile").

    Returns
    -------
    xarray.Dataset
        Over the design factors: ``worst_<o>``, ``mean_<o>``, ``quantile_<o>`` per objective (its
        units); ``worst_margin`` (constraint) and ``violation_probability`` with its Wilson bounds
        (constraint, conditions) [1]; ``failure_probability`` (any constraint violated or status
        not ok; conditions) with its bounds [1]; ``robust_feasible``; ``robust_rank`` (Pareto rank
        of the robust-feasible designs over the worst-case or quantile objectives, moocore;
        −1 excluded); per answer (objective or constraint) the condition and noise values where
        its worst case occurs (``binding_<name>``, dimension ``answer``).

    Notes
    -----
    Worst case: over every condition and every draw, corners included; mean: over the conditions
    (equally) and the samples (their weights); quantile: the highest over the conditions of the
    samples' q-quantile (inverted CDF); each NaN wherever a scenario of the design failed. A
    violation probability counts the samples (corners have weight 0) whose status is not ok or
    whose margin is < 0.
    """
    from . import explore

    design, conds, order = _layout(ds, robust)
    nd = len(design)
    weight = ds["noise_weight"].values
    samples = weight > 0
    shape = tuple(ds.sizes[d] for d in design)
    cshape = tuple(ds.sizes[c] for c in conds)
    coords = {d: ds[d] for d in design}
    coords.update({c: ds[c] for c in conds})
    for v in ds.data_vars:  # a sampled design's factors, on its design points
        if ds[v].ndim and set(ds[v].dims) <= set(design):
            coords[v] = ds[v]
    ok = _cube(ds, "status", order, nd) == st.CODE["ok"]
    out, cols, worst_at = _objective_answers(ds, objectives, robust, (order, nd, design, shape))
    names = list(constraints)
    wm, vp, violated = _constraint_answers(ds, constraints, ok, samples, (order, nd), worst_at)
    n = int(samples.sum())
    fail = violated[:, :, samples].sum(axis=2)
    feasible = (fail / n <= robust["max_failure_probability"]).all(axis=1)
    if cols:
        rank = explore.pareto_rank(np.stack(cols, axis=1), feasible)
    else:
        rank = np.full(feasible.shape, -1, np.int64)
    out.update(_probabilities(names, wm, vp, fail, n, design, conds, shape, cshape))
    out.update(_verdicts(feasible, rank, design, shape, objectives, robust))
    out.update(_binding(ds, worst_at, conds, order, design, shape))
    res = xr.Dataset(out, coords=coords).assign_coords(_answer_coords(worst_at, constraints))
    res.attrs.update(_summary_attrs(ds, robust, conds, n))
    return res


def _objective_answers(ds, objectives, robust, layout):
    """Per objective its worst case, mean and quantile over the design factors; the columns the
    robust ranks compare; where each worst case occurs."""
    order, nd, design, shape = layout
    weight = ds["noise_weight"].values
    out, cols, worst_at = {}, [], {}
    for item in objectives:
        name, sense = item.split(":")
        sign = 1.0 if sense == "min" else -1.0
        v = sign * _cube(ds, name, order, nd).astype(float)
        worst, mean, quant = _stats(v, weight, robust["quantile"])
        attrs = _attrs(ds, name)
        for what, vals, text in (
            ("worst", worst, "worst case over conditions and noise (corners included) of"),
            ("mean", mean, "mean over conditions and noise samples of"),
            ("quantile", quant, f"highest {robust['quantile']:g}-quantile over conditions of"),
        ):
            out[f"{what}_{name}"] = (
                design,
                (sign * vals).reshape(shape),
                {**attrs, "long_name": f"{text} {attrs.get('long_name', name)}"},
            )
        cols.append((worst if robust["objectives"] == "worst" else quant).reshape(-1))
        worst_at[name] = _argworst(v)
    return out, cols, worst_at


def _constraint_answers(ds, constraints, ok, samples, layout, worst_at):
    """Per constraint the worst margin and the violating samples per condition (a failed status
    violates); every scenario's violation of any constraint; where each worst margin occurs
    (added to ``worst_at``)."""
    from . import explore

    order, nd = layout
    violated = ~ok
    wm, vp = [], []
    for output, (op, limit) in constraints.items():
        m = explore.constraint_margin(_cube(ds, output, order, nd), op, limit)
        with np.errstate(invalid="ignore"):
            bad = ~ok | np.isnan(m) | (m < 0)
        violated = violated | bad
        m = np.where(ok, m, np.nan)
        wm.append(np.where(np.isnan(m).any(axis=(1, 2)), np.nan, np.nanmin(m, axis=(1, 2))))
        vp.append(bad[:, :, samples].sum(axis=2))
        worst_at[output] = _argworst(-m)
    return wm, vp, violated


def _verdicts(feasible, rank, design, shape, objectives, robust) -> dict:
    """``robust_feasible`` and ``robust_rank`` over the design factors."""
    return {
        "robust_feasible": (
            design,
            feasible.reshape(shape).astype(np.int8),
            {
                "long_name": "probability of failure (a constraint violated or status not ok) at "
                f"most {robust['max_failure_probability']:g} at every operating condition",
                "units": "1",
                "flag_values": np.array([0, 1], np.int8),
                "flag_meanings": "not_robust robust",
            },
        ),
        "robust_rank": (
            design,
            rank.reshape(shape),
            {
                "long_name": "Pareto rank among robust-feasible designs over their "
                f"{robust['objectives']} objectives (0: the robust front; -1: excluded)",
                "units": "1",
                "objectives": " ".join(objectives),
                "robust_objectives": robust["objectives"],
            },
        ),
    }


def _answer_coords(worst_at, constraints) -> dict:
    """The ``answer`` and ``constraint`` coordinates of the robust answers."""
    coords = {
        "answer": (
            "answer",
            np.array(list(worst_at), dtype=object),
            {
                "long_name": "objective or constrained output whose worst case the binding "
                "values locate",
                "units": "1",
            },
        )
    }
    if constraints:
        coords["constraint"] = (
            "constraint",
            np.array(list(constraints), dtype=object),
            {
                "long_name": "constrained output",
                "units": "1",
                "limits": " ".join(f"{k}:{op}:{v:.6g}" for k, (op, v) in constraints.items()),
            },
        )
    return coords


def _probabilities(names, wm, vp, fail, n, design, conds, shape, cshape) -> dict:
    """Worst margins and violation / failure probabilities with their Wilson bounds."""
    out = {}
    cdims = tuple(design) + tuple(conds)
    text = f"({100 * CONFIDENCE:g} % Wilson score bound over {n} noise samples)"
    if names:
        k = np.stack(vp).reshape((len(names),) + shape + cshape)
        lo, hi = wilson_interval(k, n)
        out["worst_margin"] = (
            ("constraint",) + tuple(design),
            np.stack(wm).reshape((len(names),) + shape),
            {
                "long_name": "worst constraint margin over conditions and noise (corners "
                "included; NaN where a scenario failed), >= 0 where met",
                "units": "1",
            },
        )
        for var, vals, what in (
            ("violation_probability", k / n, "probability of violating the constraint"),
            (
                "violation_probability_low",
                lo,
                f"lower bound {text} of the probability of violation",
            ),
            (
                "violation_probability_high",
                hi,
                f"upper bound {text} of the probability of violation",
            ),
        ):
            out[var] = (("constraint",) + cdims, vals, {"long_name": what, "units": "1"})
    f = fail.reshape(shape + cshape)
    lo, hi = wilson_interval(f, n)
    for var, vals, what in (
        ("failure_probability", f / n, "probability of failure (a constraint violated or status "
         "not ok) over the noise at the condition"),
        ("failure_probability_low", lo, f"lower bound {text} of the probability of failure"),
        ("failure_probability_high", hi, f"upper bound {text} of the probability of failure"),
    ):  # fmt: skip
        out[var] = (cdims, vals, {"long_name": what, "units": "1"})
    return out


def _binding(ds, worst_at, conds, order, design, shape) -> dict:
    """Per answer, the condition and noise values at each design's worst case."""
    draws = ds.sizes[NOISE_DIM]
    cshape = tuple(ds.sizes[c] for c in conds)
    idx = np.stack([worst_at[a] for a in worst_at]) if worst_at else np.zeros((0, 1), int)
    cond_idx, draw = np.divmod(idx, draws)
    sub = np.unravel_index(cond_idx, cshape) if conds else ()
    dims = ("answer",) + tuple(design)
    out = {}
    for c, s in zip(conds, sub, strict=True):
        out[f"binding_{c}"] = (
            dims,
            ds[c].values[s].reshape((-1,) + shape),
            {**_attrs(ds, c), "long_name": f"{_attrs(ds, c).get('long_name', c)} where the "
             "worst case occurs"},
        )  # fmt: skip
    out["binding_noise"] = (
        dims,
        draw.reshape((-1,) + shape),
        {"long_name": "noise draw where the worst case occurs (index on noise)", "units": "1"},
    )
    for v in ds.data_vars:
        if ds[v].dims == (NOISE_DIM,) and v != "noise_weight":
            out[f"binding_{v}"] = (
                dims,
                ds[v].values[draw].reshape((-1,) + shape),
                {**_attrs(ds, v), "long_name": f"{_attrs(ds, v).get('long_name', v)} where the "
                 "worst case occurs"},
            )  # fmt: skip
    return out


def _summary_attrs(ds, robust, conds, n) -> dict:
    return {
        "title": f"robust answers: {ds.attrs.get('title', '')}",
        "study": ds.attrs.get("study", ""),
        "conditions": " ".join(conds),
        "noise_parameters": " ".join(robust["noise"]) if "noise" in robust else "",
        "noise_samples": int(n),
        "quantile": float(robust["quantile"]),
        "max_failure_probability": float(robust["max_failure_probability"]),
        "robust_objectives": robust["objectives"],
        "confidence": CONFIDENCE,
        "source": "clutchlab",
    }


def front_view(answers_ds, attrs=None) -> xr.Dataset:
    """Robust answers as a study-like Dataset over the designs, for comparing robust fronts.

    The robust objective of each objective (its worst case or its quantile, as the robust ranks
    compared them) becomes a variable of that name with ``worst_`` or ``quantile_`` in front,
    ``robust_feasible`` becomes ``feasible`` and ``robust_rank`` becomes ``pareto_rank`` (ranked
    over all designs at once: ``ranked_within`` empty), so that
    :func:`clutchlab.explore.refinement_gain` measures how far a refining stage moved the robust
    front.

    Parameters
    ----------
    answers_ds : xarray.Dataset
        Robust answers (:func:`answers`, ``results/<study>/robust.h5``).
    attrs : dict or None
        Attributes of the view (e.g. the study result's, with ``refine_from``); None: the
        answers' own.

    Returns
    -------
    xarray.Dataset
        Variables ``<worst|quantile>_<objective>`` [the objective's unit], ``feasible`` [-],
        ``pareto_rank`` [-] and ``status`` (all 0: the robust verdict is in ``feasible``), over
        the design factors; attribute ``robust_view`` = 1.
    """
    rank = answers_ds["robust_rank"]
    which = rank.attrs["robust_objectives"]
    objectives = []
    data = {}
    for item in rank.attrs["objectives"].split():
        name, sense = item.split(":")
        column = f"{which}_{name}"
        data[column] = answers_ds[column]
        objectives.append(f"{column}:{sense}")
    feasible = answers_ds["robust_feasible"]
    data["feasible"] = feasible.astype(bool)
    data["status"] = xr.zeros_like(feasible, dtype=np.int8)
    data["pareto_rank"] = rank.copy(data=rank.values, deep=False).assign_attrs(
        objectives=" ".join(objectives), ranked_within=""
    )
    view_attrs = dict(answers_ds.attrs if attrs is None else attrs)
    view_attrs["robust_view"] = 1  # pages say "designs" and "robust front"
    return xr.Dataset(data, attrs=view_attrs)

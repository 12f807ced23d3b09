"""Design answers from stored results: feasibility, Pareto ranks, variance decomposition.

Pure functions on arrays and on any stored study Dataset (``clutchlab.store.load``), for the
pipeline and for notebooks: an engineer asks a new question of results without rerunning them.

* :func:`pareto_rank` — non-dominated sorting (rank 0 = the Pareto front, 1 = the front once
  rank 0 is removed, ...); −1 where a design is excluded (infeasible, a non-finite objective).
  The sorting itself is moocore's (``moocore.pareto_rank``, compiled C); this module decides which
  rows take part and which are compared (groups).
* :func:`hypervolume` — the exact volume a set of points dominates up to a reference point
  (``moocore.hypervolume``).
* :func:`feasible` — every constraint met and status ok, with the margin of each constraint.
* :func:`grid_variance_decomposition` — exact main and total effects of a full factorial grid.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import moocore
import numpy as np

from . import status as st

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "pareto_rank",
    "dominates",
    "feasible",
    "condition_factors",
    "annotate",
    "hypervolume",
    "best_compromise",
    "refinement_gain",
    "objective_table",
    "front_order",
    "grid_variance_decomposition",
    "sobol_indices",
    "sensitivity",
    "robust",
    "best_robust",
    "binding_answer",
    "robust_scenario",
]


def dominates(a, b) -> bool:
    """Whether ``a`` dominates ``b`` (minimisation): no worse in every objective and better in one.

    Parameters
    ----------
    a, b : array_like (M,)
        Objective values of two designs, each column in one unit.

    Returns
    -------
    bool
        True where ``a`` dominates ``b``.
    """
    a, b = np.asarray(a), np.asarray(b)
    return bool(np.all(a <= b) and np.any(a < b))


def pareto_rank(values, include=None, groups=None):
    """Non-dominated rank of each row of ``values`` (N, M), every objective minimised.

    Parameters
    ----------
    values : array_like (N, M), or a stored study Dataset
        Objectives [any units; each column in one unit]; negate a column to maximise it. Given a
        Dataset, ``include`` is the list of objectives ("name:min"/"name:max") and ``groups`` the
        factors to rank within (default: its operating conditions that are grid dimensions, as
        the pipeline ranks); the designs taking part are those with ``feasible`` 1 (status ok
        where the Dataset has no ``feasible``); returns a labelled DataArray shaped like
        ``status``, e.g. ``pareto_rank(ds, ["slip_work:min", "lockup_time:min"])`` for a question
        the stored ranks did not ask.
    include : array_like of bool (N,) or None
        Rows that take part (e.g. the feasible designs); rows outside it, and rows with a
        non-finite objective (NaN, ±inf), get rank −1 and do not dominate anything.
    groups : array_like (N,) or None
        Group label of each row [1] (e.g. one group per operating condition): each group is
        ranked on its own, a row compared only with the rows of its group. A row whose label is
        NaN belongs to no group and gets rank −1.

    Returns
    -------
    numpy.ndarray of int64 (N,)
        0 for the Pareto front, k for the front after removing ranks < k, −1 for excluded rows.
        Equal rows share a rank (neither dominates the other).

    Raises
    ------
    ValueError
        ``values`` is not two-dimensional, or ``include`` or ``groups`` has not one entry a row.

    Notes
    -----
    The sorting is ``moocore.pareto_rank`` (López-Ibáñez et al., moocore): Jensen's (2003)
    O(N log N) sweep for two objectives; for three or more it takes off one front at a time
    (O(N² log N) at worst for three). It is called on the rows that take part only: moocore
    itself ranks a row with a NaN objective as dominating.
    """
    if hasattr(values, "data_vars"):  # a study Dataset
        return _dataset_rank(values, include, groups)
    f = np.asarray(values, dtype=float)
    if f.ndim != 2:
        raise ValueError(f"values must be (designs, objectives), got shape {f.shape}")
    ok = np.isfinite(f).all(axis=1)
    if include is not None:
        ok &= _per_row(include, f.shape[0], "include").astype(bool)
    rank = np.full(f.shape[0], -1, dtype=np.int64)
    if groups is None:
        _rank_into(rank, f, np.flatnonzero(ok))
        return rank
    labels = _per_row(groups, f.shape[0], "groups")
    if labels.dtype.kind in "fc":
        ok &= ~np.isnan(labels)
    idx = np.flatnonzero(ok)
    _, gid = np.unique(labels[idx], return_inverse=True)
    order = np.argsort(gid.reshape(-1), kind="stable")
    bounds = np.flatnonzero(np.diff(gid.reshape(-1)[order])) + 1
    for part in np.split(idx[order], bounds):
        _rank_into(rank, f, part)
    return rank


def _per_row(a, n, name) -> np.ndarray:
    """``a`` as a flat array of ``n`` entries (one a row), else ValueError naming ``name``."""
    a = np.asarray(a).reshape(-1)
    if a.shape[0] != n:
        raise ValueError(f"{name} must have one entry per row of values ({n}), got {a.shape[0]}")
    return a


def _rank_into(rank, f, rows) -> None:
    """Write the Pareto ranks of the rows ``rows`` of ``f`` (finite, taking part) into ``rank``."""
    if rows.size:
        rank[rows] = moocore.pareto_rank(f[rows])


def _dataset_rank(ds, objectives, within):
    """The Dataset form of :func:`pareto_rank`: ranks of the feasible designs as a DataArray."""
    kept = ds["feasible"] if "feasible" in ds else ds["status"] == st.CODE["ok"]
    ranked = annotate(
        ds.assign(status=ds["status"].where(kept.astype(bool), st.CODE["invalid_input"])),
        list(objectives),
        {},
        within=within,
    )
    return ranked["pareto_rank"]


def _check_objectives(ds, objectives) -> None:
    """ValueError naming an objective that is not "output:min" or "output:max" of ``ds``
    ("slip_work:MIN" ranked it maximised)."""
    for o in objectives:
        name, _, sense = str(o).partition(":")
        if sense not in ("min", "max") or name not in ds:
            raise ValueError(
                f"objective {o!r}: give 'output:min' or 'output:max' of an output of the result"
            )


def _check_constraints(ds, constraints) -> None:
    """ValueError naming a constraint that is not output -> ("min" or "max", a finite limit in
    SI) of ``ds`` ("<=" was read as a minimum)."""
    for output, spec in constraints.items():
        op, limit = (
            (tuple(spec) + (None, None))[:2] if isinstance(spec, (tuple, list)) else (spec, None)
        )
        number = isinstance(limit, (int, float, np.integer, np.floating)) and not isinstance(
            limit, (bool, np.bool_)
        )
        if output not in ds or op not in ("min", "max") or not (number and np.isfinite(limit)):
            raise ValueError(
                f"constraint {output}: {spec!r}: give an output of the result -> ('min' or "
                "'max', its limit as a finite number in SI)"
            )


def feasible(ds, constraints: dict) -> tuple[np.ndarray, dict]:
    """Feasibility of every scenario of a study Dataset.

    The margin is what every margin of clutchlab is, capacity over demand minus one, ≥ 0 where met
    (:func:`constraint_margin`), NaN where the output is NaN. A scenario is feasible where its
    status is ok and every margin is ≥ 0.

    Parameters
    ----------
    ds : xarray.Dataset
        A study result (a ``status`` and the constrained outputs).
    constraints : dict
        Output name -> ("max" or "min", limit in the output's SI units).

    Returns
    -------
    feasible : numpy.ndarray of bool
        Shaped like ``status``.
    margins : dict of numpy.ndarray
        Output name -> margin [-], shaped like ``status``.
    """
    _check_constraints(ds, constraints)
    ok = np.asarray(ds["status"].values == st.CODE["ok"])
    margins = {}
    for output, (op, limit) in constraints.items():
        v = np.broadcast_to(ds[output].values, ok.shape).astype(float)
        m = constraint_margin(v, op, limit)
        margins[output] = m
        with np.errstate(invalid="ignore"):
            ok = ok & (m >= 0)
    return ok, margins


def constraint_margin(value, op, limit):
    """Margin of ``value`` against a limit [1]: capacity over demand minus one, as every margin
    output of the studies (a sprag's allowable/stress − 1, a roller's μ/tan(α/2) − 1, ...): for a
    positive limit, limit/value − 1 under a maximum (inf for a value ≤ 0: nothing to carry) and
    value/limit − 1 over a minimum. A zero limit (a margin output ≥ 0) gives the value itself
    (−value under a maximum), a negative one (limit − value)/|limit| or (value − limit)/|limit|.
    ≥ 0 exactly where the constraint is met; NaN where the value is NaN."""
    v = np.asarray(value, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        if limit > 0:
            m = np.where(v > 0, limit / v - 1.0, np.inf) if op == "max" else v / limit - 1.0
            return np.where(np.isnan(v), np.nan, m)
        if limit == 0:
            return -v if op == "max" else v + 0.0
        return (limit - v) / -limit if op == "max" else (v - limit) / -limit


def condition_factors(ds) -> tuple[list[str], list[str]]:
    """The operating conditions (:attr:`~clutchlab.studies.Study.conditions`) among the factors.

    Parameters
    ----------
    ds : xarray.Dataset
        A study result.

    Returns
    -------
    grouped : list of str
        The conditions it is ranked within: grid dimensions, the conditions a refined design kept
        at its first stage's grid values, options drawn per scenario (and ``noise`` of a robust
        study).
    sampled : list of str
        The conditions sampled on ``run``, which cannot be grouped.
    """
    from . import studies

    conditions = studies.get(ds.attrs["study"]).conditions if "study" in ds.attrs else ()
    dims = ds["status"].dims
    if "noise" in dims:  # a robust study: its conditions and each noise draw (robust answers)
        conditions = (*ds.attrs.get("conditions", "").split(), "noise")
    factors = ds.attrs.get("factors", "").split()
    kept = ds.attrs.get("refine_within", "").split()
    options = ds.attrs.get(
        "option_factors", ""
    ).split()  # drawn per scenario, but a few choices: grouped
    grouped = [c for c in conditions if c in dims or c in kept or c in options]
    return grouped, [c for c in conditions if c in factors and c not in grouped]


def flat(ds, name) -> np.ndarray:
    """A per-scenario variable or factor coordinate of a study Dataset as a flat array, in the
    order of ``status`` (grid or ``run``); a new array (numpy's broadcasting: xarray's would copy
    every coordinate of a sampled design on each call)."""
    var, dims = ds[name], ds["status"].dims
    if not set(var.dims) <= set(dims):
        return var.broadcast_like(ds["status"]).transpose(*dims).values.reshape(-1)
    values = var.transpose(*(d for d in dims if d in var.dims)).values
    shape = [ds.sizes[d] if d in var.dims else 1 for d in dims]
    return np.broadcast_to(values.reshape(shape), ds["status"].shape).reshape(-1).copy()


def unique_rows(a, return_inverse=False):
    """``numpy.unique(a, axis=0)``: the distinct rows of a 2-D array in lexicographic order (and,
    with ``return_inverse``, the index of each row among them), in about linear time where a few
    distinct rows repeat among 10^6 (pandas' hash factorisation, column by column; numpy sorts
    the rows as records). Arrays with NaN go to numpy."""
    import pandas as pd

    a = np.asarray(a)
    if a.ndim != 2 or 0 in a.shape or (a.dtype.kind == "f" and np.isnan(a).any()):
        return np.unique(a, axis=0, return_inverse=return_inverse)
    code, uniques = np.zeros(len(a), dtype=np.int64), []
    for col in a.T:
        c, u = pd.factorize(col, sort=True)
        if len(u) and code.max() > (2**62) // len(u):  # too many combinations for one int64
            return np.unique(a, axis=0, return_inverse=return_inverse)
        code = code * len(u) + c
        uniques.append(np.asarray(u, dtype=a.dtype))
    inverse, keys = pd.factorize(code, sort=True)
    keys = np.asarray(keys, dtype=np.int64)
    rows = np.empty((len(keys), a.shape[1]), dtype=a.dtype)
    for j in range(a.shape[1] - 1, -1, -1):
        rows[:, j] = uniques[j][keys % len(uniques[j])]
        keys = keys // len(uniques[j])
    return (rows, inverse) if return_inverse else rows


def group_ids(ds, within) -> np.ndarray | None:
    """One integer per scenario numbering its combination of the values of ``within``."""
    if not within:
        return None
    gid = np.zeros(ds["status"].size, dtype=np.int64)
    for w in within:
        _, inverse = np.unique(flat(ds, w), return_inverse=True)
        gid = gid * (int(inverse.max()) + 1) + inverse.reshape(-1)
    return gid


def front_order(ds) -> np.ndarray:
    """Flat indices of the Pareto front's designs (rank 0), in reading order.

    Grouped by the operating conditions they were ranked within, then along the first objective.

    Parameters
    ----------
    ds : xarray.Dataset
        An annotated study result (``pareto_rank``).

    Returns
    -------
    numpy.ndarray of int
        Flat indices (order of ``status``).
    """
    rank = ds["pareto_rank"].values.reshape(-1)
    front = np.flatnonzero(rank == 0)
    first = ds["pareto_rank"].attrs["objectives"].split()[0].split(":")[0]
    keys = [flat(ds, first)[front]] + [
        flat(ds, w)[front] for w in ds["pareto_rank"].attrs.get("ranked_within", "").split()[::-1]
    ]
    return front[np.lexsort(keys)]


def spread(indices, k) -> np.ndarray:
    """At most ``k`` of ``indices``, evenly spread along them (first and last kept)."""
    if indices.size <= k:
        return indices
    return indices[np.unique(np.linspace(0, indices.size - 1, k).round().astype(int))]


def annotate(ds, objectives, constraints, within=None):
    """``ds`` with the design answers added: feasibility, constraint margins and Pareto ranks.

    Operating conditions sampled on ``run`` cannot be grouped: they are ranked together with the
    design factors and named in the attribute ``conditions_mixed``.

    Parameters
    ----------
    ds : xarray.Dataset
        A study result.
    objectives : list of str
        "name:min" / "name:max".
    constraints : dict
        Output name -> ("max" or "min", limit [SI]), as :func:`feasible`.
    within : list of str or None
        Grid dimensions to rank within (each of their value combinations has its own front);
        default: the study's operating conditions that are grid dimensions (e.g. the engagement's
        load torque and driven inertia), since a design cannot choose its load.

    Returns
    -------
    xarray.Dataset
        ``ds`` with ``feasible``, ``constraint_margin`` (dimension ``constraint``, one entry per
        constrained output) and ``pareto_rank`` over ``objectives`` among the feasible designs
        (−1: infeasible or an objective NaN).
    """
    import xarray as xr

    _check_objectives(ds, objectives)
    dims = ds["status"].dims
    grid_conditions, mixed = condition_factors(ds)
    within = grid_conditions if within is None else list(within)
    ok, margins = feasible(ds, {k: tuple(v) for k, v in constraints.items()})
    out = ds.copy()
    out["feasible"] = (
        dims,
        ok.astype(np.int8),
        {
            "long_name": "design meets every constraint and its status is ok",
            "units": "1",
            "flag_values": np.array([0, 1], np.int8),
            "flag_meanings": "infeasible feasible",
        },
    )
    if margins:
        names = list(margins)
        out["constraint_margin"] = xr.DataArray(
            np.stack([margins[k] for k in names]),
            dims=("constraint",) + dims,
            attrs={
                "long_name": "constraint margin, capacity over demand minus one: limit/value - 1 "
                "for a max, value/limit - 1 for a min (a zero limit: the value's distance); "
                ">= 0 where met",
                "units": "1",
            },
        )
        out = out.assign_coords(
            constraint=(
                "constraint",
                np.array(names, dtype=object),
                {
                    "long_name": "constrained output and its limit",
                    "units": "1",
                    "limits": " ".join(f"{k}:{op}:{v:.6g}" for k, (op, v) in constraints.items()),
                },
            )
        )
    cols = []
    for output, sense in (o.split(":") for o in objectives):
        v = np.broadcast_to(ds[output].values, ok.shape).astype(float).reshape(-1)
        cols.append(v if sense == "min" else -v)
    groups = group_ids(ds, within)
    rank = (
        pareto_rank(np.stack(cols, axis=1), ok.reshape(-1), groups).reshape(ok.shape)
        if cols
        else np.full(ok.shape, -1)
    )
    attrs = {
        "long_name": "Pareto rank among feasible designs "
        "(0: the front; -1: infeasible or an objective NaN)"
        + (f", within each {' and '.join(within)}" if within else ""),
        "units": "1",
        "objectives": " ".join(objectives),
        "ranked_within": " ".join(within),
    }
    if mixed:
        attrs["conditions_mixed"] = " ".join(mixed)
    out["pareto_rank"] = (dims, rank, attrs)
    return out


def hypervolume(points, reference) -> float:
    """Exact hypervolume of the region that ``points`` dominate and that dominates ``reference``,
    every objective minimised: the area (2 objectives) or volume between the front and the
    reference point.

    Parameters
    ----------
    points : array_like (N, M)
        Objective values of N designs [any units, one unit a column; the volume is in their
        product]; negate a column to maximise it. Points not better than the reference in every
        objective add nothing; dominated and repeated points add nothing either. Every entry
        must be finite: a non-finite row (a failed design) is refused, not dropped, since a
        volume without it would look valid and be too small — drop such rows first (e.g.
        ``points[np.isfinite(points).all(axis=1)]``) where that is what you mean.
    reference : array_like (M,)
        Reference point [units of ``points``], finite; its width M must equal the points'.

    Returns
    -------
    float
        The hypervolume [product of the objectives' units]; 0.0 for no points.

    Raises
    ------
    ValueError
        ``points`` is not (N, M) with M the reference's width (the message names both widths),
        a point or the reference is not finite, or the volume overflows float64.

    Notes
    -----
    Computed by ``moocore.hypervolume`` (López-Ibáñez et al., moocore): O(N log N) for 2 and 3
    objectives (HV3D+), O(N²) for 4 (HV4D+, Guerreiro & Fonseca 2017), inclusion–exclusion for
    small sets and the recursive algorithm of Fonseca et al. (2006) above.
    """
    ref = np.asarray(reference, dtype=float)
    if ref.ndim != 1 or ref.size == 0 or not np.isfinite(ref).all():
        raise ValueError(f"reference must be a finite point (M,), got {reference!r}")
    p = np.asarray(points, dtype=float)
    if p.size == 0 and p.ndim <= 2:
        return 0.0
    width = p.shape[1] if p.ndim == 2 else None
    if width != ref.size:
        raise ValueError(
            f"points must be (designs, objectives) with the reference's {ref.size} objectives, "
            + (f"got {width} objectives" if width else f"got shape {p.shape}")
        )
    bad = np.flatnonzero(~np.isfinite(p).all(axis=1))
    if bad.size:
        raise ValueError(
            f"{bad.size} of {len(p)} points have a non-finite objective (first: row {bad[0]}); "
            "drop them first if that is what is meant"
        )
    p = p[(p < ref).all(axis=1)]
    volume = float(moocore.hypervolume(p, ref)) if len(p) else 0.0
    if not np.isfinite(volume):
        raise ValueError("the hypervolume overflows float64: rescale the objectives")
    return volume


def objective_table(ds, objectives, within) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Flat per-scenario arrays of a study Dataset for ranking.

    Parameters
    ----------
    ds : xarray.Dataset
        An annotated study result (with ``feasible``).
    objectives : list of str
        "name:min" / "name:max".
    within : list of str
        The conditions ranked within.

    Returns
    -------
    objectives : numpy.ndarray (N, M)
        The objectives to minimise ("name:max" negated).
    feasible : numpy.ndarray of bool (N,)
        Feasibility of each scenario.
    conditions : numpy.ndarray (N, len(within))
        The values of the conditions ``within``.
    """
    cols = [flat(ds, o.split(":")[0]) * (1.0 if o.endswith(":min") else -1.0) for o in objectives]
    key = (
        np.stack([flat(ds, w) for w in within], axis=1)
        if within
        else np.zeros((ds["status"].size, 0))
    )
    return np.stack(cols, axis=1), flat(ds, "feasible").astype(bool), key


def best_compromise(ds) -> int | None:
    """Flat index of the front design nearest its front's ideal point.

    Each objective is normalised over the feasible designs of its operating condition (best 0,
    worst 1) and the Euclidean distance to the origin is smallest; where the designs are ranked
    within operating conditions, on the front of the condition nearest the default design's (the
    first choice of an option). One design that answers "which one?" when the objectives weigh
    alike; the front itself is the full answer.

    Parameters
    ----------
    ds : xarray.Dataset
        An annotated study result (:func:`annotate`: ``pareto_rank`` and ``feasible``).

    Returns
    -------
    int or None
        The flat index (order of ``status``); None without a front.
    """
    from . import studies

    if "pareto_rank" not in ds or not (ds["pareto_rank"].values == 0).any():
        return None
    objectives = ds["pareto_rank"].attrs["objectives"].split()
    within = ds["pareto_rank"].attrs.get("ranked_within", "").split()
    f, ok, key = objective_table(ds, objectives, within)
    ok &= np.isfinite(f).all(axis=1)
    rank = ds["pareto_rank"].values.reshape(-1)
    best, best_d = None, np.inf
    combos = unique_rows(key[ok]) if within else np.zeros((1, 0))
    if within and combos.size:  # the operating condition nearest the seed design's
        seed = studies.get(ds.attrs["study"]).defaults if "study" in ds.attrs else {}
        with np.errstate(invalid="ignore"):  # a condition may be inf (a held engine)
            ptp = np.ptp(combos, axis=0)
            span = np.where(np.isfinite(ptp) & (ptp > 0), ptp, 1.0)
            target = np.array(
                [seed.get(w, 0.0) for w in within]
            )  # an option: its first choice (code 0)
            # equal values (inf included) are at distance 0, an inf against a finite one far
            gap = np.where(combos == target, 0.0, np.abs(combos - target) / span)
        combos = combos[[int(np.argmin(np.nan_to_num(gap**2, nan=np.inf).sum(axis=1)))]]
    for combo in combos:
        group = ok & (key == combo).all(axis=1)
        lo, hi = f[group].min(axis=0), f[group].max(axis=0)
        norm = (f - lo) / np.where(hi > lo, hi - lo, 1.0)
        d = np.where(group & (rank == 0), np.sqrt((norm**2).sum(axis=1)), np.inf)
        i = int(np.argmin(d))
        if d[i] < best_d:
            best, best_d = i, d[i]
    return best


def refinement_gain(first, second):
    """How far a refining stage moved the Pareto fronts of its first stage.

    Per operating condition the first stage ranked within (one group if none): the hypervolume of
    the first stage's front and of the front of both stages together, in objectives normalised by
    the first stage's feasible designs of that group (ideal 0, worst 1; reference point 1.1 in
    each).

    Parameters
    ----------
    first : xarray.Dataset
        The annotated result of the first stage.
    second : xarray.Dataset
        The annotated result of the refining stage.

    Returns
    -------
    xarray.Dataset
        On dimension ``group`` (with the values of the conditions ranked within):
        ``hypervolume_before``, ``hypervolume_after`` [-], ``feasible_first``,
        ``feasible_second`` and ``front_from_second`` (designs of the refining stage on the joint
        front).
    """
    import xarray as xr

    objectives = first["pareto_rank"].attrs["objectives"].split()
    within = first["pareto_rank"].attrs.get("ranked_within", "").split()
    f1, ok1, k1 = objective_table(first, objectives, within)
    f2, ok2, k2 = objective_table(second, objectives, within)
    combos = unique_rows(k1[ok1]) if within else np.zeros((1, 0))
    rows = []
    for combo in combos:
        g1 = ok1 & (k1 == combo).all(axis=1) & np.isfinite(f1).all(axis=1)
        g2 = ok2 & (k2 == combo).all(axis=1) & np.isfinite(f2).all(axis=1)
        if not g1.any():
            continue
        ideal, worst = f1[g1].min(axis=0), f1[g1].max(axis=0)
        scale = np.where(worst > ideal, worst - ideal, np.maximum(np.abs(worst), 1e-300))
        norm1, norm2 = (f1[g1] - ideal) / scale, (f2[g2] - ideal) / scale
        ref = np.full(len(objectives), 1.1)
        before = hypervolume(norm1, ref)
        union = np.concatenate([norm1, norm2])
        after = hypervolume(union, ref)
        on_front = pareto_rank(union) == 0
        rows.append(
            (combo, before, after, int(g1.sum()), int(g2.sum()), int(on_front[len(norm1) :].sum()))
        )
    return xr.Dataset(
        {
            "hypervolume_before": (
                "group",
                [r[1] for r in rows],
                {
                    "long_name": "hypervolume of the first stage's front "
                    "(objectives normalised per group)",
                    "units": "1",
                },
            ),
            "hypervolume_after": (
                "group",
                [r[2] for r in rows],
                {"long_name": "hypervolume of the front of both stages together", "units": "1"},
            ),
            "feasible_first": (
                "group",
                [r[3] for r in rows],
                {"long_name": "feasible designs, first stage", "units": "1"},
            ),
            "feasible_second": (
                "group",
                [r[4] for r in rows],
                {"long_name": "feasible designs, refining stage", "units": "1"},
            ),
            "front_from_second": (
                "group",
                [r[5] for r in rows],
                {"long_name": "designs of the refining stage on the joint front", "units": "1"},
            ),
        },
        coords={
            "group": (
                "group",
                np.arange(len(rows)),
                {"long_name": "operating-condition group", "units": "1"},
            ),
            **{
                w: ("group", np.array([r[0][j] for r in rows], float), dict(first[w].attrs))
                for j, w in enumerate(within)
            },
        },
        attrs={
            "objectives": " ".join(objectives),
            "ranked_within": " ".join(within),
            "scenarios_first": int(first["status"].size),
            "scenarios_second": int(second["status"].size),
            "reference": "1.1 in every objective normalised to the first stage's feasible designs "
            "of the group (best 0, worst 1); maximised objectives negated",
        },
    )


def grid_variance_decomposition(y, axes_names) -> dict:
    """Main and total effects of the factors of a full factorial grid.

    Main effect of factor i: Var(E[y | x_i]) / Var(y); total effect: E[Var(y | x_~i)] / Var(y),
    every cell weighted equally — on a complete grid the grid's own variance decomposition, exact.
    Failed cells (NaN) are not filled: every mean and variance runs over the finite cells only,
    each weighted by its count (the indices of the successful designs; exact again when nothing
    failed — with cells missing they are no exact decomposition, and a main effect may exceed its
    total), and ``failed`` says how many cells that left out.

    Parameters
    ----------
    y : array_like
        The output on the grid, one axis per factor.
    axes_names : list of str
        The factors' names, one per axis of ``y``.

    Returns
    -------
    dict
        {"first_order": {name: S_i}, "total": {name: ST_i}, "variance": Var(y), "failed": count}.

    Raises
    ------
    ValueError
        If ``axes_names`` has not one name per axis of ``y``.
    """
    y = np.asarray(y, dtype=float)
    if y.ndim != len(axes_names):
        raise ValueError("one axis name per axis of y")
    ok = np.isfinite(y)
    n = int(ok.sum())
    yz = np.where(ok, y, 0.0)
    mean = yz.sum() / n if n else np.nan
    var = float(np.sum(np.where(ok, (y - mean) ** 2, 0.0)) / n) if n else np.nan
    first, total = {}, {}
    with np.errstate(invalid="ignore", divide="ignore"):
        for i, name in enumerate(axes_names):
            others = tuple(j for j in range(y.ndim) if j != i)
            cnt = ok.sum(axis=others)
            m_i = yz.sum(axis=others) / cnt  # E[y | x_i] over the finite cells of each level
            v_main = np.nansum(cnt * (m_i - mean) ** 2) / n
            cnt_g = ok.sum(axis=i)
            m_g = yz.sum(axis=i) / cnt_g  # E[y | x_~i]
            v_g = np.where(ok, (y - np.expand_dims(m_g, i)) ** 2, 0.0).sum(
                axis=i
            )  # n_g · Var(y | x_~i)
            first[name] = float(v_main / var) if var > 0 else np.nan
            total[name] = float(v_g.sum() / n / var) if var > 0 else np.nan
    return {"first_order": first, "total": total, "variance": var, "failed": int(y.size - n)}


def sobol_indices(y, n_factors, names, conf_level=0.95, seed=1) -> dict:
    """First-order and total Sobol indices with confidence intervals from a Saltelli design.

    The design is in :func:`clutchlab.doe.saltelli_unit` order (blocks of A, AB^(1..d), B); the
    indices are SALib's (the maintained standard; Saltelli 2010 and Jansen estimators, bootstrap
    intervals). Failed scenarios (NaN) are not filled: a base point's whole block is left out when
    any of its d + 2 scenarios failed (each estimator term needs all of them).

    Parameters
    ----------
    y : array_like
        The output of every scenario, in design order.
    n_factors : int
        Number d of factors.
    names : list of str
        The factors' names.
    conf_level : float
        Confidence level of the bootstrap intervals.
    seed : int
        Seed of the bootstrap's random numbers (≥ 1: SALib leaves its generator unseeded for 0).

    Returns
    -------
    dict
        ``first_order``, ``total``, ``first_order_conf``, ``total_conf`` (name -> value),
        ``failed`` (the failed scenarios) and ``blocks_used`` (the blocks that remain).
    """
    from SALib.analyze import sobol

    if not seed:
        raise ValueError(
            "seed must be a positive integer (SALib ignores 0 and draws unseeded intervals)"
        )

    y = np.asarray(y, dtype=float).reshape(-1, n_factors + 2)
    keep = np.isfinite(y).all(axis=1)
    out = {"failed": int((~np.isfinite(y)).sum()), "blocks_used": int(keep.sum())}
    nan = {k: np.full(n_factors, np.nan) for k in ("S1", "S1_conf", "ST", "ST_conf")}
    if keep.sum() < 2 or np.var(y[keep]) == 0:
        res = nan
    else:
        problem = {"num_vars": n_factors, "names": list(names), "bounds": [[0.0, 1.0]] * n_factors}
        res = sobol.analyze(
            problem,
            y[keep].reshape(-1),
            calc_second_order=False,
            conf_level=conf_level,
            print_to_console=False,
            seed=seed,
        )
    out.update(
        {
            "first_order": dict(zip(names, np.asarray(res["S1"], float), strict=True)),
            "first_order_conf": dict(zip(names, np.asarray(res["S1_conf"], float), strict=True)),
            "total": dict(zip(names, np.asarray(res["ST"], float), strict=True)),
            "total_conf": dict(zip(names, np.asarray(res["ST_conf"], float), strict=True)),
        }
    )
    return out


def sensitivity(ds, outputs) -> xr.Dataset:
    """Main and total effects of every factor of a study result on ``outputs`` and on failure.

    The failure indicator is 1 where the status is not ok. A factorial grid is decomposed by
    :func:`grid_variance_decomposition` (exact), a ``saltelli`` design by :func:`sobol_indices`
    (with 95 % confidence intervals).

    Parameters
    ----------
    ds : xarray.Dataset
        A study result on a factorial grid or a ``saltelli`` design.
    outputs : list of str
        The outputs to decompose.

    Returns
    -------
    xarray.Dataset
        Dimensions ``output`` and ``factor``: ``first_order``, ``total`` and their ``*_conf``
        half-widths (NaN for a grid: no sampling error) [-], ``failed`` (scenarios that failed per
        output).

    Raises
    ------
    ValueError
        For another sampled design (lhs, sobol).
    """
    dims = list(ds["status"].dims)
    design = ds.attrs.get("design", "factorial" if dims != ["run"] else "")
    if dims == ["run"] and design != "saltelli":
        raise ValueError(
            f"design {design!r} gives no sensitivity indices: use factorial or saltelli"
        )
    factor_names = dims if dims != ["run"] else ds.attrs["factors"].split()
    names = list(dict.fromkeys(list(outputs)))
    rows = []
    for name in names + ["failure"]:
        if name == "failure":
            y = (ds["status"].values != st.CODE["ok"]).astype(float)
        else:
            y = ds[name].broadcast_like(ds["status"]).transpose(*dims).values
        if dims == ["run"]:
            rows.append(sobol_indices(y, len(factor_names), factor_names))
        else:
            r = grid_variance_decomposition(y, dims)
            r["first_order_conf"] = r["total_conf"] = dict.fromkeys(dims, np.nan)
            rows.append(r)
    return _sensitivity_dataset(rows, names + ["failure"], factor_names, design, ds.attrs)


def _sensitivity_dataset(rows, out_names, dims, design, attrs) -> xr.Dataset:
    """The indices of :func:`sensitivity` (one row per output) as a labelled Dataset."""
    import xarray as xr

    return xr.Dataset(
        {
            "first_order": (
                ("output", "factor"),
                [[r["first_order"][f] for f in dims] for r in rows],
                {"long_name": "first-order (main effect) index Var(E[y|x_i])/Var(y)", "units": "1"},
            ),
            "total": (
                ("output", "factor"),
                [[r["total"][f] for f in dims] for r in rows],
                {"long_name": "total effect index E[Var(y|x_~i)]/Var(y)", "units": "1"},
            ),
            "first_order_conf": (
                ("output", "factor"),
                [[r["first_order_conf"][f] for f in dims] for r in rows],
                {
                    "long_name": "95 % confidence half-width of first_order (NaN: exact, a grid)",
                    "units": "1",
                },
            ),
            "total_conf": (
                ("output", "factor"),
                [[r["total_conf"][f] for f in dims] for r in rows],
                {
                    "long_name": "95 % confidence half-width of total (NaN: exact, a grid)",
                    "units": "1",
                },
            ),
            "failed": (
                "output",
                [r["failed"] for r in rows],
                {
                    "long_name": "scenarios whose output is NaN "
                    "(left out; saltelli: with their whole block)",
                    "units": "1",
                },
            ),
        },
        coords={
            "output": (
                "output",
                np.array(out_names, dtype=object),
                {"long_name": "output (failure: 1 where status is not ok)", "units": "1"},
            ),
            "factor": (
                "factor",
                np.array(dims, dtype=object),
                {"long_name": "factor of the design", "units": "1"},
            ),
        },
        attrs={
            "method": (
                "exact variance decomposition of the full factorial grid; failed cells left out "
                "(means and variances over the finite cells, count-weighted), counted in 'failed'"
            )
            if design != "saltelli"
            else (
                "Sobol indices from a Saltelli design (SALib sobol.analyze, "
                "calc_second_order=False, 95 % bootstrap intervals); a base point's block is left "
                "out when any of its scenarios failed"
            ),
            "title": attrs.get("title", ""),
        },
    )


def robust(ds, objectives=None, constraints=None, **settings):
    """Robust answers of a stored crossed study result (design × conditions × noise), over its
    design factors only (:func:`clutchlab.robust.answers`): per objective its worst case, mean
    and quantile; per constraint its worst margin and its probability of violation at each
    condition with a Wilson interval; ``robust_feasible``, ``robust_rank`` and where each worst
    case occurs.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored result of a robust study (a ``noise`` dimension), e.g. ``clutchlab.store.load``
        or a lazily opened file: only the columns the answers need are read.
    objectives : list of str, "worst", "quantile" or None
        "name:min" / "name:max"; None: the study's stored objectives; "worst" or "quantile": the
        stored objectives, the robust front ranked on that statistic (the robust setting).
    constraints : dict or None
        Output -> ("max" or "min", limit [SI]); None: the study's stored constraints.
    **settings
        Overrides of the stored robust settings: ``quantile``, ``max_failure_probability``,
        ``conditions`` (list of dimensions).

    Returns
    -------
    xarray.Dataset
        Labelled DataArrays over the design factors (units and long_name on each).

    Raises
    ------
    ValueError
        ``ds`` is not a crossed result (no ``noise`` dimension); an objective, constraint or
        setting that is not one (named).
    """
    import yaml

    from . import robust as rb
    from .config import ROBUST_DEFAULTS

    if rb.NOISE_DIM not in ds.dims or "noise_weight" not in ds:
        raise ValueError("not a robust study result: it has no 'noise' dimension and draws")
    if isinstance(objectives, str) and objectives in ("worst", "quantile"):
        # (the setting, which shares the keyword's name)
        objectives, settings = None, {**settings, "objectives": objectives}
    if isinstance(objectives, str):
        raise ValueError(
            f"objectives must be a list of 'output:min' / 'output:max', or 'worst' or 'quantile' "
            f"(what the robust front ranks), got {objectives!r}"
        )
    section = yaml.safe_load(ds.attrs["config"]) if "config" in ds.attrs else {}
    stored = dict(section.get("robust") or {})
    stored.setdefault("conditions", ds.attrs.get("conditions", "").split())
    for key in ("quantile", "max_failure_probability", "objectives"):
        stored.setdefault(key, ROBUST_DEFAULTS[key])
    stored.update(settings)
    if objectives is None:
        objectives = section.get("objectives") or ds["pareto_rank"].attrs["objectives"].split()
    if constraints is None:
        constraints = section.get("constraints", {})
    _check_objectives(ds, objectives)
    _check_constraints(ds, constraints)
    constraints = {k: tuple(v) for k, v in constraints.items()}
    _check_robust_settings(ds, settings, stored)
    names = ["status", "noise_weight"] + [o.split(":")[0] for o in objectives] + list(constraints)
    names += [v for v in ds.data_vars if ds[v].dims == (rb.NOISE_DIM,)]
    names += ds.attrs.get("design_factors", "").split()  # a sampled design's, on its points
    columns = ds[list(dict.fromkeys(names))].load()
    out = rb.answers(columns, list(objectives), constraints, stored)
    for key in ("config", "clutchlab_source", "clutchlab_design_hash", "clutchlab_version"):
        if key in ds.attrs:  # the provenance of the result they were asked of
            out.attrs[key] = ds.attrs[key]
    return out


def _check_robust_settings(ds, settings, stored) -> None:
    """ValueError naming a robust setting given to :func:`robust` that is unknown or out of its
    range (a condition the result has no dimension of was dropped without a word)."""
    known = {"quantile", "max_failure_probability", "objectives", "conditions"}
    unknown = sorted(set(settings) - known)
    if unknown:
        raise ValueError(f"unknown robust setting {unknown[0]!r}: give one of {sorted(known)}")
    q, p = stored["quantile"], stored["max_failure_probability"]
    if not (isinstance(q, (int, float)) and not isinstance(q, bool) and 0.0 < q <= 1.0):
        raise ValueError(f"quantile must be a number in (0, 1], got {q!r}")
    if not (isinstance(p, (int, float)) and not isinstance(p, bool) and 0.0 <= p < 1.0):
        raise ValueError(f"max_failure_probability must be a number in [0, 1), got {p!r}")
    if stored["objectives"] not in ("worst", "quantile"):
        raise ValueError(f"objectives must be 'worst' or 'quantile', got {stored['objectives']!r}")
    conditions = stored["conditions"]
    if isinstance(conditions, str) or any(c not in ds.dims for c in conditions):
        raise ValueError(
            f"conditions must be a list of the result's dimensions {list(ds.dims)}, got {conditions!r}"
        )


def best_robust(answers) -> int | None:
    """Flat index (over the design factors) of the best robust design.

    Of the robust front (``robust_rank`` 0), the one nearest the ideal point of its robust
    objectives (worst case or quantile, as ranked), each normalised over the robust-feasible
    designs (best 0, worst 1).

    Parameters
    ----------
    answers : xarray.Dataset
        Robust answers (:func:`robust`).

    Returns
    -------
    int or None
        The flat index; None without a robust front.
    """
    rank = answers["robust_rank"].values.reshape(-1)
    if not (rank == 0).any():
        return None
    which = answers["robust_rank"].attrs["robust_objectives"]
    cols = []
    for item in answers["robust_rank"].attrs["objectives"].split():
        name, sense = item.split(":")
        v = answers[f"{which}_{name}"].values.reshape(-1).astype(float)
        cols.append(v if sense == "min" else -v)
    f = np.stack(cols, axis=1)
    ok = rank >= 0
    lo, hi = f[ok].min(axis=0), f[ok].max(axis=0)
    norm = (f - lo) / np.where(hi > lo, hi - lo, 1.0)
    d = np.where(rank == 0, np.sqrt((norm**2).sum(axis=1)), np.inf)
    return int(np.argmin(d))


def binding_answer(answers, j) -> str:
    """The answer that binds design ``j``: its constraint of the least worst-case margin.

    Parameters
    ----------
    answers : xarray.Dataset
        Robust answers (:func:`robust`).
    j : int
        A design, flat over the design factors of ``answers``.

    Returns
    -------
    str
        The constrained output whose worst margin over the conditions and the noise is the least
        (the first constraint where every margin is NaN); the first objective where the study has
        no constraint.
    """
    names = [str(a) for a in answers["answer"].values]
    if "constraint" not in answers.coords or "worst_margin" not in answers:
        return names[0]
    constrained = [str(c) for c in answers["constraint"].values]
    design = list(answers["robust_rank"].dims)
    m = answers["worst_margin"].transpose("constraint", *design).values
    m = m.reshape(len(constrained), -1)[:, j]
    return constrained[int(np.nanargmin(m))] if np.isfinite(m).any() else constrained[0]


def robust_scenario(ds, answers, j, answer=None) -> tuple[int, str]:
    """Flat scenario index of a crossed result where a design meets its binding condition and noise.

    Parameters
    ----------
    ds : xarray.Dataset
        A crossed (robust) study result.
    answers : xarray.Dataset
        Its robust answers (:func:`robust`).
    j : int
        A design, flat over the design factors of ``answers``.
    answer : str or None
        The answer whose worst case is wanted (default: the one that binds the design,
        :func:`binding_answer`).

    Returns
    -------
    index : int
        Flat index into ``ds``'s ``status`` where the worst case of ``answer`` occurs.
    answer : str
        That answer's name.
    """
    if answer is None:
        answer = binding_answer(answers, j)
    design = list(answers["robust_rank"].dims)
    at = np.unravel_index(j, answers["robust_rank"].shape)
    index = []
    for dim in ds["status"].dims:
        if dim in design:
            index.append(int(at[design.index(dim)]))
            continue
        value = answers[f"binding_{dim}"].sel(answer=answer).values[at]
        where = np.flatnonzero(ds[dim].values == value)
        index.append(int(where[0]))
    return int(np.ravel_multi_index(index, ds["status"].shape)), str(answer)

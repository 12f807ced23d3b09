"""The design a run's pages show, and its traces.

A study's trace pages (time traces, the heat of an engagement, capacity curves over speed) draw
one design of the run: :func:`shown_design` chooses it — in one place, so that a different notion
of "best" (a robust best design, say) changes every page at once. Today it is the best compromise
(:func:`clutchlab.explore.best_compromise`: the feasible front design nearest the ideal point).
Its traces are only known once the chunks are merged (the best design is a question asked of the
whole result), so they are computed after the merge, by the study's own public ``traces``
function (:attr:`clutchlab.studies.Study.traces`), and stored beside the result
(``results/<study>/traces.h5``, the workflow's ``traces`` job): figures never run a solver.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from . import display, explore, studies

__all__ = [
    "shown_design",
    "best_design",
    "design_inputs",
    "design_text",
    "is_paper_design",
    "compute",
    "attach",
]

#: attributes of a traces Dataset (and of a result the traces were attached to) naming the design
ATTRS = ("shown_index", "shown_design", "shown_reason", "shown_is_paper")


def _factors(ds) -> list[str]:
    dims = list(ds["status"].dims)
    if dims == ["run"]:
        return ds.attrs.get("factors", "").split()
    points = ds.attrs.get("design_factors", "").split()  # a crossed sampled design's, on "point"
    return [f for d in dims for f in (points if d == "point" and points else [d])]


def _objectives(ds) -> list[str]:
    if "pareto_rank" in ds:
        return ds["pareto_rank"].attrs["objectives"].split()
    return list(studies.get(ds.attrs["study"]).objectives) if "study" in ds.attrs else []


def shown_design(ds) -> tuple[int | None, str]:
    """The design a run's pages show: (flat scenario index, why it is the one).

    The best compromise (:func:`clutchlab.explore.best_compromise`) where the run has a feasible
    front; else, among the designs that meet every constraint (whatever their status) or, failing
    those, among all designs with finite objectives, the one nearest the ideal point of their own
    front (the same rule); else the first scenario whose status is ok; None when there is none.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored study result with its design answers (``feasible``, ``pareto_rank``).

    Returns
    -------
    (int or None, str)
    """
    if "noise" in ds.dims and "noise_weight" in ds:  # a robust study: its best robust design
        answers = explore.robust(ds)
        j = explore.best_robust(answers)
        if j is not None:
            i, answer = explore.robust_scenario(ds, answers, j)
            return i, (
                "the run's best robust design (the robust front design nearest the ideal point "
                f"of its {answers['robust_rank'].attrs['robust_objectives']} objectives), at its "
                f"binding condition and noise draw (where its {answer} is worst)"
            )
    i = explore.best_compromise(ds)
    if i is not None:
        return i, "the run's best compromise (the feasible front design nearest the ideal point)"
    objectives = _objectives(ds)
    if objectives:
        f = np.stack([explore.flat(ds, o.split(":")[0]) for o in objectives], axis=1)
        finite = np.isfinite(f).all(axis=1)
        met = finite.copy()
        if "constraint_margin" in ds:
            margins = ds["constraint_margin"].transpose("constraint", *ds["status"].dims).values
            met &= (margins.reshape(margins.shape[0], -1) >= 0).all(axis=0)
        for candidates, why in (
            (met, "no feasible design: of the designs that meet every constraint (whatever their "
             "status), the one nearest the ideal point"),
            (finite, "no design meets every constraint: of the computed designs, the one nearest "
             "the ideal point"),
        ):  # fmt: skip
            if candidates.any():
                return _nearest_ideal(ds, objectives, candidates), why
    ok = np.flatnonzero(explore.flat(ds, "status") == 0)
    if ok.size:
        return int(ok[0]), "no design with finite objectives: the first design with status ok"
    return None, "no design of this run has status ok"


def best_design(ds) -> int | None:
    """Flat index of the run's best design (the design :func:`shown_design` shows where the run
    has a feasible front; the one the summary and the answers page call best), else None. Read
    from the attributes a result carries once its traces are attached, computed otherwise."""
    if "shown_index" in ds.attrs:
        i, reason = int(ds.attrs["shown_index"]), ds.attrs.get("shown_reason", "")
    else:
        i, reason = shown_design(ds)
    return i if i is not None and i >= 0 and reason.startswith("the run's best") else None


def _nearest_ideal(ds, objectives, candidates) -> int:
    """best_compromise among ``candidates`` taken as the feasible designs."""
    dims = ds["status"].dims
    mod = ds.assign(
        status=(dims, np.zeros(ds["status"].shape, np.int8)),
        feasible=(dims, candidates.reshape(ds["status"].shape).astype(np.int8)),
    )
    within = (
        ds["pareto_rank"].attrs.get("ranked_within", "").split() if "pareto_rank" in ds else None
    )
    mod["pareto_rank"] = explore.pareto_rank(mod, objectives, within)
    i = explore.best_compromise(mod)
    return int(np.flatnonzero(candidates)[0]) if i is None else i


def _parameters(ds):
    return studies.get(ds.attrs["study"]).parameters


def design_inputs(ds, i) -> tuple[dict, dict]:
    """(inputs, chosen options) of scenario ``i`` of a stored result: every fixed value and its
    factor values as scalars (SI), and the choices of the options it draws per scenario."""
    options = ds.attrs.get("option_factors", "").split()
    inputs, chosen = {}, {}
    for p in _parameters(ds):
        if p.name in ds and ds[p.name].ndim == 0:
            inputs[p.name] = float(ds[p.name])
    for name in _factors(ds):
        v = explore.flat(ds, name)[i]
        if name in options:
            chosen[name] = ds[name].attrs["flag_meanings"].split()[int(v)]
        else:
            inputs[name] = float(v)
    if "noise" in inputs:  # a robust study: the scenario's noise draw applied, as its chunk did
        k = int(inputs.pop("noise"))
        for v in ds.data_vars:
            if ds[v].dims == ("noise",) and v != "noise_weight":
                p = v[: -len("_noise")]
                d = float(ds[v].values[k])
                inputs[p] = inputs[p] * (1.0 + d) if ds[v].attrs.get("relative") else d
    return inputs, chosen


def design_text(ds, i) -> str:
    """Scenario ``i``'s factor values in the units engineers read: ``sprags = 22, sprag_length =
    22 mm``; an option drawn per scenario by its choice."""
    parts = []
    for name in _factors(ds):
        v = explore.flat(ds, name)[i]
        meanings = ds[name].attrs.get("flag_meanings", "").split()
        if name == "noise":  # a robust study's noise draw: each noise parameter's deviation
            parts += [_noise_text(ds, n, int(v)) for n in ds.data_vars if ds[n].dims == ("noise",)]
            continue
        if meanings:
            parts.append(f"{name} = {meanings[int(v)]}")
        else:
            parts.append(f"{name} = {display.text(v, display.unit_of(ds, name))}")
    return ", ".join(parts) if parts else "the run's one design"


def _noise_text(ds, name, k) -> str:
    """One noise parameter's draw ``k`` as engineers read it (a relative one in %)."""
    if name == "noise_weight":
        return f"noise draw {k}" + (" (a corner)" if ds[name].values[k] == 0 else "")
    d = float(ds[name].values[k])
    if ds[name].attrs.get("relative"):
        return f"{name} {100 * d:+.1f} %"
    return f"{name} = {display.text(d, display.unit_of(ds, name))}"


def is_paper_design(ds, i) -> bool:
    """Whether scenario ``i`` is the source paper's design: every parameter at the study's default
    (the paper's value; relative 1e-6) and every option drawn per scenario at its first choice."""
    inputs, chosen = design_inputs(ds, i)
    for p in _parameters(ds):
        v = inputs.get(p.name, p.default)
        if not (v == p.default or np.isclose(v, p.default, rtol=1e-6, atol=0.0)):
            return False
    return all(ds[o].attrs["flag_meanings"].split()[0] == c for o, c in chosen.items())


def _options(ds, options) -> dict:
    if options is not None:
        return dict(options)
    import yaml

    return dict((yaml.safe_load(ds.attrs.get("config", "")) or {}).get("options", {}))


def compute(ds, options=None) -> xr.Dataset:
    """The traces of the design a run shows (:func:`shown_design`), by the study's ``traces``.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored study result with its design answers (the columns :func:`needed` names suffice).
    options : dict or None
        The study's resolved options (default: those stored in the result's ``config`` attribute).

    Returns
    -------
    xarray.Dataset
        The traces (empty when the study has none, no design can be shown or the design has none:
        an invalid spring, a wedge that does not lock), with attributes ``shown_index`` (flat
        scenario index, -1 for none), ``shown_design`` (its factor values in display units),
        ``shown_reason`` and ``shown_is_paper`` (1 where it is the source paper's design).
    """
    study = studies.get(ds.attrs["study"])
    i, reason = shown_design(ds)
    out = xr.Dataset()
    if i is not None and study.traces is not None:
        inputs, chosen = design_inputs(ds, i)
        out = study.traces(inputs, study.full_options({**_options(ds, options), **chosen}))
    out.attrs.update(
        shown_index=-1 if i is None else int(i),
        shown_design="" if i is None else design_text(ds, i),
        shown_reason=reason,
        shown_is_paper=int(i is not None and is_paper_design(ds, i)),
    )
    if i is not None:
        status = int(explore.flat(ds, "status")[i])
        from . import status as st

        out.attrs["shown_status"] = st.FLAGS.get(status, str(status))
    return out


def needed(ds) -> list[str]:
    """The variables of a stored result that :func:`compute` reads (a million-scenario result is
    not loaded whole): status, the design answers, the objectives, the fixed values."""
    names = ["status", "feasible", "pareto_rank", "constraint_margin"]
    names += [o.split(":")[0] for o in _objectives(ds)]
    names += [p.name for p in _parameters(ds) if p.name in ds.data_vars and ds[p.name].ndim == 0]
    names += [f for f in _factors(ds) if f in ds.data_vars]
    names += [v for v in ds.data_vars if ds[v].dims == ("noise",)]  # a robust study's draws
    if "noise" in ds.dims and "constraint_margin" in ds:  # its constrained outputs
        names += [str(c) for c in ds["constraint"].values]
    names += ds.attrs.get("design_factors", "").split()  # a sampled robust design's, on its points
    return [n for n in dict.fromkeys(names) if n in ds.variables]


def attach(ds, traces) -> xr.Dataset:
    """A result with its traces (:func:`compute`) added for the pages: their variables and
    coordinates, and the attributes naming the design shown."""
    out = ds.assign({k: v for k, v in traces.data_vars.items()})
    out.attrs.update({k: traces.attrs[k] for k in (*ATTRS, "shown_status") if k in traces.attrs})
    return out

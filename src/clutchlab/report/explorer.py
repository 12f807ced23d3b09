"""The interactive explorer of a study: one self-contained HTML page per study
(``<study>_explorer.html``) with every design on parallel coordinates and a linked scatter.

The page holds plotly.js (inline: no network needed; its official ``gl2d`` partial bundle, which
carries the parallel coordinates and the WebGL scatter, a third of the full bundle's size: see
:data:`PLOTLY_BUNDLE`), the designs' values in the units engineers
read (:mod:`clutchlab.display`) and a small script (``explorer.js`` beside this module) that links
the views: brushing an axis of the parallel coordinates (plotly's ``constraintrange``) filters the
scatter of any two quantities, shows the count of designs left and offers them as CSV; hovering a
design in the scatter shows all its values. The page's own API, ``window.clutchlabExplorer``
(``setRange(axis, lo, hi)``, ``count()``, ``csv()``, ...), is what the browser test drives.

Axes: the design factors (with the operating conditions and options drawn per scenario), the
objectives (marked min/max), the constrained outputs (with their limits), every other
per-design output, the status, feasibility and the ranks. A value that is NaN (a design whose
status is not ok) is drawn on a "NaN" band below its axis' range: brushing that band selects
those designs.

A study larger than :data:`MAX_DESIGNS` is shown as a sample: every Pareto-front design and a
uniform random sample of the others (``numpy.random.default_rng(seed)``), said on the page.
"""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from .. import display, store
from .. import status as st
from ..explore import flat
from .common import SENSE_WORDS

__all__ = [
    "MAX_DESIGNS",
    "PLOTLY_BUNDLE",
    "Axis",
    "axes",
    "sample",
    "page",
    "plotly_js",
    "write",
    "write_dataset",
]

#: plotly.js as the page inlines it: the official ``gl2d`` partial bundle (traces parcoords,
#: scattergl, scatter, splom; 1.5 MB instead of the full bundle's 4.8 MB, about 2 s less CPU time
#: to read in a browser, docs/explorer.md), the file ``dist/plotly-gl2d.min.js`` of plotly.js' npm
#: package at the version of the full bundle plotly.py ships (a test checks the two agree;
#: docs/explorer.md says how to refresh it)
PLOTLY_BUNDLE = "plotly-gl2d.min.js"

#: designs a page holds at most, from pages of 1 000 to 10 000 designs measured in headless
#: Chromium with software WebGL (docs/explorer.md): above a fixed cost of about 2 s of CPU time
#: (plotly.js read, WebGL contexts and shaders), drawing takes about 0.5 ms of CPU time a design
#: at 12 axes shown, and a brush drawn with the mouse stays under a second of it up to here
MAX_DESIGNS = 3_000
#: where a NaN sits below an axis' range, as a share of the range
NAN_BAND = 0.08
#: a study with more axes than this shows its other outputs (neither objective nor constrained)
#: hidden at first ("all outputs" shows them): software WebGL draws time ∝ axes × lines
SHOWN_AXES = 14


@dataclass
class Axis:
    """One axis of the parallel coordinates: a quantity of every design in its display unit.

    ``values`` are display-unit values with NaN replaced by ``nan`` (below the range) where the
    axis has any; ``codes``: the meanings of a flagged quantity's codes (status, an option)."""

    name: str
    label: str
    header: str
    role: str
    values: np.ndarray
    codes: dict = field(default_factory=dict)
    nan: float | None = None

    def spec(self) -> dict:
        """The axis as the page's script reads it (values encoded separately)."""
        keep = np.isfinite(self.values) & (
            self.values != self.nan if self.nan is not None else True
        )
        finite = self.values[keep]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
        out = {"name": self.name, "label": self.label, "header": self.header, "role": self.role}
        if self.codes:
            shown = sorted(int(c) for c in np.unique(finite))
            out["tickvals"] = shown
            out["ticktext"] = [self.codes.get(c, str(c)) for c in shown]
            out["range"] = [min(shown, default=0) - 0.5, max(shown, default=0) + 0.5]
            out["codes"] = {str(k): v for k, v in self.codes.items()}
            return out
        constant = not hi > lo  # one value (or none): one tick at it, not nano-scaled ones
        value = lo
        if constant:
            pad = max(abs(value) * 0.05, 0.5)
            lo, hi = value - pad, value + pad
        if constant:
            out["tickvals"], out["ticktext"] = [value], [format(value, ".4g")]
        if self.nan is not None:
            ticks = [value] if constant else [float(t) for t in _ticks(lo, hi)]
            out["tickvals"] = [self.nan] + ticks
            out["ticktext"] = ["NaN"] + [format(t, ".4g") for t in ticks]
            out["nan"] = self.nan
            lo = self.nan - 0.02 * (hi - lo)
        out["range"] = [lo, hi]
        return out


def _ticks(lo, hi):
    """About six round tick values within [lo, hi]."""
    from matplotlib.ticker import MaxNLocator

    t = MaxNLocator(nbins=6).tick_values(lo, hi)
    return t[(t >= lo - 1e-12 * abs(hi - lo)) & (t <= hi + 1e-12 * abs(hi - lo))]


def _factors(ds) -> list[str]:
    from .answers import factors

    return factors(ds)


def _limits(ds) -> dict:
    """Constrained output -> its limit as the user would write it (``max 200 degC``)."""
    if "constraint" not in ds.coords:
        return {}
    out = {}
    for item in ds["constraint"].attrs.get("limits", "").split():
        name, op, limit = item.split(":")
        if name in ds:
            u = display.unit_of(ds, name)
            out[name] = f"{op} {display.text(float(limit), u, '.4g')}"
    return out


def _objectives(ds) -> dict:
    """Objective -> "min"/"max" of a ranked result (none where the study has no ranks)."""
    if "pareto_rank" not in ds:
        return {}
    items = ds["pareto_rank"].attrs.get("objectives", "").split()
    return dict(o.split(":") for o in items)


def _per_design(ds, name) -> bool:
    """``name`` has one value per design (its dimensions are the status' dimensions)."""
    return set(ds[name].dims) == set(ds["status"].dims) and ds[name].ndim == ds["status"].ndim


def _order(ds) -> list[tuple[str, str]]:
    """(name, role) of the axes in page order."""
    factors = _factors(ds)
    objectives, limits = _objectives(ds), _limits(ds)
    outputs = [
        n
        for n in ds.data_vars
        if n not in factors
        and _per_design(ds, n)
        and ds[n].dtype.kind == "f"
        and "flag_meanings" not in ds[n].attrs
    ]
    ranks = [n for n in ds.data_vars if n.endswith("_rank") and _per_design(ds, n)]
    order = [(n, "factor") for n in factors]
    order += [(n, "objective") for n in objectives if n in outputs]
    order += [(n, "constrained") for n in limits if n in outputs and n not in objectives]
    order += [(n, "output") for n in outputs if n not in objectives and n not in limits]
    order += [(n, "status") for n in ("status", "feasible") if n in ds]
    return order + [(n, "rank") for n in ranks]


def axes(ds, rows=None) -> list[Axis]:
    """The axes of a study's explorer, each with its values in the unit engineers read.

    Parameters
    ----------
    ds : xarray.Dataset
        A merged study result (``clutchlab.store.load``).
    rows : array_like of int or None
        Flat design indices (order of ``status``) to keep; None: every design.

    Returns
    -------
    list of Axis
        Factors, objectives, constrained outputs, the other per-design outputs, status,
        feasibility and ranks.
    """
    objectives, limits = _objectives(ds), _limits(ds)
    out = []
    for name, role in _order(ds):
        v = flat(ds, name)
        v = np.asarray(v if rows is None else v[rows])
        meanings = ds[name].attrs.get("flag_meanings", "").split()
        if meanings:
            codes = [int(c) for c in np.atleast_1d(ds[name].attrs["flag_values"])]
            out.append(
                Axis(name, name.replace("_", " "), name, role, v.astype(float),
                     dict(zip(codes, meanings, strict=True)))
            )  # fmt: skip
            continue
        u = display.unit_of(ds, name) if role != "rank" else display.Unit("", "")
        label = display.label(name, u)
        if name in objectives:
            label += f" ({SENSE_WORDS[objectives[name]]})"
        if name in limits:
            label += f" ({limits[name]})"
        out.append(_numeric(name, label, display.column(name, u), role, u(v.astype(float))))
    return out


def _numeric(name, label, header, role, values) -> Axis:
    """A numeric axis; NaN values moved to a band below the finite values' range."""
    nan = ~np.isfinite(values)
    if not nan.any():
        return Axis(name, label, header, role, values)
    finite = values[~nan]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    span = hi - lo if hi > lo else max(abs(lo) * 0.1, 1.0)
    slot = lo - NAN_BAND * span
    return Axis(name, label, header, role, np.where(nan, slot, values), nan=slot)


def sample(ds, limit=MAX_DESIGNS, seed=0) -> np.ndarray:
    """Flat indices (ascending) of the designs a page holds: every design of a study of at most
    ``limit``; else every Pareto-front design (rank 0 of ``pareto_rank``) and a uniform random
    sample of the others (``numpy.random.default_rng(seed)``) up to ``limit`` in all (more where
    the front alone is larger: each front design is kept)."""
    n = int(ds["status"].size)
    if n <= limit:
        return np.arange(n)
    front = flat(ds, "pareto_rank") == 0 if "pareto_rank" in ds else np.zeros(n, bool)
    kept = np.flatnonzero(front)
    rest = np.flatnonzero(~front)
    k = max(int(limit) - kept.size, 0)
    drawn = np.random.default_rng(seed).choice(rest, size=min(k, rest.size), replace=False)
    return np.sort(np.concatenate([kept, drawn]))


def _b64(a) -> str:
    return base64.b64encode(np.ascontiguousarray(a, dtype="<f8").tobytes()).decode("ascii")


def _note(ds, rows, seed) -> str:
    """What the page holds, in one sentence."""
    n, k = int(ds["status"].size), int(rows.size)
    if k == n:
        return f"Every design of the study: {n}."
    front = int((flat(ds, "pareto_rank") == 0).sum()) if "pareto_rank" in ds else 0
    if k == front:
        return (
            f"The {front} Pareto-front designs of the study's {n} designs (a page holds every "
            "front design, and no other where they fill it); counts are of the designs shown."
        )
    return (
        f"A sample of {k} of the study's {n} designs: every Pareto-front design ({front}) and "
        f"a uniform random sample of the others (random-number seed {seed}); counts are of the designs shown."
    )


def page_data(ds, limit=MAX_DESIGNS, seed=0) -> dict:
    """Everything the page's script reads (axes, values base64 float64, the note)."""
    rows = sample(ds, limit, seed)
    ax = axes(ds, rows)
    objectives = [a.name for a in ax if a.role == "objective"]
    numeric = [a.name for a in ax if not a.codes and a.role != "rank"]
    first = (objectives + [n for n in numeric if n not in objectives])[:2]
    specs = [dict(a.spec(), values=_b64(a.values)) for a in ax]
    for spec in specs:
        spec["shown"] = len(specs) <= SHOWN_AXES or spec["role"] != "output"
    return {
        "study": ds.attrs.get("study", ""),
        "title": ds.attrs.get("title", ""),
        "studySize": int(ds["status"].size),
        "note": _note(ds, rows, seed),
        "design": _b64(rows),
        "axes": specs,
        "scatter": first,
        "grouped": ds["pareto_rank"].attrs.get("ranked_within", "") if "pareto_rank" in ds else "",
        "flagOk": st.CODE["ok"],
    }


def plotly_js() -> str:
    """The plotly.js bundle the page inlines (:data:`PLOTLY_BUNDLE`)."""
    return resources.files(__package__).joinpath(PLOTLY_BUNDLE).read_text(encoding="utf-8")


def page(ds, limit=MAX_DESIGNS, seed=0, version="") -> str:
    """The explorer of a study as one self-contained HTML text (plotly.js inline)."""
    data = page_data(ds, limit, seed)
    app = resources.files(__package__).joinpath("explorer.js").read_text(encoding="utf-8")
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    title = f"{data['study']} explorer"
    return TEMPLATE.format(
        title=title,
        heading=f"{title}: {data['title']}",
        note=data["note"],
        version=version,
        plotly=plotly_js(),
        data=payload,
        app=app,
    )


def write(result_path, out_path, limit=MAX_DESIGNS, seed=0) -> Path:
    """Write ``<study>_explorer.html`` of a merged study result (atomic: written, then renamed).

    Parameters
    ----------
    result_path : path
        The study's merged HDF5 result.
    out_path : path
        The HTML file to write.
    limit : int
        Designs the page holds at most (:data:`MAX_DESIGNS`); a larger study is sampled.
    seed : int
        Seed of that sample.

    Returns
    -------
    Path
        ``out_path``.
    """
    return write_dataset(store.load(result_path), out_path, limit, seed)


def write_dataset(ds, out_path, limit=MAX_DESIGNS, seed=0) -> Path:
    """:func:`write` of a merged study result already in memory (its Dataset ``ds``)."""
    from .. import __version__

    text = page(ds, limit, seed, version=__version__)
    out_path = Path(out_path)
    out_path.parent.mkdir(parents=True, exist_ok=True)
    with store.atomic(out_path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return out_path


TEMPLATE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{title}</title>
<style>
body {{ font-family: sans-serif; margin: 12px; color: #222; }}
h1 {{ font-size: 18px; margin: 0 0 4px 0; }}
#note, #help {{ font-size: 13px; color: #555; margin: 2px 0; }}
#controls {{ margin: 8px 0; font-size: 14px; }}
#controls label {{ margin-right: 12px; }}
#count {{ font-weight: bold; font-size: 15px; margin-right: 16px; }}
#parcoords {{ overflow-x: auto; }}
#lower {{ display: flex; gap: 16px; align-items: flex-start; }}
#design {{ font-size: 12px; border-collapse: collapse; min-width: 320px; }}
#design td {{ padding: 1px 6px; border-bottom: 1px solid #eee; }}
#design td:last-child {{ text-align: right; }}
</style></head>
<body>
<h1>{heading}</h1>
<div id="note">{note}</div>
<div id="help">Drag along an axis to keep a range of it (drag again to add one, click outside a
range to remove it); the scatter, the count and the CSV follow. Hover a design in the scatter for
its values. The scatter opens on the designs whose status is ok (double-click it to see every
design), a quantity whose positive values span two decades or more on a log axis. NaN: below an
axis' range. clutchlab {version}.</div>
<div id="controls">
<span id="count"></span>
<label>colour <select id="colour"></select></label>
<label>scatter x <select id="sx"></select></label>
<label>y <select id="sy"></select></label>
<label><input type="checkbox" id="alloutputs"> all outputs</label>
<button id="reset">clear ranges</button>
<button id="download">download selection (CSV)</button>
</div>
<div id="parcoords"></div>
<div id="lower"><div id="scatter"></div>
<table id="design"><tr><td>hover a design in the scatter for its values</td></tr></table></div>
<script>performance.mark("clutchlab:plotly");</script>
<script type="text/javascript">{plotly}</script>
<script type="application/json" id="clutchlab-data">{data}</script>
<script type="text/javascript">{app}</script>
</body></html>
"""

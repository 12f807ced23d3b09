"""The design-answers page of a study: how many designs are feasible, which constraint binds most
often, the Pareto front with the seed design marked, and the front's designs as a table
(also ``<study>_pareto.csv``)."""

from __future__ import annotations

import csv
import itertools
import textwrap

import matplotlib.pyplot as plt
import numpy as np

from .. import display, studies
from .. import status as st
from ..explore import flat as _flat
from ..explore import front_order, objective_table, pareto_rank, spread
from .common import (
    A4_LANDSCAPE,
    FRONTS_NAMED,
    SENSE_WORDS,
    constraint_limit,
    constraints,
    drawn,
    drawn_note,
    fitted_table,
    front_colour,
    table_rows_fitting,
    wrap_even,
    wrap_name,
)

MAX_ROWS = 15
MAX_COLUMNS = 10  # columns of an answers page's front table (its constrained outputs beyond)


def factors(ds) -> list[str]:
    """The study's factors: its dimensions (factorial) or the ``factors`` attribute (sampled)."""
    dims = list(ds["status"].dims)
    return ds.attrs.get("factors", "").split() if dims == ["run"] else dims


def _outputs(ds) -> tuple[list[str], list[str]]:
    """(objectives, the constrained outputs that are not objectives) of a ranked result."""
    objectives = [o.split(":")[0] for o in ds["pareto_rank"].attrs["objectives"].split()]
    constrained = [str(c) for c in ds["constraint"].values] if "constraint" in ds.coords else []
    return objectives, [c for c in constrained if c not in objectives]


def front_rows(ds, typeset=False, max_rows=MAX_ROWS) -> tuple[list[str], list[list]]:
    """Header and rows of the front's designs (at most ``max_rows``, spread along the first
    objective, per operating condition where the ranks are): factor values, objectives, the other
    constrained outputs and every constraint's margin, in the units engineers read (the header
    names each column's unit as a config writes it, ``sheet_thickness [mm]``, or typeset for a
    page, ``N·m``; :mod:`clutchlab.display`); an option drawn per scenario by its choice. A robust
    result's noise draw is given by its deviations (``friction_coefficient_noise [%]``) after the
    draw's index, which a page leaves out."""
    return design_rows(ds, spread(front_order(ds), max_rows), typeset)


def design_rows(ds, front, typeset=False) -> tuple[list[str], list[list]]:
    """Header and rows of the designs at flat indices ``front`` (:func:`front_rows`)."""
    objectives, constrained = _outputs(ds)
    names = factors(ds)
    options = {
        o: ds[o].attrs["flag_meanings"].split() for o in ds.attrs.get("option_factors", "").split()
    }
    draws = _noise_draws(ds)
    at = names.index("noise") + 1 if draws else len(names)
    names = names[:at] + list(draws) + names[at:]
    if typeset and draws:
        names.remove("noise")
    columns = names + objectives + constrained
    units = {n: draws[n][1] if n in draws else display.unit_of(ds, n) for n in columns}
    header = [
        n
        if n in options
        else (f"{n} [{units[n].label}]" if typeset else display.column(n, units[n]))
        for n in columns
    ]
    values = {n: draws[n][0] if n in draws else _flat(ds, n) for n in columns}
    rows = [
        [
            options[n][int(values[n][i])] if n in options else float(units[n](values[n][i]))
            for n in columns
        ]
        for i in front
    ]
    if "constraint_margin" in ds:
        margins = ds["constraint_margin"].transpose("constraint", *ds["status"].dims).values
        margins = margins.reshape(margins.shape[0], -1)
        # (a margin output held ≥ 0 is its own constraint margin: not written twice)
        same = {c for c, op, limit in constraints(ds) if op == "min" and limit == 0.0}
        kept = [k for k, c in enumerate(ds["constraint"].values) if str(c) not in same]
        header += [f"{ds['constraint'].values[k]}_constraint_margin [-]" for k in kept]
        rows = [r + [float(margins[k, i]) for k in kept] for r, i in zip(rows, front, strict=True)]
    return header, rows


def _noise_draws(ds) -> dict:
    """A robust result's noise deviations: ``<param>_noise`` -> (its value at each flat scenario,
    SI or relative; its display unit: % where relative); empty without a noise dimension."""
    if "noise" not in ds.dims:
        return {}
    draw = _flat(ds, "noise").astype(np.int64)
    out = {}
    for v in ds.data_vars:
        if v.endswith("_noise") and ds[v].dims == ("noise",):
            relative = bool(ds[v].attrs.get("relative"))
            unit = display.Unit("%", "%", 100.0) if relative else display.unit_of(ds, v)
            out[v] = (ds[v].values[draw], unit)
    return out


def _value_text(ds, name, v) -> str:
    """ "name value unit" of a factor in its display unit; a flagged code (an option drawn per
    scenario) by its meaning."""
    meanings = ds[name].attrs.get("flag_meanings", "").split()
    if meanings:
        return f"{name} {meanings[int(v)]}"
    return f"{name} {display.text(v, display.unit_of(ds, name))}"


def best_text(ds) -> str:
    """The best design (:func:`clutchlab.traces.best_design`: today the best compromise) in one
    line: its factors, then its objectives, in the units engineers read."""
    from ..traces import best_design

    i = best_design(ds)
    if i is None:
        return "no feasible design on a Pareto front"
    objectives, _ = _outputs(ds)
    parts = [_value_text(ds, n, _flat(ds, n)[i]).replace(" ", " = ", 1) for n in factors(ds)]
    goals = [_value_text(ds, n, _flat(ds, n)[i]).replace(" ", " = ", 1) for n in objectives]
    return ", ".join(parts) + " -> " + ", ".join(goals)


#: what the best design does over its life, where a study has it (clutchlab.wear): the reserve
#: at the end of the wear allowance and its least over the wear, the life in engagements, the
#: largest engagement rate the cooling allows, the last engagement's lock-up time
LIFE = (
    "reserve_factor_worn",
    "reserve_factor_least",
    "life_engagements",
    "max_engagement_rate",
    "lockup_time_worn",
)


def life_text(ds) -> str:
    """The best design's numbers over its life (:data:`LIFE`, those the study has) in one line in
    the units engineers read; "" where the study has none or no design is best."""
    from ..traces import best_design

    names = [n for n in LIFE if n in ds]
    i = best_design(ds) if names and "pareto_rank" in ds else None
    if i is None:
        return ""
    return ", ".join(_value_text(ds, n, _flat(ds, n)[i]).replace(" ", " = ", 1) for n in names)


# a sampled (continuous) factor's best value within this share of its range of a bound sits "at
# the edge" of the range
EDGE_SHARE = 0.02


def edge_notes(ds, short=False) -> list[str]:
    """One note per design factor at which the best compromise sits at the edge of the range the
    run gave it (its smallest or largest value; within 2 % of the range for a sampled factor): the
    answer may lie beyond, so the range should be widened. Operating conditions and options drawn
    per scenario are not design choices and get none. ``short``: "sprags (upper, 22)"."""
    from ..explore import condition_factors
    from ..traces import best_design

    i = best_design(ds)
    if i is None:
        return []
    conditions = set(sum(condition_factors(ds), [])) | set(studies.get(name_of(ds)).conditions)
    options = set(ds.attrs.get("option_factors", "").split())
    front = front_order(ds)
    notes = []
    for n in factors(ds):
        if n in conditions or n in options or "flag_meanings" in ds[n].attrs:
            continue
        v = _flat(ds, n)
        lo, hi = np.nanmin(v), np.nanmax(v)
        if not hi > lo:
            continue
        tol = 0.0 if "run" not in ds["status"].dims else EDGE_SHARE * (hi - lo)
        for end, bound in (("upper", hi), ("lower", lo)):
            if abs(v[i] - bound) > tol:
                continue
            u = display.unit_of(ds, n)
            if short:
                notes.append(f"{n} ({end}, {display.text(bound, u)})")
                continue
            at = int((np.abs(v[front] - bound) <= tol).sum())
            items = "scenarios" if "noise" in ds.dims else "designs"  # (a robust study's)
            notes.append(
                f"best design at the {end} edge of the {n} range ({display.text(lo, u)} to "
                f"{display.text(hi, u)}; {at} of {front.size} front {items} there): widen the "
                f"range of {n}"
            )
    return notes


def name_of(ds) -> str:
    return ds.attrs.get("study", "")


def _text(v, fmt) -> str:
    return v if isinstance(v, str) else format(v, fmt)


def write_csv(ds, path) -> None:
    """``<study>_pareto.csv``: the front's designs (:func:`front_rows`), units in the header."""
    header, rows = front_rows(ds)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for r in rows:
            w.writerow([_text(v, ".6g") for v in r])


def limits_text(ds) -> str:
    """The constraints as the user would write them: ``contact_stress max: 3041 MPa``."""
    if "constraint" not in ds.coords:
        return "none"
    parts = []
    for output, op, value in constraints(ds):
        kind = display.temperature_kind(ds[output].attrs) if output in ds else None
        si = ds[output].attrs.get("units", "1") if output in ds else "1"
        parts.append(display.limit_text(output, op, value, si, kind))
    return "; ".join(parts)


def _failing(ds) -> tuple[list[str], list[int], list[str]]:
    """(labels, counts, colours) of the bars: designs per status that is not ok, then designs
    failing each constraint."""
    codes, counts = np.unique(ds["status"].values[ds["status"].values != 0], return_counts=True)
    names = [f"status {st.FLAGS.get(int(c), str(c))}" for c in codes]
    viol = [int(n) for n in counts]
    colours = ["0.5"] * len(names)
    if "constraint_margin" in ds:
        for c in ds["constraint"].values:
            names.append(str(c))
            viol.append(int((ds["constraint_margin"].sel(constraint=c).values < 0).sum()))
            colours.append("tab:red")
    return names, viol, colours


def page(name, ds):
    """The design answers of a study: feasible share, the statuses and constraints that fail most,
    the Pareto front with the run's best design (and the source paper's design where it is one of
    the run's scenarios), the front's designs as a table, and an answer at the edge of a factor's
    range said as such; every number in the units engineers read."""
    objectives = ds["pareto_rank"].attrs["objectives"].split()
    feas = _flat(ds, "feasible").astype(bool)
    rank = ds["pareto_rank"].values.reshape(-1)
    fig = plt.figure(figsize=A4_LANDSCAPE)
    notes = edge_notes(ds)[:4]
    if notes:  # an answer at the edge of a factor's range, said under the title
        fig.text(
            0.06, 0.905, "\n".join(textwrap.shorten(n, 190) for n in notes), fontsize=8,
            va="top", color="tab:red",
        )  # fmt: skip
    top = 0.82 - 0.022 * len(notes)
    grid = fig.add_gridspec(
        2, 2, height_ratios=[1.5, 1.0], width_ratios=[1.0, 1.6], top=top, bottom=0.03, wspace=0.35
    )
    ax_c = fig.add_subplot(grid[0, 0])
    ax_t = fig.add_subplot(grid[1, :])
    _failing_panel(ax_c, ds)
    # a crossed (robust) result: every scenario is a design at a condition and a noise draw; its
    # fronts are drawn per operating condition, pooled over the draws (markers, not joined)
    crossed = "noise" in ds.dims
    within = ds["pareto_rank"].attrs.get("ranked_within", "").split()
    groups = [w for w in within if w != "noise"]
    _front_panels(fig, grid[0, 1], ds, objectives, feas, rank, groups, crossed)
    fig.text(
        0.64, top + 0.012, _front_caption(ds, objectives, groups, crossed), fontsize=8,
        ha="center", va="bottom",
    )  # fmt: skip
    n_rows = _front_table(ax_t, ds)
    life = life_text(ds)
    if life:  # the best design over its life (wear allowance, lining life, engagement rate)
        fig.text(0.06, 0.925, textwrap.shorten("best design over its life: " + life, 190),
                 fontsize=8, va="top")  # fmt: skip
    n = feas.size
    what = "scenarios" if crossed else "designs"
    title = (
        f"Design answers, study '{name}': {int(feas.sum())} of {n} {what} feasible "
        f"({100 * feas.mean():.0f} %), {int((rank == 0).sum())} on the Pareto front"
    )
    if (rank == 0).any():
        title += f" (table: {n_rows} spread along it; {name}_pareto.csv)"
    elif n_rows:
        title += (
            f"; table: the {n_rows} nearest to feasible (status ok first, then the largest "
            "least margin; a margin < 0 fails; ★ the design shown)"
        )
    fig.suptitle("\n".join(wrap_even(title, 120)), fontsize=11)
    return fig


def _failing_panel(ax, ds):
    """The statuses and constraints that fail most, as bars (designs or scenarios failing each)."""
    names, viol, colours = _failing(ds)
    ax.barh(range(len(names)), viol, height=0.6, color=colours)
    # (a status on a line of its own after the word: "status\nnever_locked", not "never_\nlocked")
    labels = [
        "\n".join(wrap_name(part, 18) for part in n.split(" ", 1)) if len(n) > 18 else n
        for n in names
    ]
    ax.set_yticks(range(len(names)), labels, fontsize=8)
    ax.set_ylim(len(names) - 0.5, -0.5)
    ax.set_xlabel(("scenarios" if "noise" in ds.dims else "designs") + " failing it")
    ax.xaxis.set_major_locator(plt.MaxNLocator(4, integer=True))
    ax.set_title(textwrap.fill("constraints: " + limits_text(ds), 55), fontsize=8)


def _front_panels(fig, cell_spec, ds, objectives, feas, rank, groups, crossed):
    """The front over the two objectives, or over every pair of them (projections, 2 rows and one
    cell left for the legend) for three or more, in the grid cell ``cell_spec``."""
    outs = [o.split(":")[0] for o in objectives]
    pairs = (
        list(itertools.combinations(outs, 2))[:6] if len(outs) > 2 else [tuple((outs + outs)[:2])]
    )
    # the legend in a cell of its own: beside the one panel (inside it hid designs, the fronts of
    # the operating conditions named most), or the free one among the projections
    beside = len(pairs) == 1
    if beside:  # (wider where it names the fronts)
        ratios = [1.75 if groups else 2.6, 1.0]
        cell = cell_spec.subgridspec(1, 2, width_ratios=ratios, wspace=0.05)
    else:
        cell = cell_spec.subgridspec(2, -(-(len(pairs) + 1) // 2), wspace=0.75, hspace=0.6)
    sense = dict(o.split(":") for o in objectives)
    marks = _marks(ds)
    for k, (ox, oy) in enumerate(pairs):
        ax = fig.add_subplot(cell[k % 2, k // 2] if len(pairs) > 1 else cell[0, 0])
        _front_panel(
            ax, ds, ox, oy, feas, rank, groups, marks, lines=len(pairs) == 1 and not crossed
        )
        for setter, o in ((ax.set_xlabel, ox), (ax.set_ylabel, oy)):
            setter(f"{o} [{display.unit_of(ds, o).label}] ({SENSE_WORDS[sense[o]]})", fontsize=8)
        ax.tick_params(labelsize=8)
        ax.xaxis.get_offset_text().set_fontsize(8)
        ax.yaxis.get_offset_text().set_fontsize(8)
    handles, labels = ax.get_legend_handles_labels()
    k = len(pairs)
    lax = fig.add_subplot(cell[0, 1] if beside else cell[k % 2, k // 2])
    lax.set_axis_off()
    labels = [textwrap.fill(t, 34 if groups else 24) for t in labels] if beside else labels
    lax.legend(handles, labels, fontsize=8, loc="upper left" if beside else "center")


def _front_caption(ds, objectives, groups, crossed) -> str:
    """What the front panels show: the objectives, the groups and how a robust result is drawn."""
    mixed = ds["pareto_rank"].attrs.get("conditions_mixed", "")
    return textwrap.fill(
        f"Pareto front over {' and '.join(objectives)}"
        + (" (projections: front designs marked, not joined)" if len(objectives) > 2 else "")
        + (
            f", one per {' and '.join(groups)} (operating conditions, not choices)"
            if groups
            else ""
        )
        + (
            "; a scenario is a design at a condition and a noise draw, ranked per condition "
            "and draw; the fronts of all draws shown per condition (the robust page ranks "
            "the designs over all of them)"
            if crossed
            else ""
        )
        + (
            f"; {mixed} sampled: ranked together with the design factors, a front design may "
            "owe its place to a light operating condition"
            if mixed
            else ""
        ),
        85,
    )


def _front_table(ax, ds):
    """The front's designs as a table (the first columns of ``<study>_pareto.csv``: factors,
    objectives and, where the page has room, the other constrained outputs, display units; as
    many rows as fit the axes, spread along the front), or the designs nearest to feasible where
    the run has none. Returns the rows shown."""
    header, rows = front_rows(ds, typeset=True)
    ax.set_axis_off()
    objectives, constrained = _outputs(ds)
    draws = len(_noise_draws(ds))
    # the CSV also has the constraints' margins (and a robust result's draw index)
    k = len(factors(ds)) + (draws - 1 if draws else 0) + len(objectives)
    k += len(constrained) if k + len(constrained) <= MAX_COLUMNS else 0
    fitting = max(table_rows_fitting(ax, header[:k]), 2)
    if not rows:
        return _nearest_table(ax, ds, fitting - 1)
    if len(rows) > fitting:
        header, rows = front_rows(ds, typeset=True, max_rows=fitting)
    cells = [[_text(v, ".4g") for v in r[:k]] for r in rows]
    fitted_table(ax, header[:k], cells)
    return len(rows)


def nearest_order(ds) -> np.ndarray:
    """Flat indices of the scenarios nearest to feasible, where none is: those whose status is
    ok first, each group the largest least constraint margin first (the scenarios whose margins
    are all known). The designs to change, and how far."""
    if "constraint_margin" not in ds:
        return np.zeros(0, dtype=np.int64)
    margins = ds["constraint_margin"].transpose("constraint", *ds["status"].dims).values
    least = np.min(margins.reshape(margins.shape[0], -1), axis=0)  # (NaN where one is unknown)
    known = np.flatnonzero(np.isfinite(least))
    failed = _flat(ds, "status")[known] != st.CODE["ok"]
    return known[np.lexsort((-least[known], failed))]


def _nearest_table(ax, ds, n) -> int:
    """Where no design is feasible: the ``n`` nearest to it (:func:`nearest_order`) as a table,
    with their status and every constraint's margin (< 0 where it fails; the page's title says
    so). Returns the rows shown."""
    near = nearest_order(ds)[:n]
    if not near.size:
        ax.text(
            0.5, 0.5, "no feasible design, none with every constraint's output known: no front "
            "(the bars above say what fails)", ha="center", va="center", fontsize=10,
            transform=ax.transAxes,
        )  # fmt: skip
        return 0
    header, rows = design_rows(ds, near, typeset=True)
    # factors, objectives and margins (the constrained outputs' values are in the CSV)
    _, constrained = _outputs(ds)
    margined = {h.split("_constraint_margin [")[0] for h in header if "_constraint_margin [" in h}
    keep = [j for j, h in enumerate(header) if h.split(" [")[0] not in set(constrained) & margined]
    head = ["status"] + [header[j].replace("_constraint_margin [-]", " margin [-]") for j in keep]
    codes = _flat(ds, "status")[near]
    shown = [i for i, _, colour in _marks(ds) if colour == "gold"]  # (the design shown: ★)
    cells = [
        [("★ " if i in shown else "") + st.FLAGS.get(int(c), str(c))]
        + [_text(r[j], ".4g") for j in keep]
        for i, c, r in zip(near, codes, rows, strict=True)
    ]
    fitted_table(ax, head, cells, widths=[1.8] + [1.0] * len(keep))  # (a status is long)
    return len(rows)


def _marks(ds, slice_only=False) -> list:
    """The designs marked on a page: the design the run's pages show (its best design; without a
    feasible one, the design nearest the ideal point, :func:`clutchlab.traces.shown_design`) and,
    unless the page is a slice through that design (``slice_only``), the source paper's design
    where it is one of the run's scenarios. [(flat index, label, face colour)]"""
    from ..traces import is_paper_design, shown_design

    if "shown_index" in ds.attrs:
        i, reason = int(ds.attrs["shown_index"]), ds.attrs.get("shown_reason", "")
    else:
        i, reason = shown_design(ds)
    marks = []
    if i is not None and i >= 0:
        label = (
            "best robust design, at its binding scenario"
            if reason.startswith("the run's best robust")
            else ("best design" if reason.startswith("the run's best") else "design shown")
        )
        if is_paper_design(ds, i):
            label += ", the source paper's"
        marks.append((i, label, "gold"))
    paper = None if slice_only else _paper_index(ds)
    if paper is not None and paper != i:
        marks.append((paper, "the source paper's design", "w"))
    return marks


def _paper_index(ds) -> int | None:
    """Flat index of the source paper's design where it is one of the run's scenarios."""
    from ..traces import _parameters, is_paper_design

    defaults = {p.name: p.default for p in _parameters(ds)}
    want = np.ones(ds["status"].size, bool)
    for n in factors(ds):
        if n in defaults and "flag_meanings" not in ds[n].attrs:
            want &= np.isclose(_flat(ds, n), defaults[n], rtol=1e-6, atol=0.0)
    hits = np.flatnonzero(want)
    return int(hits[0]) if hits.size and is_paper_design(ds, int(hits[0])) else None


def _front_panel(ax, ds, ox, oy, feas, rank, within, marks, lines):
    """Feasible and infeasible designs over two objectives (display units; the axes span the
    feasible designs, infeasible ones beyond are counted, not drawn), the front (one per
    operating condition where ranked within them; joined where it is the whole front, marked where
    a projection) and the marked designs."""
    ux, uy = display.unit_of(ds, ox), display.unit_of(ds, oy)
    x, y = ux(_flat(ds, ox)), uy(_flat(ds, oy))
    dots = {}
    for mask, size, colour, label in (
        (~feas, 6, "0.75", "infeasible"),
        (feas & (rank > 0), 8, "tab:blue", "feasible"),
    ):
        if not mask.any():  # (a mark in the legend only where it is drawn)
            continue
        show = drawn(mask)
        dots[label] = ax.scatter(
            x[show],
            y[show],
            s=size if mask.size < 2000 else 3,
            c=colour,
            rasterized=True,
            label=label + drawn_note(int(mask.sum())),
        )
    front = np.flatnonzero(rank == 0)
    key = (
        np.stack([_flat(ds, w) for w in within], axis=1)[front]
        if within
        else np.zeros((front.size, 0))
    )
    combos = np.unique(key, axis=0)
    for j, combo in enumerate(combos):
        members = front[(key == combo).all(axis=1)]
        members = members[np.argsort(x[members], kind="stable")]
        if within:
            label = (
                "front at "
                + ", ".join(_value_text(ds, w, v) for w, v in zip(within, combo, strict=False))
                if j < FRONTS_NAMED
                else (f"... {len(combos) - FRONTS_NAMED} more" if j == FRONTS_NAMED else None)
            )
        else:
            label = "Pareto front"
        ax.plot(
            x[members],
            y[members],
            "o-" if lines else "o",
            ms=4 if within or not lines else 5,
            label=label,
            color=front_colour(j) if within else "tab:red",
            zorder=2.5 if j < FRONTS_NAMED else 2.2,  # (the others' fronts under)
        )
    for i, label, colour in marks:
        if np.isfinite(x[i]) and np.isfinite(y[i]):
            ax.plot(x[i], y[i], "*", ms=16 if lines else 11, mfc=colour, mec="k", label=label)
    out = _feasible_limits(ax, x, y, feas)
    if out and "infeasible" in dots:  # (said in the legend: a note on the panel hid points)
        label, beyond = dots["infeasible"].get_label(), f"{out} beyond the axes"
        label = f"{label[:-1]}; {beyond})" if label.endswith(")") else f"{label} ({beyond})"
        dots["infeasible"].set_label(label)
    missing = int((~(np.isfinite(x) & np.isfinite(y))).sum())
    if missing:  # (a design without an objective's value is not drawn: counted)
        noun = "scenarios" if "noise" in ds.dims else "designs"
        ax.plot([], [], " ", label=f"{missing} {noun} not drawn: {ox} or {oy} NaN")
    _limit_lines(ax, ds, ox, oy)
    ax.grid(alpha=0.3)


def _limit_lines(ax, ds, ox, oy):
    """The constraint limits on the objectives drawn, as dashed lines where they fall inside the
    panel (how far the designs are from feasible)."""
    xlim, ylim = ax.get_xlim(), ax.get_ylim()
    named = False
    for name, axis, view in ((ox, "x", xlim), (oy, "y", ylim)):
        limit = constraint_limit(ds, name)
        if limit is None:
            continue
        v = float(display.unit_of(ds, name)(limit))
        if not min(view) <= v <= max(view):
            continue
        line = ax.axvline if axis == "x" else ax.axhline
        line(v, color="tab:red", ls="--", lw=1, label=None if named else "constraint limit")
        named = True
    ax.set_xlim(xlim)
    ax.set_ylim(ylim)


def _feasible_limits(ax, x, y, feas) -> int:
    """Axis ranges from the feasible designs (5 % margin), so that a few far infeasible designs do
    not squeeze the front into a corner. Returns how many designs are left outside."""
    ok = feas & np.isfinite(x) & np.isfinite(y)
    if not ok.any():
        return 0
    box = []
    for v, setter, scale in ((x, ax.set_xlim, ax.get_xscale()), (y, ax.set_ylim, ax.get_yscale())):
        lo, hi = float(v[ok].min()), float(v[ok].max())
        pad = 0.05 * (hi - lo) if hi > lo else 0.05 * abs(hi) or 1.0
        if scale == "linear":
            setter(lo - pad, hi + pad)
            box.append((lo - pad, hi + pad))
    if len(box) < 2:
        return 0
    (x0, x1), (y0, y1) = box
    finite = np.isfinite(x) & np.isfinite(y)
    return int((finite & ((x < x0) | (x > x1) | (y < y0) | (y > y1))).sum())


def sensitivity_page(name, se):
    """First-order and total indices of every factor, one panel per output (failure included)."""
    outputs = [str(o) for o in se["output"].values]
    factors_ = [str(f) for f in se["factor"].values]
    ncol = min(3, len(outputs))
    nrow = -(-len(outputs) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=A4_LANDSCAPE, squeeze=False)
    x = np.arange(len(factors_))
    for ax, out in zip(axes.ravel(), outputs, strict=False):
        s1 = se["first_order"].sel(output=out).values
        st_ = se["total"].sel(output=out).values
        c1, ct = (se[v].sel(output=out).values for v in ("first_order_conf", "total_conf"))
        # horizontal bars: the factor names read along their own line, wrapped at underscores
        ax.barh(
            x - 0.2,
            s1,
            height=0.4,
            label="first order",
            color="tab:blue",
            xerr=None if np.isnan(c1).all() else c1,
            capsize=2,
        )
        ax.barh(
            x + 0.2,
            st_,
            height=0.4,
            label="total",
            color="tab:orange",
            xerr=None if np.isnan(ct).all() else ct,
            capsize=2,
        )
        failed = int(se["failed"].sel(output=out))
        left_out = f" ({failed} failed scenarios left out: not an exact decomposition)"
        ax.set_title(textwrap.fill(out + (left_out if failed else ""), 45), fontsize=9)
        if np.isnan(s1).all() and np.isnan(st_).all():
            ax.text(
                0.5,
                0.5,
                textwrap.fill(
                    "no variance to explain: every scenario fails, or none does"
                    if out == "failure"
                    else "no variance to explain: every scenario equal, or none ok",
                    24,
                ),
                transform=ax.transAxes,
                ha="center",
                va="center",
                fontsize=8,
                color="0.3",
                bbox=dict(facecolor="w", edgecolor="0.7"),
            )
        ax.set_xlim(
            min(0.0, float(np.nanmin(np.r_[s1, st_, 0.0])) * 1.1),
            max(1.0, float(np.nanmax(np.r_[s1, st_, 0.0])) * 1.05),
        )
        ax.grid(alpha=0.3, axis="x")
        ax.set_yticks(x, [wrap_name(f, 13) for f in factors_], fontsize=8)
        ax.set_ylim(len(factors_) - 0.5, -0.5)
        ax.tick_params(axis="x", labelsize=8)
    for ax in axes.ravel()[len(outputs) :]:
        ax.set_axis_off()
    axes[0, 0].legend(fontsize=8)
    fig.suptitle(
        f"Sensitivity, study '{name}': share of each output's variance explained by a factor alone "
        "(first order) and with its interactions (total); failure = 1 where status is not ok"
    )
    fig.text(
        0.01,
        0.01,
        textwrap.fill(
            "Method: " + se.attrs.get("method", "") + ". Failed scenarios are left "
            "out of an output's indices (counted in its title): the rest of the grid is then "
            "unbalanced and its indices are no exact variance decomposition (a first-order index "
            "may exceed its total).",
            170,
        ),
        fontsize=8,
        color="0.3",
    )
    fig.tight_layout(rect=(0, 0.04, 1, 0.93))
    return fig


def write_refinement_csv(gain, path) -> None:
    """One row per operating-condition group: hypervolume before and after, design counts."""
    within = gain.attrs["ranked_within"].split()
    names = within + [
        "hypervolume_before",
        "hypervolume_after",
        "feasible_first",
        "feasible_second",
        "front_from_second",
    ]
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(names)
        for g in gain["group"].values:
            w.writerow([f"{float(gain[n].sel(group=g)):.6g}" for n in names])


def refinement_page(name, first, second, gain):
    """How the refining stage moved the fronts: hypervolume per operating condition before and
    after, and the fronts of the first stage and of both stages over the first two objectives."""
    objectives = first["pareto_rank"].attrs["objectives"].split()
    within = gain.attrs["ranked_within"].split()
    fig, (ax_h, ax_f) = plt.subplots(
        1, 2, figsize=A4_LANDSCAPE, gridspec_kw={"width_ratios": [1.0, 1.6]}
    )
    labels = _hypervolume_panel(ax_h, first, gain, within)
    _refined_fronts_panel(ax_f, first, second, gain, objectives, within, labels)
    n1, n2 = int(gain.attrs["scenarios_first"]), int(gain.attrs["scenarios_second"])
    before, after = float(gain["hypervolume_before"].sum()), float(gain["hypervolume_after"].sum())
    robust = bool(second.attrs.get("robust_view"))
    items, fronts = ("designs", "robust front") if robust else ("scenarios", "fronts")
    fig.suptitle(
        f"Refinement of study '{name}': {n2} new {items} near the {fronts} of {n1} "
        f"(first stage: {second.attrs.get('refine_from', '?')}); hypervolume summed over "
        f"{len(labels)} group(s) {before:.4f} -> {after:.4f} ({100 * (after / before - 1):+.1f} %)"
        if before > 0
        else f"Refinement of study '{name}': no first-stage front"
    )
    fig.text(
        0.01,
        0.01,
        textwrap.fill(
            (
                "Robust fronts: each design's worst case or quantile over every operating condition "
                "and noise draw, robust-feasible designs only. "
                if robust
                else ""
            )
            + "Dashed: the first stage's front; solid: the front of both stages together (per operating "
            "condition, one colour each). Hypervolume: the objective-space area the front dominates up to "
            f"the reference point ({gain.attrs['reference']}); it grows where the refining stage found "
            "better trade-offs. Factors kept at the front designs' values: operating conditions, counts, choices.",
            170,
        ),
        fontsize=8,
        color="0.3",
    )
    fig.tight_layout(rect=(0, 0.06, 1, 0.92))
    return fig


def _hypervolume_panel(ax, first, gain, within) -> list[str]:
    """The hypervolume of each group before and after the refinement, as bars; the groups'
    labels (their operating conditions)."""
    labels = [
        ", ".join(_value_text(first, w, float(gain[w].sel(group=g))) for w in within)
        or "all designs"
        for g in gain["group"].values
    ]
    y = np.arange(len(labels))
    ax.barh(y - 0.2, gain["hypervolume_before"], height=0.4, color="tab:blue", label="first stage")
    ax.barh(y + 0.2, gain["hypervolume_after"], height=0.4, color="tab:red", label="both stages")
    for k, (b, a) in enumerate(
        zip(gain["hypervolume_before"].values, gain["hypervolume_after"].values, strict=False)
    ):
        if b > 0:
            ax.text(a, k + 0.2, f" {100 * (a / b - 1):+.1f} %", va="center", fontsize=8)
    ax.set_yticks(y, [textwrap.fill(lab, 22) for lab in labels], fontsize=8)
    ax.set_ylim(len(labels) - 0.5, -0.5)
    ax.set_xlabel("hypervolume (objectives normalised per group)")
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=2)
    ax.grid(alpha=0.3, axis="x")
    return labels


def _refined_fronts_panel(ax, first, second, gain, objectives, within, labels):
    """Both stages' feasible designs over the first two objectives, with the first stage's front
    (dashed) and the front of both stages together (solid) of each group."""
    outs = [o.split(":")[0] for o in objectives]
    ox, oy = (outs + outs)[:2]
    ux, uy = display.unit_of(first, ox), display.unit_of(first, oy)
    x1, y1, x2, y2 = (
        ux(_flat(first, ox)),
        uy(_flat(first, oy)),
        ux(_flat(second, ox)),
        uy(_flat(second, oy)),
    )
    f1, ok1, key1 = objective_table(first, objectives, within)
    f2, ok2, key2 = objective_table(second, objectives, within)
    f_all = np.concatenate([f1, f2])
    ax.scatter(
        x1[drawn(ok1)], y1[drawn(ok1)], s=8, c="0.7", label="first stage, feasible", rasterized=True
    )
    ax.scatter(
        x2[drawn(ok2)],
        y2[drawn(ok2)],
        s=8,
        c="tab:orange",
        label="refining stage, feasible",
        rasterized=True,
    )
    sense = np.array([1.0 if o.endswith(":min") else -1.0 for o in objectives[:2]])
    x_all, y_all = np.r_[x1, x2], np.r_[y1, y2]
    front1 = first["pareto_rank"].values.reshape(-1) == 0  # ranked per group already
    for j, g in enumerate(gain["group"].values):
        combo = np.array([float(gain[w].sel(group=g)) for w in within])
        in1 = ok1 & (key1 == combo).all(axis=1)
        joint = pareto_rank(f_all, np.r_[in1, ok2 & (key2 == combo).all(axis=1)]) == 0
        for members, xs, ys, style, which in (
            (front1 & in1, x1, y1, "--", "first-stage"),
            (joint, x_all, y_all, "-", "joint"),
        ):
            order = np.argsort(xs[members] * sense[0], kind="stable")
            label = f"{which} front" + (f", {labels[j]}" if within else "") if j < 4 else None
            if j == 4:  # (the groups past the fourth: one colour, named once)
                label = f"{which} fronts of {gain['group'].size - 4} more groups"
            ax.plot(
                xs[members][order],
                ys[members][order],
                style,
                color=plt.cm.tab10(j if j < 4 else 9),
                lw=1.2,
                label=label,
            )
    ax.set_xlabel(display.label(ox, display.unit_of(first, ox)))
    ax.set_ylabel(display.label(oy, display.unit_of(first, oy)))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=2)

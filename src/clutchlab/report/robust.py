"""Report pages of a robust study: the robust front and the best robust design first.

Drawn from the robust answers stored beside a robust study's result (``robust.h5``,
:func:`clutchlab.explore.robust`): the worst-case (or quantile) objectives of every design, the
robust-feasible designs and the robust front, the best robust design
(:func:`clutchlab.explore.best_robust`) with its probability of failure at each operating
condition and its Wilson interval, and the condition and noise draw where its worst case occurs.
"""

from __future__ import annotations

import itertools
import textwrap

import matplotlib.pyplot as plt
import numpy as np

from .. import display, explore
from ..robust import CONFIDENCE, wilson_interval
from .common import A4_LANDSCAPE, SENSE_WORDS, fitted_table, shortened_to

__all__ = ["page", "best_text", "summary_lines", "write_csv", "front_rows"]

MAX_ROWS = 8  # robust front designs in the page's table, spread along it (all in the CSV)
TABLE_FONT = 8.0  # [pt]


def _design_dims(ra) -> list[str]:
    return list(ra["robust_rank"].dims)


def _factors(ra) -> list[str]:
    """The design factors of the robust answers: grid dimensions, or the sampled factors on
    ``point``."""
    dims = _design_dims(ra)
    sampled = [
        c for c in ra.coords if c not in dims and ra[c].dims and set(ra[c].dims) <= set(dims)
    ]
    return [d for d in dims if d != "point"] + sampled


def _flat(ra, name) -> np.ndarray:
    dims = _design_dims(ra)
    return ra[name].broadcast_like(ra["robust_rank"]).transpose(*dims).values.reshape(-1)


def _objectives(ra) -> list[tuple[str, str]]:
    return [tuple(o.split(":")) for o in ra["robust_rank"].attrs["objectives"].split()]


def _which(ra) -> str:
    return ra["robust_rank"].attrs["robust_objectives"]


def _v(ra, name, v) -> str:
    return display.text(v, display.unit_of(ra, name))


def design_text(ra, j) -> str:
    """Design ``j``'s factor values in engineers' units."""
    return ", ".join(f"{f} = {_v(ra, f, _flat(ra, f)[j])}" for f in _factors(ra))


def _failure(ra, j) -> tuple[float, float, float, dict]:
    """Design ``j``'s highest probability of failure over the conditions, its Wilson bounds and
    the condition where it occurs ({condition: value}; None where every condition has it)."""
    conds = ra.attrs.get("conditions", "").split()
    nd = int(np.prod([ra.sizes[d] for d in _design_dims(ra)], dtype=np.int64))
    p, lo, hi = (
        ra[v].transpose(*_design_dims(ra), *conds).values.reshape(nd, -1)[j]
        for v in ("failure_probability", "failure_probability_low", "failure_probability_high")
    )
    k = int(np.argmax(p))
    if p.size > 1 and np.all(p == p[k]) and np.all(hi == hi[k]):
        return float(p[k]), float(lo[k]), float(hi[k]), None
    at = np.unravel_index(k, tuple(ra.sizes[c] for c in conds)) if conds else ()
    where = {c: float(ra[c].values[i]) for c, i in zip(conds, at, strict=True)}
    return float(p[k]), float(lo[k]), float(hi[k]), where


def binding_text(ra, j, answer=None, lead=True) -> str:
    """Where design ``j``'s worst case of ``answer`` occurs (default: the constraint that binds
    it, :func:`clutchlab.explore.binding_answer`): the condition values and the noise draw
    (``lead``: after the answer's name)."""
    answer = answer or explore.binding_answer(ra, j)
    parts = []
    for c in ra.attrs.get("conditions", "").split():
        v = _v(ra, f"binding_{c}", _flat_answer(ra, ra[f"binding_{c}"].sel(answer=answer))[j])
        parts.append(f"{c} = {v}" if lead else v)
    for var in ra.data_vars:
        if var.startswith("binding_") and var.endswith("_noise") and var != "binding_noise":
            d = _flat_answer(ra, ra[var].sel(answer=answer))[j]
            name = var[len("binding_") : -len("_noise")]
            if ra[var].attrs.get("units", "1") == "1":
                parts.append(f"{name} {100 * d:+.1f} %")
            else:
                parts.append(f"{name} = {_v(ra, var, d)}")
    return (f"{answer} worst at " if lead else "") + ", ".join(parts)


def _flat_answer(ra, da) -> np.ndarray:
    return da.transpose(*_design_dims(ra)).values.reshape(-1)


def best_text(ra) -> str:
    """The best robust design, its worst-case and quantile objectives, its highest probability of
    failure with its interval and condition, and where its worst case binds."""
    j = explore.best_robust(ra)
    if j is None:
        return "no robust design: " + _none_reason(ra)
    q = ra.attrs.get("quantile", 0.95)
    objs = "; ".join(
        f"{name} worst {_v(ra, f'worst_{name}', _flat(ra, f'worst_{name}')[j])}, "
        f"{q:g}-quantile {_v(ra, f'quantile_{name}', _flat(ra, f'quantile_{name}')[j])}"
        for name, _ in _objectives(ra)
    )
    p, lo, hi, where = _failure(ra, j)
    at = (
        "every operating condition"
        if where is None
        else ", ".join(f"{c} = {_v(ra, c, v)}" for c, v in where.items())
    )
    return (
        f"{design_text(ra, j)}: {objs}; highest probability of failure {100 * p:.2g} % "
        f"(95 % interval {100 * lo:.2g}-{100 * hi:.2g} %{', at ' + at if at else ''}); "
        + binding_text(ra, j)
    )


def _none_reason(ra) -> str:
    feas = _flat(ra, "robust_feasible").astype(bool)
    limit = ra.attrs.get("max_failure_probability", 0.01)
    return (
        f"no design fails in at most {100 * limit:.2g} % of its noise draws at every condition"
        if not feas.any()
        else "the robust-feasible designs have no finite robust objectives"
    )


def summary_lines(ra) -> list[str]:
    """The summary page's lines of a robust study (before its per-condition answers)."""
    feas = _flat(ra, "robust_feasible").astype(bool)
    rank = _flat(ra, "robust_rank")
    conds = ra.attrs.get("conditions", "").split()
    ncond = int(np.prod([ra.sizes[c] for c in conds], dtype=np.int64)) if conds else 1
    noise = ", ".join(ra.attrs.get("noise_parameters", "").split()) or "none"
    best = (
        best_text(ra)
        if explore.best_robust(ra) is not None
        else f"none ({_none_reason(ra)})"  # (not "no robust design" twice)
    )
    return [
        f"robust: {int(feas.sum())} of {feas.size} designs fail in at most "
        f"{100 * ra.attrs.get('max_failure_probability', 0.01):.2g} % of the noise draws (an "
        "estimate of the probability of failure; its 95 % bounds on the robust page) "
        + (
            f"at each of {ncond} operating conditions ({', '.join(conds)})"
            if conds
            else "at the one operating condition"
        )
        + f" over {ra.attrs.get('noise_samples', 0)} noise samples of {noise}; "
        f"{int((rank == 0).sum())} on the robust front ({_which(ra)} objectives)",
        "best robust design: " + best,
    ]


def front_rows(ra, typeset=False) -> tuple[list[str], list[list[str]]]:
    """(header, rows) of the robust front designs along the first objective; the header's units
    as a config writes them (``[rad/s^3]``) or ``typeset`` for a page (``[rad/s³]``)."""
    rank = _flat(ra, "robust_rank")
    front = np.flatnonzero(rank == 0)
    if not front.size:
        return [], []
    first = _objectives(ra)[0][0]
    front = front[np.argsort(_flat(ra, f"{_which(ra)}_{first}")[front], kind="stable")]
    factors = _factors(ra)
    cols = [f"{w}_{n}" for n, _ in _objectives(ra) for w in ("worst", "quantile")]
    units = [display.unit_of(ra, c) for c in factors + cols]
    header = [
        f"{c} [{u.label}]" if typeset and u.label else display.column(c, u)
        for c, u in zip(factors + cols, units, strict=True)
    ]
    conds = " / ".join([*ra.attrs.get("conditions", "").split(), "noise"])
    binds = "binding constraint" if "constraint" in ra.coords else "objective"
    header += ["P(failure) max [%]", "95 % interval [%]", binds, f"worst at {conds}"]
    rows = []
    for j in front:
        p, lo, hi, _ = _failure(ra, j)
        row = [format(display.unit_of(ra, f)(_flat(ra, f)[j]), ".4g") for f in factors]
        row += [format(display.unit_of(ra, c)(_flat(ra, c)[j]), ".4g") for c in cols]
        answer = explore.binding_answer(ra, j)
        row += [f"{100 * p:.2g}", f"{100 * lo:.2g}-{100 * hi:.2g}", answer]
        row.append(binding_text(ra, j, answer, lead=False))
        rows.append(row)
    return header, rows


def write_csv(ra, path) -> None:
    """The robust front designs as CSV (every one), units in the column headers."""
    import csv

    header, rows = front_rows(ra)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header or ["no robust front design"])
        w.writerows(rows)


def page(name, ra):
    """The robust answers of a study: every design's robust objectives (robust-feasible designs
    and the robust front marked, the best robust design starred), the best robust design's
    probability of failure at each condition with its interval, and the robust front's table."""
    fig = plt.figure(figsize=A4_LANDSCAPE)
    grid = fig.add_gridspec(
        2, 2, height_ratios=[1.3, 1.0], top=0.76, bottom=0.03, wspace=0.3, hspace=0.35
    )
    _front_panel(fig.add_subplot(grid[0, 0]), ra)
    _failure_panel(fig.add_subplot(grid[0, 1]), ra)
    ax = fig.add_subplot(grid[1, :])
    ax.set_axis_off()
    header, rows = front_rows(ra, typeset=True)
    shown = [rows[i] for i in explore.spread(np.arange(len(rows)), MAX_ROWS)]
    if rows:
        _front_table(ax, header, shown)
    else:
        ax.text(0.5, 0.5, "no robust front: " + _none_reason(ra), ha="center", fontsize=10)
    feas = _flat(ra, "robust_feasible").astype(bool)
    rank = _flat(ra, "robust_rank")
    spread = " spread along it" if len(shown) < len(rows) else ""
    fig.suptitle(
        textwrap.fill(
            f"Robust answers, study '{name}': {int(feas.sum())} of {feas.size} designs meet every "
            f"limit in all but at most "
            f"{100 * ra.attrs.get('max_failure_probability', 0.01):.2g} % of the noise draws (the "
            "estimated probability of failure) at every operating "
            f"condition; {int((rank == 0).sum())} on the robust front"
            + (f" (table: {len(shown)}{spread}; {name}_robust.csv)" if rows else ""),
            130,
        ),
        fontsize=11,
    )
    fig.text(0.04, 0.915, textwrap.fill("best robust design: " + best_text(ra), 165),
             fontsize=8, va="top")  # fmt: skip
    fig.text(0.04, 0.835, textwrap.fill(resolution_text(ra), 165), fontsize=8, va="top",
             color="0.3")  # fmt: skip
    return fig


def _front_table(ax, header, rows) -> None:
    """The robust front's table (:func:`clutchlab.report.common.fitted_table`): the binding
    constraint and where it binds in one last column, wider: on three lines (the noise draw on
    the last) or two where the rows fit the axes so, else on one, each shortened to the
    column."""
    widths = [0.075] * (len(header) - 2) + [0.33]
    share = widths[-1] / sum(widths)
    line_in = 1.2 * TABLE_FONT / 72.0
    room_in = ax.get_position().height * ax.figure.get_figheight() - 4.6 * line_in
    lines = next((n for n in (3, 2) if len(rows) * (n + 0.6) * line_in <= room_in), 1)

    def cell(binding, where):
        if lines == 3:  # (where: the conditions, then the noise draw on a line of its own)
            where = "\n".join(where.rsplit(", ", 1))
        sep = ":\n" if lines > 1 else ": "
        return shortened_to(ax, f"{binding}{sep}{where}", share, TABLE_FONT)

    cells = [r[:-2] + [cell(r[-2], r[-1])] for r in rows]
    fitted_table(ax, header[:-2] + [f"{header[-2]}: {header[-1]}"], cells, widths, TABLE_FONT)


def resolution_text(ra) -> str:
    """What the run's noise sample count can tell: the 95 % upper bound of the probability of
    failure of a design that failed in none of the draws, and the draws a bound at the study's
    limit would take (Wilson score interval, k = 0: upper bound z²/(n + z²))."""
    n = int(ra.attrs.get("noise_samples", 0))
    limit = float(ra.attrs.get("max_failure_probability", 0.01))
    if n <= 0:
        return ""
    upper = float(wilson_interval(0, n, float(ra.attrs.get("confidence", CONFIDENCE)))[1])
    z2 = upper * n / (1 - upper)
    needed = int(np.ceil(z2 * (1 - limit) / limit)) if limit > 0 else 0
    text = (
        f"{n} noise draws a condition: a design that fails in none of them may still fail with "
        f"probability up to {100 * upper:.2g} % (95 % upper bound)"
    )
    if upper > limit:
        text += (
            f"; robust-feasible compares the estimate with the {100 * limit:.2g} % limit, and "
            f"a bound below it takes {needed} draws or more (noise_samples)"
        )
    return text


def _front_panel(ax, ra) -> None:
    objs = _objectives(ra)
    which = _which(ra)
    (ox, sx), (oy, sy) = (objs + objs)[:2]
    x = display.unit_of(ra, f"{which}_{ox}")(_flat(ra, f"{which}_{ox}"))
    y = display.unit_of(ra, f"{which}_{oy}")(_flat(ra, f"{which}_{oy}"))
    feas = _flat(ra, "robust_feasible").astype(bool)
    rank = _flat(ra, "robust_rank")
    for mask, size, colour, label in (
        (~feas, 8, "0.75", "not robust"),
        (feas & (rank != 0), 10, "tab:blue", "robust-feasible"),  # (the front drawn below)
    ):
        if mask.any():  # (a mark in the legend only where it is drawn)
            ax.scatter(x[mask], y[mask], s=size, color=colour, label=label)
    front = np.flatnonzero(rank == 0)
    front = front[np.argsort(x[front])]
    ax.plot(x[front], y[front], "o-", color="tab:red", ms=4, label="robust front")
    j = explore.best_robust(ra)
    if j is not None:
        ax.plot(x[j], y[j], "*", color="k", ms=14, label="best robust design")
    for setter, o, s in ((ax.set_xlabel, ox, sx), (ax.set_ylabel, oy, sy)):
        u = display.unit_of(ra, f"{which}_{o}")
        setter(f"{which} {o.replace('_', ' ')} [{u.label}] ({SENSE_WORDS[s]})", fontsize=8)
    ax.tick_params(labelsize=8)
    ax.legend(fontsize=8)
    ax.set_title(f"{which}-case objectives over conditions and noise", fontsize=9)


def _named_every(ax, labels) -> int:
    """Name every k-th of the x ticks' ``labels``, k the least for which the names drawn do not
    overprint side by side (measured on the page). Returns k."""
    renderer = ax.figure.canvas.get_renderer()
    for k in range(1, len(labels) + 1):
        ax.set_xticks(range(len(labels)), [t if i % k == 0 else "" for i, t in enumerate(labels)])
        boxes = [t.get_window_extent(renderer) for t in ax.get_xticklabels() if t.get_text()]
        if not any(a.padded(2.0).overlaps(b) for a, b in itertools.pairwise(boxes)):
            return k
    return len(labels)


def _failure_panel(ax, ra) -> None:
    j = explore.best_robust(ra)
    conds = ra.attrs.get("conditions", "").split()
    if j is None:
        ax.set_axis_off()
        ax.text(0.5, 0.5, "no robust design", ha="center")
        return
    nd = int(np.prod([ra.sizes[d] for d in _design_dims(ra)], dtype=np.int64))
    p, lo, hi = (
        100 * ra[v].transpose(*_design_dims(ra), *conds).values.reshape(nd, -1)[j]
        for v in ("failure_probability", "failure_probability_low", "failure_probability_high")
    )
    labels = []
    for k in range(p.size):
        at = np.unravel_index(k, tuple(ra.sizes[c] for c in conds)) if conds else ()
        labels.append(
            "\n".join(_v(ra, c, ra[c].values[i]) for c, i in zip(conds, at, strict=True))
            or "nominal"
        )
    ax.bar(range(p.size), p, color="tab:blue")
    err = [np.maximum(p - lo, 0.0), np.maximum(hi - p, 0.0)]
    ax.errorbar(range(p.size), p, yerr=err, fmt="none", color="k", capsize=4)
    ax.axhline(100 * ra.attrs.get("max_failure_probability", 0.01), color="tab:red", ls="--",
               label="allowed")  # fmt: skip
    ax.tick_params(labelsize=8)
    k = _named_every(ax, labels)
    if k > 1:
        ax.set_title(
            f"best robust design at each operating condition (one in {k} named)", fontsize=9
        )
    ax.set_xlabel(" / ".join(conds) or "no operating condition", fontsize=8)
    ax.set_ylabel("probability of failure [%] (95 % Wilson interval)", fontsize=8)
    if k == 1:
        ax.set_title("best robust design at each operating condition", fontsize=9)
    ax.legend(fontsize=8)
    ax.tick_params(labelsize=8)

"""The design-answers page of a study: how many designs are feasible, which constraint binds most
often, the Pareto front with the seed design marked, and the front's designs as a table
(also ``<study>_pareto.csv``)."""

from __future__ import annotations

import csv
import itertools
import textwrap

import matplotlib.pyplot as plt
import numpy as np

from .. import studies
from ..explore import flat as _flat
from ..explore import front_order, objective_table, pareto_rank, spread
from .common import A4_LANDSCAPE, drawn, drawn_note, seed_view

MAX_ROWS = 15


def factors(ds) -> list[str]:
    """The study's factors: its dimensions (factorial) or the ``factors`` attribute (sampled)."""
    dims = list(ds["status"].dims)
    return ds.attrs.get("factors", "").split() if dims == ["run"] else dims


def front_rows(ds) -> tuple[list[str], list[list]]:
    """Header and rows of the front's designs (at most ``MAX_ROWS``, spread along the first
    objective, per operating condition where the ranks are): factor values and objectives in SI,
    an option drawn per scenario by the name of its choice."""
    objectives = [o.split(":")[0] for o in ds["pareto_rank"].attrs["objectives"].split()]
    names = factors(ds)
    options = {
        o: ds[o].attrs["flag_meanings"].split() for o in ds.attrs.get("option_factors", "").split()
    }
    cols = {n: _flat(ds, n) for n in names}
    front = spread(front_order(ds), MAX_ROWS)
    header = [
        n if n in options else f"{n} [{ds[n].attrs.get('units', '')}]" for n in names + objectives
    ]
    rows = [
        [options[n][int(cols[n][i])] if n in options else float(cols[n][i]) for n in names]
        + [float(_flat(ds, o)[i]) for o in objectives]
        for i in front
    ]
    return header, rows


def _value_text(ds, name, v) -> str:
    """ "name value" of a factor, a flagged code (an option drawn per scenario) by its meaning."""
    meanings = ds[name].attrs.get("flag_meanings", "").split()
    return f"{name} {meanings[int(v)]}" if meanings else f"{name} {v:.4g}"


def best_text(ds) -> str:
    """The best compromise design (:func:`clutchlab.explore.best_compromise`) in one line:
    its factors, then its objectives."""
    from ..explore import best_compromise

    i = best_compromise(ds)
    if i is None:
        return "no feasible design on a Pareto front"
    objectives = [o.split(":")[0] for o in ds["pareto_rank"].attrs["objectives"].split()]
    parts = []
    for n in factors(ds) + objectives:
        v = _flat(ds, n)[i]
        unit = ds[n].attrs.get("units", "")
        if unit == "rad":  # angles read in degrees
            v, unit = np.rad2deg(v), "deg"
        parts.append(
            _value_text(ds, n, v).replace(" ", " = ", 1)
            + ("" if unit in ("1", "") or ds[n].attrs.get("flag_meanings") else f" {unit}")
        )
    k = len(factors(ds))
    return ", ".join(parts[:k]) + " -> " + ", ".join(parts[k:])


def _text(v, fmt) -> str:
    return v if isinstance(v, str) else format(v, fmt)


def write_csv(ds, path) -> None:
    header, rows = front_rows(ds)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for r in rows:
            w.writerow([_text(v, ".6g") for v in r])


def page(name, ds):
    study = studies.get(name)
    objectives = ds["pareto_rank"].attrs["objectives"].split()
    outs = [o.split(":")[0] for o in objectives]
    feas = _flat(ds, "feasible").astype(bool)
    rank = ds["pareto_rank"].values.reshape(-1)
    fig = plt.figure(figsize=A4_LANDSCAPE)
    grid = fig.add_gridspec(
        2, 2, height_ratios=[1.5, 1.0], width_ratios=[1.0, 1.6], top=0.83, bottom=0.03
    )
    ax_c = fig.add_subplot(grid[0, 0])
    ax_t = fig.add_subplot(grid[1, :])
    # which constraint binds most often (and how many designs have no number: status not ok)
    names, viol = ["status not ok"], [int((ds["status"].values != 0).sum())]
    if "constraint_margin" in ds:
        names += [str(c) for c in ds["constraint"].values]
        viol += [
            int((ds["constraint_margin"].sel(constraint=c).values < 0).sum()) for c in names[1:]
        ]
    ax_c.barh(range(len(names)), viol, height=0.6, color=["0.5"] + ["tab:red"] * (len(names) - 1))
    ax_c.set_yticks(range(len(names)), [textwrap.fill(n, 18) for n in names], fontsize=8)
    ax_c.set_ylim(len(names) - 0.5, -0.5)
    ax_c.set_xlabel("designs failing it")
    ax_c.xaxis.set_major_locator(plt.MaxNLocator(4, integer=True))
    limits = ds["constraint"].attrs.get("limits", "") if "constraint" in ds.coords else "none"
    ax_c.set_title(textwrap.fill("constraints: " + limits, 50), fontsize=8)
    # the front: over the two objectives, or every pair of them (projections) for three or more
    within = ds["pareto_rank"].attrs.get("ranked_within", "").split()
    pairs = (
        list(itertools.combinations(outs, 2))[:6] if len(outs) > 2 else [tuple((outs + outs)[:2])]
    )
    # projections: 2 rows, one cell left for the legend
    cell = (
        grid[0, 1].subgridspec(1, 1)
        if len(pairs) == 1
        else grid[0, 1].subgridspec(2, -(-(len(pairs) + 1) // 2), wspace=0.75, hspace=0.55)
    )
    sense = dict(o.split(":") for o in objectives)
    seed = seed_view(ds, study.defaults)
    for k, (ox, oy) in enumerate(pairs):
        ax = fig.add_subplot(cell[k % 2, k // 2] if len(pairs) > 1 else cell[0, 0])
        _front_panel(
            ax, ds, ox, oy, feas, rank, within, seed, lines=len(pairs) == 1, legend=len(pairs) == 1
        )
        small = len(pairs) > 1
        ax.set_xlabel(
            f"{ox} [{ds[ox].attrs.get('units', '')}] ({sense[ox]})", fontsize=7 if small else None
        )
        ax.set_ylabel(
            f"{oy} [{ds[oy].attrs.get('units', '')}] ({sense[oy]})", fontsize=7 if small else None
        )
        if small:
            ax.tick_params(labelsize=6)
            ax.xaxis.get_offset_text().set_fontsize(6)
            ax.yaxis.get_offset_text().set_fontsize(6)
    if len(pairs) > 1:  # the legend in the free cell
        k = len(pairs)
        lax = fig.add_subplot(cell[k % 2, k // 2])
        lax.set_axis_off()
        lax.legend(
            *ax.get_legend_handles_labels(),
            fontsize=6,
            loc="center",
            title="front at" if within else None,
            title_fontsize=6,
        )
    mixed = ds["pareto_rank"].attrs.get("conditions_mixed", "")
    fig.text(
        0.62,
        0.895,
        textwrap.fill(
            f"Pareto front over {' and '.join(objectives)}"
            + (" (projections: front designs marked, not joined)" if len(outs) > 2 else "")
            + (
                f", one per {' and '.join(within)} (operating conditions, not choices)"
                if within
                else ""
            )
            + (
                f"; {mixed} sampled: ranked together with the design factors, a front design may owe its "
                "place to a light operating condition"
                if mixed
                else ""
            ),
            90,
        ),
        fontsize=8,
        ha="center",
        va="top",
    )
    # the front's designs
    header, rows = front_rows(ds)
    ax_t.set_axis_off()
    if rows:
        table = ax_t.table(
            cellText=[[_text(v, ".4g") for v in r] for r in rows],
            colLabels=[textwrap.fill(h, 16) for h in header],
            cellLoc="center",
            bbox=(0.0, 0.0, 1.0, 1.0),
        )  # the table fills its axes, never past the page
        table.auto_set_font_size(False)
        table.set_fontsize(7)
        header_share = 2.0 / (len(rows) + 2)  # the wrapped column names get two rows' height
        for (i, j), c in table.get_celld().items():
            c.set_height(header_share if i == 0 else (1.0 - header_share) / len(rows))
    n = feas.size
    fig.suptitle(
        f"Design answers, study '{name}': {int(feas.sum())} of {n} designs feasible "
        f"({100 * feas.mean():.0f} %), {int((rank == 0).sum())} on the Pareto front"
        + (f" (table: {len(rows)} spread along it; {name}_pareto.csv)" if rows else "")
    )
    return fig


def _front_panel(ax, ds, ox, oy, feas, rank, within, seed, lines, legend):
    """Feasible and infeasible designs over two objectives, the front (one per operating condition
    where ranked within them; joined where it is the whole front, marked where a projection) and
    the seed design."""
    x, y = _flat(ds, ox), _flat(ds, oy)
    for mask, size, colour, label in (
        (~feas, 6, "0.8", "infeasible"),
        (feas & (rank > 0), 8, "tab:blue", "feasible"),
    ):
        show = drawn(mask)
        ax.scatter(
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
                ", ".join(_value_text(ds, w, v) for w, v in zip(within, combo))
                if j < 8
                else (f"... {len(combos) - 8} more" if j == 8 else None)
            )
        else:
            label = "Pareto front"
        ax.plot(
            x[members],
            y[members],
            "o-" if lines else "o",
            ms=4 if within or not lines else 5,
            label=label,
            color=plt.cm.tab10(j % 10) if within else "tab:red",
        )
    sx, sy = float(seed[ox]), float(seed[oy])
    if np.isfinite(sx) and np.isfinite(sy):
        ax.plot(sx, sy, "*", ms=16 if lines else 11, mfc="gold", mec="k", label="seed design")
    if legend:
        ax.legend(
            fontsize=7 if lines else 5, title="front at" if within else None, title_fontsize=7
        )
    ax.grid(alpha=0.3)


def sensitivity_page(name, se):
    """First-order and total indices of every factor, one panel per output (failure included)."""
    outputs = [str(o) for o in se["output"].values]
    factors_ = [str(f) for f in se["factor"].values]
    ncol = min(3, len(outputs))
    nrow = -(-len(outputs) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=A4_LANDSCAPE, squeeze=False)
    x = np.arange(len(factors_))
    for ax, out in zip(axes.ravel(), outputs):
        s1 = se["first_order"].sel(output=out).values
        st_ = se["total"].sel(output=out).values
        c1, ct = (se[v].sel(output=out).values for v in ("first_order_conf", "total_conf"))
        ax.bar(
            x - 0.2,
            s1,
            width=0.4,
            label="first order",
            color="tab:blue",
            yerr=None if np.isnan(c1).all() else c1,
            capsize=2,
        )
        ax.bar(
            x + 0.2,
            st_,
            width=0.4,
            label="total",
            color="tab:orange",
            yerr=None if np.isnan(ct).all() else ct,
            capsize=2,
        )
        failed = int(se["failed"].sel(output=out))
        ax.set_title(out + (f" ({failed} failed scenarios left out)" if failed else ""), fontsize=9)
        ax.set_ylim(
            min(0.0, float(np.nanmin(np.r_[s1, st_, 0.0])) * 1.1),
            max(1.0, float(np.nanmax(np.r_[s1, st_, 0.0])) * 1.05),
        )
        ax.grid(alpha=0.3, axis="y")
        ax.set_xticks(x, [textwrap.fill(f, 14) for f in factors_], fontsize=7, rotation=30)
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
            "out of an output's indices (counted in its title).",
            190,
        ),
        fontsize=7,
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
    outs = [o.split(":")[0] for o in objectives]
    within = gain.attrs["ranked_within"].split()
    fig, (ax_h, ax_f) = plt.subplots(
        1, 2, figsize=A4_LANDSCAPE, gridspec_kw={"width_ratios": [1.0, 1.6]}
    )
    labels = [
        ", ".join(f"{w} {float(gain[w].sel(group=g)):.4g}" for w in within) or "all designs"
        for g in gain["group"].values
    ]
    y = np.arange(len(labels))
    ax_h.barh(
        y - 0.2, gain["hypervolume_before"], height=0.4, color="tab:blue", label="first stage"
    )
    ax_h.barh(y + 0.2, gain["hypervolume_after"], height=0.4, color="tab:red", label="both stages")
    for k, (b, a) in enumerate(
        zip(gain["hypervolume_before"].values, gain["hypervolume_after"].values)
    ):
        if b > 0:
            ax_h.text(a, k + 0.2, f" {100 * (a / b - 1):+.1f} %", va="center", fontsize=7)
    ax_h.set_yticks(y, [textwrap.fill(lab, 22) for lab in labels], fontsize=7)
    ax_h.set_ylim(len(labels) - 0.5, -0.5)
    ax_h.set_xlabel("hypervolume (objectives normalised per group)")
    ax_h.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=2)
    ax_h.grid(alpha=0.3, axis="x")
    ox, oy = (outs + outs)[:2]
    x1, y1, x2, y2 = _flat(first, ox), _flat(first, oy), _flat(second, ox), _flat(second, oy)
    f1, ok1, key1 = objective_table(first, objectives, within)
    f2, ok2, key2 = objective_table(second, objectives, within)
    f_all = np.concatenate([f1, f2])
    ax_f.scatter(
        x1[drawn(ok1)], y1[drawn(ok1)], s=8, c="0.7", label="first stage, feasible", rasterized=True
    )
    ax_f.scatter(
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
            ax_f.plot(
                xs[members][order],
                ys[members][order],
                style,
                color=plt.cm.tab10(j % 10),
                lw=1.2,
                label=label,
            )
    ax_f.set_xlabel(f"{ox} [{first[ox].attrs.get('units', '')}]")
    ax_f.set_ylabel(f"{oy} [{first[oy].attrs.get('units', '')}]")
    ax_f.grid(alpha=0.3)
    ax_f.legend(fontsize=6, ncol=2)
    n1, n2 = int(gain.attrs["scenarios_first"]), int(gain.attrs["scenarios_second"])
    before, after = float(gain["hypervolume_before"].sum()), float(gain["hypervolume_after"].sum())
    fig.suptitle(
        f"Refinement of study '{name}': {n2} new scenarios near the fronts of {n1} "
        f"(first stage: {second.attrs.get('refine_from', '?')}); hypervolume summed over "
        f"{len(labels)} group(s) {before:.4f} -> {after:.4f} ({100 * (after / before - 1):+.1f} %)"
        if before > 0
        else f"Refinement of study '{name}': no first-stage front"
    )
    fig.text(
        0.01,
        0.01,
        textwrap.fill(
            "Dashed: the first stage's front; solid: the front of both stages together (per operating "
            "condition, one colour each). Hypervolume: the objective-space area the front dominates up to "
            f"the reference point ({gain.attrs['reference']}); it grows where the refining stage found "
            "better trade-offs. Factors kept at the front designs' values: operating conditions, counts, choices.",
            190,
        ),
        fontsize=7,
        color="0.3",
    )
    fig.tight_layout(rect=(0, 0.05, 1, 0.92))
    return fig

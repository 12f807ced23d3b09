"""The design-answers page of a study: how many designs are feasible, which constraint binds most
often, the Pareto front with the seed design marked, and the front's designs as a table
(also ``<study>_pareto.csv``)."""
from __future__ import annotations

import csv
import textwrap

import matplotlib.pyplot as plt
import numpy as np

from .. import studies
from .common import A4_LANDSCAPE, seed_view

MAX_ROWS = 15


def factors(ds) -> list[str]:
    """The study's factors: its dimensions (factorial) or the ``factors`` attribute (sampled)."""
    dims = list(ds["status"].dims)
    return ds.attrs.get("factors", "").split() if dims == ["run"] else dims


def _flat(ds, name):
    """A per-scenario variable or factor coordinate as a flat array in the order of ``status``."""
    return ds[name].broadcast_like(ds["status"]).transpose(*ds["status"].dims).values.reshape(-1)


def front_rows(ds) -> tuple[list[str], list[list]]:
    """Header and rows of the front's designs (at most ``MAX_ROWS``, spread along the first
    objective, per operating condition where the ranks are): factor values and objectives in SI."""
    objectives = [o.split(":")[0] for o in ds["pareto_rank"].attrs["objectives"].split()]
    names = factors(ds)
    rank = ds["pareto_rank"].values.reshape(-1)
    front = np.flatnonzero(rank == 0)
    cols = {n: _flat(ds, n) for n in names}
    # grouped by operating condition (where ranked within them), then along the first objective
    keys = [_flat(ds, objectives[0])[front]] + [_flat(ds, w)[front] for w in
                                                 ds["pareto_rank"].attrs.get("ranked_within", "").split()[::-1]]
    front = front[np.lexsort(keys)]
    if front.size > MAX_ROWS:
        front = front[np.unique(np.linspace(0, front.size - 1, MAX_ROWS).round().astype(int))]
    header = [f"{n} [{ds[n].attrs.get('units', '')}]" for n in names + objectives]
    rows = [[float(cols[n][i]) for n in names] + [float(_flat(ds, o)[i]) for o in objectives] for i in front]
    return header, rows


def write_csv(ds, path) -> None:
    header, rows = front_rows(ds)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for r in rows:
            w.writerow([f"{v:.6g}" for v in r])


def page(name, ds):
    study = studies.get(name)
    objectives = ds["pareto_rank"].attrs["objectives"].split()
    outs = [o.split(":")[0] for o in objectives]
    feas = _flat(ds, "feasible").astype(bool)
    rank = ds["pareto_rank"].values.reshape(-1)
    fig = plt.figure(figsize=A4_LANDSCAPE)
    grid = fig.add_gridspec(2, 2, height_ratios=[1.5, 1.0], width_ratios=[1.0, 1.6])
    ax_c = fig.add_subplot(grid[0, 0])
    ax_f = fig.add_subplot(grid[0, 1])
    ax_t = fig.add_subplot(grid[1, :])
    # which constraint binds most often
    # which constraint binds most often (and how many designs have no number: status not ok)
    names, viol = ["status not ok"], [int((ds["status"].values != 0).sum())]
    if "constraint_margin" in ds:
        names += [str(c) for c in ds["constraint"].values]
        viol += [int((ds["constraint_margin"].sel(constraint=c).values < 0).sum()) for c in names[1:]]
    ax_c.barh(range(len(names)), viol, height=0.6, color=["0.5"] + ["tab:red"] * (len(names) - 1))
    ax_c.set_yticks(range(len(names)), [textwrap.fill(n, 18) for n in names], fontsize=8)
    ax_c.set_ylim(len(names) - 0.5, -0.5)
    ax_c.set_xlabel("designs failing it")
    limits = ds["constraint"].attrs.get("limits", "") if "constraint" in ds.coords else "none"
    ax_c.set_title(textwrap.fill("constraints: " + limits, 50), fontsize=8)
    # the front over the first two objectives
    ox, oy = (outs + outs)[:2]  # one objective: plotted against itself
    x, y = _flat(ds, ox), _flat(ds, oy)
    ax_f.scatter(x[~feas], y[~feas], s=6, c="0.8", label="infeasible")
    ax_f.scatter(x[feas & (rank > 0)], y[feas & (rank > 0)], s=8, c="tab:blue", label="feasible")
    front = np.flatnonzero(rank == 0)
    within = ds["pareto_rank"].attrs.get("ranked_within", "").split()
    if within:  # one front per combination of operating conditions
        key = np.stack([_flat(ds, w) for w in within], axis=1)[front]
        combos = np.unique(key, axis=0)
        for j, combo in enumerate(combos):
            members = front[(key == combo).all(axis=1)]
            members = members[np.argsort(x[members], kind="stable")]
            label = (", ".join(f"{w} {v:.4g}" for w, v in zip(within, combo)) if j < 8
                     else (f"... {len(combos) - 8} more" if j == 8 else None))
            ax_f.plot(x[members], y[members], "o-", ms=4, label=label, color=plt.cm.tab10(j % 10))
    else:
        ordered = front[np.argsort(x[front], kind="stable")]
        ax_f.plot(x[ordered], y[ordered], "o-", color="tab:red", ms=5, label="Pareto front")
    seed = seed_view(ds, study.defaults)
    sx, sy = float(seed[ox]), float(seed[oy])
    if np.isfinite(sx) and np.isfinite(sy):
        ax_f.plot(sx, sy, "*", ms=16, mfc="gold", mec="k", label="seed design")
    sense = dict(o.split(":") for o in objectives)
    ax_f.set_xlabel(f"{ox} [{ds[ox].attrs.get('units', '')}] ({sense[ox]})")
    ax_f.set_ylabel(f"{oy} [{ds[oy].attrs.get('units', '')}] ({sense[oy]})")
    ax_f.legend(fontsize=7, title="front at" if within else None, title_fontsize=7)
    ax_f.grid(alpha=0.3)
    mixed = ds["pareto_rank"].attrs.get("conditions_mixed", "")
    ax_f.set_title(textwrap.fill(
        f"Pareto front over {' and '.join(objectives[:2])}"
        + (f" (of {len(objectives)} objectives)" if len(objectives) > 2 else "")
        + (f", one per {' and '.join(within)} (operating conditions, not choices)" if within else "")
        + (f"; {mixed} sampled: ranked together with the design factors, a front design may owe its "
           "place to a light operating condition" if mixed else ""), 90), fontsize=8)
    # the front's designs
    header, rows = front_rows(ds)
    ax_t.set_axis_off()
    if rows:
        table = ax_t.table(cellText=[[f"{v:.4g}" for v in r] for r in rows],
                           colLabels=[textwrap.fill(h, 16) for h in header], loc="upper center", cellLoc="center")
        table.auto_set_font_size(False)
        table.set_fontsize(7)
        table.scale(1.0, 1.1)
        for j in range(len(header)):  # room for the wrapped column names
            table[0, j].set_height(2 * table[0, j].get_height())
    n = feas.size
    fig.suptitle(f"Design answers, study '{name}': {int(feas.sum())} of {n} designs feasible "
                 f"({100 * feas.mean():.0f} %), {front.size} on the Pareto front"
                 + (f" (table: {len(rows)} spread along it; {name}_pareto.csv)" if rows else ""))
    return fig


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
        ax.bar(x - 0.2, s1, width=0.4, label="first order", color="tab:blue",
               yerr=None if np.isnan(c1).all() else c1, capsize=2)
        ax.bar(x + 0.2, st_, width=0.4, label="total", color="tab:orange",
               yerr=None if np.isnan(ct).all() else ct, capsize=2)
        failed = int(se["failed"].sel(output=out))
        ax.set_title(out + (f" ({failed} failed scenarios left out)" if failed else ""), fontsize=9)
        ax.set_ylim(min(0.0, float(np.nanmin(np.r_[s1, st_, 0.0])) * 1.1),
                    max(1.0, float(np.nanmax(np.r_[s1, st_, 0.0])) * 1.05))
        ax.grid(alpha=0.3, axis="y")
        ax.set_xticks(x, [textwrap.fill(f, 14) for f in factors_], fontsize=7, rotation=30)
    for ax in axes.ravel()[len(outputs):]:
        ax.set_axis_off()
    axes[0, 0].legend(fontsize=8)
    fig.suptitle(f"Sensitivity, study '{name}': share of each output's variance explained by a factor alone "
                 "(first order) and with its interactions (total); failure = 1 where status is not ok")
    fig.text(0.01, 0.01, textwrap.fill("Method: " + se.attrs.get("method", "") + ". Failed scenarios are left "
                                       "out of an output's indices (counted in its title).", 190),
             fontsize=7, color="0.3")
    fig.tight_layout(rect=(0, 0.04, 1, 0.93))
    return fig

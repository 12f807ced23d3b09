"""Report pages and helpers shared by every study: seed selection, title page, validation table."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np

from .. import status as st

A4_LANDSCAPE = (11.69, 8.27)


def with_curves(ds):
    """A sampled result that stores its per-scenario curves for a subset of scenarios (dimension
    ``curve_run``, issue 16 item 5) as the Dataset of that subset on ``run``, curves included;
    any other result unchanged. Pages that draw curves pick their designs from it."""
    if "curve_run" not in ds.dims:
        return ds
    curves = [n for n, v in ds.data_vars.items() if "curve_run" in v.dims]
    position = {int(r): i for i, r in enumerate(ds["run"].values)}
    base = ds.drop_vars(curves + ["curve_run"]).isel(
        run=[position[int(r)] for r in ds["curve_run"].values]
    )
    return base.assign(
        {
            n: (
                tuple("run" if d == "curve_run" else d for d in ds[n].dims),
                ds[n].values,
                ds[n].attrs,
            )
            for n in curves
        }
    )


def seed_view(ds, seed, keep=()):
    """The scenario(s) nearest the ``seed`` design (parameter -> value): factorial dims other
    than ``keep`` selected at the seed value; a sampled design gives the run nearest in normalised
    distance."""
    if "run" in ds.dims:
        dist = np.zeros(ds.sizes["run"])
        options = ds.attrs.get("option_factors", "").split()
        for name in ds.attrs.get("factors", "").split():
            v = ds[name].values
            if (
                name in options
            ):  # an option drawn per scenario: its first listed choice, as the traces
                dist += np.where(v == 0, 0.0, 1e6)
                continue
            dist += ((v - seed[name]) / (np.ptp(v) or 1.0)) ** 2
        return ds.isel(run=int(np.argmin(dist)))
    sel = {d: seed[d] for d in ds.dims if d in seed and d not in keep}
    return ds.sel(sel, method="nearest") if sel else ds


def fixed_text(sub, dims):
    """ "name = value unit" for the scalar coordinates ``dims`` of a selection (angles in deg)."""
    out = []
    for d in dims:
        if d in sub.coords and sub[d].ndim == 0:
            v, u = float(sub[d]), sub[d].attrs.get("units", "")
            v, u = (np.rad2deg(v), "deg") if u == "rad" else (v, "" if u == "1" else u)
            out.append(f"{d} = {v:.4g} {u}".rstrip())
    return ", ".join(out)


def title_page(title, version, results, validations, pages=None, job_seconds=None):
    """The summary page: per study what was run (and how long its jobs took: ``job_seconds``,
    study -> (jobs, seconds)), its status counts, its best compromise design and the pages that
    show it (``pages``: study -> page stems); the validation verdict."""
    from . import status_counts
    from .answers import best_text

    fig = plt.figure(figsize=A4_LANDSCAPE)
    # the title is the user's text: drawn as it is written ("$" is not mathtext), wrapped to the page
    fig.text(
        0.06,
        0.95,
        "\n".join(textwrap.wrap(title, 70)),
        fontsize=20,
        weight="bold",
        va="top",
        parse_math=False,
    )
    fig.text(0.06, 0.855, f"clutchlab {version}", fontsize=11, color="0.3")
    blocks = []
    for name, ds in results.items():
        n = int(np.prod([ds.sizes[d] for d in ds["status"].dims])) if ds["status"].dims else 1
        dims = ", ".join(f"{d} ({ds.sizes[d]})" for d in ds["status"].dims)
        lines = [
            f"Study '{name}': {ds.attrs.get('title', '')}",
            f"  {n} scenarios, design {ds.attrs.get('design')}, dimensions: {dims}",
            f"  model: {ds.attrs.get('model', '')}",
            *(
                [
                    f"  computed by {job_seconds[name][0]} jobs in {job_seconds[name][1]:.1f} s of job time (chunks and "
                    "merge, Snakemake's benchmark files)"
                ]
                if job_seconds and name in job_seconds
                else []
            ),
            "  status: " + ", ".join(f"{k} {v}" for k, v in status_counts(ds).items()),
        ]
        if "pareto_rank" in ds:
            lines.append("  best compromise: " + best_text(ds))
        if pages and pages.get(name):
            lines.append("  pages: " + ", ".join(pages[name]))
        blocks.append(
            [
                w
                for line in lines
                for w in textwrap.wrap(line, 120, subsequent_indent="    ") or [""]
            ]
        )
    # the studies' lines share the page between the title and the footnote (0.80 .. 0.10)
    n_lines = sum(len(b) for b in blocks) + 0.7 * len(blocks) + (2 if validations else 0)
    step = min(0.03, 0.70 / max(n_lines, 1))
    size = min(10.0, 330.0 * step)
    y = 0.80
    for block in blocks:
        for wrapped in block:
            fig.text(0.06, y, wrapped, fontsize=size, family="monospace")
            y -= step
        y -= 0.7 * step
    if validations:
        n = sum(v.sizes["row"] for v in validations)
        ok = sum(int(v["passed"].sum()) for v in validations)
        fig.text(
            0.06,
            y - step,
            f"Validation: {ok} of {n} reproduced seed numbers within tolerance "
            "(table on the last page, validation.csv).",
            fontsize=10,
        )
    fig.text(
        0.06,
        0.04,
        "Units: SI inside every result file (units attribute on each variable); "
        "figures use mm, kN and MPa where marked.",
        fontsize=8,
        color="0.4",
    )
    return fig


def validation_table(validations):
    rows = []
    for v in validations:
        for i in range(v.sizes["row"]):
            rows.append(
                [
                    str(v["seed"].values[i]),
                    textwrap.fill(str(v["quantity"].values[i]), 40),
                    textwrap.fill(str(v["source"].values[i]), 20),
                    f"{float(v['published'].values[i]):.5g}",
                    f"{float(v['computed'].values[i]):.5g}",
                    str(v["units"].values[i]),
                    f"{float(v['rel_error'].values[i]):.2e}",
                    f"{float(v['tolerance'].values[i]):.0e}",
                    "yes" if int(v["passed"].values[i]) else "NO",
                    textwrap.fill(str(v["note"].values[i]), 54),
                ]
            )
    cols = [
        "seed",
        "quantity",
        "source",
        "published",
        "computed",
        "units",
        "rel. error",
        "tol.",
        "pass",
        "note",
    ]
    return table_page(
        "Validation against the seed papers",
        cols,
        rows,
        [0.035, 0.2, 0.09, 0.065, 0.065, 0.06, 0.06, 0.04, 0.035, 0.25],
    )


def hard_case_table(ds):
    """The hard cases (:mod:`clutchlab.hardcases`) as a table page."""
    rows = []
    for i in range(ds.sizes["case"]):
        err = float(ds["error"].values[i])
        rows.append(
            [
                textwrap.fill(str(ds["study"].values[i]), 12),
                textwrap.fill(str(ds["name"].values[i]), 30),
                textwrap.fill(str(ds["right_answer"].values[i]), 34),
                textwrap.fill(str(ds["source"].values[i]), 24),
                textwrap.fill(str(ds["computed"].values[i]), 34),
                "status"
                if np.isnan(err)
                else f"{err:.1e}" + (" rel." if ds["error_kind"].values[i] == "relative" else ""),
                "" if np.isnan(err) else f"{float(ds['tolerance'].values[i]):.0e}",
                "yes" if int(ds["passed"].values[i]) else "NO",
                textwrap.fill(str(ds["off_the_shelf"].values[i]), 38),
            ]
        )
    cols = [
        "study",
        "case",
        "right answer",
        "source",
        "clutchlab (this run)",
        "error",
        "tol.",
        "pass",
        "off-the-shelf solver",
    ]
    n_pass = int(ds["passed"].values.sum())
    return table_page(
        f"Hard cases: {n_pass} of {ds.sizes['case']} pass (computed in this run; hard_cases.csv)",
        cols,
        rows,
        [0.06, 0.14, 0.16, 0.115, 0.16, 0.06, 0.035, 0.03, 0.19],
    )


def table_page(title, cols, rows, widths):
    """A table page that grows with its rows (multi-line cells); a "NO" in the column "pass" is red."""
    n_lines = sum(max(c.count("\n") + 1 for c in r) for r in rows) + 1
    height = max(A4_LANDSCAPE[1], 0.95 + 0.16 * n_lines + 0.09 * len(rows))
    fig = plt.figure(figsize=(A4_LANDSCAPE[0], height))
    ax = fig.add_axes([0.01, 0.02, 0.98, 1.0 - 0.9 / height])
    ax.axis("off")
    fig.text(0.02, 1.0 - 0.45 / height, title, fontsize=14, weight="bold")
    table = ax.table(
        cellText=rows, colLabels=cols, loc="upper center", cellLoc="left", colWidths=widths
    )
    table.auto_set_font_size(False)
    table.set_fontsize(6.5)
    cells = table.get_celld()
    lines = {}
    for (r, c), cell in cells.items():
        lines[r] = max(lines.get(r, 1), cell.get_text().get_text().count("\n") + 1)
    verdict = cols.index("pass")
    for (r, c), cell in cells.items():
        cell.set_height((0.022 * lines[r] + 0.01) * A4_LANDSCAPE[1] / height)
        if r > 0 and c == verdict and cell.get_text().get_text() == "NO":
            cell.set_facecolor("#f4c7c3")
    return fig


def contour_level(ax, x, y, z, level, **kw):
    """The contour of ``z`` at ``level`` where the grid can carry one (at least 2 × 2 points) and the
    level is crossed; None otherwise (a design may hold a single value of a mapped factor)."""
    z = np.asarray(z, float)
    if z.ndim != 2 or min(z.shape) < 2 or not (np.nanmin(z) < level < np.nanmax(z)):
        return None
    return ax.contour(x, y, z, levels=[level], **kw)


# above this many designs a sampled map shows binned shares instead of one marker per design
SCATTER_MAX = 4000


def _edges(v, bins):
    """Bin edges for a map axis: midway between the values of a discrete factor (at most ``bins``
    distinct values, e.g. a count), else ``bins`` equal bins."""
    u = np.unique(v[np.isfinite(v)])
    if 1 < u.size <= bins:
        mid = (u[1:] + u[:-1]) / 2
        return np.r_[u[0] - (mid[0] - u[0]), mid, u[-1] + (u[-1] - mid[-1])]
    return bins


def sampled_category_map(ax, x, y, category, categories, bins=30):
    """Map of a sampled design over two factors: each design a marker coloured by its category
    (index into ``categories``, a tuple of (label, colour); the first is "passes") for up to
    :data:`SCATTER_MAX` designs, else per 2-D bin the share of designs in the first category (an
    image, so the page stays small and fast at 10⁶ designs). Returns the legend handles."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D

    x, y, category = (np.asarray(v).reshape(-1) for v in (x, y, category))
    if x.size <= SCATTER_MAX:
        ax.scatter(
            x,
            y,
            c=category,
            s=14,
            cmap=ListedColormap([c for _, c in categories]),
            norm=BoundaryNorm(np.arange(len(categories) + 1) - 0.5, len(categories)),
            rasterized=True,
        )
        return [
            Line2D([], [], ls="", marker="s", color=c, ms=9, label=lab) for lab, c in categories
        ]
    from scipy.stats import binned_statistic_2d

    share = binned_statistic_2d(
        x, y, (category == 0).astype(float), "mean", bins=[_edges(x, bins), _edges(y, bins)]
    )
    mesh = ax.pcolormesh(
        share.x_edge,
        share.y_edge,
        share.statistic.T,
        cmap="RdYlGn",
        vmin=0,
        vmax=1,
        rasterized=True,
    )
    ax.figure.colorbar(
        mesh, ax=ax, label=f"share of designs: {categories[0][0]} ({x.size} designs binned)"
    )
    return []


def texts_outside(fig) -> list[str]:
    """The texts of a figure (titles, labels, legends, table cells, notes; not tick labels, which
    matplotlib clips to the axes) that reach beyond the page."""
    import math

    from matplotlib.text import Text

    renderer = fig.canvas.get_renderer()
    ticks = set()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            ticks |= {
                id(t)
                for tick in axis.get_major_ticks() + axis.get_minor_ticks()
                for t in (tick.label1, tick.label2)
            }
    width, height = fig.bbox.width, fig.bbox.height
    out = []
    for t in fig.findobj(Text):
        if id(t) in ticks or not t.get_visible() or not t.get_text().strip():
            continue
        bb = t.get_window_extent(renderer)
        if not all(map(math.isfinite, (bb.x0, bb.y0, bb.x1, bb.y1))):
            continue
        if bb.x0 < -1 or bb.y0 < -1 or bb.x1 > width + 1 or bb.y1 > height + 1:
            out.append(t.get_text())
    return out


def status_categories(status, categories: dict, other: int) -> np.ndarray:
    """A category number per scenario from its status ({meaning: number}; ``other`` for the rest)."""
    status = np.asarray(status)
    cat = np.full(status.shape, other)
    for meaning, k in categories.items():
        cat[status == st.CODE[meaning]] = k
    return cat


def robust_limits(z, symmetric=False, cap=None):
    """Colour limits from the 1st and 99th percentiles of the finite values (a few near-singular
    designs, e.g. near a jam, must not set the scale), optionally symmetric about 0 or capped."""
    z = np.asarray(z, dtype=float)
    z = z[np.isfinite(z)]
    if z.size == 0:
        return (-1.0, 1.0) if symmetric else (0.0, 1.0)
    lo, hi = np.percentile(z, [1, 99])
    if symmetric:
        lim = max(abs(lo), abs(hi)) or 1.0
        return -lim, lim
    if cap is not None:
        hi = min(hi, cap)
    return float(lo), float(hi if hi > lo else lo + 1.0)


def sampled_value_map(ax, x, y, z, label, cmap="viridis", limits=None, bins=30):
    """Map of a sampled design's output over two factors: markers coloured by value for up to
    :data:`SCATTER_MAX` designs, else the median per 2-D bin (an image); colours clipped to
    ``limits`` (default :func:`robust_limits`), the colour bar extended where values lie beyond."""
    x, y, z = (np.asarray(v, dtype=float).reshape(-1) for v in (x, y, z))
    vmin, vmax = limits or robust_limits(z)
    finite = np.isfinite(z)
    extend = {
        (False, False): "neither",
        (True, False): "min",
        (False, True): "max",
        (True, True): "both",
    }[(bool((z[finite] < vmin).any()), bool((z[finite] > vmax).any()))]
    if x.size <= SCATTER_MAX:
        m = ax.scatter(
            x[finite],
            y[finite],
            c=z[finite],
            s=10,
            cmap=cmap,
            vmin=vmin,
            vmax=vmax,
            rasterized=True,
        )
    else:
        from scipy.stats import binned_statistic_2d

        med = binned_statistic_2d(
            x[finite],
            y[finite],
            z[finite],
            "median",
            bins=[_edges(x[finite], bins), _edges(y[finite], bins)],
        )
        m = ax.pcolormesh(
            med.x_edge,
            med.y_edge,
            med.statistic.T,
            cmap=cmap,
            vmin=vmin,
            vmax=vmax,
            rasterized=True,
        )
        label += f" (median per bin, {x.size} designs)"
    ax.figure.colorbar(m, ax=ax, label=label, extend=extend)
    return m


# most markers a scatter layer draws; above, an even random subset (the same every run) stands for
# the designs, said on the page, so a page of 10^6 designs draws in about a second
DRAW_MAX = 20_000


def drawn(mask_or_n) -> np.ndarray:
    """Indices of the designs a scatter layer draws: all of them (a boolean mask's True entries,
    or range(n)) up to :data:`DRAW_MAX`, else a fixed random subset of that size, in order."""
    idx = np.flatnonzero(mask_or_n) if np.ndim(mask_or_n) else np.arange(int(mask_or_n))
    if idx.size <= DRAW_MAX:
        return idx
    return np.sort(np.random.default_rng(0).choice(idx, DRAW_MAX, replace=False))


def drawn_note(n: int) -> str:
    """'' or the page's note that a subset of the designs is drawn."""
    return "" if n <= DRAW_MAX else f" ({DRAW_MAX} of {n} designs drawn, chosen at random)"

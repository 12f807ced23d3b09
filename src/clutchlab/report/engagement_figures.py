"""Figures of the engagement study: efficiency-smoothness trade-off and maps."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np

from .. import display
from .. import status as st
from ..explore import flat, unique_rows
from .answers import _marks, _value_text
from .common import (
    A4_LANDSCAPE,
    FRONTS_NAMED,
    colour_extend,
    constraints,
    drawn,
    drawn_note,
    fixed_text,
    front_colour,
    hatch_cells,
    legend_clear_of_data,
    robust_limits,
    sampled_value_map,
    shown,
    shown_name,
    wrap_even,
)

# the source paper's design: where the run shows no design of its own
SEED = {
    "sheet_thickness": 2.334e-3,
    "ramp_time": 0.15,
    "friction_coefficient": 0.4,
    "driven_inertia": 0.021,
    "load_torque": 44.0,
}


def _flat(ds, name):
    return ds[name].values.ravel()


def _status_counts(status, drawn_ok: int) -> str:
    """'N ok scenarios drawn; M lock new but not when worn, K never lock, L other statuses' (the
    parts that are not zero)."""
    worn = int((status == st.CODE["worn_not_locked"]).sum())
    never = int((status == st.CODE["never_locked"]).sum())
    other = status.size - int((status == st.CODE["ok"]).sum()) - worn - never
    parts = [f"{drawn_ok} ok scenarios drawn"]
    for n, what in ((worn, "lock new but not when worn"), (never, "never lock")):
        if n:
            parts.append(f"{n} {what}")
    if other:
        parts.append(f"{other} of other statuses")
    return "; ".join(parts[:1]) + ("; " + ", ".join(parts[1:]) if parts[1:] else "")


def tradeoff(ds):
    ok = (_flat(ds, "status") == st.CODE["ok"]) & np.isfinite(_flat(ds, "peak_jerk"))
    feasible = _flat(ds, "feasible").astype(bool) if "feasible" in ds else ok
    fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
    # the scenarios a constraint fails in grey (coloured, they read as answers), the others
    # coloured by their lock-up time
    failing = np.flatnonzero(ok & ~feasible)
    if failing.size:
        pick = failing[drawn(failing.size)]
        ax.scatter(
            _flat(ds, "slip_work")[pick] / 1e3, _flat(ds, "peak_jerk")[pick], s=10, c="0.75",
            rasterized=True, label="a constraint fails (status ok)",
        )  # fmt: skip
    good = np.flatnonzero(ok & feasible)
    w, j, t = (_flat(ds, n)[good] for n in ("slip_work", "peak_jerk", "lockup_time"))
    show = drawn(w.size)
    sc = ax.scatter(
        w[show] / 1e3,
        j[show],
        c=t[show] * 1e3,
        cmap="viridis",
        s=28 if w.size < 2000 else 6,
        edgecolor="k",
        linewidth=0.3 if w.size < 2000 else 0,
        rasterized=True,
    )
    fig.colorbar(sc, ax=ax, label="lock-up time [ms] (feasible scenarios)")
    rank = ds["pareto_rank"] if "pareto_rank" in ds else None
    if rank is not None and rank.attrs["objectives"] == "slip_work:min peak_jerk:min":
        _fronts(ax, ds, rank.attrs.get("ranked_within", "").split())
    w_all, j_all = _flat(ds, "slip_work") / 1e3, _flat(ds, "peak_jerk")
    for i, label, colour in _marks(ds):
        if np.isfinite(w_all[i]) and np.isfinite(j_all[i]):
            ax.plot(w_all[i], j_all[i], "*", ms=18, mfc=colour, mec="k", label=label)
    ax.set_yscale("log")
    ax.set_xlabel("slip work [kJ]  (efficiency: lower is better)")
    ax.set_ylabel("peak output jerk [rad/s³]  (smoothness: lower is better)")
    title = "Efficiency-smoothness trade-off of the engagement (%s)%s" % (
        _status_counts(_flat(ds, "status"), int(ok.sum())),
        drawn_note(int(ok.sum())),
    )
    model = "model: " + ds.attrs.get("model_used", ds.attrs.get("model", ""))
    ax.set_title("\n".join(wrap_even(title, 110) + wrap_even(model, 110)), fontsize=10)
    ax.grid(alpha=0.3, which="both")
    legend_clear_of_data(fig, ax)
    return fig


def _fronts(ax, ds, within):
    """The stored fronts (feasible designs only), one per operating condition and noise draw
    ranked within: a colour per operating condition (:func:`front_colour`), named
    once with its values in display units and the number of its draws' fronts."""
    front = _flat(ds, "pareto_rank") == 0
    conditions = [w for w in within if w != "noise"]
    key = np.stack([flat(ds, w) for w in within], axis=1) if within else np.zeros((front.size, 0))
    cond = [within.index(c) for c in conditions]
    groups = np.unique(key[front][:, cond], axis=0)
    for k, combo in enumerate(groups):
        draws = np.unique(key[front & (key[:, cond] == combo).all(axis=1)], axis=0)
        where = ", ".join(_value_text(ds, c, v) for c, v in zip(conditions, combo, strict=True))
        label = (
            ("Pareto front" + (f" at {where}" if conditions else " (feasible designs)"))
            + (f" ({len(draws)} noise draws)" if "noise" in within else "")
            if k < FRONTS_NAMED
            else (
                f"... {len(groups) - FRONTS_NAMED} more operating conditions"
                if k == FRONTS_NAMED
                else None
            )
        )
        for d, draw in enumerate(draws):
            members = np.flatnonzero(front & (key == draw).all(axis=1))
            members = members[np.argsort(_flat(ds, "slip_work")[members], kind="stable")]
            ax.plot(
                _flat(ds, "slip_work")[members] / 1e3,
                _flat(ds, "peak_jerk")[members],
                "-",
                lw=1.5 if len(draws) == 1 else 0.8,
                color=front_colour(k) if within else "r",
                label=label if d == 0 else None,
                zorder=2.5 if k < FRONTS_NAMED else 2.2,
            )


def maps(ds):
    """Slip work and lock-up time over (ramp time, clamp force) at the other factors' values of the
    design the run shows (its best design)."""
    fig, axes = plt.subplots(1, 2, figsize=A4_LANDSCAPE, gridspec_kw={"wspace": 0.45})
    if "run" in ds.dims or not {"ramp_time", "sheet_thickness"} <= set(ds.dims):
        for ax, name in zip(axes, ("slip_work", "lockup_time"), strict=False):
            u = display.unit_of(ds, name)
            sampled_value_map(
                ax,
                1e3 * flat(ds, "ramp_time")
                if "ramp_time" in ds.coords
                else np.zeros(ds["status"].size),
                flat(ds, "clamp_load") / 1e3,
                u(flat(ds, name)),
                display.label(name, u),
            )
            ax.set_xlabel("ramp time [ms]")
            ax.set_ylabel("clamp force [kN]")
        fig.suptitle(
            f"Slip work and lock-up time of {ds['status'].size} designs over ramp time and clamp force "
            "(colours clipped to the 1st-99th percentiles)"
        )
        return fig
    at = shown(ds) or SEED  # the other factors at the design the run shows
    others = {d: at[d] for d in ds.dims if d in at and d not in ("ramp_time", "sheet_thickness")}
    sub = ds.sel(others, method="nearest") if others else ds
    extra = [d for d in sub.dims if d not in ("ramp_time", "sheet_thickness")]
    if extra:
        sub = sub.isel({d: 0 for d in extra})
    sub = sub.transpose("sheet_thickness", "ramp_time")
    force = sub["clamp_load"].values[:, 0] / 1e3
    order = np.argsort(force)
    x = sub["ramp_time"].values * 1e3
    # an engagement that never locks has no slip work of an engagement (only its window's)
    bad = ~np.isfinite(sub["lockup_time"].values[order])
    for ax, name, scale, unit in (
        (axes[0], "slip_work", 1e-3, "kJ"),
        (axes[1], "lockup_time", 1e3, "ms"),
    ):
        z = np.where(bad, np.nan, sub[name].values[order] * scale)
        m = ax.pcolormesh(x, force[order], z, shading="nearest", cmap="magma_r")
        fig.colorbar(m, ax=ax, label=f"{name.replace('_', ' ')} [{unit}]")
        if bad.any():
            xx, yy = np.meshgrid(x, force[order])
            ax.plot(xx[bad], yy[bad], "kx", label="never locks")
        limit = next(((op, v) for n, op, v in constraints(ds) if n == name), None)
        if limit is not None:  # the cells over the study's limit hatched
            with np.errstate(invalid="ignore"):
                over = z > limit[1] * scale if limit[0] == "max" else z < limit[1] * scale
            shown_limit = f"{limit[1] * scale:.4g} {unit}"
            hatch_cells(ax, x, force[order], over, f"{name} {limit[0]}: {shown_limit} fails")
        if ax.get_legend_handles_labels()[0]:  # (under the map: on it, it hid a cell)
            ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.1))
        ax.set_xlabel("ramp (engagement) time [ms]")
        ax.set_ylabel("clamp force from the spring design [kN]")
    fig.subplots_adjust(bottom=0.2)
    fixed = fixed_text(sub, list(others))
    fig.suptitle(
        "Slip work and lock-up time over ramp time and clamp force"
        + (f"\n(other factors at the design shown: {fixed})" if fixed else "")
    )
    return fig


def traces(ds):
    """Traces of the design the run shows (paper 000 Figs. 7-11): clamp force, speeds, torque and
    slip work, jerk."""
    fig, axes = plt.subplots(
        2, 2, figsize=A4_LANDSCAPE, gridspec_kw={"hspace": 0.35, "wspace": 0.45, "top": 0.83}
    )  # (wide enough between the columns for panel c's right axis and panel d's label)
    if "trace_time" not in ds.dims:
        axes[0, 0].text(
            0.5,
            0.5,
            textwrap.fill(f"no traces: {shown_name(ds)}", 60),
            ha="center",
            transform=axes[0, 0].transAxes,
        )
        return fig
    t = ds["trace_time"].values * 1e3
    ax = axes[0, 0]
    ax.plot(t, ds["trace_clamp_force"].values / 1e3, "k-")
    ax.set_ylabel("clamp force [kN]")
    ax.set_title("(a) clamp force (cf. Fig. 7)", fontsize=10)
    ax = axes[0, 1]
    for name, style in (("engine_speed", "k-"), ("hub_speed", "b--"), ("output_speed", "r-")):
        ax.plot(t, ds[f"trace_{name}"].values * 30 / np.pi, style, label=name.replace("_", " "))
    ax.set_ylabel("speed [rpm]")
    ax.legend(fontsize=8)
    ax.set_title("(b) speeds (cf. Fig. 8)", fontsize=10)
    ax = axes[1, 0]
    ax.plot(t, ds["trace_friction_torque"].values, "b-", label="clutch torque [N·m]")
    ax2 = ax.twinx()
    ax2.plot(t, ds["trace_slip_work"].values / 1e3, "r-", label="slip work [kJ]")
    ax.set_ylabel("clutch torque [N·m]", color="b")
    ax2.set_ylabel("slip work [kJ]", color="r")
    ax.legend(handles=ax.get_lines()[:1] + ax2.get_lines()[:1], fontsize=8, loc="lower right")
    ax.set_title("(c) clutch torque and slip work (cf. Figs. 9-10)", fontsize=10)
    ax = axes[1, 1]
    ax.plot(t, ds["trace_jerk"].values, "k-")
    ax.set_ylabel("output jerk [rad/s³]")
    ax.set_title("(d) output jerk (cf. Fig. 11)", fontsize=10)
    t_lock = float(ds["trace_lockup_time"]) * 1e3
    for ax in axes.ravel():
        ax.set_xlabel("time [ms]")
        ax.grid(alpha=0.3)
        if np.isfinite(t_lock):
            ax.axvline(t_lock, color="g", ls=":", lw=1)
    fig.suptitle(
        "\n".join(
            textwrap.wrap(f"Traces of {shown_name(ds)}", 125)
            + textwrap.wrap(
                f"lock-up at {t_lock:.1f} ms (green); model: {ds.attrs.get('model_used', '')}", 125
            )
        ),
        fontsize=10,
    )
    return fig


def heat_page(ds):
    """Heat: the friction-face and bulk temperature of the design the run shows over the engagement
    and over engagements in a row; the peak friction-face temperature over the design; the
    trade-off coloured by it."""
    fig, axes = plt.subplots(
        2, 2, figsize=A4_LANDSCAPE, gridspec_kw={"hspace": 0.45, "wspace": 0.5, "top": 0.85}
    )
    if "trace_surface_temperature" in ds:
        _heat_traces(axes[0, 0], axes[0, 1], ds)
    else:
        axes[0, 0].text(
            0.5,
            0.5,
            textwrap.fill(f"no traces: {shown_name(ds)}", 50),
            ha="center",
            transform=axes[0, 0].transAxes,
        )
    temp = _flat(ds, "peak_surface_temperature") - 273.15
    ok = (_flat(ds, "status") == st.CODE["ok"]) & np.isfinite(temp)
    _heat_map(axes[1, 0], ds, temp, ok)
    _heat_tradeoff(fig, axes[1, 1], ds, temp, ok)
    for a in axes.ravel():
        a.grid(alpha=0.3)
    fig.suptitle(
        "\n".join(
            [
                "Heat: friction face and parts (pressure plate, flywheel: cast iron; linings: "
                "organic; assumed materials, clutchlab.heat)"
            ]
            + wrap_even(f"(a), (b): {shown_name(ds)}", 125)
        ),
        fontsize=10,
    )
    return fig


def _heat_traces(ax, ax_seq, ds):
    """(a) the face and bulk temperature of the design shown over its engagement, with the slip
    power; (b) its bulk temperature over engagements in a row."""
    t = ds["trace_time"].values * 1e3
    ax.plot(
        t,
        ds["trace_surface_temperature"].values - 273.15,
        "r-",
        label="friction face (flash, Duhamel)",
    )
    ax.plot(t, ds["trace_bulk_temperature"].values - 273.15, "k--", label="bulk (lumped)")
    ax2 = ax.twinx()
    ax2.plot(t, ds["trace_slip_power"].values / 1e3, "b:", lw=1, label="slip power")
    ax2.set_ylabel("slip power [kW] (dotted)")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("pressure plate temperature [°C]")
    # the legend over a band of headroom above both axes' curves (inside them it hid the curves)
    for a in (ax, ax2):
        lo, hi = a.get_ylim()
        a.set_ylim(lo, hi + 0.3 * (hi - lo))
    lines = ax.get_lines() + ax2.get_lines()
    ax.legend(lines, [line.get_label() for line in lines], fontsize=8, loc="upper center", ncol=2)
    ax.set_title(
        "(a) design shown: peak face %.1f °C"
        % (float(ds["trace_peak_surface_temperature"]) - 273.15),
        fontsize=10,
    )
    n = ds["engagement_number"].values
    ax_seq.plot(n, ds["trace_sequence_temperature"].values - 273.15, "ko-", ms=3)
    ax_seq.set_xlabel("engagement in a row")
    ax_seq.set_ylabel("bulk temperature just after it [°C]")
    ax_seq.set_title(
        "(b) design shown, engagements in a row: "
        + ds["trace_sequence_temperature"]
        .attrs["long_name"]
        .split(" just")[0]
        .replace("bulk temperature of the ", ""),
        fontsize=10,
    )


def _heat_map(ax, ds, temp, ok):
    """(c) the peak face temperature over ramp time and clamp force (a grid: the hottest design
    of each point over the other factors)."""
    x = 1e3 * flat(ds, "ramp_time") if "ramp_time" in ds.coords else np.zeros(ok.size)
    x, y, z = x[ok], flat(ds, "clamp_load")[ok] / 1e3, temp[ok]
    pairs, inverse = unique_rows(np.stack([x, y], axis=1), return_inverse=True)
    note = "all designs"
    if (
        len(pairs) < x.size
    ):  # a grid: designs that differ in other factors share a point; draw the hottest
        hottest = np.full(len(pairs), -np.inf)
        np.maximum.at(hottest, inverse.ravel(), z)
        x, y, z, note = pairs[:, 0], pairs[:, 1], hottest, "the hottest over the other factors"
    # (the colours of (d): the same temperature reads the same on both panels)
    sampled_value_map(
        ax, x, y, z, "peak face temperature [°C]", cmap="inferno", limits=robust_limits(temp[ok])
    )
    ax.set_xlabel("ramp time [ms]")
    ax.set_ylabel("clamp force [kN]")
    ax.set_title(
        f"(c) peak face temperature, one engagement ({note.replace('the hottest', 'max')})",
        fontsize=10,
    )


def _heat_tradeoff(fig, ax, ds, temp, ok):
    """(d) the specific friction work against the peak jerk, coloured by the peak face
    temperature."""
    show = drawn(ok)
    vmin, vmax = robust_limits(temp[ok])  # (as (c)'s)
    m = ax.scatter(
        _flat(ds, "specific_friction_work")[show] / 1e3,
        _flat(ds, "peak_jerk")[show],
        c=temp[show],
        vmin=vmin,
        vmax=vmax,
        cmap="inferno",
        s=12,
        edgecolors="0.2",  # the hottest colours are pale: an edge keeps them visible on white
        linewidths=0.4,
        rasterized=True,
    )
    extend = colour_extend(temp[ok], vmin, vmax)
    fig.colorbar(m, ax=ax, label="peak friction-face temperature [°C]", extend=extend)
    ax.set_yscale("log")
    ax.set_xlabel("specific friction work [kJ/m²]")
    ax.set_ylabel("peak output jerk [rad/s³]")
    ax.set_title(
        "\n".join(
            textwrap.wrap("(d) trade-off coloured by temperature%s" % drawn_note(int(ok.sum())), 55)
        ),
        fontsize=10,
    )


# page stem -> function drawing it from the study's Dataset, in report order
PAGES = {"tradeoff": tradeoff, "maps": maps, "traces": traces, "heat": heat_page}

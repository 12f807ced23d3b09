"""Figures of the roller study: contact stress and engagement time against roller count (paper 003
allowable band), the feasible region over (z, α), the seed design's engagement trace (Fig. 7)."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap

from .. import status as st
from ..explore import flat
from ..published import ROLLER_CLUTCH
from ..studies.roller import DYNAMIC_STRESS_FACTOR, PARAMETERS, RPM
from .answers import _marks
from .common import (
    A4_LANDSCAPE,
    drawn,
    drawn_note,
    fixed_text,
    sampled_category_map,
    seed_view,
    shown,
    shown_name,
    status_categories,
    wrap_even,
)

SEED = {p.name: p.default for p in PARAMETERS}
BAND = (  # MPa, paper 003 section 2.2 (10^6 wedging cycles)
    ROLLER_CLUTCH["contact_allowable_min"].value,
    ROLLER_CLUTCH["contact_allowable_max"].value,
)


def _needs(ds, dims):
    if not set(dims) <= set(ds.dims):
        fig = plt.figure(figsize=A4_LANDSCAPE)
        fig.text(0.5, 0.5, f"needs a factorial design over {', '.join(dims)}", ha="center")
        return fig
    return None


def _stress_time_axes(axes):
    """Contact stress (with the allowable band and the limit above which a dynamic stress is far
    out) and engagement time against the roller count."""
    axes[0].axhspan(
        *BAND, color="r", alpha=0.2, label=f"allowable {BAND[0]:g}-{BAND[1]:g} MPa (10^6 cycles)"
    )
    axes[0].axhline(
        DYNAMIC_STRESS_FACTOR * BAND[0],
        color="r",
        ls="--",
        lw=1,
        label=f"{DYNAMIC_STRESS_FACTOR:g} x allowable: above it dynamic_overstress",
    )
    axes[0].set_yscale("log")
    axes[0].set_ylabel("contact stress [MPa]")
    axes[1].set_ylabel("engagement time [ms]")
    for ax in axes:
        ax.set_xlabel("number of rollers z")
        ax.grid(alpha=0.3, which="both")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)


def overstress_note(ds) -> str:
    """The page note on peak dynamic contact stresses far above the allowable ('' if none): every
    design above DYNAMIC_STRESS_FACTOR × it, whatever its status (a design whose static stress
    fails too has status above_allowable, and the highest dynamic stresses)."""
    code = ds["status"].values.reshape(-1)
    ratio = (ds["peak_contact_stress"] / ds["contact_allowable"]).values.reshape(-1)
    with np.errstate(invalid="ignore"):
        far = ratio > DYNAMIC_STRESS_FACTOR
    if not far.any():
        return ""
    flagged = int((code[far] == st.CODE["dynamic_overstress"]).sum())
    others = sorted({st.FLAGS.get(int(c), str(c)) for c in code[far]} - {"dynamic_overstress"})
    first = (
        f", the other {int(far.sum()) - flagged} fail first as {', '.join(others)}"
        if others
        else ""
    )
    return (
        f"{int(far.sum())} of {code.size} designs: peak dynamic contact stress "
        f"{np.nanmin(ratio[far]):.1f}-{np.nanmax(ratio[far]):.1f} x the allowable (above "
        f"{DYNAMIC_STRESS_FACTOR:g} x; {flagged} with status dynamic_overstress{first}): the "
        "wedging impact, mostly the contact damping term, not the static load, decides these "
        "designs; the value depends on the assumed damping, inertias and penetration depth. They "
        "are not feasible."
    )


def _note(fig, ds):
    note = overstress_note(ds)
    if note:
        fig.text(0.06, 0.015, textwrap.fill(note, 170), fontsize=8, color="tab:red")
        fig.subplots_adjust(bottom=0.16)


def _sampled_stress_engagement(ds):
    """Sampled design: every design's static and peak dynamic contact stress and engagement time
    against its roller count (a small sideways jitter shows the spread), with the median per count."""
    fig, axes = plt.subplots(1, 2, figsize=A4_LANDSCAPE, gridspec_kw={"wspace": 0.3})
    z = ds["rollers"].values
    jitter = (np.random.default_rng(0).random(z.size) - 0.5) * 0.4
    locks = ds["status"].values != st.CODE["not_self_locking"]
    series = (
        (axes[0], "contact_stress", 1e6, "k", "static, eq. 3 at T_c", np.ones(z.size, bool)),
        (axes[0], "peak_contact_stress", 1e6, "tab:blue", "peak dynamic", locks),
        (axes[1], "engagement_time", 1e-3, "tab:green", "engagement time", locks),
    )
    for ax, name, unit, colour, label, keep in series:
        v = ds[name].values / unit
        show = drawn(keep)
        ax.scatter(z[show] + jitter[show], v[show], s=3, color=colour, alpha=0.3, rasterized=True)
        counts = np.unique(z[keep & np.isfinite(v)])
        ax.plot(
            counts,
            [np.median(v[keep & (z == c) & np.isfinite(v)]) for c in counts],
            "o-",
            color=colour,
            label=f"{label} (median per count)",
        )
    _stress_time_axes(axes)
    fig.suptitle(
        f"Roller count: contact stress and engagement time of {z.size} sampled designs "
        "(self-locking ones for the dynamic values)" + drawn_note(z.size),
        fontsize=10,
    )
    _note(fig, ds)
    return fig


def stress_engagement(ds):
    if "run" in ds.dims and "rollers" in ds.attrs.get("factors", "").split():
        return _sampled_stress_engagement(ds)
    fig = _needs(ds, ("rollers",))
    if fig is not None:
        return fig
    keep = ("rollers", "wedge_angle") if "wedge_angle" in ds.dims else ("rollers",)
    sub = seed_view(ds, shown(ds) or SEED, keep=keep)
    z = sub["rollers"].values
    fig, axes = plt.subplots(1, 2, figsize=A4_LANDSCAPE, gridspec_kw={"wspace": 0.3})
    angles = sub["wedge_angle"].values if "wedge_angle" in sub.dims else [None]
    cmap = plt.get_cmap("viridis")
    for i, a in enumerate(angles):
        c = sub.sel(wedge_angle=a) if a is not None else sub
        colour = cmap(i / max(len(angles) - 1, 1))
        label = f"alpha {np.rad2deg(a):.1f} deg" if a is not None else None
        locks = c["status"].values != st.CODE["not_self_locking"]
        if not locks.any():
            continue
        axes[1].plot(
            z[locks], c["engagement_time"].values[locks] * 1e3, "o-", color=colour, label=label
        )
        if i == 0 or a is None:
            axes[0].plot(z, c["contact_stress"].values / 1e6, "ko-", label="static, eq. 3 at T_c")
        axes[0].plot(
            z[locks],
            c["peak_contact_stress"].values[locks] / 1e6,
            "s--",
            color=colour,
            ms=4,
            label=f"peak dynamic, {label}" if label else "peak dynamic",
        )
    _stress_time_axes(axes)
    axes[0].set_title(
        "Static (eq. 3, independent of alpha) and peak dynamic contact stress", fontsize=10
    )
    axes[1].set_title("Engagement time (self-locking wedge angles only)", fontsize=10)
    fixed = fixed_text(sub, [d for d in ds.dims if d not in keep])
    fig.suptitle(
        "Roller count: contact stress and engagement time"
        + (f"; other factors at the design shown: {fixed}" if fixed else ""),
        fontsize=10,
    )
    _note(fig, ds)
    return fig


CATEGORIES = (
    ("ok", "#4daf4a"),
    ("static stress above allowable", "#ffb000"),
    ("not self-locking", "#e41a1c"),
    ("never engaged / not converged", "k"),
    ("overrunning (mode)", "0.7"),
    (f"dynamic stress > {DYNAMIC_STRESS_FACTOR:g} x allowable", "#984ea3"),
)


def _categories(code):
    return status_categories(
        code,
        {
            "ok": 0,
            "above_allowable": 1,
            "not_self_locking": 2,
            "overrunning": 4,
            "dynamic_overstress": 5,
        },
        3,
    )


def feasible_region(ds):
    if "run" in ds.dims and {"rollers", "wedge_angle"} <= set(ds.attrs.get("factors", "").split()):
        fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
        handles = sampled_category_map(
            ax,
            ds["rollers"].values,
            np.rad2deg(ds["wedge_angle"].values),
            _categories(ds["status"].values),
            CATEGORIES,
        )
        _mark(ax, ds)
        ax.set_xlabel("number of rollers z")
        ax.set_ylabel("wedge angle alpha [deg]")
        if handles:
            ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
            fig.subplots_adjust(right=0.72)
        ax.set_title(
            f"Feasible region of {ds['status'].size} sampled designs (all other factors too)",
            fontsize=9,
        )
        return fig
    fig = _needs(ds, ("rollers", "wedge_angle"))
    if fig is not None:
        return fig
    sub = seed_view(
        ds[["status", "contact_stress", "engagement_time", "limit_wedge_angle"]],
        shown(ds) or SEED,
        keep=("rollers", "wedge_angle"),
    ).transpose("wedge_angle", "rollers")
    cat = _categories(sub["status"].values)
    z, a = sub["rollers"].values, np.rad2deg(sub["wedge_angle"].values)
    fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
    ax.pcolormesh(
        z,
        a,
        cat,
        shading="nearest",
        cmap=ListedColormap([c for _, c in CATEGORIES]),
        norm=BoundaryNorm(np.arange(len(CATEGORIES) + 1) - 0.5, len(CATEGORIES)),
        edgecolors="w",
        lw=0.5,
    )
    for j, aa in enumerate(a):
        for i, zz in enumerate(z):
            te = sub["engagement_time"].values[j, i]
            if np.isfinite(te):
                ax.text(zz, aa, f"{te * 1e3:.2f}", ha="center", va="center", fontsize=8)
    lim = np.rad2deg(np.unique(sub["limit_wedge_angle"].values))
    for v in lim:
        ax.axhline(v, color="k", ls="--", lw=1)
    ax.plot(
        [],
        [],
        "k--",
        label=f"self-locking limit 2 atan(mu) = {', '.join(f'{v:.2f}' for v in lim)} deg",
    )
    _mark(ax, ds)
    for label, colour in CATEGORIES:
        ax.plot([], [], "s", color=colour, ms=10, label=label)
    ax.set_xlabel("number of rollers z")
    ax.set_ylabel("wedge angle alpha [deg]")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    fig.subplots_adjust(right=0.72)
    ax.set_title(
        textwrap.fill(
            "Feasible region (numbers: engagement time in ms); other factors at the design shown: "
            + fixed_text(sub, [d for d in ds.dims if d not in ("rollers", "wedge_angle")]),
            110,
        ),
        fontsize=9,
    )
    _note(fig, ds)
    return fig


def _mark(ax, ds):
    """The run's best design (and the source paper's where it is a scenario of the run)."""
    for i, label, colour in _marks(ds, slice_only="run" not in ds.dims):
        ax.plot(
            flat(ds, "rollers")[i],
            np.rad2deg(flat(ds, "wedge_angle")[i]),
            "*",
            ms=20,
            mfc=colour,
            mec="k",
            label=label,
        )


def engagement_trace(ds):
    fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
    if "trace_driven_speed" not in ds:
        ax.text(
            0.5,
            0.5,
            textwrap.fill(f"no trace (the design does not self-lock): {shown_name(ds)}", 80),
            ha="center",
            transform=ax.transAxes,
        )
        return fig
    t = ds["trace_time"].values * 1e3
    for name, style in (("driving", "k-"), ("wedge", "b--"), ("driven", "r-")):
        ax.plot(t, ds[f"trace_{name}_speed"].values / RPM, style, label=f"{name} ring")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("speed [rpm]")
    ax2 = ax.twinx()
    ax2.plot(
        t,
        ds["trace_contact_force"].values / 1e3,
        color="0.6",
        lw=0.8,
        label="contact force per roller",
    )
    ax2.set_ylabel("contact force [kN]")
    marks = (
        ("trace_stick_time", "B: wedge ring synchronous", "b"),
        ("trace_engagement_time", "C: engaged", "r"),
    )
    for name, label, colour in marks:
        v = float(ds[name])
        if np.isfinite(v):
            ax.axvline(v * 1e3, color=colour, ls=":", label=f"{label} {v * 1e3:.3f} ms")
    stop, rel = float(ds["trace_control_stop_time"]), float(ds["trace_release_time"])
    if np.isfinite(rel):
        ax.axvspan(
            stop * 1e3,
            (stop + rel) * 1e3,
            color="g",
            alpha=0.2,
            label=f"release: control ring stopped at {stop * 1e3:.2f} ms, free after {rel * 1e3:.3f} ms",
        )
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, loc="center right", fontsize=8)
    ax.grid(alpha=0.3)
    ax.set_title(
        "\n".join(
            wrap_even(f"Engagement from rest of {shown_name(ds)}", 125)
            + textwrap.wrap(
                "passive load: the driven ring is held at rest until the wedge's torque reaches "
                "it (cf. the source paper's Figs. 7 and 9); inertias and penetration depth assumed",
                125,
            )
        ),
        fontsize=10,
    )
    return fig


# page stem -> function drawing it from the study's Dataset, in report order
PAGES = {
    "stress_engagement": stress_engagement,
    "feasible_region": feasible_region,
    "engagement_trace": engagement_trace,
}

"""Figures of the centrifugal study: capacity curves (paper 001 Fig. 5), release/reserve map over
(α, f), start-up and engine-failure traces (Figs. 6-8)."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np

from .. import status as st
from ..explore import flat
from ..published import CENTRIFUGAL_CLUTCH
from ..studies.centrifugal import PARAMETERS, RPM
from .answers import _marks
from .common import (
    A4_LANDSCAPE,
    constraint_limit,
    contour_level,
    fixed_text,
    robust_limits,
    sampled_value_map,
    shown,
    shown_name,
    with_curves,
    wrap_even,
)
from .common import seed_view as _seed_view

SEED = {p.name: p.default for p in PARAMETERS}


def seed_view(ds, keep=()):
    """The grid (or sampled run) at the design the run shows (its best design; the source paper's
    where the run shows none), dims in ``keep`` kept."""
    return _seed_view(ds, shown(ds) or SEED, keep)


def capacity_curves(ds):
    target = shown(ds) or SEED  # the shown design's factors, from the whole run
    subset = "curve_run" in ds.dims
    ds = with_curves(ds)  # a large sampled design stores the curves of a subset
    sub = _seed_view(ds, target)
    rpm = ds["speed"].values / RPM
    fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
    ax.plot(
        rpm, sub["capacity_forward_curve"].values, "b-", lw=2, label="forward capacity M(n) (eq. 1)"
    )
    ax.plot(
        rpm,
        sub["capacity_reverse_curve"].values,
        "r-",
        lw=2,
        label="reverse capacity M'(n) (eq. 2)",
    )
    ax.plot(
        rpm, sub["engine_torque_curve"].values, "k-", label="engine torque (shape illustrative)"
    )
    ax.plot(
        rpm, sub["passive_torque_curve"].values, "k--", label="passive (back-driven) engine torque"
    )
    if "pressure_angle" in ds.dims and "run" not in ds.dims:
        other = seed_view(ds, keep=("pressure_angle",))
        for a in other["pressure_angle"].values:
            c = other.sel(pressure_angle=a)
            if int(c["status"]) == st.CODE["ok"] and not np.isclose(
                a, float(sub["pressure_angle"])
            ):
                ax.plot(rpm, c["capacity_reverse_curve"].values, "r-", lw=0.6, alpha=0.5)
        ax.plot(
            [], [], "r-", lw=0.6, alpha=0.5, label="M'(n) at the other pressure angles of the grid"
        )
    idle = (
        CENTRIFUGAL_CLUTCH["idle_speed_min"].value,
        CENTRIFUGAL_CLUTCH["idle_speed_max"].value,
    )
    ax.axvspan(*idle, color="0.85", label="idle %g-%g rpm (must be disengaged)" % idle)
    w0 = float(sub["engagement_speed"]) / RPM
    ax.axvline(w0, color="g", ls=":", label=f"engagement speed {w0:.0f} rpm")
    rated = float(sub["rated_speed"]) / RPM if "rated_speed" in sub else 5500.0
    ax.axvline(rated, color="0.4", ls="-.", lw=0.8, label=f"rated {rated:.0f} rpm")
    top = np.nanmax(sub["capacity_forward_curve"].values[rpm <= 1.1 * rated])
    ax.set_ylim(0, 1.15 * top if np.isfinite(top) and top > 0 else 1.0)
    ax.set_xlabel("engine speed [rpm]")
    ax.set_ylabel("torque [N·m]")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=9)
    ax.set_title(
        "\n".join(
            wrap_even(f"Capacity curves of {shown_name(ds)}", 130)
            + (
                [
                    f"curves stored for 1 in {int(ds.attrs.get('curve_stride', 0)) or 'N'} designs: "
                    "those of the stored design nearest it"
                ]
                if subset
                else []
            )
            + [
                f"M = {float(sub['capacity_forward']):.1f} N·m, M' = "
                f"{float(sub['capacity_reverse']):.1f} N·m, reserve "
                f"{float(sub['reserve_factor']):.2f} at rated speed"
            ]
        ),
        fontsize=10,
    )
    return fig


def release_map(ds):
    """Release margin and forward reserve over (α, f): a map of the grid at the design shown, or
    of every design of a sampled run."""
    fig, axes = plt.subplots(1, 2, figsize=A4_LANDSCAPE, gridspec_kw={"wspace": 0.35})
    keep = ("pressure_angle", "friction_coefficient")
    if "run" in ds.dims or not set(keep) <= set(ds.dims):
        return _sampled_release_map(fig, axes, ds)
    sub = seed_view(ds, keep=keep).transpose("friction_coefficient", "pressure_angle", ...)
    for ax, name, cmap, label in (
        (
            axes[0],
            "release_margin",
            "RdBu",
            "release margin T_p / M' - 1 at rated [-]\n"
            "(> 0: the clutch lets go when the engine dies)",
        ),
        (
            axes[1],
            "reserve_factor",
            "viridis",
            "reserve factor M / T_e at rated [-] (colour capped at 4)",
        ),
    ):
        _release_panel(fig, ax, ds, sub, name, cmap, label)
    fixed = fixed_text(sub, [d for d in ds.dims if d not in keep])
    fig.suptitle(
        "Release margin and forward reserve over (alpha, f)"
        + (f"\n(other factors at the design shown: {fixed})" if fixed else "")
    )
    return fig


def _sampled_release_map(fig, axes, ds):
    """Release margin and reserve of every design of a sampled run (or a grid without both α and
    f), jammed designs left out."""
    code = ds["status"].values.reshape(-1)
    ok = code != st.CODE["jammed"]
    # colour limits from the designs without a near-singular capacity (near_jam: M ∝ 1/(1 - f tan(alpha)))
    scale = code == st.CODE["ok"]
    for ax, name in zip(axes, ("release_margin", "reserve_factor"), strict=False):
        x = (
            np.rad2deg(ds["pressure_angle"].values.ravel())
            if "pressure_angle" in ds.coords
            else np.zeros(ok.size)
        )
        y = (
            ds["friction_coefficient"].values.ravel()
            if "friction_coefficient" in ds.coords
            else np.zeros(ok.size)
        )
        z = np.broadcast_to(ds[name].values, ds["status"].shape).reshape(-1)
        limits = robust_limits(
            z[scale] if scale.any() else z[ok], symmetric=name == "release_margin", cap=4.0
        )
        sampled_value_map(
            ax,
            x[ok],
            y[ok],
            z[ok],
            f"{name} [{ds[name].attrs['units']}]",
            cmap="RdBu" if name == "release_margin" else "viridis",
            limits=limits,
        )
        ax.set_xlabel("pressure angle [deg]")
        ax.set_ylabel("friction coefficient f")
    near = int((code == st.CODE["near_jam"]).sum())
    fig.suptitle(
        f"Release margin and forward reserve of {ok.size} designs ({int((~ok).sum())} jammed left "
        f"out, {near} near_jam drawn but not scaling the colours;\ncolours clipped to the 1st-99th "
        "percentiles of the ok designs, reserve at 4)"
    )
    return fig


def _friction_deviation(sub) -> float:
    """The relative friction deviation of the noise draw a selection shows (0 without one)."""
    v = sub.get("friction_coefficient_noise")
    if v is None or v.ndim or not v.attrs.get("relative"):
        return 0.0
    return float(v)


def _release_panel(fig, ax, ds, sub, name, cmap, label):
    """One output over the (α, f) grid ``sub``: its colour map and contour, the jam region, the
    near-jam line and the marked designs."""
    a = np.rad2deg(sub["pressure_angle"].values)
    f = sub["friction_coefficient"].values
    z = np.where(sub["status"].values == st.CODE["jammed"], np.nan, sub[name].values)
    if name == "release_margin":  # (inf where M' = 0: not scaling the colours)
        lim = np.nanmax(np.abs(z[np.isfinite(z)])) if np.isfinite(z).any() else 1.0
        m = ax.pcolormesh(a, f, z, shading="nearest", cmap=cmap, vmin=-lim, vmax=lim)
        if contour_level(ax, a, f, z, 0.0, colors="k", linewidths=1.5) is not None:
            ax.plot([], [], "k-", lw=1.5, label="release margin 0")
    else:
        m = ax.pcolormesh(
            a, f, z, shading="nearest", cmap=cmap, vmin=0.0, vmax=min(np.nanmax(z), 4.0)
        )
        level = constraint_limit(ds, "reserve_factor")
        if (
            level is not None
            and contour_level(ax, a, f, z, level, colors="w", linewidths=1.2, linestyles="--")
            is not None
        ):
            ax.plot([], [], "w--", label=f"reserve {level:g} (the constraint)")
    fig.colorbar(m, ax=ax, label=label)
    # jam region: (1 + r)·f·tan(alpha) >= 1 at the noise draw shown (r its friction deviation; f
    # the design's nominal value on this axis), drawn exactly as f = 1/((1 + r)·tan(alpha))
    r = _friction_deviation(sub)
    aa = np.linspace(a.min(), a.max(), 200)
    fj = 1.0 / ((1.0 + r) * np.tan(np.deg2rad(aa)))
    ax.fill_between(
        aa,
        fj,
        f.max() + 0.5 * (f.max() - f.min()),
        where=fj <= f.max(),
        hatch="xx",
        facecolor="none",
        edgecolor="k",
        lw=0.5,
        label="jammed: f tan(alpha) >= 1" + (f" (f {100 * r:+.3g} %: this draw)" if r else ""),
    )
    fs = sub.get("friction_scatter")
    scatter = float(fs) if fs is not None and fs.ndim == 0 else 0.0
    if scatter > 0:
        ax.plot(
            aa,
            fj / (1.0 + scatter),
            "k--",
            lw=1.0,
            label=f"near_jam above: (1 + {scatter:g})·f·tan(alpha) >= 1",
        )
    for i, mark, colour in _marks(ds, slice_only=True):
        ax.plot(
            np.rad2deg(flat(ds, "pressure_angle")[i]),
            flat(ds, "friction_coefficient")[i],
            "*",
            ms=16,
            mfc=colour,
            mec="k",
            label=mark,
        )
    # the grid's cells whole, the first and last row too
    half = 0.5 * np.diff(f)[[0, -1]] if f.size > 1 else np.array([0.05, 0.05])
    ax.set_ylim(f.min() - half[0], f.max() + half[1])
    ax.set_xlabel("linkage pressure angle alpha [deg]")
    ax.set_ylabel("friction coefficient f")
    ax.legend(loc="lower left", fontsize=8)


def traces(ds):
    fig, axes = plt.subplots(1, 2, figsize=A4_LANDSCAPE, gridspec_kw={"wspace": 0.3})
    if "failure_engine_speed" not in ds:
        for ax in axes:
            ax.text(
                0.5,
                0.5,
                textwrap.fill(f"no traces: {shown_name(ds)}", 50),
                ha="center",
                transform=ax.transAxes,
            )
        return fig
    for ax, prefix, dim, title in (
        (axes[0], "startup", "startup_time_axis", "Start-up (cf. Fig. 6)"),
        (axes[1], "failure", "failure_time", "Engine failure at rated speed (cf. Fig. 8)"),
    ):
        t = ds[dim].values
        ax.plot(t, ds[f"{prefix}_engine_speed"].values / RPM, "k-", label="engine (shoe carrier)")
        ax.plot(t, ds[f"{prefix}_rotor_speed"].values / RPM, "b--", label="rotor side (drum)")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("speed [rpm]")
        ax.set_title(title)
        ax.grid(alpha=0.3)
    t_lock = float(ds["startup_lockup_time"])
    if np.isfinite(t_lock):
        axes[0].axvline(t_lock, color="g", ls=":", label=f"lock-up {t_lock:.2f} s")
    t_rel = float(ds["failure_release_time"])
    axes[1].axvline(
        t_rel, color="r", ls=":", label=f"release {t_rel * 1e3:.1f} ms after the failure"
    )
    for ax in axes:
        ax.legend(fontsize=9)
    fig.suptitle(
        "\n".join(
            wrap_even(f"Traces of {shown_name(ds)}", 120)
            + ["DOP853, lock-up and release located as events; inertias and loads assumed"]
        ),
        fontsize=11,
    )
    return fig


# page stem -> function drawing it from the study's Dataset, in report order
PAGES = {"capacity_curves": capacity_curves, "release_map": release_map, "traces": traces}

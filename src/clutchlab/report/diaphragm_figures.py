"""Figures of the diaphragm_spring study: F(λ) family with A/B/C/D, reserve-factor map."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import TwoSlopeNorm

from .. import status as st
from .. import studies
from ..explore import flat
from .common import (
    A4_LANDSCAPE,
    SCATTER_MAX,
    constraint_limit,
    contour_level,
    fixed_text,
    label_contour,
    sampled_value_map,
    seed_view,
    shown,
    with_curves,
)

MARKERS = {
    "A": ("^", "peak A"),
    "C": ("o", "flat C"),
    "D": ("v", "valley D"),
    "B": ("s", "operating B"),
}


def _seed(**targets) -> dict:
    """The seed design (the study's defaults, lambda_B/lambda_C = 0.9) with ``targets``."""
    return {**studies.get("diaphragm_spring").defaults, "operating_point_factor": 0.9, **targets}


def _others(ds, keep) -> list[str]:
    """Factor dimensions a page does not draw (selected at the seed design's value)."""
    return [d for d in ds.dims if d in _seed() and d not in keep]


def load_curves(ds):
    """F(λ) for every cone-height ratio at the best design's thickness, radius ratio and operating
    point (the middle of the grid where the run shows no design)."""
    fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
    ds = with_curves(ds)  # a large sampled design stores the curves of a subset
    if "run" in ds.dims:  # sampled design: a spread of designs ordered by H/h
        order = np.argsort(
            ds["cone_height_ratio"].values if "cone_height_ratio" in ds.coords else ds["run"].values
        )
        picks = order[np.linspace(0, len(order) - 1, min(9, len(order))).astype(int)]
        sub = ds.isel(run=picks)
        members = [sub.isel(run=i) for i in range(sub.sizes["run"])]
        fixed = "sampled design: 9 scenarios spread over H/h"
    else:
        at = shown(ds) or {}  # the best design's thickness and radius ratio (else the middle)
        mid = {
            d: at.get(d, float(ds[d].values[len(ds[d]) // 2]))
            for d in ("sheet_thickness", "radius_ratio", "operating_point_factor")
            if d in ds.dims
        }
        sub = seed_view(ds, _seed(**mid), keep=("cone_height_ratio",))
        if "cone_height_ratio" in sub.dims:
            members = [sub.isel(cone_height_ratio=i) for i in range(sub.sizes["cone_height_ratio"])]
        else:
            members = [sub]
        others = [
            d
            for d in _others(ds, ("cone_height_ratio",))
            if d not in ("sheet_thickness", "radius_ratio", "operating_point_factor")
        ]
        fixed = ", ".join(
            [
                f"h = {float(sub['sheet_thickness']) * 1e3:.3g} mm",
                f"R/r = {float(sub['radius_ratio']):.3g}",
                f"lambda_B/lambda_C = {float(sub['operating_point_factor']):.2g}",
            ]
            + (
                [f"wear allowance = {float(sub['wear_allowance']) * 1e3:.3g} mm"]
                if "wear_allowance" in sub and sub["wear_allowance"].ndim == 0
                else []
            )
            + ([fixed_text(sub, others)] if others else [])
        )
    cmap = plt.get_cmap("viridis")
    for i, m in enumerate(members):
        color = cmap(i / max(1, len(members) - 1))
        ratio = float(m["cone_height_ratio"])
        ax.plot(
            m["curve_deflection"] * 1e3,
            m["curve_load"] / 1e3,
            color=color,
            lw=1.4,
            label=f"H/h = {ratio:.2f}"
            + ("" if int(m["status"]) == 0 else f" ({st.FLAGS[int(m['status'])]})"),
        )
        _wear_travel(ax, m, color)
        for p, (marker, _) in MARKERS.items():
            key = {"A": "peak", "C": "flat", "D": "valley", "B": "operating"}[p]
            x, y = (
                float(m[f"deflection_{key}"]),
                float(m[{"B": "clamp_load"}.get(p, f"load_{key}")]),
            )
            if np.isfinite(x) and np.isfinite(y):
                ax.plot(x * 1e3, y / 1e3, marker, color=color, ms=6, mec="k", mew=0.6)
    for marker, name in MARKERS.values():
        ax.plot([], [], marker, color="w", mec="k", label=name)
    if "deflection_worn" in ds:
        ax.plot([], [], color="0.3", lw=4, alpha=0.35, label="wear travel B -> worn")
        ax.plot([], [], "P", color="w", mec="k", label="fully worn")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.set_xlabel("deflection at the pressure-plate load point lambda [mm]")
    ax.set_ylabel("spring load F [kN]")
    ax.set_title(
        "Diaphragm spring load-deflection curves, Almen-Laszlo eq. (10) of paper 000 (shaded: the "
        "wear travel)\n" + fixed
    )
    ax.legend(ncol=2, fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)
    return fig


def _wear_travel(ax, m, color):
    """The operating point's path as the lining wears (from B at λ_B to λ_B − Δ on the member's
    curve; its stored samples in between) and the fully worn point, where the result has them."""
    if "deflection_worn" not in m:
        return
    lam_b, lam_w = float(m["deflection_operating"]), float(m["deflection_worn"])
    load_b, load_w = float(m["clamp_load"]), float(m["clamp_load_worn"])
    if not all(np.isfinite(v) for v in (lam_b, lam_w, load_b, load_w)):
        return
    lam_w = max(lam_w, 0.0)  # (an unloaded spring: at λ = 0, no load)
    x, y = np.asarray(m["curve_deflection"]), np.asarray(m["curve_load"])
    inside = (x > lam_w) & (x < lam_b)
    xs = np.concatenate([[lam_w], x[inside], [lam_b]])
    ys = np.concatenate([[load_w], y[inside], [load_b]])
    ax.plot(xs * 1e3, ys / 1e3, color=color, lw=6, alpha=0.35, solid_capstyle="butt")
    ax.plot(lam_w * 1e3, load_w / 1e3, "P", color=color, ms=8, mec="k", mew=0.6)


def reserve_map(ds):
    """Reserve factor over (h, H/h), one panel per radius ratio, at λ_B = 0.9·λ_C."""
    if "run" in ds.dims:
        ok = (ds["status"] == st.CODE["ok"]).values
        fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
        h, ratio = flat(ds, "sheet_thickness") * 1e3, flat(ds, "cone_height_ratio")
        sampled_value_map(
            ax,
            h[ok],
            ratio[ok],
            flat(ds, "reserve_factor")[ok],
            "reserve factor [-]",
            cmap="RdYlGn",
        )
        if (~ok).any() and ok.size <= SCATTER_MAX:
            ax.scatter(
                h[~ok], ratio[~ok], marker="x", c="k", s=8, label="status not ok", rasterized=True
            )
            ax.legend()
        ax.set_xlabel("sheet thickness h [mm]")
        ax.set_ylabel("cone height ratio H/h")
        ax.set_title(
            f"Reserve factor (torque capacity / engine maximum torque) of {ok.size} designs "
            f"({int((~ok).sum())} with status not ok{' left out' if ok.size > SCATTER_MAX else ''})"
        )
        return fig
    keep = ("cone_height_ratio", "sheet_thickness", "radius_ratio")
    at = shown(ds) or {}  # the other factors at the design the run shows (else the seed's)
    sub = seed_view(ds, _seed(**{d: at[d] for d in ds.dims if d in at and d not in keep}), keep)
    others = [d for d in _others(ds, keep) if d != "operating_point_factor"]
    panels = sub["radius_ratio"].values if "radius_ratio" in sub.dims else [None]
    fig, axes = plt.subplots(1, len(panels), figsize=A4_LANDSCAPE, sharey=True, squeeze=False)
    rf_all = sub["reserve_factor"].values
    vmax = float(np.nanmax(rf_all)) if np.isfinite(rf_all).any() else 2.0
    norm = TwoSlopeNorm(vmin=0.0, vcenter=1.0, vmax=max(vmax, 1.5))
    op_factor = float(sub["operating_point_factor"])
    limit = constraint_limit(ds, "reserve_factor")
    fixed = {
        d: [float(sub[d])] for d in ("cone_height_ratio", "sheet_thickness") if d not in sub.dims
    }
    if fixed:  # a fixed value: a map one cell wide
        sub = sub.drop_vars(list(fixed)).expand_dims(fixed)
    for ax, rr in zip(axes[0], panels, strict=False):
        p = (sub.sel(radius_ratio=rr) if rr is not None else sub).transpose(
            "cone_height_ratio", "sheet_thickness", ...
        )
        rf = p["reserve_factor"].values
        x = p["sheet_thickness"].values * 1e3
        y = p["cone_height_ratio"].values
        mesh = ax.pcolormesh(x, y, rf, cmap="RdYlGn", norm=norm, shading="nearest")
        cs = contour_level(ax, x, y, rf, 1.0, colors="k", linewidths=1.2)
        if cs is not None:
            label_contour(ax, cs, "1.0", 0.35)
        if limit is not None and limit != 1.0:
            cs = contour_level(ax, x, y, rf, limit, colors="k", linewidths=1.0, linestyles="--")
            if cs is not None:
                label_contour(ax, cs, f"{limit:g}", 0.65)
        code = p["status"].values
        xx, yy = np.meshgrid(x, y)
        for c, mk in (
            (st.CODE["monotone_no_hump"], "."),
            (st.CODE["snap_through"], "x"),
            (st.CODE["invalid_geometry"], "*"),
        ):
            sel = code == c
            if sel.any():
                ax.plot(xx[sel], yy[sel], mk, color="0.2", ms=4, label=st.FLAGS[c])
        ax.axhline(np.sqrt(2), color="0.4", ls="--", lw=0.8)
        ax.set_title(f"R/r = {rr:.3g}" if rr is not None else "")
    fig.supxlabel("sheet thickness h [mm]")
    axes[0][0].set_ylabel("cone height ratio H/h  (dashed: sqrt 2)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    if handles:  # below the panels: a panel is too narrow for the status names
        fig.legend(handles, labels, fontsize=8, loc="lower left", ncol=len(handles))
    fig.colorbar(
        mesh,
        ax=axes[0].tolist(),
        label="reserve factor = capacity / T_emax [-]  (black line: 1.0"
        + (f"; dashed: {limit:g}, the constraint)" if limit not in (None, 1.0) else ")"),
    )
    fig.suptitle(
        textwrap.fill(
            "Torque reserve factor at lambda_B = %.2g lambda_C%s; markers: status (no hump = no "
            "wear compensation, snap-through, invalid)"
            % (op_factor, " (the design shown)" if at else ""),
            110,
        )
        + (f"\n{fixed_text(sub, others)}" if others else "")
    )
    return fig


# page stem -> function drawing it from the study's Dataset, in report order
PAGES = {"load_curves": load_curves, "reserve_map": reserve_map}

"""Figures of the sprag study: stresses and gripping angle against torque with the allowables
(paper 002 Table 2), the map of geometries that pass every allowable, impact-torque curves (Fig. 4)."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap

from ..explore import flat
from ..published import SPRAG_TABLE2
from ..studies.sprag import CHECKS, PARAMETERS
from .answers import _marks
from .common import (
    A4_LANDSCAPE,
    drawn,
    drawn_note,
    fixed_text,
    sampled_category_map,
    seed_view,
    shown,
    status_categories,
    value_at_shown,
)

SEED = {p.name: p.default for p in PARAMETERS}
MPA = 1e6
STRESSES = (
    ("contact_stress_inner", "contact inner", "C0"),
    ("contact_stress_outer", "contact outer", "C1"),
    ("vm_stress_inner", "shaft inner (von Mises)", "C2"),
    ("vm_stress_outer", "outer race (von Mises)", "C3"),
)


def _table2(field):
    """Torques [N m] and the published values of ``field`` (a stress [MPa] or V [deg]) of paper
    002's Table 2, theory column (:data:`clutchlab.published.SPRAG_TABLE2`)."""
    return list(SPRAG_TABLE2), [getattr(row, field) for row in SPRAG_TABLE2.values()]


def _allowable(sub, name):
    return float(np.atleast_1d(sub[name].values)[0]) if name in sub else SEED[name]


def stress_vs_torque(ds):
    fig, axes = plt.subplots(1, 2, figsize=A4_LANDSCAPE, gridspec_kw={"wspace": 0.28})
    if "run" in ds.dims and "torque" in ds.attrs.get("factors", "").split():
        return _sampled_stress_vs_torque(fig, axes, ds)
    if "torque" not in ds.dims:
        for ax in axes:
            ax.text(
                0.5,
                0.5,
                "torque is not a dimension of this design",
                ha="center",
                transform=ax.transAxes,
            )
        return fig
    sub = seed_view(ds, shown(ds) or SEED, keep=("torque",))
    paper = _at_paper(sub)  # Table 2's numbers belong to the paper's geometry only
    t = sub["torque"].values
    ax = axes[0]
    for name, label, colour in STRESSES:
        ax.plot(t, sub[name].values / MPA, "-", color=colour, label=label)
        if paper:
            ax.plot(*_table2(name), "o", mfc="none", color=colour)
    ax.axhline(
        _allowable(sub, "contact_allowable") / MPA,
        color="k",
        ls="--",
        lw=1,
        label="contact allowable",
    )
    ax.axhline(
        _allowable(sub, "shaft_allowable") / MPA, color="k", ls=":", lw=1, label="shaft allowable"
    )
    if paper:
        ax.plot([], [], "ko", mfc="none", label="the source paper's Table 2 (theory)")
    ax.set_xlabel("torque [N·m]")
    ax.set_ylabel("stress [MPa]")
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.plot(t, np.rad2deg(sub["gripping_angle"].values), "b-", label="V (inner contact)")
    ax.plot(t, np.rad2deg(sub["gripping_angle_outer"].values), "b--", label="W (outer contact)")
    if paper:
        ax.plot(
            *_table2("gripping_angle"),
            "bo",
            mfc="none",
            label="the source paper's Table 2 V (theory)",
        )
    ax.axhline(
        np.rad2deg(_allowable(sub, "gripping_angle_allowable")),
        color="r",
        ls="--",
        lw=1,
        label="allowable V (pop-out beyond)",
    )
    ax.set_xlabel("torque [N·m]")
    ax.set_ylabel("gripping angle [deg]")
    ax.legend(fontsize=8)
    for a in axes:
        a.grid(alpha=0.3)
    c = np.unique(sub["compliance_factor_used"].values)
    fig.suptitle(
        "\n".join(
            textwrap.wrap(
                "Stresses and gripping angle against torque: "
                + ("the source paper's geometry" if paper else "the geometry of the design shown")
                + f" ({fixed_text(sub, [d for d in ds.dims if d != 'torque']) or 'fixed'})",
                130,
            )
            + [f"deflection compliance factor {', '.join(f'{x:.4g}' for x in c)} (1 = physical)"]
        ),
        fontsize=11,
    )
    return fig


def _at_paper(sub) -> bool:
    """Whether a torque sweep is at the source paper's geometry (Table 2 applies there only)."""
    for name, v in SEED.items():
        if name in sub.coords or name in sub.data_vars:
            x = sub[name]
            if x.ndim == 0 and not np.isclose(float(x), v, rtol=1e-6, atol=0.0):
                return False
    return True


def _sampled_stress_vs_torque(fig, axes, ds):
    """Sampled design: every design's stresses and gripping angle against its torque (all other
    factors varying too), the allowables and the paper 002 Table 2 values."""
    t = ds["torque"].values
    show = drawn(t.size)
    ax = axes[0]
    for name, label, colour in STRESSES:
        ax.scatter(
            t[show], ds[name].values[show] / MPA, s=2, alpha=0.3, color=colour, rasterized=True
        )
        ax.plot(*_table2(name), "o", mfc="none", color=colour, label=label)
    ax.axhline(
        _allowable(ds, "contact_allowable") / MPA,
        color="k",
        ls="--",
        lw=1,
        label="contact allowable",
    )
    ax.axhline(
        _allowable(ds, "shaft_allowable") / MPA, color="k", ls=":", lw=1, label="shaft allowable"
    )
    ax.set_ylabel("stress [MPa]")
    ax.legend(fontsize=8, title="dots: designs; circles: paper 002 Table 2", title_fontsize=8)
    ax = axes[1]
    ax.scatter(
        t[show],
        np.rad2deg(ds["gripping_angle"].values[show]),
        s=2,
        alpha=0.3,
        color="b",
        rasterized=True,
    )
    ax.plot(*_table2("gripping_angle"), "bo", mfc="none", label="paper 002 Table 2 V (theory)")
    ax.axhline(
        np.rad2deg(_allowable(ds, "gripping_angle_allowable")),
        color="r",
        ls="--",
        lw=1,
        label="allowable V (pop-out beyond)",
    )
    ax.set_ylabel("gripping angle V [deg]")
    ax.legend(fontsize=8)
    for a in axes:
        a.set_xlabel("torque [N·m]")
        a.grid(alpha=0.3)
    others = [f for f in ds.attrs.get("factors", "").split() if f != "torque"]
    fig.suptitle(
        f"Stresses and gripping angle of {t.size} sampled designs against torque"
        + (f" ({', '.join(others)} varying too)" if others else "")
        + drawn_note(t.size)
    )
    return fig


CATEGORIES = (
    ("passes every allowable", "#4daf4a"),
    ("stress above allowable", "#ffb000"),
    ("pop-out risk (V above allowable)", "#e41a1c"),
    ("roll-over", "#984ea3"),
    ("sprag does not span the races", "0.6"),
    ("not converged", "k"),
)


def _category(status):
    return status_categories(
        status,
        {"ok": 0, "above_allowable": 1, "pop_out_risk": 2, "roll_over": 3, "invalid_geometry": 4},
        5,
    )


def pass_map(ds):
    pairs = [
        p
        for p in (("sprag_length", "sprags"), ("centre_distance", "sprag_outer_radius"))
        if set(p) <= set(ds.dims)
    ]
    fig, axes = plt.subplots(
        1, max(len(pairs), 1), figsize=A4_LANDSCAPE, squeeze=False, gridspec_kw={"wspace": 0.3}
    )
    if "run" in ds.dims:
        plt.close(fig)
        return _sampled_pass_map(ds)
    if not pairs:
        axes[0, 0].text(
            0.5,
            0.5,
            "needs a factorial design over (sprag_length, sprags) or\n"
            "(centre_distance, sprag_outer_radius)",
            ha="center",
            transform=axes[0, 0].transAxes,
        )
        return fig
    at = shown(ds) or SEED  # the other factors at the design the run shows
    torque = None
    if "torque" in ds.dims:
        torque = float(ds["torque"].sel(torque=at.get("torque", 750.0), method="nearest"))
    cmap = ListedColormap([c for _, c in CATEGORIES])
    norm = BoundaryNorm(np.arange(len(CATEGORIES) + 1) - 0.5, len(CATEGORIES))
    for ax, (x, y) in zip(axes[0], pairs, strict=False):
        view = ds[["status"] + [f"margin_{k}" for k in CHECKS]]
        sub = seed_view(
            view, {**SEED, **at, **({"torque": torque} if torque else {})}, keep=(x, y)
        ).transpose(y, x)
        cat = _category(sub["status"].values)
        scale = {n: (1e3, "mm") if sub[n].attrs.get("units") == "m" else (1.0, "") for n in (x, y)}
        xv, yv = sub[x].values * scale[x][0], sub[y].values * scale[y][0]
        ax.pcolormesh(
            xv, yv, cat, cmap=cmap, norm=norm, shading="nearest", edgecolors="w", linewidth=0.5
        )
        margin = np.minimum.reduce([sub[f"margin_{k}"].values for k in CHECKS])
        starred = _mark(ax, ds, x, y, scale)
        # a starred cell's number below its star (the star would hide it)
        dy = 0.3 * (np.ptp(yv) / (yv.size - 1) if yv.size > 1 else 1.0)
        for j, yy in enumerate(yv):
            for i, xx in enumerate(xv):
                if np.isfinite(margin[j, i]):
                    star = any(np.isclose(xx, sx) and np.isclose(yy, sy) for sx, sy in starred)
                    ax.text(xx, yy - dy if star else yy, f"{margin[j, i]:+.2f}", ha="center",
                            va="center", fontsize=8)  # fmt: skip
        ax.set_xlabel(f"{x.replace('_', ' ')} [{scale[x][1] or '-'}]")
        ax.set_ylabel(f"{y.replace('_', ' ')} [{scale[y][1] or '-'}]")
        ax.set_title(
            textwrap.fill(fixed_text(sub, [d for d in ds.dims if d not in (x, y)]), 70), fontsize=8
        )
    for label, colour in CATEGORIES:
        axes[0, 0].plot([], [], "s", color=colour, ms=10, label=label)
    labelled = {}  # (each label once: every map marks the same designs)
    for ax in axes.flat:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            labelled.setdefault(label, handle)
    fig.legend(labelled.values(), labelled.keys(), loc="lower center", ncol=4, fontsize=8)
    fig.subplots_adjust(bottom=0.2)
    fig.suptitle(
        "Which sprag geometries pass every allowable (numbers: smallest margin of safety, "
        "allowable/value - 1)"
    )
    return fig


def _mark(ax, ds, x, y, scale) -> list[tuple[float, float]]:
    """The design the run shows (and, on a map of every design, the source paper's where it is a
    scenario of the run); returns where the stars are (in the map's units)."""
    at = []
    for i, label, colour in _marks(ds, slice_only="run" not in ds.dims):
        xy = (flat(ds, x)[i] * scale[x][0], flat(ds, y)[i] * scale[y][0])
        ax.plot(*xy, "*", ms=18, mfc=colour, mec="k", label=label)
        at.append(xy)
    return at


def _sampled_pass_map(ds):
    """The pass map of a sampled design: over the geometry pairs that are factors (else the first
    two factors), each design's category (or, for many designs, the share passing per bin)."""
    factors = ds.attrs.get("factors", "").split()
    pairs = [
        p
        for p in (("sprag_length", "sprags"), ("centre_distance", "sprag_outer_radius"))
        if set(p) <= set(factors)
    ] or ([tuple(factors[:2])] if len(factors) >= 2 else [])
    fig, axes = plt.subplots(
        1, max(len(pairs), 1), figsize=A4_LANDSCAPE, squeeze=False, gridspec_kw={"wspace": 0.3}
    )
    if not pairs:
        axes[0, 0].text(
            0.5, 0.5, "a map needs two factors", ha="center", transform=axes[0, 0].transAxes
        )
        return fig
    cat = _category(ds["status"].values)
    handles = []
    for ax, (x, y) in zip(axes[0], pairs, strict=False):
        scale = {n: (1e3, "mm") if ds[n].attrs.get("units") == "m" else (1.0, "") for n in (x, y)}
        handles = sampled_category_map(
            ax, ds[x].values * scale[x][0], ds[y].values * scale[y][0], cat, CATEGORIES
        )
        _mark(ax, ds, x, y, scale)
        ax.set_xlabel(f"{x.replace('_', ' ')} [{scale[x][1] or ds[x].attrs.get('units', '-')}]")
        ax.set_ylabel(f"{y.replace('_', ' ')} [{scale[y][1] or ds[y].attrs.get('units', '-')}]")
        others = [f for f in factors if f not in (x, y)]
        ax.set_title(
            "all designs of the sample" + (f" (over {', '.join(others)} too)" if others else ""),
            fontsize=8,
        )
    if handles:
        fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=8)
        fig.subplots_adjust(bottom=0.2)
    fig.suptitle(
        f"Which sprag geometries pass every allowable ({ds['status'].size} sampled designs)"
    )
    return fig


def impact_torque(ds):
    fig, axes = plt.subplots(
        2, 3, figsize=A4_LANDSCAPE, gridspec_kw={"wspace": 0.35, "hspace": 0.45}
    )
    ax = axes[0, 0]
    ax.plot(ds["impact_time"].values, ds["impact_torque"].values, "k-")
    ax.axhline(float(ds["impact_steady_torque"]), color="b", ls="--", lw=1, label="√(P₀·C)")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("torque T [N·m]")
    ax.set_title("(a) T(t) from the peak T₀ at t₀", fontsize=10)
    ax.legend(fontsize=8)
    panels = (
        ("impact_power", 1e-3, "input power P₀ [kW]", "(b)"),
        ("output_inertia", 1.0, "output inertia J [kg·m²]", "(c)"),
        ("impact_damping", 1.0, "damping C [N·m·s²]", "(d)"),
        ("initial_speed", 30 / np.pi, "initial speed ω₀ [rpm]", "(e)"),
    )
    for ax, (name, scale, label, tag) in zip(axes.ravel()[1:], panels, strict=False):
        ax.plot(ds[f"sweep_{name}"].values * scale, ds[f"peak_torque_vs_{name}"].values, "r-")
        ax.set_xlabel(label)
        ax.set_ylabel("peak torque T₀ [N·m]")
        ax.set_title(f"{tag} T₀ against {label.split('[')[0].strip()}", fontsize=10)
    axes[1, 2].axis("off")
    nominal = {n: value_at_shown(ds, n, SEED[n]) for n in SEED}
    axes[1, 2].text(
        0,
        0.95,
        "Nominal impact (the design shown;\nassumed, not printed in the source paper):\n"
        f"P₀ = {nominal['impact_power'] / 1e3:.4g} kW, C = {nominal['impact_damping']:.4g} N·m·s²,\n"
        f"J = {nominal['output_inertia']:.4g} kg·m², t₀ = {nominal['rise_time'] * 1e3:.4g} ms,\n"
        f"ω₀ = {nominal['initial_speed'] * 30 / np.pi:.4g} rpm: √(P₀·C) = "
        f"{float(ds['impact_steady_torque']):.4g} N·m.\n"
        "T₀ rises with P₀, J, C and falls with ω₀\n(the source paper's Fig. 4 b-e).",
        va="top",
        fontsize=9,
    )
    for ax in axes.ravel()[:5]:
        ax.grid(alpha=0.3)
    fig.suptitle(
        "Impact torque of the starter (paper 002 eqs. 1-5, Fig. 4): J·ω·dω/dt + C·ω² = P₀, T = P₀/ω"
    )
    return fig


# page stem -> function drawing it from the study's Dataset, in report order
PAGES = {"stress_vs_torque": stress_vs_torque, "pass_map": pass_map, "impact_torque": impact_torque}

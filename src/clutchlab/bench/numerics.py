"""The numerics section of the report: a cheap run of each solver benchmark for
the studies of the run, in seconds on small samples, so the report of the run that produced the
numbers shows how fast and how accurate each solver was against the natural alternatives measured
in the same run, and the ratio at equal error. The full benchmarks stay targets of their own
(``snakemake benchmark_compliant``, ``benchmark_roller``, ``benchmark_sprag``, ``benchmark``).

* engagement — the compliant driveline the study runs (:mod:`clutchlab.bench.compliant`):
  clutchlab over its accuracy sweep against per-scenario ``solve_ivp`` RK45 (as usually written)
  and DOP853 (as an expert would), reference DOP853 at rtol 1e-13;
* roller — the wedging (:mod:`clutchlab.bench.roller`): the compiled DOP853/SDIRK4 against
  per-scenario LSODA and Radau, reference Radau at rtol 1e-12;
* sprag — the gripping-angle fixed point (:mod:`clutchlab.bench.sprag`): vectorised against
  per-scenario ``brentq``, reference brentq at xtol 1e-15;
* centrifugal — the release after an engine failure (:func:`release_benchmark`): the closed form
  against integrating the held phase with ``solve_ivp`` (RK45, DOP853) and the release as an
  event, reference DOP853 at rtol 1e-13.

The diaphragm statics and the centrifugal capacities are closed forms without an iterative
alternative worth timing; their checks are the validation table and the hard cases.

``python -m clutchlab.bench.numerics OUTDIR STUDY... [--friction-laws constant_mu,stribeck]``
writes ``<name>_benchmark.csv`` per solver.
"""

from __future__ import annotations

from pathlib import Path

__all__ = [
    "SIZES",
    "files",
    "run",
    "release_benchmark",
    "roller_figure",
    "sprag_figure",
    "centrifugal_figure",
    "pages",
]

# small samples: seconds each on one core (the full benchmarks use 10^4 to 10^6)
SIZES = {
    "engagement": dict(n=300, n_ref=3),
    "roller": dict(n=6),
    "sprag": dict(n=2000, n_ref=40),
    "centrifugal": dict(n=20_000, n_ref=30),
}
FILES = {
    "engagement": "compliant_benchmark.csv",
    "roller": "roller_benchmark.csv",
    "sprag": "sprag_benchmark.csv",
    "centrifugal": "centrifugal_benchmark.csv",
}
RELEASE_RTOLS = (1e-3, 1e-5, 1e-7, 1e-9)


def files(study_names) -> list[str]:
    """The CSV names the numerics run writes for these studies."""
    return [FILES[s] for s in study_names if s in FILES]


def run(outdir, study_names, friction_laws=None) -> list[Path]:
    """Run the small benchmark of each study's solver into ``outdir``; the engagement's on the
    friction laws ``friction_laws`` (of :data:`clutchlab.bench.compliant.VARIANTS`; default all:
    a study's are :func:`clutchlab.studies.engagement.friction_laws`), so that a run compiles only
    the solvers its studies use. Returns the CSV files written."""
    from functools import partial

    from . import compliant, roller, sprag

    runner = {
        "engagement": partial(compliant.run, variants=friction_laws or compliant.VARIANTS),
        "roller": roller.run,
        "sprag": sprag.run,
        "centrifugal": release_benchmark,
    }
    out = []
    for s in study_names:
        if s in runner:
            print(f"numerics: {s} ({FILES[s]}, {SIZES[s]})", flush=True)
            runner[s](outdir, **SIZES[s])
            out.append(Path(outdir) / FILES[s])
    return out


def release_design(n, seed=0) -> dict:
    """Random centrifugal designs around seed 001 (spring, friction, pressure angle, passive torque,
    inertias) that stay engaged at rated speed."""
    import numpy as np

    from ..studies.centrifugal import PARAMETERS

    rng = np.random.default_rng(seed)
    d = {p.name: np.full(n, p.default) for p in PARAMETERS}
    d["spring_force"] = rng.uniform(380.0, 480.0, n)
    d["friction_coefficient"] = rng.uniform(0.3, 0.45, n)
    d["pressure_angle"] = np.deg2rad(rng.uniform(25.0, 45.0, n))
    d["rated_passive_torque"] = rng.uniform(40.0, 90.0, n)
    d["engine_inertia"] = rng.uniform(0.01, 0.05, n)
    d["rotor_inertia"] = rng.uniform(0.2, 1.0, n)
    return d


_RELEASE = (
    "rated_speed",
    "shoes",
    "friction_coefficient",
    "pressure_angle",
    "shoe_mass",
    "shoe_radius",
    "drum_radius",
    "spring_force",
    "engine_inertia",
    "rotor_inertia",
    "rotor_load_torque",
    "rated_passive_torque",
    "static_fraction",
)


def _release_ivp(p, method, rtol):
    """The held phase integrated, the release (T_need = M') as a terminal event: its time [s]."""
    from scipy.integrate import solve_ivp

    from .. import centrifugal as cf

    k, p0, p2, caps = cf._params(p)
    je, jr = p["engine_inertia"], p["rotor_inertia"]

    def g(t, y):
        needed = cf.needed_reverse_torque(
            y[0], engine_inertia=je, rotor_inertia=jr, rotor_drag=k, p0=p0, p2=p2
        )
        return needed - caps(y[0])[1]

    if g(0.0, [p["rated_speed"]]) >= 0:
        return 0.0
    g.terminal, g.direction = True, 1
    sol = solve_ivp(
        lambda t, y: [-(p0 + (p2 + k) * y[0] ** 2) / (je + jr)],
        (0.0, 60.0),
        [p["rated_speed"]],
        method=method,
        rtol=rtol,
        atol=rtol * 1e-3,
        events=g,
    )
    return float(sol.t_events[0][0]) if sol.t_events[0].size else float("nan")


def release_benchmark(outdir, n=20_000, n_ref=30) -> list[dict]:
    """Centrifugal release after an engine failure: the closed form (:func:`clutchlab.centrifugal.
    release_after_failure`, vectorised over n designs, best of 3) against per-scenario solve_ivp
    RK45 and DOP853 over :data:`RELEASE_RTOLS` on n_ref designs; error = max |release time − DOP853
    at rtol 1e-13| over those; writes ``centrifugal_benchmark.csv``."""
    import time

    import numpy as np

    from .. import centrifugal as cf
    from ._common import per_scenario_sweep, write_rows

    d = release_design(n)
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        res = cf.release_after_failure(**{k: d[k] for k in _RELEASE})
        best = min(best, time.perf_counter() - t0)
    scen = [{k: float(v[i]) for k, v in d.items()} for i in range(n_ref)]
    ref = np.array([_release_ivp(p, "DOP853", 1e-13) for p in scen])
    rows = [
        dict(
            method="clutchlab closed form (vectorised)",
            rtol=float("nan"),
            seconds_per_scenario=best / n,
            max_release_time_error_s=float(np.nanmax(np.abs(res["release_time"][:n_ref] - ref))),
        )
    ]
    rows += per_scenario_sweep(
        _release_ivp,
        scen,
        ref,
        ("RK45", "DOP853"),
        RELEASE_RTOLS,
        "max_release_time_error_s",
        "scipy solve_ivp {method} per scenario (release event)",
    )
    for r in rows:
        print(
            f"{r['method']:<55s} rtol {r['rtol']:.0e}: {r['seconds_per_scenario'] * 1e6:10.2f} us/scenario, "
            f"max |release time error| {r['max_release_time_error_s']:.1e} s"
        )
    Path(outdir).mkdir(parents=True, exist_ok=True)
    write_rows(rows, Path(outdir) / FILES["centrifugal"])
    return rows


def centrifugal_figure(rows):
    return _wp_figure(
        rows,
        "max_release_time_error_s",
        "clutchlab",
        "Work-precision of the centrifugal release after an engine failure (small sample of this run): "
        "closed form against integrating the held phase\nper scenario with solve_ivp and the release as an "
        "event; reference: DOP853 at rtol 1e-13; error = max |release time - reference|",
        "max |release time error| [s]",
        "rtol",
    )


def _read(path) -> list[dict]:
    import csv

    def num(v):
        try:
            return float(v)
        except ValueError:
            return v

    with open(path, newline="") as fh:
        return [{k: num(v) for k, v in row.items()} for row in csv.DictReader(fh)]


def _ratios(rows, error, ours):
    """(alternative row, fastest of our rows with equal or smaller error, time ratio) per
    alternative row."""
    mine = [r for r in rows if r["method"].startswith(ours)]
    out = []
    for r in rows:
        if r["method"].startswith(ours):
            continue
        match = [m for m in mine if m[error] <= r[error]]
        if match:
            m = min(match, key=lambda m: m["seconds_per_scenario"])
            out.append((r, m, r["seconds_per_scenario"] / m["seconds_per_scenario"]))
    return out


def _setting(r, key) -> str:
    v = r.get(key)
    return f" at {key} {v:.0e}" if isinstance(v, float) and v == v else ""


def _wp_figure(rows, error, ours, title, ylabel, label_key):
    import matplotlib.pyplot as plt

    from ..report.common import A4_LANDSCAPE, label_points

    fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
    labels = []
    for j, method in enumerate(dict.fromkeys(r["method"] for r in rows)):
        pts = sorted(
            (r for r in rows if r["method"] == method), key=lambda r: -r[error]
        )  # along the tolerance
        x = [r["seconds_per_scenario"] for r in pts]
        y = [max(r[error], 1e-17) for r in pts]
        ax.loglog(x, y, "o-" if len(pts) > 1 else "o", color=f"C{j}", ms=7, label=method)
        labels += [
            (r["seconds_per_scenario"], max(r[error], 1e-17), _setting(r, label_key)[4:], f"C{j}")
            for r in pts
            if _setting(r, label_key)
        ]
    lines = [
        f"vs {r['method']}{_setting(r, label_key)} (error {r[error]:.1e}): {ratio:.0f}x faster"
        for r, _, ratio in _ratios(rows, error, ours)
    ]
    ax.margins(0.15)
    ax.set_xlabel("time per scenario [s] (this machine, this run)")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.subplots_adjust(bottom=0.27)  # the ratios below the axes, clear of the points
    fig.text(
        0.08,
        0.015,
        "clutchlab at equal or better error:\n" + "\n".join(lines[:10])
        if lines
        else "no alternative reached an error clutchlab's settings cover",
        fontsize=8,
        va="bottom",
        family="monospace",
    )
    ax.set_title(title, fontsize=10)
    label_points(ax, labels)
    return fig


def roller_figure(rows):
    return _wp_figure(
        rows,
        "max_engagement_error_s",
        "clutchlab",
        "Work-precision of the roller wedging (small sample of this run): compiled DOP853/SDIRK4 against "
        "per-scenario solve_ivp LSODA and Radau\nreference: Radau at rtol 1e-12 with the analytic "
        "Jacobian, piecewise over slip and stick; error = max |engagement time - reference|",
        "max |engagement time error| [s]",
        "rtol",
    )


def sprag_figure(rows):
    rows = [
        r for r in rows if r["max_V_error_rad"] == r["max_V_error_rad"]
    ]  # the timed-only 10x size: no error
    return _wp_figure(
        rows,
        "max_V_error_rad",
        "clutchlab",
        "Work-precision of the sprag gripping-angle fixed point (small sample of this run): "
        "vectorised statics against per-scenario brentq\nreference: brentq at xtol 1e-15; error = "
        "max |V - V_ref| over the scenarios with an answer",
        "max |gripping angle error| [rad]",
        "xtol",
    )


def pages(numerics_dir, study_names=None) -> list[tuple]:
    """(stem, figure) of the numerics CSV of each of ``study_names`` present in ``numerics_dir``,
    in their order (default: every study's; a CSV an earlier run of other studies left in the
    folder is not this run's)."""
    from . import compliant

    draw = {
        "engagement": lambda f: compliant.work_precision_figure(compliant.read_rows(f)),
        "roller": lambda f: roller_figure(_read(f)),
        "sprag": lambda f: sprag_figure(_read(f)),
        "centrifugal": lambda f: centrifugal_figure(_read(f)),
    }
    d = Path(numerics_dir)
    names = list(FILES) if study_names is None else study_names
    return [
        (f"numerics_{s}", draw[s](d / FILES[s]))
        for s in names
        if s in FILES and (d / FILES[s]).exists()
    ]


def stems(study_names) -> list[str]:
    return [f"numerics_{s}" for s in study_names if s in FILES]


def main(argv=None) -> None:
    import argparse

    ap = argparse.ArgumentParser(prog="python -m clutchlab.bench.numerics", description=__doc__)
    ap.add_argument("outdir")
    ap.add_argument("studies", nargs="+")
    ap.add_argument(
        "--friction-laws",
        default=None,
        help="comma-separated friction laws of the engagement's benchmark (default: all of "
        "constant_mu,stribeck,table,fade)",
    )
    a = ap.parse_args(argv)
    run(a.outdir, a.studies, a.friction_laws.split(",") if a.friction_laws else None)


if __name__ == "__main__":
    main()

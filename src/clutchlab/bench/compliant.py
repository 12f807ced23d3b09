"""Benchmark of the model the engagement study runs: the compliant driveline, speed against error.

``python -m clutchlab.bench.compliant [outdir] [--scenarios N] [--reference-scenarios M]`` (or
``snakemake --cores 1 benchmark_compliant``) prints and writes ``compliant_benchmark.csv`` and
``compliant_work_precision.png``, all measured in one run:

* design: the default engagement study's ranges (seed 000 engine held at 570 rad/s, driven
  inertia 0.021-0.05 kg m², load 44-80 N m, peak capacity 150-300 N m, ramp 0.05-0.3 s, damper
  4498 N m/rad, damping ratio 0.05, hub share 0.5, window 0.6 s); four variants: constant μ (the
  default study: every phase in closed form), Stribeck μ (μ_s/μ_k = 1.3, v_s 5-50 rad/s), a
  measured μ(slip) table (μ 0.5 at rest falling to 0.39 at 6000 rpm, μ_s/μ_k = 1.3) and friction
  fade (β 0.005-0.02 /K from the ambient temperature, the source paper (000) lining's face
  temperature factor: the face temperature a state of the solver); the slipping phases of the last
  three by exponential collocation (:mod:`clutchlab.engagement._slip_phase`);
* reference: :func:`clutchlab.reference.compliant`, scipy DOP853 at rtol = atol = 1e-13 with
  per-mode restarts and the jerk peak refined on the dense output, on M scenarios;
* error: the largest relative error over those M scenarios in lock-up time, slip work and peak
  output jerk (each column, and their maximum);
* clutchlab: :func:`clutchlab.engagement.simulate` over N scenarios in one call (the median of 3
  of the wall time, and of the process CPU time); constant μ has nothing to tune, the other
  variants are swept over the study's ``accuracy`` 1e-3 to 1e-7 (tolerances of
  :func:`clutchlab.studies.engagement.tolerances`);
* scipy per scenario, the same model written with ``solve_ivp`` (per-mode restarts, terminal
  events): RK45 with the jerk taken at its steps (as one usually writes it) and DOP853 with the
  jerk refined on its dense output (as an expert would), each over a sweep of rtol (atol = rtol/1000).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from .. import engagement as eng
from .. import reference
from ..studies.engagement import tolerances
from ._common import parse, save_figure, write_rows

METRICS = ("lockup_time", "slip_work", "peak_jerk")
COLUMNS = (
    "variant",
    "method",
    "setting",
    "seconds_per_scenario",
    "cpu_seconds_per_scenario",
    "err_lockup_time",
    "err_slip_work",
    "err_peak_jerk",
    "max_rel_error",
    "scenarios",
)
CLUTCHLAB = "clutchlab (closed-form phases, collocation or DOPRI5 where nonlinear)"
RK45 = "scipy solve_ivp RK45 per scenario (jerk at steps)"
DOP853 = "scipy solve_ivp DOP853 per scenario (jerk on dense output)"
SCIPY_RTOLS = {RK45: (1e-3, 1e-5, 1e-7, 1e-9), DOP853: (1e-5, 1e-7, 1e-9)}
ACCURACIES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7)
VARIANTS = ("constant_mu", "stribeck", "table", "fade")
LABELS = {
    "constant_mu": "constant μ (default study)",
    "stribeck": "Stribeck μ",
    "table": "measured μ(slip) table",
    "fade": "friction fade (face temperature)",
}
#: a measured μ(slip) table: slip speeds [rad/s] and μ/μ_k (μ_k = 0.4)
TABLE = (
    np.array([0.0, 500.0, 3000.0, 6000.0]) * np.pi / 30,
    np.array([0.5, 0.45, 0.40, 0.39]) / 0.4,
)


def design(n, variant, seed=0):
    """Random scenarios in the default engagement study's ranges (keyword arguments of simulate)."""
    rng = np.random.default_rng(seed)
    d = dict(
        engine_speed=570.0,
        engine_inertia=np.inf,
        engine_torque=0.0,
        driven_inertia=rng.uniform(0.021, 0.05, n),
        load_torque=rng.uniform(44.0, 80.0, n),
        peak_capacity=rng.uniform(150.0, 300.0, n),
        ramp_time=rng.uniform(0.05, 0.3, n),
        damper_stiffness=4498.0,
        damping_ratio=0.05,
        hub_fraction=0.5,
        t_end=0.6,
    )
    if variant == "stribeck":
        d.update(static_ratio=1.3, stribeck_speed=rng.uniform(5.0, 50.0, n))
    elif variant == "table":
        d.update(static_ratio=1.3, friction_table=TABLE)
    elif variant == "fade":
        from ..heat import face_temperature_rise

        d.update(
            fade_coefficient=rng.uniform(0.005, 0.02, n),
            fade_onset=0.0,
            face_temperature_factor=float(face_temperature_rise(1.0, 0.1125, 0.075, 2)),
        )
    return d


def _scenario(d, i):
    return {k: (v[i] if _per_scenario(k, v) else v) for k, v in d.items()}


def _per_scenario(key, value):
    """Whether a design entry holds one value a scenario (the friction table is shared)."""
    return key != "friction_table" and np.ndim(value) > 0


def _head(d, m):
    """The first m scenarios of a design."""
    return {k: (v[:m] if _per_scenario(k, v) else v) for k, v in d.items()}


def _errors(values, ref):
    """Largest relative error of each metric over the scenarios (values, ref: metric -> array); a
    value NaN where the reference is not (or the reverse: a scenario that locks up in one of them
    only) is an infinite error."""
    out = []
    for k in METRICS:
        v, r = np.asarray(values[k], dtype=float), np.asarray(ref[k], dtype=float)
        if not np.array_equal(np.isfinite(v), np.isfinite(r)):
            out.append(np.inf)
            continue
        ok = np.isfinite(r)
        out.append(float(np.max(np.abs(v[ok] - r[ok]) / np.abs(r[ok]), initial=0.0)))
    return out


def _row(variant, method, setting, seconds, errs, scenarios, cpu=None):
    cpu = seconds if cpu is None else cpu
    values = (variant, method, setting, seconds, cpu, *errs, max(errs), scenarios)
    return dict(zip(COLUMNS, values, strict=True))


def run(outdir="results/benchmark", n=10_000, n_ref=10, variants=VARIANTS):
    """Time and check the compliant engagement on ``n`` scenarios of each friction law in
    ``variants`` (of :data:`VARIANTS`; the reference on the first ``n_ref``); write
    ``compliant_benchmark.csv`` and ``compliant_work_precision.png`` to ``outdir``."""
    unknown = set(variants) - set(VARIANTS)
    if unknown:
        raise ValueError(f"unknown friction laws {sorted(unknown)}: choose from {VARIANTS}")
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    rows = []
    for variant in variants:
        d = design(n, variant)
        ref_d = _head(d, n_ref)
        ref, row = _reference(ref_d, n_ref, variant)
        rows.append(row)
        rows += _clutchlab_rows(d, n, n_ref, variant, ref)
        rows += _scipy_rows(ref_d, n_ref, variant, ref)
    write_rows(rows, outdir / "compliant_benchmark.csv")
    for variant in variants:
        ratios = speed_ratios(rows, variant)
        for r, o, ratio in ratios:
            print(
                f"  [{variant}] vs {r['method']} {r['setting']} (max rel. error {r['max_rel_error']:.1e}): clutchlab "
                f"{o['setting']} is {ratio:.0f}x faster per scenario at equal or better error"
            )
        if ratios:
            print(f"  [{variant}] smallest ratio {min(x[2] for x in ratios):.0f}x")
    fig = work_precision_figure(rows)
    save_figure(fig, outdir / "compliant_work_precision.png")
    return rows


def _reference(ref_d, n_ref, variant):
    """The DOP853 rtol 1e-13 reference of the first n_ref scenarios: (metric -> array, its row)."""
    t = time.perf_counter()
    refs = [reference.compliant(_scenario(ref_d, i), rtol=1e-13, atol=1e-13) for i in range(n_ref)]
    t_ref = (time.perf_counter() - t) / n_ref
    n_ok = sum(r["status"] == "ok" for r in refs)
    print(
        f"[{variant}] reference: scipy DOP853 rtol 1e-13, {n_ref} scenarios ({n_ok} lock up), "
        f"{t_ref * 1e3:.0f} ms/scenario"
    )
    ref = {k: np.array([r[k] for r in refs]) for k in METRICS}
    row = _row(variant, "DOP853 reference (per scenario)", "rtol 1e-13", t_ref, [0.0] * 3, n_ref)
    return ref, row


def _clutchlab_rows(d, n, n_ref, variant, ref):
    """clutchlab over m scenarios in one call, for each accuracy (constant μ: exact), as the study
    runs it: with the slip power history for the face temperature (which solve_ivp does not
    compute: the comparison is conservative). Median of 3 runs, wall and process CPU time."""
    m = n if variant == "constant_mu" else max(n // 5, n_ref)
    dm = _head(d, m)
    eng.simulate(**_head(dm, 4), compliant=True)  # load the compiled kernel outside the timing
    rows = []
    for acc in (None,) if variant == "constant_mu" else ACCURACIES:
        kw = {} if acc is None else dict(zip(("rtol", "atol"), tolerances(acc), strict=True))
        wall, cpu = [], []
        for _ in range(3):
            t, c = time.perf_counter(), time.process_time()
            res = eng.simulate(**dm, compliant=True, power_history=True, **kw)
            wall.append((time.perf_counter() - t) / m)
            cpu.append((time.process_time() - c) / m)
        errs = _errors({k: res[k][:n_ref] for k in METRICS}, ref)
        setting = "exact" if acc is None else f"accuracy {acc:.0e}"
        w, c = float(np.median(wall)), float(np.median(cpu))
        rows.append(_row(variant, CLUTCHLAB, setting, w, errs, m, cpu=c))
        print(
            f"[{variant}] clutchlab {setting}: {w * 1e6:8.1f} us/scenario ({c * 1e6:.1f} us CPU; "
            f"{m} in one call), errors lock-up {errs[0]:.1e}, slip work {errs[1]:.1e}, "
            f"peak jerk {errs[2]:.1e}"
        )
    return rows


def _scipy_rows(ref_d, n_ref, variant, ref):
    """The same model written with solve_ivp per scenario, over each method's rtol sweep."""
    rows = []
    for method, rtols in SCIPY_RTOLS.items():
        for rtol in rtols:
            t = time.perf_counter()
            out = [
                reference.compliant(
                    _scenario(ref_d, i),
                    method=method.split()[2],
                    rtol=rtol,
                    atol=rtol * 1e-3,
                    jerk_peak="dense" if method == DOP853 else "steps",
                )
                for i in range(n_ref)
            ]
            dt = (time.perf_counter() - t) / n_ref
            errs = _errors({k: [o[k] for o in out] for k in METRICS}, ref)
            rows.append(_row(variant, method, f"rtol {rtol:.0e}", dt, errs, n_ref))
            print(
                f"[{variant}] {method} rtol {rtol:.0e}: {dt * 1e3:8.1f} ms/scenario, errors lock-up "
                f"{errs[0]:.1e}, slip work {errs[1]:.1e}, peak jerk {errs[2]:.1e}"
            )
    return rows


def read_rows(path) -> list[dict]:
    import csv

    text = ("variant", "method", "setting")
    with open(path, newline="") as fh:
        return [
            {k: (v if k in text else float(v)) for k, v in row.items()}
            for row in csv.DictReader(fh)
        ]


def speed_ratios(rows, variant):
    """For every scipy row of ``variant``: (that row, the fastest clutchlab row with equal or smaller
    maximum relative error, the ratio of their times per scenario)."""
    ours = [r for r in rows if r["variant"] == variant and r["method"] == CLUTCHLAB]
    out = []
    for r in rows:
        if r["variant"] == variant and r["method"].startswith("scipy"):
            match = [o for o in ours if o["max_rel_error"] <= r["max_rel_error"]]
            if match:
                o = min(match, key=lambda o: o["seconds_per_scenario"])
                out.append((r, o, r["seconds_per_scenario"] / o["seconds_per_scenario"]))
    return out


def work_precision_figure(rows):
    """One panel per friction law in the rows (constant μ, Stribeck μ, μ table, fade): max relative
    error of lock-up time, slip work and peak jerk against time per scenario, one line per method
    over its tolerances."""
    import matplotlib.pyplot as plt

    from ..report.common import label_points

    variants = [v for v in VARIANTS if any(r["variant"] == v for r in rows)]
    shape = (2, 2) if len(variants) > 2 else (1, max(len(variants), 1))
    fig, axes = plt.subplots(*shape, figsize=(11.69, 8.27), sharey=True, squeeze=False)
    colors = {CLUTCHLAB: "C0", RK45: "C1", DOP853: "C2"}
    for ax in axes.flat[len(variants) :]:
        ax.set_visible(False)
    labels = {v: [] for v in variants}
    for ax, variant in zip(axes.flat, variants, strict=False):
        label = LABELS[variant]
        for name, marker in ((CLUTCHLAB, "o-"), (RK45, "s-"), (DOP853, "^-")):
            pts = [r for r in rows if r["variant"] == variant and r["method"] == name]
            if not pts:
                continue
            ax.loglog(
                [r["seconds_per_scenario"] for r in pts],
                [max(r["max_rel_error"], 1e-16) for r in pts],
                marker,
                label=name if variant == variants[0] else None,
                color=colors[name],
                ms=8 if len(pts) == 1 else 6,
            )
            labels[variant] += [
                (
                    r["seconds_per_scenario"],
                    max(r["max_rel_error"], 1e-16),
                    r["setting"],
                    colors[name],
                )
                for r in pts
            ]
        ratios = [x[2] for x in speed_ratios(rows, variant)]
        ax.set_title(
            f"{label}"
            + (
                f"\nclutchlab {min(ratios):.0f}-{max(ratios):.0f}x faster at equal or better error"
                if ratios
                else ""
            ),
            fontsize=10,
        )
        ax.set_xlabel("time per scenario [s]")
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[:, 0]:
        ax.set_ylabel(
            "max relative error of lock-up time, slip work, peak jerk\n"
            "(reference: scipy DOP853, rtol 1e-13)"
        )
    fig.suptitle(
        "Work-precision of the compliant engagement (the default study's model and ranges)"
    )
    fig.legend(loc="lower center", ncol=2, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.07, 1, 0.95))
    for ax, variant in zip(axes.flat, variants, strict=False):
        label_points(ax, labels[variant])
    return fig


def main(argv=None):
    a = parse(__doc__, 10_000, argv, reference_scenarios=10)
    run(a.outdir, a.scenarios, a.reference_scenarios)


if __name__ == "__main__":
    main()

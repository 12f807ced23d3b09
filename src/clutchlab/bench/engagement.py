"""Engagement benchmark: speed against error, measured in one run (not a unit test).

``python -m clutchlab.bench.engagement [outdir] [--scenarios N]`` (or ``snakemake benchmark``) prints and
writes ``engagement_benchmark.csv`` and ``work_precision.png``:

* a random design of N (default 10⁴) scenarios with Stribeck friction, held engine;
* reference: scipy DOP853 at rtol = atol = 1e-12 (max_step 1 ms) on the smooth pieces of each
  scenario (from the analytic start of motion, split at the ramp end), for a subset of scenarios;
* clutchlab's solver (compiled, one call) over the whole design at every half decade of
  tolerance from 1e-2 to 1e-12 (so that a scipy error is matched closely) (time per scenario of the
  whole batch, median of 3 runs; lock-up error on
  the reference subset);
* per-scenario ``scipy.integrate.solve_ivp`` RK45 with a terminal lock-up event (as written
  first, and with ``max_step`` 10 ms: without it the first steps grow over the start of motion
  and the lock-up time is off by up to 5 ms at any rtol) at several
  tolerances on the reference subset (the straightforward way to write the problem);
* clutchlab's closed form (constant μ) at 10⁶ scenarios (best of 3).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from .. import engagement as eng
from ._common import parse, save_figure, write_rows

RS = 1.3  # μ_s/μ_k


def design(n, seed=0):
    rng = np.random.default_rng(seed)
    return dict(
        engine_speed=rng.uniform(300, 600, n),
        driven_inertia=rng.uniform(0.01, 0.1, n),
        load_torque=rng.uniform(0, 80, n),
        peak_capacity=rng.uniform(200, 400, n),
        ramp_time=rng.uniform(0.05, 0.3, n),
        stribeck_speed=rng.uniform(5, 50, n),
    )


def _rhs_factory(we, cmax, tr, tm, jv, vs):
    def rhs(t, y):
        c = cmax * min(t / tr, 1.0)
        return [(c * (1.0 + (RS - 1.0) * np.exp(-(((we - y[0]) / vs) ** 2))) - tm) / jv]

    return rhs


def reference(d, i):
    we, cmax, tr, tm, jv, vs = (
        d[k][i]
        for k in (
            "engine_speed",
            "peak_capacity",
            "ramp_time",
            "load_torque",
            "driven_inertia",
            "stribeck_speed",
        )
    )
    rhs = _rhs_factory(we, cmax, tr, tm, jv, vs)
    t0 = tr * tm / (cmax * (1.0 + (RS - 1.0) * np.exp(-((we / vs) ** 2))))
    lock = lambda t, y: we - y[0]  # noqa: E731
    lock.terminal, lock.direction = True, -1
    y, t = [0.0], t0
    for t_b in (tr, 5.0):
        sol = solve_ivp(
            rhs, (t, t_b), y, method="DOP853", rtol=1e-12, atol=1e-12, events=lock, max_step=1e-3
        )
        if sol.t_events[0].size:
            return sol.t_events[0][0]
        y, t = sol.y[:, -1], t_b
    return np.nan


def rk45_per_scenario(d, i, rtol, max_step=np.inf):
    """The usual way: one solve_ivp per scenario, parked driven side inside the RHS, terminal event."""
    we, cmax, tr, tm, jv, vs = (
        d[k][i]
        for k in (
            "engine_speed",
            "peak_capacity",
            "ramp_time",
            "load_torque",
            "driven_inertia",
            "stribeck_speed",
        )
    )
    rhs = _rhs_factory(we, cmax, tr, tm, jv, vs)

    def f(t, y):
        a = rhs(t, y)[0]
        return [a if (y[0] > 0 or a > 0) else 0.0]

    lock = lambda t, y: we - y[0]  # noqa: E731
    lock.terminal, lock.direction = True, -1
    sol = solve_ivp(
        f,
        (0.0, 5.0),
        [0.0],
        method="RK45",
        rtol=rtol,
        atol=rtol * 1e-2,
        events=lock,
        max_step=max_step,
    )
    return sol.t_events[0][0] if sol.t_events[0].size else np.nan


def run(outdir="results/benchmark", n=10_000, n_ref=200):
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    d = design(n)
    sub = np.arange(n_ref)
    t = time.perf_counter()
    ref = np.array([reference(d, i) for i in sub])
    t_ref = (time.perf_counter() - t) / n_ref
    rows = [("DOP853 reference (per scenario)", 1e-12, t_ref, 0.0)]
    print(f"reference: scipy DOP853 rtol 1e-12, {n_ref} scenarios, {t_ref * 1e3:.2f} ms/scenario")
    kw = dict(engine_inertia=np.inf, engine_torque=0.0, static_ratio=RS, t_end=2.0)
    eng.simulate(
        **{k: v[:10] for k, v in d.items()}, **kw
    )  # load (or compile) the kernel outside the timing
    for rtol in CLUTCHLAB_RTOLS:
        runs = []
        for _ in range(3):  # median of 3 (one batch of n takes only ~0.1 s)
            t = time.perf_counter()
            s = eng.simulate(**d, **kw, rtol=rtol, atol=rtol)
            runs.append((time.perf_counter() - t) / n)
        dt = float(np.median(runs))
        err = float(np.max(np.abs(s["lockup_time"][sub] - ref)))
        rows.append((CLUTCHLAB, rtol, dt, err))
        print(
            f"clutchlab simulate rtol {rtol:.1e}: {dt * 1e6:8.1f} us/scenario ({n} in one batch), "
            f"max lock-up error {err:.2e} s"
        )
    for name, max_step in ((RK45, np.inf), (RK45_MAXSTEP, 1e-2)):
        for rtol in (1e-4, 1e-6, 1e-8, 1e-10):
            t = time.perf_counter()
            lk = np.array([rk45_per_scenario(d, i, rtol, max_step) for i in sub])
            dt = (time.perf_counter() - t) / n_ref
            err = float(np.max(np.abs(lk - ref)))
            rows.append((name, rtol, dt, err))
            print(
                f"{name} rtol {rtol:.0e}: {dt * 1e6:8.1f} us/scenario, max lock-up error {err:.2e} s"
            )
    # closed form at 1e6
    m = 1_000_000
    rng = np.random.default_rng(1)
    cf = dict(
        engine_speed=rng.uniform(300, 600, m),
        engine_inertia=np.inf,
        engine_torque=0.0,
        driven_inertia=rng.uniform(0.01, 0.1, m),
        load_torque=rng.uniform(0, 80, m),
        peak_capacity=rng.uniform(200, 400, m),
        ramp_time=rng.uniform(0.05, 0.3, m),
    )
    times = []
    for _ in range(3):
        t = time.perf_counter()
        eng.closed_form(**cf)
        times.append((time.perf_counter() - t) / m)
    print(
        f"closed form (constant mu, ramp), {m} scenarios: {min(times) * 1e6:.3f} us/scenario (best of 3; "
        f"runs {', '.join(f'{x * 1e6:.3f}' for x in times)})"
    )
    rows.append(("clutchlab closed form (constant mu), 1e6 scenarios", 0.0, min(times), np.nan))
    table = [
        dict(
            zip(
                COLUMNS,
                r
                + (
                    m
                    if r[0].startswith("clutchlab closed")
                    else n
                    if r[0].startswith("clutchlab")
                    else n_ref,
                ),
                strict=False,
            )
        )
        for r in rows
    ]
    write_rows(table, outdir / "engagement_benchmark.csv")
    ratios = speed_ratios(table)
    for r, o, ratio in ratios:
        print(
            f"  vs {r['method']} rtol {r['rtol']:.0e} (error {r['max_lockup_error_s']:.1e} s): clutchlab rtol "
            f"{o['rtol']:.1e} is {ratio:.0f}x faster per scenario at equal or better error"
        )
    best = min((x[2] for x in ratios), default=None)
    if best is not None:
        print(f"  smallest ratio {best:.0f}x")
    fig = work_precision_figure(table)
    save_figure(fig, outdir / "work_precision.png")
    return rows, best


CLUTCHLAB_RTOLS = tuple(10.0 ** (-k / 2) for k in range(4, 25))  # every half decade, 1e-2 to 1e-12
COLUMNS = ("method", "rtol", "seconds_per_scenario", "max_lockup_error_s", "scenarios")
CLUTCHLAB, RK45 = "clutchlab DOPRI5 (numba, exact events)", "scipy solve_ivp RK45 per scenario"
RK45_MAXSTEP = "scipy solve_ivp RK45 per scenario, max_step 10 ms"


def read_rows(path) -> list[dict]:
    """The rows of ``engagement_benchmark.csv`` (numbers as floats)."""
    import csv

    with open(path, newline="") as fh:
        return [
            {k: (v if k == "method" else float(v)) for k, v in row.items()}
            for row in csv.DictReader(fh)
        ]


def speed_ratios(rows):
    """For every scipy row: (that row, the fastest clutchlab row with equal or smaller error, the
    ratio of their times per scenario); rows as in :func:`read_rows`."""
    ours = [r for r in rows if r["method"] == CLUTCHLAB]
    out = []
    for r in rows:
        if r["method"].startswith("scipy solve_ivp"):
            match = [o for o in ours if o["max_lockup_error_s"] <= r["max_lockup_error_s"]]
            if match:
                o = min(match, key=lambda o: o["seconds_per_scenario"])
                out.append((r, o, r["seconds_per_scenario"] / o["seconds_per_scenario"]))
    return out


def work_precision_figure(rows):
    """Log-log work-precision diagram (max lock-up time error against time per scenario, one line per
    method over its tolerances) from the benchmark's rows; a report page and the benchmark's PNG."""
    import matplotlib.pyplot as plt

    from ..report.common import label_points

    fig, ax = plt.subplots(figsize=(11.69, 8.27))
    labels = []
    for j, (name, marker) in enumerate(((CLUTCHLAB, "o-"), (RK45, "s-"), (RK45_MAXSTEP, "^-"))):
        pts = [r for r in rows if r["method"] == name]
        ax.loglog(
            [r["seconds_per_scenario"] for r in pts],
            [max(r["max_lockup_error_s"], 1e-16) for r in pts],
            marker,
            color=f"C{j}",
            label=f"{name} ({int(pts[0]['scenarios']) if pts else 0} scenarios)",
        )
        labels += [
            (
                r["seconds_per_scenario"],
                max(r["max_lockup_error_s"], 1e-16),
                f"rtol {r['rtol']:.0e}",
                f"C{j}",
            )
            for r in pts
            if abs(np.log10(r["rtol"]) - round(np.log10(r["rtol"]))) < 1e-9  # the decades only
        ]
    for r in rows:
        if r["method"].startswith("clutchlab closed form"):
            ax.axvline(
                r["seconds_per_scenario"],
                color="g",
                ls="--",
                label=f"closed form (constant μ), {r['seconds_per_scenario'] * 1e6:.2f} µs/scenario, exact",
            )
    ref = [r for r in rows if r["method"].startswith("DOP853 reference")]
    ax.set_xlabel("time per scenario [s]")
    ax.set_ylabel(
        "max |lock-up time error| [s]\n(reference: scipy DOP853, rtol 1e-12"
        + (f", {ref[0]['seconds_per_scenario'] * 1e3:.1f} ms/scenario)" if ref else ")")
    )
    ratios = [x[2] for x in speed_ratios(rows)]
    ax.set_title(
        "Work-precision of the engagement solvers, Stribeck friction, held engine (random design)"
        + (
            f"\nclutchlab is {min(ratios):.0f}-{max(ratios):.0f}x faster per scenario than solve_ivp RK45 "
            "at equal or better error"
            if ratios
            else ""
        )
    )
    ax.grid(True, which="both", alpha=0.3)
    # below the axes: the curves span the whole plot
    ax.legend(fontsize=9, loc="upper center", bbox_to_anchor=(0.5, -0.09), ncol=2)
    fig.subplots_adjust(bottom=0.22)
    label_points(ax, labels)
    return fig


def main(argv=None):
    a = parse(__doc__, 10_000, argv, reference_scenarios=200)
    run(a.outdir, a.scenarios, a.reference_scenarios)


if __name__ == "__main__":
    main()

"""Roller-clutch wedging benchmark: the compiled SDIRK4 against scipy's stiff solvers, speed against
error measured in one run (not a unit test).

``python -m clutchlab.bench.roller [outdir] [--scenarios N]`` (or ``snakemake benchmark_roller``)
prints and writes ``roller_benchmark.csv``:

* N (default 40) random wedging scenarios around the seed 003 design (inertias, wedge angle,
  loaded rollers, load, damping, penetration depth, preload);
* reference: scipy ``solve_ivp`` Radau at rtol 1e-12 with the analytic Jacobian, piecewise over the
  slip and stick phases with the stick and engagement events (:func:`scipy_engagement`);
* clutchlab (:func:`clutchlab.roller.simulate`, one call for all scenarios) at rtol 1e-4 ... 1e-10
  in decades (it stops at the engagement once past the force peak, as scipy stops at the event);
* per-scenario ``solve_ivp`` LSODA and Radau (same right-hand side and Jacobian, compiled) at
  rtol 1e-4 ... 1e-10;
* error = max |engagement time − reference| over the scenarios; time per scenario; for each scipy
  method the ratio of its time to clutchlab's at equal or better error.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from .. import _contact_kernel as _k
from .. import roller
from ._common import parse, per_scenario_sweep, write_rows

RTOLS = tuple(10.0 ** -np.arange(4.0, 10.01, 0.5))


def design(n, seed=0):
    """Random scenarios around the seed 003 design (keyword arrays for :func:`roller.simulate`)."""
    rng = np.random.default_rng(seed)
    return dict(
        driving_speed=np.full(n, 2000 * roller.RPM),
        load_torque=rng.uniform(1000, 2500, n),
        wedge_inertia=10 ** rng.uniform(-5.5, -4, n),
        driven_inertia=10 ** rng.uniform(-2.5, -1.5, n),
        contact_radius=np.full(n, 0.15),
        rollers_loaded=rng.integers(3, 9, n).astype(float),
        wedge_angle=np.deg2rad(rng.uniform(8, 12, n)),
        friction_coefficient=np.full(n, 0.12),
        spring_force=rng.uniform(2, 6, n),
        stiffness=np.full(n, 1.0671e10),
        damping=10 ** rng.uniform(5.5, 6.5, n),
        penetration_depth=10 ** rng.uniform(-4.5, -3.5, n),
        end_time=np.full(n, 3e-3),
    )


def scipy_engagement(p, method, rtol):
    """Engagement time of one scenario with ``solve_ivp``, phase by phase (the kernel's modes: the
    wedge ring slipping or stuck, the driven ring held at rest by its load or turning), each phase
    ended by the first switching event, the kernel's compiled right-hand side, Jacobian, events and
    mode changes."""
    f, jac, work = np.zeros(4), np.zeros((4, 4)), np.zeros((25, 4))
    atol = np.array([rtol * 1e-4, rtol * p[_k.WD], rtol * 1e-4, rtol * p[_k.WD]])

    def fun(mode):
        def rhs(t, y):
            _k.rhs(_k.ROLLER, t, y, p, mode, f, jac, False)
            return f.copy()

        def jacobian(t, y):
            _k.rhs(_k.ROLLER, t, y, p, mode, f, jac, True)
            return jac.copy()

        return rhs, jacobian

    def ev(which, mode):
        def g(t, y):
            return _k.event(_k.ROLLER, t, y, p, mode, which, work)

        g.terminal, g.direction = True, -1
        return g

    extra = {} if method == "LSODA" else {"first_step": 1e-9}
    mode, t, y = _k.initial_mode(p), 0.0, np.zeros(4)
    for _ in range(20):  # phases
        switching = [
            e
            for e in (_k.EV_STICK, _k.EV_BREAKAWAY, _k.EV_STOP)
            if _k.switching_active(e, mode, t, p)
        ]
        rhs, jacobian = fun(mode)
        s = solve_ivp(
            rhs,
            (t, p[_k.TEND]),
            y,
            method=method,
            rtol=rtol,
            atol=atol,
            jac=jacobian,
            events=[ev(_k.EV_SYNC, mode)] + [ev(e, mode) for e in switching],
            **extra,
        )
        if s.t_events[0].size:
            return s.t_events[0][0]
        hits = [(s.t_events[i + 1][0], i) for i in range(len(switching)) if s.t_events[i + 1].size]
        if not hits:
            return np.nan
        t, i = min(hits)
        y = s.y_events[i + 1][0].copy()
        mode = _k.switch_mode(mode, switching[i], y, p)
    return np.nan


def run(outdir="results/benchmark", n=40):
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    d = design(n)
    P, _ = roller.parameter_rows(**d)
    t0 = time.perf_counter()
    ref = np.array([scipy_engagement(p, "Radau", 1e-12) for p in P])
    print(
        f"reference: Radau rtol 1e-12, {(time.perf_counter() - t0) / n * 1e3:.0f} ms per scenario; "
        f"engagement times {np.nanmin(ref) * 1e3:.3f}-{np.nanmax(ref) * 1e3:.3f} ms"
    )
    roller.simulate(**{k: v[:2] for k, v in d.items()})  # load the compiled kernel before timing
    rows = []
    for rtol in RTOLS:
        best = np.inf
        for _ in range(3):
            t0 = time.perf_counter()
            res = roller.simulate(rtol=rtol, **d)
            best = min(best, time.perf_counter() - t0)
        rows.append(
            dict(
                method="clutchlab SDIRK4 (numba, events by re-stepping)",
                rtol=rtol,
                seconds_per_scenario=best / n,
                max_engagement_error_s=float(np.nanmax(np.abs(res["engagement_time"] - ref))),
            )
        )
    rows += per_scenario_sweep(
        scipy_engagement,
        P,
        ref,
        ("LSODA", "Radau"),
        (1e-4, 1e-6, 1e-8, 1e-10),
        "max_engagement_error_s",
        "scipy solve_ivp {method} per scenario",
    )
    for r in rows:
        print(
            f"{r['method']:<50s} rtol {r['rtol']:.0e}: {r['seconds_per_scenario'] * 1e6:9.1f} us/scenario, "
            f"max |engagement time error| {r['max_engagement_error_s']:.2e} s"
        )
    mine = [r for r in rows if r["method"].startswith("clutchlab")]
    for method in ("LSODA", "Radau"):
        for r in (r for r in rows if method in r["method"]):
            ok = [m for m in mine if m["max_engagement_error_s"] <= r["max_engagement_error_s"]]
            if ok:
                m = min(ok, key=lambda m: m["seconds_per_scenario"])
                print(
                    f"ratio vs {method} at rtol {r['rtol']:.0e} (error {r['max_engagement_error_s']:.1e} s): "
                    f"{r['seconds_per_scenario'] / m['seconds_per_scenario']:.0f}x "
                    f"(clutchlab rtol {m['rtol']:.0e}, error {m['max_engagement_error_s']:.1e} s)"
                )
    write_rows(rows, outdir / "roller_benchmark.csv")
    return rows


def main(argv=None):
    a = parse(__doc__, 40, argv)
    run(a.outdir, a.scenarios)


if __name__ == "__main__":
    main()

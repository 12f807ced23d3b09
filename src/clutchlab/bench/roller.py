"""Roller-clutch wedging benchmark: the compiled integrator against scipy's stiff solvers, speed and
error measured in one run (not a unit test).

``python -m clutchlab.bench.roller [outdir] [--scenarios N] [--reference M] [--baseline SRC]
[--no-study]`` (or ``snakemake benchmark_roller``; run in the project folder: it reads
``config/``) prints and writes three tables (the report's numerics section, :func:`run` with its
defaults, only the first):

``roller_benchmark.csv``, speed against error:

* N (default 40) random wedging scenarios around the source paper (003)'s design (inertias,
  wedge angle, loaded rollers, load, damping, penetration depth, preload; no release);
* reference: scipy ``solve_ivp`` Radau at rtol 1e-12 with the analytic Jacobian, piecewise over the
  modes, ended by the switching events (:func:`scipy_outputs`);
* clutchlab (:func:`clutchlab.roller.simulate`, one call for all scenarios) at rtol 1e-4 ... 1e-10
  in half decades (it stops at the engagement once past the force peak, as scipy stops at the
  event);
* per-scenario ``solve_ivp`` LSODA and Radau (same right-hand side and Jacobian, compiled) at
  rtol 1e-4 ... 1e-10;
* error = max |engagement time − reference| over the scenarios; time per scenario; for each scipy
  method the ratio of its time to clutchlab's at equal or better error.

``roller_study_speed.csv`` and ``roller_study_accuracy.csv``, the studies' designs at the study's
tolerance (:data:`clutchlab.studies.roller.RTOL`):

* speed: every simulated scenario of 8 192 Sobol designs of ``config/million.yaml``'s roller
  ranges and of the default config's grid (``config/config.yaml``), in one call each: µs per
  simulated scenario (process CPU time and wall time, the best of 3), accepted, rejected and
  implicit steps, f evals, with the load average; with ``--baseline SRC`` (the ``src`` folder of
  another checkout of clutchlab, e.g. the code before a change) the same calls of that code,
  alternating with this code's in subprocesses, in the same run;
* accuracy: M (default 10) random designs of each against :func:`scipy_outputs` (Radau rtol
  1e-12): the largest relative error of each output the study stores (stick time, backlash of the
  wedge ring, engagement time, total backlash, peak contact force, release time) and the number
  of statuses that differ.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from .. import _contact_systems as _s
from .. import roller
from ._common import per_scenario_sweep, write_rows

RTOLS = tuple(10.0 ** -np.arange(4.0, 10.01, 0.5))
#: outputs of :func:`clutchlab.roller.simulate` the roller study stores (peak stress and dynamic
#: factor follow from the peak force)
OUTPUTS = (
    "stick_time",
    "slip_backlash",
    "engagement_time",
    "backlash",
    "peak_contact_force",
    "release_time",
)
CONFIGS = {"million": ("config/million.yaml", 8192), "grid": ("config/config.yaml", None)}
_STATUS = {"ok": 0, "never_locked": 4}


def design(n, seed=0):
    """Random scenarios around the source paper (003)'s design (keyword arrays for
    :func:`roller.simulate`)."""
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


def study_scenarios(configfile, samples=None):
    """Keyword arrays of :func:`roller.simulate` for the scenarios a config's roller study
    simulates (``samples``: the design's sample count instead of the config's)."""
    from .. import config, doe
    from ..studies import flat_inputs
    from ..studies import roller as study

    raw = config.read_file(configfile)
    raw["studies"] = ["roller"]
    if samples:
        raw["roller"]["samples"] = samples
    ds = doe.build_design(config.resolve(raw)["roller"])
    if "run" not in ds.dims:  # a factorial grid: its scenarios in a row
        ds = ds.stack(run=list(ds.dims)).reset_index("run")
    names = {q.name for q in study.PARAMETERS}
    p = flat_inputs({k: ds[k].values for k in [*ds.coords, *ds.data_vars] if k in names})
    s = study.statics(p, "one_flank")
    n = p["rollers"].size
    run = (s["self_locking_margin"] > 0) & (study._refused(p, s) == 0)
    run &= roller.engages("bidirectional_lock", np.sign(p["drive_direction"]))
    return {k: np.broadcast_to(v, (n,))[run].copy() for k, v in study.dynamics_inputs(p, s).items()}


# ----------------------------------------------------------------------------------- reference
def _force(t, y, p, mode):
    return _s.roller_contact(t, y, p, mode)[2][0]


def _phase(p, mode, t, end, y, method, rtol, until_engaged):
    """One solve_ivp run in ``mode`` from (t, y) to ``end``, ended by the first switching event
    (the engagement too if ``until_engaged``): (solution, the active switching events)."""
    f, jac, scratch = np.zeros(4), np.zeros((4, 4)), (np.zeros(4), np.zeros((4, 4)))
    atol = np.array([rtol * 1e-4, rtol * p[_s.WD], rtol * 1e-4, rtol * p[_s.WD]])

    def rhs(t, y):
        _s.rhs(_s.ROLLER, t, y, p, mode, f, jac, False)
        return f.copy()

    def jacobian(t, y):
        _s.rhs(_s.ROLLER, t, y, p, mode, f, jac, True)
        return jac.copy()

    def ev(which, terminal):
        def g(t, y):
            return _s.event(_s.ROLLER, t, y, p, mode, which, *scratch)

        g.terminal, g.direction = terminal, -1
        return g

    switching = [e for e in _s.SWITCHING if _s.switching_active(e, mode, t, p)]
    events = [ev(_s.EV_SYNC, until_engaged), ev(_s.EV_PEAK, False)]
    events += [ev(e, True) for e in switching]
    extra = {"jac": jacobian} if method in ("Radau", "BDF", "LSODA") else {}
    if method != "LSODA":
        extra["first_step"] = 1e-10
    sol = solve_ivp(rhs, (t, end), y, method=method, rtol=rtol, atol=atol, events=events, **extra)
    return sol, switching


def _record(p, mode, sol, t_end, out):
    """The engagement and the force's maxima in a phase's solution up to t_end."""
    if np.isnan(out["engagement_time"]) and sol.t_events[0].size and sol.t_events[0][0] <= t_end:
        ys = sol.y_events[0][0]
        out["engagement_time"] = sol.t_events[0][0]
        out["backlash"] = (ys[_s.Y_SLIP] + ys[_s.Y_TRAVEL]) / p[_s.RC]
    points = [
        *zip(sol.t_events[1], sol.y_events[1], strict=True),
        *zip(sol.t, sol.y.T, strict=True),
    ]
    for ti, yi in points:
        if ti <= t_end:
            out["peak_contact_force"] = max(out["peak_contact_force"], _force(ti, yi, p, mode))


def scipy_outputs(p, method="Radau", rtol=1e-12, until_engaged=False):
    """Every output of one scenario (a row of :func:`roller.parameter_rows`) with ``solve_ivp``,
    mode by mode (the kernel's modes, right-hand side, Jacobian, events and mode changes; the
    clock's breaks: control ring stopped, claws at the rollers), to the release or the end time
    (to the engagement if ``until_engaged``). Returns a dict of :data:`OUTPUTS`, ``status``
    (ok or never_locked) and ``nfev``."""
    out = dict.fromkeys(OUTPUTS, np.nan)
    out.update(peak_contact_force=0.0, nfev=0)
    mode, t, y = _s.initial_mode(p), 0.0, np.zeros(4)
    for _ in range(100):  # phases
        end = _s.next_break(t, p)
        sol, switching = _phase(p, mode, t, end, y, method, rtol, until_engaged)
        out["nfev"] += sol.nfev
        hits = [
            (sol.t_events[i + 2][0], i) for i in range(len(switching)) if sol.t_events[i + 2].size
        ]
        _record(p, mode, sol, min(hits)[0] if hits else sol.t[-1], out)
        if until_engaged and sol.t_events[0].size:
            break
        if not hits:  # the clock's break (the claws switched on there) or the end
            t, y = end, sol.y[:, -1].copy()
            mode |= _s.CLAWS if t >= p[_s.TCLAW] else 0
            if t >= p[_s.TEND]:
                break
            continue
        t, i = min(hits)
        y = sol.y_events[i + 2][0].copy()
        out["peak_contact_force"] = max(out["peak_contact_force"], _force(t, y, p, mode))
        e = switching[i]
        mode = _s.switch_mode(mode, e, y, p)
        if e == _s.EV_STICK:
            out["stick_time"], out["slip_backlash"] = t, y[_s.Y_SLIP] / p[_s.RC]
        if e == _s.EV_RELEASE:
            out["release_time"] = t - p[_s.TREL]
            break
    out["status"] = "never_locked" if np.isnan(out["engagement_time"]) else "ok"
    return out


def scipy_engagement(p, method, rtol):
    """Engagement time of one scenario with ``solve_ivp`` (:func:`scipy_outputs` to the
    engagement)."""
    return scipy_outputs(p, method, rtol, until_engaged=True)["engagement_time"]


# ----------------------------------------------------------------------------------- speed
_TIMER = """
import json, os, sys, time
import numpy as np
from clutchlab import roller
kw = dict(np.load(sys.argv[1]))
rtol = float(sys.argv[2])
roller.simulate(rtol=rtol, **{k: v[:2] for k, v in kw.items()})  # load the compiled kernel
best = None
for _ in range(3):
    w0, c0 = time.perf_counter(), time.process_time()
    r = roller.simulate(rtol=rtol, **kw)
    run = (time.process_time() - c0, time.perf_counter() - w0)
    best = run if best is None or run[0] < best[0] else best
n = kw["driving_speed"].size
row = dict(cpu_us=best[0] / n * 1e6, wall_us=best[1] / n * 1e6, load=os.getloadavg()[0])
for k in ("n_steps", "n_rejected", "n_fev", "n_implicit"):
    if k in r:
        row[k] = float(np.mean(r[k]))
print(json.dumps(row))
"""


def _time(src, path, rtol):
    """One timing of :func:`roller.simulate` (the best of 3 calls) on the scenarios saved at
    ``path``, in a subprocess importing clutchlab from ``src`` (None: this one)."""
    env = dict(os.environ)
    if src is not None:
        env["PYTHONPATH"] = str(src)
    out = subprocess.run(
        [sys.executable, "-c", _TIMER, str(path), repr(rtol)],
        env=env,
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def speed(rtol, baseline=None, rounds=2):
    """Rows of µs per simulated scenario on the studies' designs (:data:`CONFIGS`), this code and
    (``baseline``: a ``src`` folder) the other, alternating, ``rounds`` times each; the best."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, (configfile, samples) in CONFIGS.items():
            path = Path(tmp) / f"{name}.npz"
            kw = study_scenarios(configfile, samples)
            np.savez(path, **kw)
            codes = {"this code": None, **({"baseline": baseline} if baseline else {})}
            best = {}
            for _ in range(rounds):
                for label, src in codes.items():
                    r = _time(src, path, rtol)
                    if label not in best or r["cpu_us"] < best[label]["cpu_us"]:
                        best[label] = r
            for label, r in best.items():
                rows.append(dict(designs=name, code=label, scenarios=len(kw["wedge_angle"]), **r))
    return rows


def accuracy(rtol, n):
    """Rows of the largest relative error of each stored output against :func:`scipy_outputs`
    (Radau rtol 1e-12) on n random designs of each of :data:`CONFIGS`, and the statuses that
    differ."""
    rows = []
    rng = np.random.default_rng(1)
    for name, (configfile, samples) in CONFIGS.items():
        kw = study_scenarios(configfile, samples)
        pick = np.sort(rng.choice(kw["wedge_angle"].size, n, replace=False))
        kw = {k: v[pick] for k, v in kw.items()}
        P, _ = roller.parameter_rows(**kw)
        ref = [scipy_outputs(p) for p in P]
        got = roller.simulate(rtol=rtol, **kw)
        row = dict(designs=name, scenarios=n)
        row["status_differs"] = int(
            sum(_STATUS[r["status"]] != g for r, g in zip(ref, got["status"], strict=True))
        )
        for k in OUTPUTS:
            a = np.array([r[k] for r in ref])
            both = np.isfinite(a) & np.isfinite(got[k])
            row[k] = float(np.max(np.abs(got[k][both] / a[both] - 1.0), initial=0.0))
            row["status_differs"] += int(np.sum(np.isfinite(a) != np.isfinite(got[k])))
        rows.append(row)
    return rows


# ----------------------------------------------------------------------------------- report
def _work_precision(P, d, ref, n):
    """Rows of clutchlab's time per scenario and engagement-time error at each rtol, then scipy's."""
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
                method="clutchlab DOP853/SDIRK4 (numba, exact events)",
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
    return rows


def _print_ratios(rows):
    """Each scipy run's time over the fastest clutchlab run with equal or better error."""
    mine = [r for r in rows if r["method"].startswith("clutchlab")]
    for method in ("LSODA", "Radau"):
        for r in (r for r in rows if method in r["method"]):
            ok = [m for m in mine if m["max_engagement_error_s"] <= r["max_engagement_error_s"]]
            if ok:
                m = min(ok, key=lambda m: m["seconds_per_scenario"])
                print(
                    f"ratio vs {method} at rtol {r['rtol']:.0e} (error "
                    f"{r['max_engagement_error_s']:.1e} s): "
                    f"{r['seconds_per_scenario'] / m['seconds_per_scenario']:.0f}x "
                    f"(clutchlab rtol {m['rtol']:.0e}, error {m['max_engagement_error_s']:.1e} s)"
                )


def run(outdir="results/benchmark", n=40, n_reference=10, baseline=None, study=False):
    """The work-precision table; with ``study`` the studies' designs' tables too (they read
    ``config/`` in the working folder)."""
    from ..studies.roller import RTOL

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    d = design(n)
    P, _ = roller.parameter_rows(**d)
    t0 = time.perf_counter()
    ref = np.array([scipy_outputs(p, until_engaged=True)["engagement_time"] for p in P])
    print(
        f"reference: Radau rtol 1e-12, {(time.perf_counter() - t0) / n * 1e3:.0f} ms per scenario; "
        f"engagement times {np.nanmin(ref) * 1e3:.3f}-{np.nanmax(ref) * 1e3:.3f} ms"
    )
    rows = _work_precision(P, d, ref, n)
    for r in rows:
        print(
            f"{r['method']:<50s} rtol {r['rtol']:.0e}: {r['seconds_per_scenario'] * 1e6:9.1f} "
            f"us/scenario, max |engagement time error| {r['max_engagement_error_s']:.2e} s"
        )
    _print_ratios(rows)
    write_rows(rows, outdir / "roller_benchmark.csv")
    if not study:
        return rows, {}
    print(f"the studies' designs at rtol {RTOL:g}:")
    tables = {"speed": speed(RTOL, baseline), "accuracy": accuracy(RTOL, n_reference)}
    for name, table in tables.items():
        for r in table:
            print(
                name,
                ", ".join(
                    f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}" for k, v in r.items()
                ),
            )
        write_rows(table, outdir / f"roller_study_{name}.csv")
    return rows, tables


def main(argv=None):
    import argparse

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("outdir", nargs="?", default="results/benchmark")
    p.add_argument("--scenarios", type=int, default=40)
    p.add_argument("--reference", type=int, default=10)
    p.add_argument("--baseline", default=None, help="src folder of another clutchlab checkout")
    p.add_argument("--no-study", action="store_true", help="the work-precision table only")
    a = p.parse_args(argv)
    run(a.outdir, a.scenarios, a.reference, a.baseline, study=not a.no_study)


if __name__ == "__main__":
    main()

"""Sprag statics benchmark: throughput and accuracy, measured in one run (not a unit test).

``python -m clutchlab.bench.sprag [outdir] [--scenarios N]`` (or ``snakemake benchmark_sprag``)
prints and writes ``sprag_benchmark.csv``:

* a random design of N (default 10⁵, and 10⁶) scenarios around the seed 002 geometry (torque,
  sprag count, length, centre distance, outer arc radius) with the physical compliance;
* clutchlab's :func:`clutchlab.sprag.statics` (gripping angle fixed point plus every stress and
  margin) on the whole design in one call on one core: scenarios per second (best of 3);
* the scipy way: per scenario, :func:`scipy.optimize.brentq` on the same fixed-point function at
  its default tolerance (and at xtol 1e-4, 1e-6, 1e-9), then the stresses — time per scenario on
  a subset and the ratio;
* error: max |V − V_ref| on the subset (scenarios with an answer) against brentq at xtol 1e-15
  (the tighter reference).
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from .. import sprag as sp
from ._common import parse, write_rows


def design(n, seed=0):
    rng = np.random.default_rng(seed)
    g = sp.SEED_GEOMETRY
    return dict(
        torque=rng.uniform(100, 1000, n),
        sprags=rng.integers(14, 23, n).astype(float),
        sprag_length=rng.uniform(12e-3, 22e-3, n),
        centre_distance=rng.uniform(0.70e-3, 0.85e-3, n),
        sprag_outer_radius=g["sprag_outer_radius"] + rng.uniform(-40e-6, 20e-6, n),
    )


def _scalar_statics(d, i, xtol):
    """One scenario the scipy way: brentq on G(V) = V - V_new(V), then the stresses."""
    kw = {k: v[i] for k, v in d.items() if k != "torque"}
    g = {k: np.atleast_1d(v) for k, v in sp._geometry(kw).items()}
    t = np.atleast_1d(d["torque"][i])
    c = np.ones(1)
    v0 = float(sp.rest_geometry(**g)["V"][0])
    v = brentq(
        lambda x: x - sp._deformed(t, np.array([x]), g, c)["V"][0], v0, np.deg2rad(80.0), xtol=xtol
    )
    de = sp._deformed(t, np.array([v]), g, c)
    radii = {
        k: de[k]
        for k in (
            "inner_race_radius",
            "outer_race_radius",
            "sprag_inner_radius",
            "sprag_outer_radius",
        )
    }
    w = np.arcsin(radii["inner_race_radius"] * np.sin(v) / radii["outer_race_radius"])
    sp.contact_stress(t, V=v, W=w, **{**g, **radii})
    sp.shaft_stress(t, V=v, W=w, **{**g, **radii})
    return v


def run(outdir="results/benchmark", n=100_000, n_ref=300):
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    rows = []
    for size in (n, 10 * n):
        d = design(size)
        best = np.inf
        for _ in range(3):
            t0 = time.perf_counter()
            res = sp.statics(**d)
            best = min(best, time.perf_counter() - t0)
        ok = int(np.sum(res["status"] != 6))  # every scenario except not_converged has its answer
        rows.append(
            dict(
                method="clutchlab statics (vectorised)",
                scenarios=size,
                seconds_per_scenario=best / size,
                scenarios_per_second=size / best,
                max_V_error_rad=np.nan,
                answered=ok,
                xtol=np.nan,
            )
        )
        print(
            f"clutchlab statics, {size:>8d} scenarios: {size / best:,.0f} scenarios/s "
            f"({best / size * 1e6:.2f} us each), statuses {np.bincount(res['status']).tolist()}"
        )
    d = design(n)
    # the reference subset: scenarios with an answer (brentq has no bracket where the sprag cannot
    # span the races or rolls over)
    keep = np.flatnonzero(~np.isnan(sp.statics(**d)["V"]))[:n_ref]
    sub = {k: v[keep] for k, v in d.items()}
    ref = np.array([_scalar_statics(sub, i, 1e-15) for i in range(n_ref)])
    mine = sp.statics(**sub)["V"]
    err_mine = float(np.nanmax(np.abs(mine - ref)))
    t0 = time.perf_counter()
    scipy_v = np.array([_scalar_statics(sub, i, 2e-12) for i in range(n_ref)])
    t_scipy = (time.perf_counter() - t0) / n_ref
    err_scipy = float(np.nanmax(np.abs(scipy_v - ref)))
    rows[0]["max_V_error_rad"] = err_mine
    rows.append(
        dict(
            method="scipy brentq per scenario (+ stresses)",
            scenarios=n_ref,
            seconds_per_scenario=t_scipy,
            scenarios_per_second=1 / t_scipy,
            max_V_error_rad=err_scipy,
            answered=n_ref,
            xtol=2e-12,
        )
    )
    for xtol in (1e-4, 1e-6, 1e-9):  # looser brentq: the work-precision line of the scipy way
        t0 = time.perf_counter()
        v = np.array([_scalar_statics(sub, i, xtol) for i in range(n_ref)])
        t = (time.perf_counter() - t0) / n_ref
        rows.append(
            dict(
                method="scipy brentq per scenario (+ stresses)",
                scenarios=n_ref,
                seconds_per_scenario=t,
                scenarios_per_second=1 / t,
                max_V_error_rad=float(np.nanmax(np.abs(v - ref))),
                answered=n_ref,
                xtol=xtol,
            )
        )
    ratio = t_scipy / rows[0]["seconds_per_scenario"]
    print(
        f"scipy brentq per scenario: {1 / t_scipy:,.0f} scenarios/s ({t_scipy * 1e6:.0f} us each)"
    )
    print(
        f"max |V error| vs brentq xtol 1e-15 on {n_ref} scenarios: clutchlab {err_mine:.1e} rad, "
        f"brentq default {err_scipy:.1e} rad"
    )
    print(f"ratio: clutchlab is {ratio:.0f}x faster per scenario than per-scenario brentq")
    write_rows(rows, outdir / "sprag_benchmark.csv")
    return rows


def main(argv=None):
    os.environ.setdefault(
        "OMP_NUM_THREADS", "1"
    )  # one core (numpy element-wise work is single-threaded)
    a = parse(__doc__, 100_000, argv)
    run(a.outdir, a.scenarios)


if __name__ == "__main__":
    main()

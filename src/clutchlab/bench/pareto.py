"""Pareto ranking and hypervolume benchmark: time against design count and objective count (not a
unit test).

``python -m clutchlab.bench.pareto [outdir] [--scenarios N] [--hv-points K]`` prints and writes
``pareto_benchmark.csv`` and ``hypervolume_benchmark.csv``.

Ranks: :func:`clutchlab.explore.pareto_rank` on N uniform random points (default 10⁶; the hardest
usual case: no correlation, hundreds of fronts) with 2, 3 and 4 objectives, 5 objectives on N/10;
best of 3 (one run for 4 and 5 objectives) after a warm-up call; the reference is the plain O(N²)
peeling (every point against every other, numpy-vectorised per point) on a subset, checked equal
and timed for the ratio.

Hypervolume: :func:`clutchlab.explore.hypervolume` of K/10 and K points (default 10⁴) with 4
objectives drawn uniformly on the unit sphere's positive orthant (every point on the front: the
hard case), reference point 1.1 in each objective. Checked against inclusion–exclusion on the
first 12 points (exact, 4 095 terms) and against the bound the sphere gives: no point dominates
anything inside the unit ball, so the volume is at most 1.1⁴ − π²/32 (the box less the ball's
orthant; 1.1^m − V_m/2^m in m objectives), approached as K grows.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from ..explore import hypervolume, pareto_rank
from ._common import parse, write_rows


def peel(f):
    """Reference: repeatedly take the non-dominated points of what is left (O(N²) per front)."""
    n = len(f)
    rank = np.full(n, -1)
    left = np.arange(n)
    k = 0
    while left.size:
        g = f[left]
        dominated = np.array(
            [np.any(np.all(g <= g[i], axis=1) & np.any(g < g[i], axis=1)) for i in range(len(g))]
        )
        rank[left[~dominated]] = k
        left = left[dominated]
        k += 1
    return rank


def inclusion_exclusion(points, reference) -> float:
    """Reference hypervolume (minimisation): the sum over every non-empty subset S of the points of
    (−1)^(|S|+1) times the volume of the box between the componentwise maximum of S and the
    reference (empty where it is not below the reference). Exact; 2^N − 1 terms."""
    p = np.asarray(points, dtype=float)
    ref = np.asarray(reference, dtype=float)
    n = len(p)
    masks = np.arange(1, 2**n)
    member = (masks[:, None] >> np.arange(n)) & 1 == 1  # (subsets, points)
    corner = np.where(member[:, :, None], p[None], -np.inf).max(axis=1)  # (subsets, objectives)
    box = np.clip(ref - corner, 0.0, None).prod(axis=1)
    sign = np.where(member.sum(axis=1) % 2 == 1, 1.0, -1.0)
    return float(np.sum(sign * box))


def sphere_front(k, m, rng):
    """``k`` points uniform on the positive orthant of the unit sphere in ``m`` objectives: a
    front on which no point dominates another."""
    x = np.abs(rng.standard_normal((k, m)))
    return x / np.linalg.norm(x, axis=1, keepdims=True)


def _best(fn, *args, repeat=3):
    """Shortest wall time of ``repeat`` calls of ``fn(*args)`` [s] and its result."""
    wall, _, out = _best_wall_cpu(fn, *args, repeat=repeat)
    return wall, out


def _best_wall_cpu(fn, *args, repeat=3):
    """Shortest wall time and shortest CPU time of this process [s] of ``repeat`` calls of
    ``fn(*args)``, and its result. The CPU time is what a shared machine's load changes least."""
    wall = cpu = np.inf
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        out = fn(*args)
        wall = min(wall, time.perf_counter() - t)
        cpu = min(cpu, time.process_time() - c)
    return wall, cpu, out


def run(outdir, n, reference=2000):
    """Rank rows: time of :func:`pareto_rank` on ``n`` uniform random designs for 2, 3, 4
    objectives (5 on n/10) and the O(N²) peeling on ``reference`` of them; writes
    ``pareto_benchmark.csv``."""
    rng = np.random.default_rng(0)
    rows = []
    for m, size in ((2, n), (3, n), (4, n), (5, max(n // 10, 1000))):
        f = rng.random((size, m))
        pareto_rank(f[:100])  # warm-up (a compile where the ranking is compiled)
        t, cpu, rank = _best_wall_cpu(pareto_rank, f, repeat=3 if m <= 3 and size <= 10**6 else 1)
        sub = f[:reference]
        t_ref, ref = _best(peel, sub, repeat=1)
        t_sub, mine = _best(pareto_rank, sub)
        same = bool((ref == mine).all())
        rows.append(
            dict(
                objectives=m,
                designs=size,
                seconds=t,
                cpu_seconds=cpu,
                fronts=int(rank.max()) + 1,
                front_size=int((rank == 0).sum()),
                reference_designs=len(sub),
                reference_seconds=t_ref,
                clutchlab_seconds_on_reference=t_sub,
                ratio=t_ref / t_sub,
                equal_to_reference=same,
            )
        )
        print(
            f"  {m} objectives, {size} designs: {t:.3f} s (CPU {cpu:.3f} s; {rank.max() + 1} "
            f"fronts, front of {(rank == 0).sum()}); O(N^2) peeling on {len(sub)}: "
            f"{t_ref:.3f} s vs {t_sub * 1e3:.2f} ms ({t_ref / t_sub:.0f}x), equal ranks: {same}"
        )
    write_rows(rows, Path(outdir) / "pareto_benchmark.csv")
    return rows


def run_hypervolume(outdir, k, m=4, sizes=None):
    """Hypervolume rows: time of :func:`hypervolume` on ``k``/10 and ``k`` points of a
    ``m``-objective sphere front (``sizes`` replaces the two counts), the inclusion–exclusion check
    on 12 points and the sphere's bound; writes ``hypervolume_benchmark.csv``."""
    rng = np.random.default_rng(1)
    ref = np.full(m, 1.1)
    bound = (
        1.1**m - np.pi ** (m / 2) / math.gamma(m / 2 + 1) / 2**m
    )  # the box less the ball's orthant
    rows = []
    for size in sizes or (max(k // 10, 12), k):
        p = sphere_front(size, m, rng)
        hypervolume(p[:12], ref)  # warm-up
        t, cpu, hv = _best_wall_cpu(hypervolume, p, ref, repeat=3 if size <= 10**4 else 1)
        exact = inclusion_exclusion(p[:12], ref)
        err = abs(hypervolume(p[:12], ref) - exact) / exact
        rows.append(
            dict(
                objectives=m,
                points=size,
                seconds=t,
                cpu_seconds=cpu,
                hypervolume=hv,
                sphere_bound=bound,
                within_bound=bool(0.0 < hv <= bound * (1 + 1e-12)),
                reference_points=12,
                relative_error_to_inclusion_exclusion=err,
                equal_to_reference=bool(err <= 1e-12),
            )
        )
        print(
            f"  hypervolume, {m} objectives, {size} points on the sphere: {t * 1e3:.1f} ms "
            f"(CPU {cpu * 1e3:.1f} ms; volume {hv:.6f}, bound {bound:.6f}); inclusion-exclusion "
            f"on 12: relative error "
            f"{err:.1e}"
        )
    write_rows(rows, Path(outdir) / "hypervolume_benchmark.csv")
    return rows


def main(argv=None):
    args = parse(__doc__, 10**6, argv, hv_points=10**4)
    Path(args.outdir).mkdir(parents=True, exist_ok=True)
    print(f"Pareto ranking benchmark ({args.scenarios} designs):")
    run(args.outdir, args.scenarios)
    print(f"Hypervolume benchmark ({args.hv_points} points):")
    run_hypervolume(args.outdir, args.hv_points)


if __name__ == "__main__":
    main()

"""Pareto ranking benchmark: time against design count and objective count (not a unit test).

``python -m clutchlab.bench.pareto [outdir] [--scenarios N]`` prints and writes
``pareto_benchmark.csv``: :func:`clutchlab.explore.pareto_rank` on N uniform random points
(default 10⁶; the hardest usual case: no correlation, hundreds of fronts) with 2, 3 and 4
objectives, 5 objectives on N/10; best of 3 (one run for 4 and 5 objectives) after a warm-up call
(numba compile); the reference
is the plain O(N²) peeling (every point against every other, numpy-vectorised per point) on a
subset, checked equal and timed for the ratio.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ._common import parse, write_rows
from ..explore import pareto_rank


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


def _best(fn, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def run(outdir, n, reference=2000):
    rng = np.random.default_rng(0)
    rows = []
    for m, size in ((2, n), (3, n), (4, n), (5, max(n // 10, 1000))):
        f = rng.random((size, m))
        pareto_rank(f[:100])  # compile
        t, rank = _best(lambda: pareto_rank(f), repeat=3 if m <= 3 and size <= 10**6 else 1)
        sub = f[:reference]
        t_ref, ref = _best(lambda: peel(sub), repeat=1)
        t_sub, mine = _best(lambda: pareto_rank(sub))
        same = bool((ref == mine).all())
        rows.append(
            dict(
                objectives=m,
                designs=size,
                seconds=t,
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
            f"  {m} objectives, {size} designs: {t:.3f} s ({rank.max() + 1} fronts, front of "
            f"{(rank == 0).sum()}); O(N^2) peeling on {len(sub)}: {t_ref:.3f} s vs {t_sub * 1e3:.2f} ms "
            f"({t_ref / t_sub:.0f}x), equal ranks: {same}"
        )
    write_rows(rows, Path(outdir) / "pareto_benchmark.csv")
    return rows


def main(argv=None):
    args = parse(__doc__, 10**6, argv)
    Path(args.outdir).mkdir(parents=True, exist_ok=True)
    print(f"Pareto ranking benchmark ({args.scenarios} designs):")
    run(args.outdir, args.scenarios)


if __name__ == "__main__":
    main()

"""Shared plumbing of the benchmark scripts: command line and CSV output."""

from __future__ import annotations

import argparse
import csv

from ..store import atomic


def write_rows(rows, path) -> None:
    """Write a list of equal-keyed dicts as a CSV table (atomically)."""
    with atomic(path) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def report_rows(rows, outdir, name) -> None:
    """Write the rows to ``outdir/name`` (:func:`write_rows`; the folder made) and print one line a row."""
    from pathlib import Path

    Path(outdir).mkdir(parents=True, exist_ok=True)
    write_rows(rows, Path(outdir) / name)
    for row in rows:
        print(", ".join(f"{k}={v}" for k, v in row.items()))


def save_figure(fig, path, dpi=120) -> None:
    """Save a figure as PNG atomically."""
    with atomic(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png")


def parse(doc, default_scenarios, argv=None, **extra):
    """``[outdir] [--scenarios N]`` (plus ``extra`` integer options: name -> default)."""
    p = argparse.ArgumentParser(description=doc.splitlines()[0])
    p.add_argument("outdir", nargs="?", default="results/benchmark")
    p.add_argument("--scenarios", type=int, default=default_scenarios)
    for name, default in extra.items():
        p.add_argument(f"--{name.replace('_', '-')}", type=int, default=default)
    return p.parse_args(argv)


def per_scenario_sweep(solve, scenarios, ref, methods, rtols, error_key, label) -> list[dict]:
    """Rows of the per-scenario scipy way: for each method and rtol, the time per scenario of
    ``solve(scenario, method, rtol)`` over ``scenarios`` and the largest |result - ref|
    (``error_key``); ``label`` is formatted with the method."""
    import time

    import numpy as np

    rows = []
    for method in methods:
        for rtol in rtols:
            t0 = time.perf_counter()
            v = np.array([solve(p, method, rtol) for p in scenarios])
            rows.append(
                {
                    "method": label.format(method=method),
                    "rtol": rtol,
                    "seconds_per_scenario": (time.perf_counter() - t0) / len(scenarios),
                    error_key: float(np.nanmax(np.abs(v - ref))),
                }
            )
    return rows

"""Shared plumbing of the benchmark scripts: command line and CSV output."""
from __future__ import annotations

import argparse
import csv


def write_rows(rows, path) -> None:
    """Write a list of equal-keyed dicts as a CSV table."""
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def parse(doc, default_scenarios, argv=None, **extra):
    """``[outdir] [--scenarios N]`` (plus ``extra`` integer options: name -> default)."""
    p = argparse.ArgumentParser(description=doc.splitlines()[0])
    p.add_argument("outdir", nargs="?", default="results/benchmark")
    p.add_argument("--scenarios", type=int, default=default_scenarios)
    for name, default in extra.items():
        p.add_argument(f"--{name.replace('_', '-')}", type=int, default=default)
    return p.parse_args(argv)

"""The numerics section of the report (issue 17 item 1): a cheap run of each solver benchmark for
the studies of the run, in seconds on small samples, so the report of the run that produced the
numbers shows how fast and how accurate each solver was against the natural alternatives measured
in the same run, and the ratio at equal error. The full benchmarks stay targets of their own
(``snakemake benchmark_compliant``, ``benchmark_roller``, ``benchmark_sprag``, ``benchmark``).

* engagement — the compliant driveline the study runs (:mod:`clutchlab.benchmark_compliant`):
  clutchlab over its accuracy sweep against per-scenario ``solve_ivp`` RK45 (as usually written)
  and DOP853 (as an expert would), reference DOP853 at rtol 1e-13;
* roller — the wedging (:mod:`clutchlab.benchmark_roller`): the compiled SDIRK4 against
  per-scenario LSODA and Radau, reference Radau at rtol 1e-12;
* sprag — the gripping-angle fixed point (:mod:`clutchlab.benchmark_sprag`): vectorised against
  per-scenario ``brentq``, reference brentq at xtol 1e-15.

The diaphragm statics and the centrifugal capacity and release are closed forms (exact to
round-off); their checks are the validation table and the hard cases.

``python -m clutchlab.numerics OUTDIR STUDY...`` writes ``<name>_benchmark.csv`` per solver.
"""
from __future__ import annotations

import sys
from pathlib import Path

__all__ = ["SIZES", "files", "run", "roller_figure", "sprag_figure", "pages"]

# small samples: seconds each on one core (the full benchmarks use 10^4 to 10^6)
SIZES = {"engagement": dict(n=300, n_ref=3), "roller": dict(n=6), "sprag": dict(n=2000, n_ref=40)}
FILES = {"engagement": "compliant_benchmark.csv", "roller": "roller_benchmark.csv", "sprag": "sprag_benchmark.csv"}


def files(study_names) -> list[str]:
    """The CSV names the numerics run writes for these studies."""
    return [FILES[s] for s in study_names if s in FILES]


def run(outdir, study_names) -> list[Path]:
    from . import benchmark_compliant, benchmark_roller, benchmark_sprag

    runner = {"engagement": benchmark_compliant.run, "roller": benchmark_roller.run, "sprag": benchmark_sprag.run}
    out = []
    for s in study_names:
        if s in runner:
            print(f"numerics: {s} ({FILES[s]}, {SIZES[s]})", flush=True)
            runner[s](outdir, **SIZES[s])
            out.append(Path(outdir) / FILES[s])
    return out


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

    from .report.common import A4_LANDSCAPE

    fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
    for j, method in enumerate(dict.fromkeys(r["method"] for r in rows)):
        pts = sorted((r for r in rows if r["method"] == method), key=lambda r: -r[error])  # along the tolerance
        x = [r["seconds_per_scenario"] for r in pts]
        y = [max(r[error], 1e-17) for r in pts]
        ax.loglog(x, y, "o-" if len(pts) > 1 else "o", color=f"C{j}", ms=7, label=method)
        for r in pts:
            if _setting(r, label_key):
                ax.annotate(_setting(r, label_key)[4:], (r["seconds_per_scenario"], max(r[error], 1e-17)),
                            textcoords="offset points", xytext=(4, 4), fontsize=6)
    lines = [f"vs {r['method']}{_setting(r, label_key)} (error {r[error]:.1e}): {ratio:.0f}x faster"
             for r, _, ratio in _ratios(rows, error, ours)]
    ax.margins(0.15)
    ax.set_xlabel("time per scenario [s] (this machine, this run)")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    ax.text(0.01, 0.01, "clutchlab at equal or better error:\n" + "\n".join(lines[:10]) if lines else
            "no alternative reached an error clutchlab's settings cover", transform=ax.transAxes, fontsize=7,
            va="bottom", family="monospace")
    ax.set_title(title, fontsize=10)
    return fig


def roller_figure(rows):
    return _wp_figure(rows, "max_engagement_error_s", "clutchlab",
                      "Work-precision of the roller wedging (small sample of this run): compiled SDIRK4 against "
                      "per-scenario solve_ivp LSODA and Radau\nreference: Radau at rtol 1e-12 with the analytic "
                      "Jacobian, piecewise over slip and stick; error = max |engagement time - reference|",
                      "max |engagement time error| [s]", "rtol")


def sprag_figure(rows):
    rows = [r for r in rows if r["max_V_error_rad"] == r["max_V_error_rad"]]  # the timed-only 10x size: no error
    return _wp_figure(rows, "max_V_error_rad", "clutchlab",
                      "Work-precision of the sprag gripping-angle fixed point (small sample of this run): "
                      "vectorised statics against per-scenario brentq\nreference: brentq at xtol 1e-15; error = "
                      "max |V - V_ref| over the scenarios with an answer", "max |gripping angle error| [rad]",
                      "xtol")


def pages(numerics_dir) -> list[tuple]:
    """(stem, figure) of every numerics CSV present in ``numerics_dir``."""
    from . import benchmark_compliant

    d = Path(numerics_dir)
    out = []
    if (d / FILES["engagement"]).exists():
        out.append(("numerics_engagement", benchmark_compliant.work_precision_figure(
            benchmark_compliant.read_rows(d / FILES["engagement"]))))
    if (d / FILES["roller"]).exists():
        out.append(("numerics_roller", roller_figure(_read(d / FILES["roller"]))))
    if (d / FILES["sprag"]).exists():
        out.append(("numerics_sprag", sprag_figure(_read(d / FILES["sprag"]))))
    return out


def stems(study_names) -> list[str]:
    return [f"numerics_{s}" for s in study_names if s in FILES]


if __name__ == "__main__":
    run(sys.argv[1], sys.argv[2:])

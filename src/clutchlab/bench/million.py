"""The million-design benchmark (issue 16): run ``config/million.yaml`` (every study at 2^20
sampled designs) through Snakemake and measure it (not a unit test).

``python -m clutchlab.bench.million [outdir] [--configfile config/million.yaml] [--cores 2]``
runs ``snakemake --forceall`` on that config as a subprocess in the current project folder and
writes ``million_benchmark.csv``: per study the scenarios, chunk jobs, the physics' own time (sum
over chunks of the time inside the study's compute function), the jobs' time (chunk, merge),
the share of job time outside the physics (reading, writing, merging, imports), the peak RSS of
the study's largest job (Snakemake's per-job benchmark files), and for the whole run the wall
time, the number of jobs and the report job. Run it alone on the machine (the timings are the
point) and not while another run uses the same results folder.
"""

from __future__ import annotations

import argparse
import csv
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from .. import config, studies
from ._common import write_rows


def _tsv(path) -> dict:
    with open(path) as fh:
        row = next(csv.DictReader(fh, delimiter="\t"))
    return {
        "seconds": float(row["s"]),
        "max_rss_mb": float(row["max_rss"]) if row["max_rss"] != "NA" else float("nan"),
    }


def measure(configfile="config/million.yaml", cores=2) -> list[dict]:
    """Run the config through Snakemake (forced) and return the whole run's row, then one per study."""
    import h5py

    cfg = config.load(configfile)
    work = Path(cfg["results"]) / "work"
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "--cores",
        str(cores),
        "--configfile",
        str(configfile),
        "--forceall",
        "--nolock",
        "--quiet",
        "progress",
    ]
    start = time.perf_counter()
    subprocess.run(cmd, check=True)
    wall = time.perf_counter() - start
    rows, jobs = [], 1  # the report job
    for name in cfg["studies"]:
        n_chunks = cfg[name][
            "chunks"
        ]  # this config's chunk files (an earlier run may have left more)
        chunks = [_tsv(work / name / "benchmark" / f"chunk_{i:04d}.tsv") for i in range(n_chunks)]
        merge = _tsv(work / name / "benchmark" / "merge.tsv")
        solver = 0.0
        for p in (work / name / f"chunk_{i:04d}.h5" for i in range(n_chunks)):
            with h5py.File(p, "r") as fh:
                solver += float(np.ravel(fh.attrs["compute_seconds"])[0])
        job_s = sum(c["seconds"] for c in chunks) + merge["seconds"]
        jobs += len(chunks) + 2  # chunks, merge, design
        rows.append(
            dict(
                study=name,
                scenarios=cfg[name]["samples"],
                chunk_jobs=len(chunks),
                physics_seconds=round(solver, 2),
                job_seconds=round(job_s, 2),
                pipeline_share=round(1 - solver / job_s, 3),
                merge_seconds=round(merge["seconds"], 2),
                peak_rss_mb=max([c["max_rss_mb"] for c in chunks] + [merge["max_rss_mb"]]),
                result_mb=round(
                    (Path(cfg["results"]) / studies.get(name).output).stat().st_size / 1e6, 1
                ),
            )
        )
    report = _tsv(work / "report_benchmark.tsv")
    rows.insert(
        0,
        dict(
            study="all",
            scenarios=sum(r["scenarios"] for r in rows),
            chunk_jobs=sum(r["chunk_jobs"] for r in rows),
            physics_seconds=round(sum(r["physics_seconds"] for r in rows), 2),
            job_seconds=round(sum(r["job_seconds"] for r in rows) + report["seconds"], 2),
            pipeline_share=round(
                1
                - sum(r["physics_seconds"] for r in rows)
                / (sum(r["job_seconds"] for r in rows) + report["seconds"]),
                3,
            ),
            merge_seconds=round(sum(r["merge_seconds"] for r in rows), 2),
            peak_rss_mb=max([r["peak_rss_mb"] for r in rows] + [report["max_rss_mb"]]),
            result_mb=round(sum(r["result_mb"] for r in rows), 1),
            wall_seconds=round(wall, 1),
            jobs=jobs,
            report_seconds=round(report["seconds"], 1),
            report_pdf_mb=round(
                (Path(cfg["results"]) / "report" / "report.pdf").stat().st_size / 1e6, 2
            ),
        ),
    )
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("outdir", nargs="?", default="results/benchmark")
    p.add_argument("--configfile", default="config/million.yaml")
    p.add_argument("--cores", type=int, default=2)
    args = p.parse_args(argv)
    print(
        f"Million-design benchmark: snakemake --cores {args.cores} --configfile {args.configfile} (forced)"
    )
    rows = measure(args.configfile, args.cores)
    for r in rows:
        print("  " + ", ".join(f"{k} {v}" for k, v in r.items()))
    Path(args.outdir).mkdir(parents=True, exist_ok=True)
    write_rows(rows, Path(args.outdir) / "million_benchmark.csv")


if __name__ == "__main__":
    main()

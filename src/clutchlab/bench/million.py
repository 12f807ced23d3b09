"""The million-design benchmark: run ``config/million.yaml`` (every study at 2^20
sampled designs) through Snakemake and measure it (not a unit test).

``python -m clutchlab.bench.million [outdir] [--configfile config/million.yaml] [--cores 2]``
runs ``snakemake --forceall`` on that config as a subprocess in the current project folder and
writes ``million_benchmark.csv``: per study the scenarios, chunk jobs, every job (design, chunks,
merge, validation, traces, pages), the physics' own time (sum over chunks of the time inside
the study's compute function, wall and CPU), the wall time of the jobs its result and its report
pages take (chunks, merge, pages) and the share of it outside the physics (``pipeline_share``:
reading, writing, merging, drawing, imports), every job's wall and CPU time and the share of CPU
outside the physics (``outside_share_cpu``; Snakemake's per-job CPU samples under-report), the
peak RSS of the study's largest job (Snakemake's per-job benchmark files); for the whole run the
same summed (``pipeline_share`` with the report and run-pages jobs, the other columns also with
the hard-case and numerics jobs), the wall time, the CPU time of Snakemake and every job
(and of Snakemake itself: that less the jobs'), the report job and the load average before and
after. Run it alone on the machine (the timings are the point) and not while another run uses the
same results folder; on a shared machine compare the CPU columns.
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

    def number(key):
        return float(row[key]) if row.get(key, "NA") != "NA" else float("nan")

    return {"seconds": number("s"), "cpu": number("cpu_time"), "max_rss_mb": number("max_rss")}


# the jobs of a study besides its chunks, by their benchmark file (work/<study>/benchmark/)
STUDY_JOBS = ("design", "merge", "validation", "traces", "pages")
# the run's jobs of no study (work/benchmark/, and the report's work/report_benchmark.tsv)
RUN_JOBS = ("hard_cases", "numerics")
# the report's jobs of no study (work/benchmark/): counted with the pages jobs and the report job
REPORT_JOBS = ("run_pages",)


def _physics(paths) -> tuple[float, float]:
    """The physics' own wall and CPU seconds, summed over chunk files."""
    import h5py

    wall = cpu = 0.0
    for p in paths:
        with h5py.File(p, "r") as fh:
            wall += float(np.ravel(fh.attrs["compute_seconds"])[0])
            cpu += float(np.ravel(fh.attrs["compute_cpu_seconds"])[0])
    return wall, cpu


def _share(inside, total) -> float:
    return round(1 - inside / total, 3) if total > 0 else float("nan")


def _study_row(cfg, work, name) -> dict:
    n_chunks = cfg[name]["chunks"]  # this config's chunk files (an earlier run may have left more)
    chunks = [_tsv(work / name / "benchmark" / f"chunk_{i:04d}.tsv") for i in range(n_chunks)]
    others = {
        job: _tsv(f)
        for job in STUDY_JOBS
        if (f := work / name / "benchmark" / f"{job}.tsv").exists()
    }
    wall, cpu = _physics(work / name / f"chunk_{i:04d}.h5" for i in range(n_chunks))
    jobs = chunks + list(others.values())
    # the jobs a study's result and its report pages take (its design, a fixed few seconds, not)
    chunk_merge = sum(c["seconds"] for c in chunks) + sum(
        others[job]["seconds"] for job in ("merge", "pages") if job in others
    )
    job_s, job_cpu = sum(j["seconds"] for j in jobs), sum(j["cpu"] for j in jobs)
    return dict(
        study=name,
        scenarios=cfg[name]["samples"],
        chunk_jobs=len(chunks),
        jobs=len(jobs),
        physics_seconds=round(wall, 2),
        physics_cpu_seconds=round(cpu, 2),
        chunk_merge_pages_seconds=round(chunk_merge, 2),
        pipeline_share=_share(wall, chunk_merge),
        job_seconds=round(job_s, 2),
        job_cpu_seconds=round(job_cpu, 2),
        outside_share_cpu=_share(cpu, job_cpu),
        merge_seconds=round(others["merge"]["seconds"], 2),
        peak_rss_mb=max(j["max_rss_mb"] for j in jobs),
        result_mb=round((Path(cfg["results"]) / studies.get(name).output).stat().st_size / 1e6, 1),
    )


def _run_row(cfg, work, rows, wall, total_cpu, load) -> dict:
    report = _tsv(work / "report_benchmark.tsv")
    drawing = [report] + [
        _tsv(f) for job in REPORT_JOBS if (f := work / "benchmark" / f"{job}.tsv").exists()
    ]
    extra = [_tsv(f) for job in RUN_JOBS if (f := work / "benchmark" / f"{job}.tsv").exists()]
    extra += drawing
    physics = sum(r["physics_seconds"] for r in rows)
    physics_cpu = sum(r["physics_cpu_seconds"] for r in rows)
    chunk_merge = sum(r["chunk_merge_pages_seconds"] for r in rows) + sum(
        j["seconds"] for j in drawing
    )
    job_s = sum(r["job_seconds"] for r in rows) + sum(j["seconds"] for j in extra)
    job_cpu = sum(r["job_cpu_seconds"] for r in rows) + sum(j["cpu"] for j in extra)
    return dict(
        study="all",
        scenarios=sum(r["scenarios"] for r in rows),
        chunk_jobs=sum(r["chunk_jobs"] for r in rows),
        jobs=sum(r["jobs"] for r in rows) + len(extra),
        physics_seconds=round(physics, 2),
        physics_cpu_seconds=round(physics_cpu, 2),
        chunk_merge_pages_seconds=round(chunk_merge, 2),
        pipeline_share=_share(physics, chunk_merge),
        job_seconds=round(job_s, 2),
        job_cpu_seconds=round(job_cpu, 2),
        outside_share_cpu=_share(physics_cpu, job_cpu),
        merge_seconds=round(sum(r["merge_seconds"] for r in rows), 2),
        peak_rss_mb=max([r["peak_rss_mb"] for r in rows] + [j["max_rss_mb"] for j in extra]),
        result_mb=round(sum(r["result_mb"] for r in rows), 1),
        wall_seconds=round(wall, 1),
        cpu_seconds=round(total_cpu, 1),
        snakemake_cpu_seconds=round(total_cpu - job_cpu, 1),
        report_seconds=round(report["seconds"], 1),
        report_pdf_mb=round(
            (Path(cfg["results"]) / "report" / "report.pdf").stat().st_size / 1e6, 2
        ),
        load_before_after=load,
    )


def measure(configfile="config/million.yaml", cores=2) -> list[dict]:
    """Run the config through Snakemake (forced) and return the whole run's row, then one per
    study. Times are wall seconds unless named CPU; the jobs' from Snakemake's benchmark files,
    the physics' from the chunk files, the run's CPU from the operating system (Snakemake and
    every job it started)."""
    import os
    import resource

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
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    load = f"{os.getloadavg()[0]:.1f}"
    start = time.perf_counter()
    subprocess.run(cmd, check=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    total_cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    load += f" {os.getloadavg()[0]:.1f}"
    rows = [_study_row(cfg, work, name) for name in cfg["studies"]]
    return [_run_row(cfg, work, rows, wall, total_cpu, load), *rows]


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

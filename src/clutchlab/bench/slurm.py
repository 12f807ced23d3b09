"""A large config through the SLURM profile: wall time, jobs, and the share of time spent
waiting on the scheduler (not a unit test; needs a SLURM cluster, e.g. ``bash .ci/slurm-up``).

``python -m clutchlab.bench.slurm [outdir] [--configfile config/million.yaml] [--local]``
runs ``snakemake --workflow-profile workflows/profiles/slurm --configfile ... --forceall`` in the
current project folder and reads back from SLURM (``squeue --states=all``; the CI cluster keeps
finished jobs for an hour) each job's submit, start and end time. It writes ``slurm_benchmark.csv``
and prints: the wall time; the jobs submitted; their run time (start to end) summed; the queue
wait (start - submit) summed over jobs as a share of the jobs' time from submission to end (on a
small cluster mostly jobs waiting for a free core); and the share of the wall time during which no
SLURM job ran: the time spent waiting on the scheduler and the status checks (submission, start,
noticing the end), plus the local target. ``--local`` also runs the same
config with ``--cores`` on this machine for comparison. Run it alone on the machine.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import time
from datetime import datetime

from ._common import report_rows

SUBMITTED = re.compile(r"Job \d+ has been submitted with SLURM jobid (\d+)")


def _times(ids) -> list[tuple[float, float, float]]:
    out = subprocess.run(
        ["squeue", "--states=all", "--noheader", "--format=%V|%S|%e", "--jobs", ",".join(ids)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return [
        tuple(datetime.fromisoformat(t).timestamp() for t in line.split("|"))
        for line in out.split()
    ]


def idle_share(intervals, t0, t1) -> float:
    """Share of [t0, t1] covered by none of the (start, end) intervals."""
    busy, cursor = 0.0, t0
    for s, e in sorted(intervals):
        s, e = max(s, cursor), min(e, t1)
        if e > s:
            busy += e - s
            cursor = e
    return 1 - busy / (t1 - t0)


def run(configfile, profile="workflows/profiles/slurm") -> dict:
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "--workflow-profile",
        profile,
        "--configfile",
        configfile,
        "--forceall",
    ]
    t0 = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    t1 = time.time()
    if proc.returncode:
        raise SystemExit(f"snakemake failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    ids = SUBMITTED.findall(proc.stdout + proc.stderr)
    times = _times(ids)
    wait = sum(start - submit for submit, start, _ in times)
    total = sum(end - submit for submit, _, end in times)
    return dict(
        run="slurm",
        configfile=configfile,
        wall_seconds=round(t1 - t0, 1),
        jobs=len(ids),
        job_seconds=round(sum(end - start for _, start, end in times)),
        queue_wait_share=round(wait / total, 3),
        no_job_running_share=round(idle_share([(s, e) for _, s, e in times], t0, t1), 3),
    )


def run_local(configfile, cores=2) -> dict:
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "--cores",
        str(cores),
        "--configfile",
        configfile,
        "--forceall",
    ]
    t0 = time.time()
    subprocess.run(cmd, check=True, capture_output=True)
    return dict(
        run=f"local --cores {cores}",
        configfile=configfile,
        wall_seconds=round(time.time() - t0, 1),
        jobs="",
        job_seconds="",
        queue_wait_share="",
        no_job_running_share="",
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("outdir", nargs="?", default="results/benchmark")
    ap.add_argument("--configfile", default="config/million.yaml")
    ap.add_argument("--local", action="store_true", help="also run the config locally (--cores 2)")
    args = ap.parse_args(argv)
    rows = [run(args.configfile)]
    if args.local:
        rows.append(run_local(args.configfile))
    report_rows(rows, args.outdir, "slurm_benchmark.csv")


if __name__ == "__main__":
    main()

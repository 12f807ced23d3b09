"""Cluster resources of the Snakemake jobs: what each job asks SLURM for.

A chunk job's memory and run time follow from the scenarios it holds (the study's size over its
chunk count) and the study's measured cost: a fixed part (Python, imports, the compiled-code
cache) plus a cost per scenario. :data:`CHUNK_COST` holds the measurement of
``python -m clutchlab.bench.resources --sizes 16384 262144`` (one chunk job of each size in a
fresh process, on the widest ranges clutchlab ships, ``config/million.yaml``, with every scenario's
curves stored as a factorial grid stores them; 2-core x86_64 workstation, 2026-11-24). A cluster
node may be slower or shared, and a design's hard corner slower than the sample, so the request
is the measurement times :data:`TIME_MARGIN` (at least :data:`MIN_RUNTIME` minutes) and times
:data:`MEMORY_MARGIN` (at least :data:`MIN_MEM_MB`). Merge and report jobs read columns of the
merged results: their memory grows with the scenarios too (session 8's million run: a 2^20 merge
peaked at 0.54 GB, the report of 5 x 2^20 at 1.38 GB).

Every job runs on one core (``cpus_per_task`` 1): the physics is single-threaded per process,
and a study runs in parallel as its chunk jobs.
"""

from __future__ import annotations

import math

from .config import scenario_count

# study -> (fixed seconds, seconds per scenario, fixed MB, MB per scenario), measured (see above)
CHUNK_COST = {
    "diaphragm_spring": (1.02, 10.5e-6, 231, 2.91 / 1024),
    "engagement": (1.36, 33.2e-6, 272, 0.30 / 1024),
    "centrifugal": (0.98, 17.2e-6, 210, 4.56 / 1024),
    "sprag": (1.18, 2.5e-6, 221, 0.30 / 1024),
    "roller": (1.30, 79.6e-6, 272, 0.33 / 1024),
}
TIME_MARGIN = 5.0
MEMORY_MARGIN = 1.5
MIN_RUNTIME = 10  # minutes
MIN_MEM_MB = 1000
# merge and report: MB fixed and per scenario (the million run's peaks with a margin of ~2)
MERGE_MB = (500, 1.0 / 1024)
REPORT_MB = (1000, 0.6 / 1024)


def _mem(mb: float) -> int:
    return int(max(MIN_MEM_MB, math.ceil(MEMORY_MARGIN * mb / 100) * 100))


def chunk_scenarios(resolved_study: dict) -> int:
    """Scenarios of the largest chunk job of a study."""
    return -(-scenario_count(resolved_study) // resolved_study["chunks"])


def chunk_resources(resolved_study: dict) -> dict:
    """mem_mb, runtime (minutes) and cpus_per_task of one chunk job of a resolved study."""
    fixed_s, per_s, fixed_mb, per_mb = CHUNK_COST[resolved_study["name"]]
    n = chunk_scenarios(resolved_study)
    runtime = max(MIN_RUNTIME, math.ceil(TIME_MARGIN * (fixed_s + per_s * n) / 60))
    return {"mem_mb": _mem(fixed_mb + per_mb * n), "runtime": runtime, "cpus_per_task": 1}


def merge_resources(resolved_study: dict) -> dict:
    """mem_mb, runtime and cpus_per_task of the merge job of a resolved study."""
    n = scenario_count(resolved_study)
    return {
        "mem_mb": _mem(MERGE_MB[0] + MERGE_MB[1] * n),
        "runtime": MIN_RUNTIME + n // 200_000,
        "cpus_per_task": 1,
    }


def report_resources(resolved: dict) -> dict:
    """mem_mb, runtime and cpus_per_task of the report job of a resolved config (all its studies)."""
    n = sum(scenario_count(resolved[s]) for s in resolved["studies"])
    return {
        "mem_mb": _mem(REPORT_MB[0] + REPORT_MB[1] * n),
        "runtime": MIN_RUNTIME + n // 500_000,
        "cpus_per_task": 1,
    }

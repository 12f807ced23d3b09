"""Cluster resources of the Snakemake jobs: what each job asks SLURM for.

A chunk job's memory and run time follow from the scenarios it holds (the study's size over its
chunk count) and the study's measured cost: a fixed part (Python, imports, the compiled-code
cache) plus a cost per scenario. :data:`CHUNK_COST` holds the measurement of
``python -m clutchlab.bench.resources --sizes 16384 262144`` (one chunk job of each size in a
fresh process, on the widest ranges clutchlab ships, ``config/million.yaml``, with every scenario's
curves stored as a factorial grid stores them; 2-core x86_64 workstation, 2026-11-27). A cluster
node may be slower or shared, and a design's hard corner slower than the sample, so the request
is the measurement times :data:`TIME_MARGIN` (at least :data:`MIN_RUNTIME` minutes) and times
:data:`MEMORY_MARGIN` (at least :data:`MIN_MEM_MB`). A study's merge and pages jobs read columns
of its merged result: their memory grows with the scenarios too (the million run of 2026-11-24: a
2^20 merge peaked at 0.54 GB). The report job joins the studies' page files and draws the run's
own pages (summary, tables, solver benchmarks): a fixed size.

Every job runs on one core (``cpus_per_task`` 1): the physics is single-threaded per process, a
study runs in parallel as its chunk jobs, and the report's pages as each study's pages job.
"""

from __future__ import annotations

import math

from .config import scenario_count

# study -> (fixed seconds, seconds per scenario, fixed MB, MB per scenario), measured (see above)
CHUNK_COST = {
    "diaphragm_spring": (1.72, 17.9e-6, 238, 2.98 / 1024),
    "engagement": (2.14, 88.1e-6, 279, 0.58 / 1024),
    "centrifugal": (1.43, 25.5e-6, 211, 4.41 / 1024),
    "sprag": (1.76, 3.8e-6, 224, 0.31 / 1024),
    "roller": (1.98, 32.1e-6, 279, 0.35 / 1024),
}
TIME_MARGIN = 5.0
MEMORY_MARGIN = 1.5
MIN_RUNTIME = 10  # minutes
MIN_MEM_MB = 1000
# merge and a study's pages: MB fixed and per scenario (the million run's peaks with a margin of ~2)
MERGE_MB = (500, 1.0 / 1024)
PAGES_MB = (500, 1.0 / 1024)
REPORT_MB = 1000


def _mem(mb: float) -> int:
    return int(max(MIN_MEM_MB, math.ceil(MEMORY_MARGIN * mb / 100) * 100))


def chunk_scenarios(resolved_study: dict) -> int:
    """Scenarios of the largest chunk job of a study."""
    return -(-scenario_count(resolved_study) // resolved_study["chunks"])


def chunk_seconds(resolved_study: dict) -> float:
    """The measured wall time [s] of one chunk job of a resolved study (no margin)."""
    fixed_s, per_s, _, _ = CHUNK_COST[resolved_study["name"]]
    return fixed_s + per_s * chunk_scenarios(resolved_study)


def chunk_resources(resolved_study: dict) -> dict:
    """mem_mb, runtime (minutes) and cpus_per_task of one chunk job of a resolved study."""
    _, _, fixed_mb, per_mb = CHUNK_COST[resolved_study["name"]]
    runtime = max(MIN_RUNTIME, math.ceil(TIME_MARGIN * chunk_seconds(resolved_study) / 60))
    mb = fixed_mb + per_mb * chunk_scenarios(resolved_study)
    return {"mem_mb": _mem(mb), "runtime": runtime, "cpus_per_task": 1}


def chunk_priority(resolved: dict, study: str, i: int) -> int:
    """Snakemake priority of chunk ``i`` of ``study`` in a resolved config: every study's first
    chunk before any other chunk (a first chunk compiles the study's kernels, its other chunks
    load them), and among equals the longest first (by :func:`chunk_seconds`: Graham's
    longest-processing-time rule, so that the run does not end waiting for one long chunk). From
    2 up to 1 + 2 x the studies (the design jobs ask for more: :data:`DESIGN_PRIORITY`)."""
    order = sorted(resolved["studies"], key=lambda s: chunk_seconds(resolved[s]))
    rank = 2 + order.index(study)
    return rank + len(order) if int(i) == 0 else rank


#: The design jobs' priority, above every chunk's (:func:`chunk_priority`): they take seconds and
#: a study's chunks wait for its design.
DESIGN_PRIORITY = 100


def merge_resources(resolved_study: dict) -> dict:
    """mem_mb, runtime and cpus_per_task of the merge job of a resolved study."""
    n = scenario_count(resolved_study)
    return {
        "mem_mb": _mem(MERGE_MB[0] + MERGE_MB[1] * n),
        "runtime": MIN_RUNTIME + n // 200_000,
        "cpus_per_task": 1,
    }


def pages_resources(resolved_study: dict) -> dict:
    """mem_mb, runtime and cpus_per_task of the pages job of a resolved study (its report pages and
    explorer)."""
    n = scenario_count(resolved_study)
    return {
        "mem_mb": _mem(PAGES_MB[0] + PAGES_MB[1] * n),
        "runtime": MIN_RUNTIME + n // 500_000,
        "cpus_per_task": 1,
    }


def report_resources(resolved: dict) -> dict:
    """mem_mb, runtime and cpus_per_task of the report job of a resolved config (the summary, the
    page files joined) and of its run-pages job (the run's own pages)."""
    return {"mem_mb": _mem(REPORT_MB), "runtime": MIN_RUNTIME, "cpus_per_task": 1}

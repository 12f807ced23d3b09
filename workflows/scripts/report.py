"""Snakemake script: build the report from stored results."""

from pathlib import Path

from clutchlab import report

sm = snakemake  # noqa: F821


def job_seconds(study):
    """(jobs, seconds) of a study's chunk and merge jobs from Snakemake's benchmark files, if any."""
    import csv

    folder = (
        Path(sm.params.work) / study / "benchmark"
    )  # this run's chunk files (an earlier run may have left more)
    files = [folder / f"chunk_{i:04d}.tsv" for i in range(sm.params.chunks[study])] + [
        folder / "merge.tsv"
    ]
    seconds = []
    for f in (f for f in files if f.exists()):
        with open(f) as fh:
            seconds += [float(row["s"]) for row in csv.DictReader(fh, delimiter="\t")]
    return (len(seconds), sum(seconds)) if seconds else None


report.build(
    dict(zip(sm.params.names, sm.input.studies)),
    list(sm.input.validation),
    Path(sm.output[0]).parent,
    title=sm.params.title,
    dpi=sm.params.dpi,
    benchmark_csv=sm.input.benchmark[0] if sm.input.benchmark else None,
    sensitivity_files=dict(zip(sm.params.sensitivity_names, sm.input.sensitivity)),
    refine_files=dict(zip(sm.params.refined_names, sm.input.refined)),
    traces_files=dict(zip(sm.params.traced_names, sm.input.traces)),
    hard_cases_file=sm.input.hard_cases[0] if sm.input.hard_cases else None,
    numerics_dir=Path(sm.input.numerics[0]).parent if sm.input.numerics else None,
    job_seconds={s: t for s in sm.params.names if (t := job_seconds(s))},
)

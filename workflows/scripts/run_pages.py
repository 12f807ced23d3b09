"""Snakemake script: the run's pages after the studies' (work-precision, validation table,
numerics, hard cases) as PNGs and the run's part of the report PDF."""

from pathlib import Path

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821
with job_log(sm.log[0]):
    from clutchlab import report

    report.run_part(
        Path(sm.output.files[0]).parent,
        sm.output.part,
        list(sm.input.validation),
        studies=list(sm.params.studies),
        dpi=sm.params.dpi,
        benchmark_csv=sm.input.benchmark[0] if sm.input.benchmark else None,
        numerics_dir=Path(sm.input.numerics[0]).parent if sm.input.numerics else None,
        hard_cases_file=sm.input.hard_cases[0] if sm.input.hard_cases else None,
    )

"""Snakemake script: build the report from stored results."""
from pathlib import Path

from clutchlab import report

sm = snakemake  # noqa: F821
report.build(dict(zip(sm.params.names, sm.input.studies)), list(sm.input.validation),
             Path(sm.output[0]).parent, title=sm.params.title, dpi=sm.params.dpi,
             benchmark_csv=sm.input.benchmark[0] if sm.input.benchmark else None,
             sensitivity_files=dict(zip(sm.params.sensitivity_names, sm.input.sensitivity)),
             refine_files=dict(zip(sm.params.refined_names, sm.input.refined)),
             hard_cases_file=sm.input.hard_cases[0] if sm.input.hard_cases else None,
             numerics_dir=Path(sm.input.numerics[0]).parent if sm.input.numerics else None)

"""Snakemake script: the interactive explorer of one study (clutchlab.report.explorer)."""

from clutchlab.report import explorer

sm = snakemake  # noqa: F821

explorer.write(sm.input[0], sm.output[0])

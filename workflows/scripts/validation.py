"""Snakemake script: the seed numbers a study reproduces, as a validation Dataset."""

from clutchlab import store, studies

sm = snakemake  # noqa: F821
store.write(studies.get(sm.wildcards.study).validation(), sm.output[0], with_checksum=True)

"""Snakemake script: build a study's design and store it (no physics here)."""

from clutchlab import doe, store

store.write(doe.build_design(snakemake.params.study), snakemake.output[0])  # noqa: F821

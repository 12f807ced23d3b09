"""Snakemake script: merge a study's chunk files into its result file."""
from clutchlab import doe, store

sm = snakemake  # noqa: F821
design = store.load(sm.input.design)
store.write(doe.merge(design, [store.load(p) for p in sm.input.chunks]), sm.output[0])

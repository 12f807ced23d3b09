"""Snakemake script: merge a study's chunk files into its result file."""
from clutchlab import doe, store

sm = snakemake  # noqa: F821
design = store.load(sm.input.design)
# each chunk's data checked against the checksum it was written with: a changed or cut chunk is
# removed and named (CorruptChunk), and the next run recomputes it
store.write(doe.merge(design, [store.load_verified(p) for p in sm.input.chunks]), sm.output[0])

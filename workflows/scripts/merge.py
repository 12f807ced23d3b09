"""Snakemake script: merge a study's chunk files into its result file."""
from clutchlab import doe, explore, store

sm = snakemake  # noqa: F821
design = store.load(sm.input.design)
# each chunk's data checked against the checksum it was written with: a changed or cut chunk is
# removed and named (CorruptChunk), and the next run recomputes it
ds = doe.merge(design, [store.load_verified(p) for p in sm.input.chunks])
# design answers over the whole study: feasibility, constraint margins, Pareto rank
store.write(explore.annotate(ds, list(sm.params.objectives), dict(sm.params.constraints)), sm.output[0])

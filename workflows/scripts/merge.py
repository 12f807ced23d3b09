"""Snakemake script: merge a study's chunk files into its result file."""
from clutchlab import doe, explore, store

sm = snakemake  # noqa: F821
design = store.load(sm.input.design)
# each chunk's data checked against the checksum it was written with: a changed or cut chunk is
# removed and named (CorruptChunk), and the next run recomputes it
ds = doe.merge(design, [store.load_verified(p) for p in sm.input.chunks])
# design answers over the whole study: feasibility, constraint margins, Pareto rank
ds = explore.annotate(ds, list(sm.params.objectives), dict(sm.params.constraints))
store.write(ds, sm.output[0])
if len(sm.output) > 1:  # a factorial grid: main and total effects on every objective and constraint
    outputs = [o.split(":")[0] for o in sm.params.objectives] + list(sm.params.constraints)
    store.write(explore.sensitivity(ds, outputs), sm.output[1])

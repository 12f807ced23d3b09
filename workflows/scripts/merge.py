"""Snakemake script: merge a study's chunk files into its result file, chunk by chunk."""

from clutchlab import pipeline, store

sm = snakemake  # noqa: F821
# each chunk's data checked against the checksum it was written with (a changed or cut chunk is
# removed and named: CorruptChunk, and the next run recomputes it), written into its region of the
# pre-sized result file; then the design answers (feasibility, constraint margins, Pareto rank)
# and, for factorial and saltelli designs, the sensitivity indices
pipeline.merge_to_file(
    store.load(sm.input.design),
    list(sm.input.chunks),
    sm.output[0],
    list(sm.params.objectives),
    dict(sm.params.constraints),
    sm.output[1] if len(sm.output) > 1 else None,
)

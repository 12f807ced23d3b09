"""Snakemake script: merge a study's chunk files into its result file, chunk by chunk."""

from clutchlab import pipeline, store, verify

sm = snakemake  # noqa: F821
# each chunk checked against the checksum it was written with (values and attributes) and against
# what produced it (this design, this study config, this source, its place among the chunks): a
# changed, cut or foreign chunk is removed and named, and the next run recomputes it. Each is
# written into its region of the pre-sized result file; then the design answers (feasibility,
# constraint margins, Pareto rank), the result's own checksum and, for factorial and saltelli
# designs, the sensitivity indices
try:
    pipeline.merge_to_file(
        store.load_verified(sm.input.design),
        list(sm.input.chunks),
        sm.output[0],
        list(sm.params.objectives),
        dict(sm.params.constraints),
        sm.output[1] if len(sm.output) > 1 else None,
        config=sm.params.config,
        source=sm.params.source,
    )
except store.CorruptChunk as exc:  # a chunk or the design, named and removed: the next run
    # recomputes it
    raise SystemExit(f"clutchlab: {exc}") from None
except verify.ProvenanceError as exc:  # the design file is not this config's or source's
    raise SystemExit(
        f"clutchlab: {sm.input.design}: {exc}; delete it and run snakemake again to rebuild it"
    ) from None

"""Snakemake script: merge a study's chunk files into its result file, chunk by chunk; then the
traces of the design its pages show."""

from pathlib import Path

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821
with job_log(sm.log[0]):
    from clutchlab import pipeline, store, verify

    # each chunk checked against the checksum it was written with (values and attributes) and
    # against what produced it (this design, this study config, this source, its place among the
    # chunks): a changed, cut or foreign chunk is removed and named, and the next run recomputes
    # it. Each is written into its region of the pre-sized result file; then the design answers
    # (feasibility, constraint margins, Pareto rank), the result's own checksum and, for factorial
    # and saltelli designs, the sensitivity indices; for a robust study its robust answers
    try:
        pipeline.merge_to_file(
            store.load_verified(sm.input.design),
            list(sm.input.chunks),
            sm.output[0],
            list(sm.params.objectives),
            dict(sm.params.constraints),
            next((p for p in sm.output if p.endswith("sensitivity.h5")), None),
            config=sm.params.config,
            source=sm.params.source,
            robust_path=next((p for p in sm.output if p.endswith("robust.h5")), None),
        )
    except store.CorruptChunk as exc:  # a chunk or the design, named and removed: the next run
        # recomputes it
        raise SystemExit(f"clutchlab: {exc}") from None
    except verify.ProvenanceError as exc:  # the design file is not this config's or source's
        raise SystemExit(
            f"clutchlab: {sm.input.design}: {exc}; delete it and run snakemake again to rebuild it"
        ) from None
    traces = next((p for p in sm.output if p.endswith("traces.h5")), None)
    if traces is not None:  # the traces of the design the study's pages show
        pipeline.traces_to_file(sm.output[0], dict(sm.params.options), traces)
    if not any(p.endswith("robust.h5") for p in sm.output):
        # not a robust study in this config: robust answers an earlier config left beside it are
        # stale
        Path(sm.output[0]).with_name("robust.h5").unlink(missing_ok=True)

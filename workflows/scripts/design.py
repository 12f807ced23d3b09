"""Snakemake script: build a study's design and store it (no physics here)."""

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821
with job_log(sm.log[0]):
    from clutchlab import doe, store, verify

    try:  # a refinement samples near a stored first-stage result: only one that verifies
        verify.require(
            {p: {"design": False} for p in sm.input},
            action="it is the first-stage result this refinement starts from: delete it and "
            "recompute it with the config that produced it",
        )
    except verify.ProvenanceError as exc:
        raise SystemExit(
            f"clutchlab: the design is not built from a file that fails:\n{exc}"
        ) from None
    # with its checksum: the chunk and merge jobs read it verified, so a design changed after it
    # was written is found (not computed from)
    store.write(doe.build_design(sm.params.study), sm.output[0], with_checksum=True)

"""Snakemake script: one study's part of the report (its pages, tables and explorer), built from
verified files only (its result against its checksum, its study config and this source; the
sensitivity and robust answers against their checksums; a refinement's first stage against its
checksum and provenance)."""

from pathlib import Path

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821


def verified_inputs():
    """The result, loaded and checked in memory (one read of the file); the other inputs checked."""
    from clutchlab import verify

    first_stage = (
        "it is the first-stage result a refinement starts from: delete it and recompute it with "
        "the config that produced it"
    )
    expected = {p: {} for p in [*sm.input.sensitivity, *sm.input.robust]}
    for p in [*sm.input.refined, *sm.input.refined_robust]:
        expected.setdefault(p, {"design": False, "action": first_stage})
    try:
        verify.require(expected)
        return verify.load_checked(
            sm.input.result, config=sm.params.config, source=sm.params.source
        )
    except verify.ProvenanceError as exc:
        raise SystemExit(
            f"clutchlab: the report is not built from a file that fails:\n{exc}"
        ) from None


def first(files):
    return files[0] if files else None


with job_log(sm.log[0]):
    from clutchlab import report

    report.study_part(
        sm.params.study,
        verified_inputs(),
        Path(sm.output.explorer).parent,
        sm.output.part,
        dpi=sm.params.dpi,
        sensitivity=first(sm.input.sensitivity),
        refine=first(sm.input.refined),
        traces=first(sm.input.traces),
        robust=first(sm.input.robust),
        refine_robust=first(sm.input.refined_robust),
        explorer=sm.output.explorer,
    )

"""Snakemake script: the interactive explorer of one study (clutchlab.report.explorer), built
from a verified result only (its checksum, its study config, this source), as the report is."""

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821
with job_log(sm.log[0]):
    from clutchlab import verify
    from clutchlab.report import explorer

    try:
        verify.require(
            {sm.input[0]: {"config": sm.params.config, "source": sm.params.source}},
            action="delete it and run snakemake again to recompute it",
        )
    except verify.ProvenanceError as exc:
        raise SystemExit(
            f"clutchlab: the explorer is not built from a file that fails:\n{exc}"
        ) from None
    explorer.write(sm.input[0], sm.output[0])

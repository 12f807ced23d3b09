"""Snakemake script: the report from the studies' parts (each drawn by its study's pages job from
its verified result), the run's part (the run_pages job) and the summary page."""

from pathlib import Path

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821


def job_seconds(study):
    """(jobs, seconds) of a study's chunk and merge jobs from Snakemake's benchmark files, if any
    (this run's: an earlier run may have left more chunk files)."""
    import csv

    seconds = []
    for f in (Path(f) for f in sm.params.job_benchmarks[study] if Path(f).exists()):
        with open(f) as fh:
            seconds += [float(row["s"]) for row in csv.DictReader(fh, delimiter="\t")]
    return (len(seconds), sum(seconds)) if seconds else None


with job_log(sm.log[0]):
    from clutchlab import report, verify

    try:
        report.assemble(
            list(sm.input.parts),
            list(sm.input.validation),
            Path(sm.output[0]).parent,
            title=sm.params.title,
            dpi=sm.params.dpi,
            run_part_pdf=sm.input.run_part[0] if sm.input.run_part else None,
            job_seconds={s: t for s in sm.params.names if (t := job_seconds(s))},
            explorers={
                s: Path(f).name for s, f in zip(sm.params.names, sm.input.explorers, strict=True)
            },
            # each study's pages must have been drawn from the result in place
            results=list(sm.input.studies),
        )
    except verify.ProvenanceError as exc:
        raise SystemExit(f"clutchlab: {exc}") from None

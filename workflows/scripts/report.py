"""Snakemake script: build the report from stored results."""

from pathlib import Path

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821


def job_seconds(study):
    """(jobs, seconds) of a study's chunk and merge jobs from Snakemake's benchmark files, if any."""
    import csv

    folder = (
        Path(sm.params.work) / study / "benchmark"
    )  # this run's chunk files (an earlier run may have left more)
    files = [folder / f"chunk_{i:04d}.tsv" for i in range(sm.params.chunks[study])] + [
        folder / "merge.tsv"
    ]
    seconds = []
    for f in (f for f in files if f.exists()):
        with open(f) as fh:
            seconds += [float(row["s"]) for row in csv.DictReader(fh, delimiter="\t")]
    return (len(seconds), sum(seconds)) if seconds else None


def verify_inputs():
    from clutchlab import verify

    """The report is built from verified files only: each study result against its checksum, its
    study config, this source and its design (work/<study>/design.h5); each sensitivity file
    against its checksum, the first-stage result of a refinement against its checksum and
    provenance (it comes from another config: its design may have been rebuilt since)."""
    first_stage = (
        "it is the first-stage result a refinement starts from: delete it and recompute it with "
        "the config that produced it"
    )
    expected = {
        path: {"config": sm.params.configs[name], "source": sm.params.source}
        for name, path in zip(sm.params.names, sm.input.studies, strict=True)
    }
    for p in [*sm.input.sensitivity, *sm.input.robust]:
        expected[p] = {}
    for p in [*sm.input.refined, *sm.input.refined_robust]:  # (this run's too, checked as one)
        expected.setdefault(p, {"design": False, "action": first_stage})
    try:
        verify.require(expected, action="delete it and run snakemake again to recompute it")
    except verify.ProvenanceError as exc:
        raise SystemExit(
            f"clutchlab: the report is not built from a file that fails:\n{exc}"
        ) from None


with job_log(sm.log[0]):
    from clutchlab import report

    verify_inputs()
    report.build(
        dict(zip(sm.params.names, sm.input.studies, strict=False)),
        list(sm.input.validation),
        Path(sm.output[0]).parent,
        title=sm.params.title,
        dpi=sm.params.dpi,
        benchmark_csv=sm.input.benchmark[0] if sm.input.benchmark else None,
        sensitivity_files=dict(
            zip(sm.params.sensitivity_names, sm.input.sensitivity, strict=False)
        ),
        refine_files=dict(zip(sm.params.refined_names, sm.input.refined, strict=False)),
        traces_files=dict(zip(sm.params.traced_names, sm.input.traces, strict=False)),
        robust_files=dict(zip(sm.params.robust_names, sm.input.robust, strict=False)),
        refine_robust_files=dict(
            zip(sm.params.refined_robust_names, sm.input.refined_robust, strict=True)
        ),
        hard_cases_file=sm.input.hard_cases[0] if sm.input.hard_cases else None,
        numerics_dir=Path(sm.input.numerics[0]).parent if sm.input.numerics else None,
        job_seconds={s: t for s in sm.params.names if (t := job_seconds(s))},
        explorers={
            s: Path(f).name for s, f in zip(sm.params.names, sm.input.explorers, strict=True)
        },
        processes=sm.threads,
    )

"""Snakemake script: the published numbers each validated study reproduces, as validation Datasets."""

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821
with job_log(sm.log[0]):
    from clutchlab import store, studies

    for name, path in zip(sm.params.studies, sm.output, strict=True):
        store.write(studies.get(name).validation(), path, with_checksum=True)

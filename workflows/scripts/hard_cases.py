"""Snakemake script: the hard cases of the studies run (clutchlab.hardcases), as a Dataset."""

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821
with job_log(sm.log[0]):
    from clutchlab import hardcases, store

    store.write(
        hardcases.to_dataset(hardcases.run(list(sm.params.studies))),
        sm.output[0],
        with_checksum=True,
    )

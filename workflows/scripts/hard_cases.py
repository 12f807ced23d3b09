"""Snakemake script: the hard cases of the studies run (clutchlab.hardcases), as a Dataset."""

from clutchlab import hardcases, store

sm = snakemake  # noqa: F821
store.write(
    hardcases.to_dataset(hardcases.run(list(sm.params.studies))), sm.output[0], with_checksum=True
)

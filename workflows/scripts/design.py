"""Snakemake script: build a study's design and store it (no physics here)."""

from clutchlab import doe, store

sm = snakemake  # noqa: F821
# with its checksum: the chunk and merge jobs read it verified, so a design changed after it was
# written is found (not computed from)
store.write(doe.build_design(sm.params.study), sm.output[0], with_checksum=True)

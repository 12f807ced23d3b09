"""Snakemake script: compute one chunk of a design (no physics here)."""
import re

from clutchlab import doe, store

sm = snakemake  # noqa: F821
i = int(re.search(r"chunk_(\d+)\.h5$", sm.output[0]).group(1))
design = store.load(sm.input[0])
store.write(doe.run_chunk(design, dict(sm.params.options), int(sm.params.chunks), i), sm.output[0],
            with_checksum=True, complevel=0)  # uncompressed: written once, read once by the merge

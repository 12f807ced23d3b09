"""Snakemake script: compute one chunk of a design (no physics here)."""

import re
import sys

from clutchlab import pipeline, store

sm = snakemake  # noqa: F821
i = int(re.search(r"chunk_(\d+)\.h5$", sm.output[0]).group(1))
try:  # the design as it was written (a changed design is removed and rebuilt by the next run)
    design = store.load_verified(sm.input[0])
except store.CorruptChunk as exc:
    raise SystemExit(f"clutchlab: {exc}") from None
with open(sm.log[0], "w") as log:

    def progress(line):  # to the job's log and to the terminal (a large chunk: after each tenth)
        for stream in (log, sys.stderr):
            print(line, file=stream, flush=True)

    ds = pipeline.run_chunk(
        design, dict(sm.params.options), int(sm.params.chunks), i, progress=progress
    )
# uncompressed: written once, read once by the merge; with its checksum (values and attributes)
# and what produced it (design hash, config, source, chunk index and count: clutchlab.verify)
store.write(ds, sm.output[0], with_checksum=True, complevel=0)

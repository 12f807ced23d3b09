"""Snakemake script: compute one chunk of a design (no physics here)."""

import re
import sys

from clutchlab._joblog import job_log

sm = snakemake  # noqa: F821
with job_log(sm.log[0]):  # progress (scenarios done, rate, time left) to the log and the terminal
    from clutchlab import pipeline, store

    i = int(re.search(r"chunk_(\d+)\.h5$", sm.output[0]).group(1))
    try:  # the design as it was written (a changed design is removed and rebuilt by the next run)
        design = store.load_verified(sm.input[0])
    except store.CorruptChunk as exc:
        raise SystemExit(f"clutchlab: {exc}") from None

    def progress(line):  # a large chunk: after each tenth
        print(line, file=sys.stderr, flush=True)

    ds = pipeline.run_chunk(
        design, dict(sm.params.options), int(sm.params.chunks), i, progress=progress
    )
    # uncompressed: written once, read once by the merge; with its checksum (values and
    # attributes) and what produced it (design hash, config, source, chunk index and count:
    # clutchlab.verify)
    store.write(ds, sm.output[0], with_checksum=True, complevel=0)

"""What one chunk job of each study costs per scenario: the measurement behind the
cluster resources of :mod:`clutchlab.cluster` (not a unit test).

``python -m clutchlab.bench.resources [outdir] [--sizes 16384 262144]`` runs, for each study of
``config/million.yaml`` (the widest ranges clutchlab ships, each study's option choices drawn per
scenario), one chunk job of each size in a fresh Python process, as the Snakemake chunk rule does
(load the design, ``pipeline.run_chunk``, write the chunk file), and records its wall time and peak RSS.
A straight line through the sizes gives the fixed cost (imports, compiled-code cache, Python) and
the cost per scenario; it writes ``resources_benchmark.csv`` and prints the table. Run it alone on
the machine.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile

from ._common import report_rows

_CHILD = r"""
import json, resource, sys, time
t0 = time.perf_counter()
import yaml
from clutchlab import config, doe, pipeline, store
cfg = yaml.safe_load(open(sys.argv[1]))
name, n, path, curves = sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5]
section = dict(cfg[name], samples=n, curves=curves)
section.pop("chunk_size", None)
rs = config.resolve({"studies": [name], name: section, "chunks": 1})[name]
design = doe.build_design(rs)
ds = pipeline.run_chunk(design, rs["options"], 1, 0)
store.write(ds, path, with_checksum=True, complevel=0)
print(json.dumps({"seconds": time.perf_counter() - t0,
                  "max_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def measure_one(configfile, name, n, curves="all") -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = subprocess.run(
            [
                sys.executable,
                "-c",
                _CHILD,
                str(configfile),
                name,
                str(n),
                f"{tmp}/chunk.h5",
                curves,
            ],
            check=True,
            capture_output=True,
            text=True,
        )
    return json.loads(out.stdout.strip().splitlines()[-1])


def measure(configfile="config/million.yaml", sizes=(16384, 262144)) -> list[dict]:
    from .. import config

    cfg = config.load(configfile)
    rows = []
    for name in cfg["studies"]:
        measure_one(configfile, name, sizes[0])  # fills the compiled-code cache
        runs = [measure_one(configfile, name, n) for n in sizes]
        dn = sizes[-1] - sizes[0]
        per_s = (runs[-1]["seconds"] - runs[0]["seconds"]) / dn
        per_mb = (runs[-1]["max_rss_mb"] - runs[0]["max_rss_mb"]) / dn
        rows.append(
            dict(
                study=name,
                sizes=" ".join(map(str, sizes)),
                seconds=" ".join(f"{r['seconds']:.2f}" for r in runs),
                max_rss_mb=" ".join(f"{r['max_rss_mb']:.0f}" for r in runs),
                fixed_seconds=round(runs[0]["seconds"] - per_s * sizes[0], 2),
                us_per_scenario=round(per_s * 1e6, 1),
                fixed_mb=round(runs[0]["max_rss_mb"] - per_mb * sizes[0]),
                kb_per_scenario=round(per_mb * 1024, 2),
            )
        )
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("outdir", nargs="?", default="results/benchmark")
    ap.add_argument("--configfile", default="config/million.yaml")
    ap.add_argument("--sizes", type=int, nargs="+", default=[16384, 262144])
    args = ap.parse_args(argv)
    rows = measure(args.configfile, tuple(args.sizes))
    report_rows(rows, args.outdir, "resources_benchmark.csv")


if __name__ == "__main__":
    main()

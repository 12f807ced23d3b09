"""What a first run compiles: each compiled (numba) kernel's first-call time, from an empty cache,
from the cache, and warm (not a unit test).

``python -m clutchlab.bench.coldstart [outdir] [--configfile config/config.yaml]`` runs, for each
model of the config's studies (and the engagement's rigid driveline, which the default run's
benchmark and numerics jobs use), one scenario of the study through :func:`clutchlab.pipeline.run_chunk`
in a fresh Python process with an empty numba cache folder (``NUMBA_CACHE_DIR``: the package's own
cache is left alone), records every kernel numba compiles on the way (numba's ``numba:compile``
events: the kernels called from Python, each with the kernels it calls), then runs the same in a
second fresh process that loads them from that cache, and a second call in each process (warm).
Times are CPU seconds of the process (the machine may be shared). It writes
``coldstart_benchmark.csv`` and prints the table.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

from ._common import report_rows

# (label, study, option overrides): the models the default run's jobs compute
CASES = (
    ("diaphragm_spring", "diaphragm_spring", {}),
    ("engagement, compliant driveline", "engagement", {"driveline": "compliant"}),
    ("engagement, rigid driveline", "engagement", {"driveline": "rigid"}),
    ("centrifugal", "centrifugal", {}),
    ("sprag", "sprag", {}),
    ("roller", "roller", {}),
)
# kernels the default run's benchmark, numerics and hard-case jobs call outside a study (the
# compliant one with a nonlinear friction law: the hard cases' judder)
CALLS = (
    (
        "engagement kernel, rigid driveline",
        "from clutchlab import engagement as e; e.simulate(engine_speed=570.0, engine_inertia=1.0,"
        " engine_torque=0.0, driven_inertia=0.03, load_torque=50.0, peak_capacity=300.0,"
        " ramp_time=0.1)",
    ),
    (
        "engagement kernel, compliant driveline, Stribeck μ",
        "from clutchlab import engagement as e; e.simulate(engine_speed=570.0,"
        " engine_inertia=float('inf'), engine_torque=0.0, driven_inertia=0.03, load_torque=50.0,"
        " peak_capacity=300.0, ramp_time=0.1, static_ratio=1.3, stribeck_speed=30.0,"
        " compliant=True, damper_stiffness=4498.0, damping_ratio=0.05)",
    ),
    (
        "Hertz impact",
        "from clutchlab import contact; contact.hertz_impact(mass=0.01, speed=1.0, stiffness=1e10)",
    ),
)

_CHILD = r"""
import json, sys, time
t0 = time.process_time()
from numba.core import event
from clutchlab import config, doe, pipeline
imports = time.process_time() - t0
import yaml
cfg = yaml.safe_load(open(sys.argv[1]))
name, options = sys.argv[2], json.loads(sys.argv[3])
if name == "python":  # a call outside a study
    def call():
        exec(options)
else:
    rs = config.resolve({**cfg, "studies": [name]})[name]
    design = doe.build_design(rs)
    chunks = pipeline.n_scenarios(design)  # one scenario a chunk
    options = {**rs["options"], **options}

    def call():
        pipeline.run_chunk(design, options, chunks, 0)
compiled, depth, start = {}, [0], {}


class Compiles(event.Listener):  # a kernel called from Python: its and its callees' compile time
    def on_start(self, ev):
        depth[0] += 1
        start[depth[0]] = time.process_time()

    def on_end(self, ev):
        if depth[0] == 1:
            key = ev.data["dispatcher"].py_func.__qualname__
            compiled[key] = compiled.get(key, 0.0) + time.process_time() - start[1]
        depth[0] -= 1


event.register("numba:compile", Compiles())
calls = []
for _ in range(2):
    t = time.process_time()
    call()
    calls.append(time.process_time() - t)
print(json.dumps({"imports": imports, "first": calls[0], "warm": calls[1], "compiled": compiled}))
"""


def _child(configfile, study, options, cache_dir) -> dict:
    # the cache's base folder: clutchlab's own import passed its folder on to child processes
    # (CLUTCHLAB_NUMBA_CACHE_BASE, which wins over NUMBA_CACHE_DIR)
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir, CLUTCHLAB_NUMBA_CACHE_BASE=cache_dir)
    out = subprocess.run(
        [sys.executable, "-c", _CHILD, str(configfile), study, json.dumps(options)],
        check=True,
        capture_output=True,
        text=True,
        env=env,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def measure(configfile="config/config.yaml") -> list[dict]:
    """One row a model: compile (empty cache), cache-load and warm first-call times."""
    rows = []
    cases = [*CASES, *((label, "python", code) for label, code in CALLS)]
    for label, study, options in cases:
        with tempfile.TemporaryDirectory() as cache:
            cold = _child(configfile, study, options, cache)
            cached = _child(configfile, study, options, cache)
        rows.append(
            dict(
                model=label,
                imports_seconds=round(cold["imports"], 2),
                first_call_empty_cache_seconds=round(cold["first"], 2),
                compile_seconds=round(sum(cold["compiled"].values()), 2),
                first_call_cached_seconds=round(cached["first"], 3),
                warm_call_seconds=round(cached["warm"], 4),
                kernels=" ".join(
                    f"{k}:{v:.1f}s" for k, v in sorted(cold["compiled"].items()) if v > 0
                ),
                recompiled_from_cache=len(cached["compiled"]),
            )
        )
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("outdir", nargs="?", default="results/benchmark")
    ap.add_argument("--configfile", default="config/config.yaml")
    args = ap.parse_args(argv)
    report_rows(measure(args.configfile), args.outdir, "coldstart_benchmark.csv")


if __name__ == "__main__":
    main()

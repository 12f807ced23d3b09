"""The robust-study benchmark: 1000 engagement designs × 4 operating conditions × 256 noise draws (and
the 2 corners): about 10^6 scenarios, run as chunk files on the machine's cores, merged with their
robust answers, and measured (not a unit test).

``python -m clutchlab.bench.robust [outdir] [--designs 1000] [--noise-samples 256] [--chunks 8]
[--cores 2] [--driveline rigid|compliant]`` writes ``robust_benchmark.csv``: scenarios, chunks, the
wall time, the physics' own time (the sum over chunks of the time inside the study's compute
function), the chunk jobs' and the merge's time (the merge includes the robust answers), the robust
answers' own time, and the share of job time outside the physics. The designs are Latin-hypercube
samples of sheet thickness, ramp time and the lining's nominal friction coefficient (held engine;
rigid driveline: the closed form, or ``--driveline compliant`` as the default study runs it: every
phase in closed form, accuracy 1e-6); the conditions the default study's driven inertias and load
torques; the noise the friction coefficient's ±20 % scatter. Run it alone on the machine.
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from .. import config, doe, explore, pipeline, store
from ._common import write_rows


def section(designs=1000, noise_samples=256, chunks=8, driveline="rigid") -> dict:
    """The benchmark's resolved engagement study (a crossed robust design)."""
    raw = {
        "design": "lhs",
        "samples": designs,
        "seed": 1,
        "chunks": chunks,
        "options": {"driveline": driveline},
        "accuracy": 1.0e-6,
        "parameters": {
            "sheet_thickness": {"min": "2.1 mm", "max": "2.6 mm"},
            "ramp_time": {"min": "0.05 s", "max": "0.3 s"},
            "friction_coefficient": {"min": 0.35, "max": 0.4},
            "driven_inertia": {"values": ["0.021 kg*m^2", "0.05 kg*m^2"], "role": "condition"},
            "load_torque": {"values": ["44 N*m", "80 N*m"], "role": "condition"},
        },
        "noise": {"friction_coefficient": {"scatter": "±20 %"}},
        "noise_samples": noise_samples,
    }
    cfg = {"studies": ["engagement"], "max_scenarios": 2**22, "engagement": raw}
    return config.resolve(cfg)["engagement"]


def _chunk(args) -> tuple[float, float]:
    """One chunk job: compute chunk i and write it; (job seconds, physics seconds)."""
    design_path, options, chunks, i, path = args
    start = time.perf_counter()
    design = store.load_verified(design_path)
    ds = pipeline.run_chunk(design, options, chunks, i)
    physics = float(ds.attrs["compute_seconds"])
    store.write(ds, path, with_checksum=True)
    return time.perf_counter() - start, physics


def measure(outdir, designs=1000, noise_samples=256, chunks=8, cores=2, driveline="rigid") -> dict:
    """Run the benchmark in ``outdir``; returns its row of figures."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    sec = section(designs, noise_samples, chunks, driveline)
    start = time.perf_counter()
    design = doe.build_design(sec)
    store.write(design, out / "design.h5", with_checksum=True)
    paths = [out / f"chunk_{i:04d}.h5" for i in range(chunks)]
    jobs = [(out / "design.h5", sec["options"], chunks, i, p) for i, p in enumerate(paths)]
    with ProcessPoolExecutor(max_workers=cores) as pool:
        times = list(pool.map(_chunk, jobs))
    merge_start = time.perf_counter()
    pipeline.merge_to_file(
        design,
        paths,
        out / "engagement.h5",
        sec["objectives"],
        sec["constraints"],
        robust_path=out / "robust.h5",
    )
    merge = time.perf_counter() - merge_start
    wall = time.perf_counter() - start
    answers_start = time.perf_counter()
    with store.open(out / "engagement.h5") as lazy:
        answers = explore.robust(lazy)
    answers_time = time.perf_counter() - answers_start
    job = sum(t for t, _ in times) + merge
    physics = sum(p for _, p in times)
    for p in paths:
        p.unlink()
    return {
        "driveline": driveline,
        "scenarios": pipeline.n_scenarios(design),
        "designs": designs,
        "conditions": 4,
        "noise_draws": design.sizes["noise"],
        "chunks": chunks,
        "cores": cores,
        "wall_s": round(wall, 2),
        "physics_s": round(physics, 2),
        "chunk_jobs_s": round(sum(t for t, _ in times), 2),
        "merge_s": round(merge, 2),
        "robust_answers_s": round(answers_time, 2),
        "outside_physics_share": round(1.0 - physics / job, 4),
        "robust_feasible_designs": int(answers["robust_feasible"].sum()),
        "robust_front_designs": int((answers["robust_rank"] == 0).sum()),
    }


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("outdir", nargs="?", default="results/benchmark/robust")
    parser.add_argument("--designs", type=int, default=1000)
    parser.add_argument("--noise-samples", type=int, default=256)
    parser.add_argument("--chunks", type=int, default=8)
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--driveline", choices=("rigid", "compliant"), default="rigid")
    args = parser.parse_args(argv)
    row = measure(
        args.outdir, args.designs, args.noise_samples, args.chunks, args.cores, args.driveline
    )
    write_rows([row], Path(args.outdir) / "robust_benchmark.csv")
    for k, v in row.items():
        print(f"{k}: {v}")


if __name__ == "__main__":
    main()

"""Benchmarks: each measures a solver or the pipeline against scipy (or a local run) in its own run
and names the model, design and tolerance it measured; never asserted in unit tests.

* :mod:`~clutchlab.bench.compliant` — the engagement study's default model (compliant driveline,
  event-driven kernel) against per-scenario ``solve_ivp`` (``snakemake benchmark_compliant``);
* :mod:`~clutchlab.bench.engagement` — the rigid Stribeck engagement, work against precision
  (``snakemake benchmark``);
* :mod:`~clutchlab.bench.roller` — the roller wedging's compiled DOP853/SDIRK4 against LSODA and Radau;
* :mod:`~clutchlab.bench.sprag` — the vectorised gripping-angle fixed point against per-scenario
  root finding;
* :mod:`~clutchlab.bench.pareto` — Pareto ranking of 10⁵–10⁶ designs and the hypervolume of
  10³–10⁴ front points;
* :mod:`~clutchlab.bench.million` — config/million.yaml through Snakemake (5 × 2²⁰ scenarios);
* :mod:`~clutchlab.bench.resources` — a chunk job's time and memory, for the SLURM requests;
* :mod:`~clutchlab.bench.slurm` — the same study through the SLURM profile against a local run;
* :mod:`~clutchlab.bench.numerics` — small runs of the solver benchmarks for the report's
  numerics pages.

Each is ``python -m clutchlab.bench.<name> OUTDIR`` and writes its ``<name>_benchmark.csv``
(:mod:`~clutchlab.bench._common`).
"""

# clutchlab workflow: config -> design -> chunk jobs -> merged HDF5 per study -> report.
# Run: snakemake --cores 2            (default study, config/config.yaml)
#      snakemake --cores 2 --configfile my.yaml --config chunks=8
from snakemake.utils import min_version

min_version("8.0")

import sys
from pathlib import Path

# The default study, unless the user names a config file: a --configfile is a complete study
# (Snakemake would otherwise deep-merge it into the default and mix factor definitions).
# --config key=value still overrides single keys of whichever file is used. The default config is
# the workflow's own (beside this Snakefile), also when run from another folder with -s.
DEFAULT_CONFIG = str(Path(workflow.basedir) / "config" / "config.yaml")
if not workflow.overwrite_configfiles:

    configfile: DEFAULT_CONFIG


import clutchlab.config

# Every config file read again as data (UTF-8, no duplicate key, no template, no alias bomb), then
# schema validation, unit conversion and physical range checks, before any job is scheduled.
# A ConfigError names the offending key in one line and stops the run here.
try:
    for _path in workflow.overwrite_configfiles or [DEFAULT_CONFIG]:
        clutchlab.config.read_file(_path)
    RESOLVED = clutchlab.config.resolve(config)
except clutchlab.config.ConfigError as _exc:
    sys.exit(f"clutchlab: {_exc}")

# Results go below the working folder (top-level key `results`, default "results"), not below the
# Snakefile: run from another folder (snakemake -s path/to/Snakefile, or --directory), say where.
if workflow.is_main_process and Path.cwd().resolve() != Path(workflow.basedir).resolve():
    print(
        f"clutchlab: results go to {Path(RESOLVED['results']).resolve()} (the working folder, "
        f"not the workflow's {workflow.basedir})",
        file=sys.stderr,
    )

# the description of Snakemake's own HTML report (`snakemake --report report.html`)
report: "workflows/report/workflow.rst"


include: "workflows/rules/common.smk"
include: "workflows/rules/study.smk"
include: "workflows/rules/report.smk"


# the target rule only collects files, and the benchmarks measure the machine they run on: they run
# where snakemake runs, not as cluster jobs
localrules:
    all,
    benchmark,
    benchmark_sprag,
    benchmark_pareto,
    benchmark_million,
    benchmark_roller,
    benchmark_compliant,


rule all:
    default_target: True
    input:
        [results(s) for s in STUDIES],
        [f for s in STUDIES for f in sensitivity_files(s)],
        REPORT_FILES,

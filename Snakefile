# clutchlab workflow: config -> design -> chunk jobs -> merged HDF5 per study -> report.
# Run: snakemake --cores 2            (default study, config/config.yaml)
#      snakemake --cores 2 --configfile my.yaml --config chunks=8
from snakemake.utils import min_version

min_version("8.0")

# The default study, unless the user names a config file: a --configfile is a complete study
# (Snakemake would otherwise deep-merge it into the default and mix factor definitions).
# --config key=value still overrides single keys of whichever file is used.
if not workflow.overwrite_configfiles:

    configfile: "config/config.yaml"


import clutchlab.config

# Schema validation, unit conversion and physical range checks, before any job is scheduled.
# A ConfigError names the offending key and stops the run here.
RESOLVED = clutchlab.config.resolve(config)

include: "workflows/rules/common.smk"
include: "workflows/rules/study.smk"
include: "workflows/rules/report.smk"


rule all:
    default_target: True
    input:
        [results(s) for s in STUDIES],
        REPORT_FILES,

# Report: figures and PDF from stored results only.
import sys
from pathlib import Path

import clutchlab

from clutchlab.report import answer_files as _answer_files
from clutchlab.report import run_stems as _run_stems
from clutchlab.report import study_stems as _study_stems
from clutchlab.bench.numerics import files as _numerics_files
from clutchlab.report import captions as _captions
from clutchlab.studies.engagement import friction_laws as _friction_laws

REPORT_DIR = f"{RESULTS}/report"
ROBUST = [s for s in STUDIES if robust_files(s)]  # robust studies: their robust page leads
BENCHMARK_PAGE = RESOLVED["report"]["benchmark"]  # the engagement work-precision page (runs the benchmark)
HARD_CASES = RESOLVED["report"]["hard_cases"]  # the hard-case table of the studies run
NUMERICS = [f"{RESULTS}/numerics/{f}" for f in _numerics_files(STUDIES)] if RESOLVED["report"]["numerics"] else []
# each study's pages (PNGs) and tables (CSVs), drawn by its own job (rule pages_<study>)
STUDY_REPORT_FILES = {
    s: [f"{REPORT_DIR}/{stem}.png" for stem in _study_stems(s, bool(sensitivity_files(s)), s in REFINED, s in ROBUST)]
    + [f"{REPORT_DIR}/{f}" for f in _answer_files([s], [s] if s in REFINED else [], ROBUST)]
    for s in STUDIES
}
# the report job's own: the PDF (the summary, every study's part, the run's part) and the summary's PNG
SUMMARY_FILES = [f"{REPORT_DIR}/report.pdf", f"{REPORT_DIR}/title.png"]
# the run's pages after the studies' (rule run_pages: work-precision, validation table, numerics, hard
# cases) and their tables; validation.csv and its page exist only where a study reproduces published
# numbers
RUN_PAGE_FILES = ([f"{REPORT_DIR}/validation.csv"] if VALIDATED else []) + [
    f"{REPORT_DIR}/{stem}.png" for stem in _run_stems(STUDIES, BENCHMARK_PAGE, HARD_CASES, bool(NUMERICS))[1:]
] + ([f"{REPORT_DIR}/hard_cases.csv"] if HARD_CASES else [])
RUN_PART = [f"{WORK}/report/run_pages.pdf"] if RUN_PAGE_FILES else []  # (none: no run pages)
REPORT_FILES = SUMMARY_FILES + RUN_PAGE_FILES + [f for s in STUDIES for f in STUDY_REPORT_FILES[s]]
# the interactive explorer of each study (one self-contained HTML page; clutchlab.report.explorer)
EXPLORERS = {s: f"{REPORT_DIR}/{s}_explorer.html" for s in STUDIES}
# a study's pages as a PDF part (and its record beside it: clutchlab.report.study_part)
PARTS = {s: f"{WORK}/{s}/report/pages.pdf" for s in STUDIES}
# Snakemake's own HTML report (`snakemake --report report.html`): every report file with its caption
# (clutchlab.report.captions, written to .snakemake/clutchlab_captions when the workflow is parsed)
_CAPTION_FILES = _captions.write(
    ".snakemake/clutchlab_captions", REPORT_FILES + list(EXPLORERS.values()), STUDIES
)


# each report file marked for Snakemake's HTML report, with its caption and category
_CAPTIONED = {
    f: report(f, caption=_CAPTION_FILES[f], category=_captions.category(Path(f).name, STUDIES))
    for f in REPORT_FILES + list(EXPLORERS.values())
}


for _study in STUDIES:

    rule:
        # one job per study, as soon as its merge is done (beside other studies' chunks and merges):
        # its pages (each drawn once, as PNG and as a page of its PDF part), its tables and its
        # interactive explorer (every design, or a sample with every front design beyond
        # clutchlab.report.explorer.MAX_DESIGNS), from its verified result
        name:
            f"pages_{_study}"
        input:
            result=results(_study),
            sensitivity=sensitivity_files(_study),
            robust=robust_files(_study),
            traces=traces_files(_study),
            refined=[refine_source(_study)] if _study in REFINED else [],
            refined_robust=[first_robust(_study)] if _study in REFINED and robust_files(_study) else [],
        output:
            explorer=_CAPTIONED[EXPLORERS[_study]],
            files=[_CAPTIONED[f] for f in STUDY_REPORT_FILES[_study]],
            part=PARTS[_study],
            record=str(Path(PARTS[_study]).with_suffix(".json")),
        benchmark:
            f"{WORK}/{_study}/benchmark/pages.tsv"
        log:
            f"{WORK}/{_study}/log/pages.log",
        params:
            study=_study,
            config=study_config(_study),  # the result is verified against its own config
            dpi=RESOLVED["report"]["dpi"],
            source=SOURCE,
        resources:
            **_cluster.pages_resources(RESOLVED[_study]),
        script:
            "../scripts/pages.py"


if RUN_PART:

    rule run_pages:
        # the run's pages after the studies' (work-precision, validation table, numerics, hard cases)
        # as PNGs and a PDF part, as soon as their inputs exist (beside the studies' jobs): the
        # report job at the end of the run only draws the summary and joins the parts
        input:
            validation=[f"{RESULTS}/{s}/validation.h5" for s in VALIDATED],
            benchmark=[f"{RESULTS}/benchmark/engagement_benchmark.csv"] if BENCHMARK_PAGE else [],
            hard_cases=[f"{RESULTS}/numerics/hard_cases.h5"] if HARD_CASES else [],
            numerics=NUMERICS,
        output:
            files=[_CAPTIONED[f] for f in RUN_PAGE_FILES],
            part=RUN_PART[0],
            record=str(Path(RUN_PART[0]).with_suffix(".json")),
        benchmark:
            f"{WORK}/benchmark/run_pages.tsv"
        log:
            f"{WORK}/log/run_pages.log",
        params:
            studies=STUDIES,
            dpi=RESOLVED["report"]["dpi"],
            source=SOURCE,
        resources:
            **_cluster.report_resources(RESOLVED),
        script:
            "../scripts/run_pages.py"


rule report:
    input:
        studies=[results(s) for s in STUDIES],  # (their stored checksums: each part is of this one)
        parts=[PARTS[s] for s in STUDIES],
        records=[str(Path(PARTS[s]).with_suffix(".json")) for s in STUDIES],
        run_part=RUN_PART,
        run_record=[str(Path(p).with_suffix(".json")) for p in RUN_PART],
        validation=[f"{RESULTS}/{s}/validation.h5" for s in VALIDATED],  # (the summary's lines)
        explorers=list(EXPLORERS.values()),  # the summary page links them
    output:
        [_CAPTIONED[f] for f in SUMMARY_FILES],
    benchmark:
        f"{WORK}/report_benchmark.tsv"
    log:
        f"{WORK}/log/report.log",
    params:
        names=STUDIES,
        title=RESOLVED["report"]["title"],
        dpi=RESOLVED["report"]["dpi"],
        source=SOURCE,
        version=clutchlab.__version__,
        # each study's chunk and merge jobs' benchmark files (the summary says their time)
        job_benchmarks={
            s: [f"{WORK}/{s}/benchmark/{Path(c).stem}.tsv" for c in chunk_files(s)]
            + [f"{WORK}/{s}/benchmark/merge.tsv"]
            for s in STUDIES
        },
    resources:
        **_cluster.report_resources(RESOLVED),
    script:
        "../scripts/report.py"


rule hard_cases:
    # each hard case of the studies run: right answer, clutchlab's value, error, off-the-shelf solver
    output:
        f"{RESULTS}/numerics/hard_cases.h5",
    benchmark:
        f"{WORK}/benchmark/hard_cases.tsv"
    log:
        f"{WORK}/log/hard_cases.log",
    # alongside the chunks, after each study's first one: it compiles the rigid engagement, the
    # compliant one's integrators and the Hertz impact (minutes on a first run), which a study's
    # first chunk compiles only where it runs that model (then this job loads it)
    priority: 2  # (as the cheapest study's later chunks: _cluster.chunk_priority)
    params:
        studies=STUDIES,
        source=SOURCE,
    resources:
        runtime=5,
        mem_mb=1000,
    script:
        "../scripts/hard_cases.py"


if NUMERICS:

    rule numerics:
        # small work-precision runs of the solvers the studies use (about 20 s; clutchlab.bench.numerics)
        output:
            NUMERICS,
        benchmark:
            f"{WORK}/benchmark/numerics.tsv"
        log:
            f"{WORK}/log/numerics.log",
        # as the hard cases: alongside the later chunks (it loads the kernels the first chunks
        # compiled), not after every merge where the report waits for it
        priority: 2
        params:
            outdir=lambda wc, output: Path(output[0]).parent,
            studies=STUDIES,
            # the engagement's friction laws (its benchmark compiles and times only these)
            laws=",".join(_friction_laws(RESOLVED["engagement"])) if "engagement" in STUDIES else "constant_mu",
            python=sys.executable,
            source=SOURCE,
        resources:
            runtime=10,
            mem_mb=2000,
        shell:
            "{params.python} -m clutchlab.bench.numerics {params.outdir} {params.studies} "
            "--friction-laws {params.laws} 2>&1 | tee {log}"


rule benchmark:
    # `snakemake --cores 1 benchmark` (about 1 minute); part of `all` when report.benchmark is true
    # (the report's work-precision page). Prints speed/error ratios against scipy measured in the
    # same run and draws the work-precision diagram.
    output:
        f"{RESULTS}/benchmark/engagement_benchmark.csv",
        f"{RESULTS}/benchmark/work_precision.png",
    threads: ALL_CORES  # alone on the machine: timings are not disturbed by other jobs
    log:
        f"{RESULTS}/benchmark/log/engagement.log",
    params:
        python=sys.executable,
        outdir=lambda wc, output: Path(output[0]).parent,
    shell:
        "{params.python} -m clutchlab.bench.engagement {params.outdir} 2>&1 | tee {log}"


rule benchmark_sprag:
    # Not part of `all`: `snakemake --cores 1 benchmark_sprag` (about 30 s). Sprag statics
    # throughput at 1e5 and 1e6 scenarios and the ratio against per-scenario scipy brentq.
    output:
        f"{RESULTS}/benchmark/sprag_benchmark.csv",
    threads: ALL_CORES
    log:
        f"{RESULTS}/benchmark/log/sprag.log",
    params:
        python=sys.executable,
        outdir=lambda wc, output: Path(output[0]).parent,
    shell:
        "{params.python} -m clutchlab.bench.sprag {params.outdir} 2>&1 | tee {log}"


rule benchmark_pareto:
    # Not part of `all`: `snakemake --cores 1 benchmark_pareto` (about 2 minutes). Pareto ranking
    # time at 1e6 designs (2, 3 and 4 objectives; 5 objectives at 1e5) against O(N^2) peeling;
    # hypervolume time of 1e3 and 1e4 points of a 4-objective front against inclusion-exclusion.
    output:
        f"{RESULTS}/benchmark/pareto_benchmark.csv",
        f"{RESULTS}/benchmark/hypervolume_benchmark.csv",
    log:
        f"{RESULTS}/benchmark/log/pareto.log",
    params:
        python=sys.executable,
        outdir=lambda wc, output: Path(output[0]).parent,
    shell:
        "{params.python} -m clutchlab.bench.pareto {params.outdir} 2>&1 | tee {log}"


rule benchmark_million:
    # Not part of `all`: `snakemake --cores 2 benchmark_million` (about 5 minutes, alone on the
    # machine). Runs config/million.yaml (every study at 2^20 sampled designs) through Snakemake
    # (forced, results/million/) and prints per study the physics' time, the jobs' time, the share
    # outside the physics, peak RSS and job counts; for the run its wall time.
    output:
        f"{RESULTS}/benchmark/million_benchmark.csv",
    threads: ALL_CORES
    log:
        f"{RESULTS}/benchmark/log/million.log",
    params:
        python=sys.executable,
        outdir=lambda wc, output: Path(output[0]).parent,
    shell:
        "{params.python} -m clutchlab.bench.million {params.outdir} --cores {threads} 2>&1 | tee {log}"


rule benchmark_roller:
    # Not part of `all`: `snakemake --cores 1 benchmark_roller` (a few minutes: the tight Radau
    # reference is slow). Compiled DOP853/SDIRK4 against per-scenario solve_ivp LSODA and Radau.
    output:
        f"{RESULTS}/benchmark/roller_benchmark.csv",
    threads: ALL_CORES
    log:
        f"{RESULTS}/benchmark/log/roller.log",
    params:
        python=sys.executable,
        outdir=lambda wc, output: Path(output[0]).parent,
    shell:
        "{params.python} -m clutchlab.bench.roller {params.outdir} 2>&1 | tee {log}"


rule benchmark_compliant:
    # Not part of `all`: `snakemake --cores 1 benchmark_compliant` (about 1 minute). The model the
    # engagement study runs (compliant driveline, constant and Stribeck mu, the default study's
    # ranges) against per-scenario solve_ivp RK45 and DOP853, errors against DOP853 at rtol 1e-13.
    output:
        f"{RESULTS}/benchmark/compliant_benchmark.csv",
        f"{RESULTS}/benchmark/compliant_work_precision.png",
    threads: ALL_CORES
    log:
        f"{RESULTS}/benchmark/log/compliant.log",
    params:
        python=sys.executable,
        outdir=lambda wc, output: Path(output[0]).parent,
    shell:
        "{params.python} -m clutchlab.bench.compliant {params.outdir} 2>&1 | tee {log}"

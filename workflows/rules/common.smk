# Paths and helpers shared by the rules. No physics here.
import clutchlab as _clutchlab
from clutchlab import cluster as _cluster
from clutchlab import config as _config
from clutchlab import studies as _studies

# the package's source hash: a param of every rule whose output the code determines, so that an
# edit to the physics (or the figures) reruns what it affects
SOURCE = _clutchlab.source_hash()

STUDIES = RESOLVED["studies"]
RESULTS = RESOLVED["results"]  # top-level key results (default "results")
WORK = f"{RESULTS}/work"
VALIDATED = [s for s in STUDIES if _studies.get(s).validation is not None]
REFINED = [s for s in STUDIES if RESOLVED[s]["design"] == "refine"]
# studies with trace pages: the traces of the design the pages show, after the merge
TRACED = [s for s in STUDIES if _studies.get(s).traces is not None]


def _all_cores():
    """--cores of a local run; 1 under a cluster executor (no total core count there)."""
    from snakemake.exceptions import WorkflowError

    try:
        return workflow.cores
    except WorkflowError:
        return 1


# the benchmark rules take every core of the machine they run on (their timings are the point; they
# are local rules: on a cluster they run where snakemake runs)
ALL_CORES = _all_cores()


def results(study):
    """Merged HDF5 result of a study, e.g. results/diaphragm_spring/diaphragm_spring.h5."""
    return f"{RESULTS}/{_studies.get(study).output}"


def sensitivity_files(study):
    """Sensitivity indices of a factorial study (its grid's variance decomposition) or a saltelli
    design (Sobol indices); none for lhs/sobol samples or a grid of no factor (one scenario)."""
    design = RESOLVED[study]["design"]
    grid = design == "factorial" and RESOLVED[study]["factors"]
    return [f"{RESULTS}/{study}/sensitivity.h5"] if grid or design == "saltelli" else []


def robust_files(study):
    """Robust answers of a robust (crossed) study, beside its result; none otherwise."""
    return [f"{RESULTS}/{study}/robust.h5"] if RESOLVED[study].get("robust") else []


def refine_source(study):
    """The first-stage result a design-refine study samples near (an input of its design)."""
    return RESOLVED[study]["refine"]["from"]


def first_robust(study):
    """The robust answers beside the first-stage result a refined robust study started from."""
    return str(Path(refine_source(study)).parent / "robust.h5")


def traces_files(study):
    """The traces of the design a study's pages show, beside its result (written by its merge
    job); none for a study without traces."""
    return [f"{RESULTS}/{study}/traces.h5"] if study in TRACED else []


def study_config(study):
    """The study's resolved config text: what its design, chunks and result must have been computed
    from (their `config` attribute; checked by the merge and the report, clutchlab.verify)."""
    return _config.study_config_text(RESOLVED[study])


def chunk_files(study):
    n = RESOLVED[study]["chunks"]
    return [f"{WORK}/{study}/chunk_{i:04d}.h5" for i in range(n)]


wildcard_constraints:
    study="|".join(STUDIES),
    i=r"\d{4}",

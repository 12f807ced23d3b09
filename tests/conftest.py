import os
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")


def refine_sources(cfg) -> list[str]:
    """The first-stage result files a config's design-refine studies read (refine.from)."""
    return [cfg[s]["refine"]["from"] for s in cfg["studies"] if cfg[s].get("design") == "refine"]


def write_first_stage(path, study="engagement"):
    """A small stored result of ``study`` at ``path`` (a 3 x 2 factorial grid of its first two
    default-config factors), for a config that refines a stored result."""
    from pathlib import Path

    import yaml

    from clutchlab import config, pipeline, store

    raw = yaml.safe_load(
        (Path(__file__).resolve().parents[1] / "config" / "config.yaml").read_text()
    )[study]
    params = {k: v for k, v in raw["parameters"].items() if isinstance(v, dict)}
    small = {}
    for k, v in list(params.items())[:2]:
        small[k] = {
            "values": (v["values"] if "values" in v else [v["min"], v["max"]])[
                : 3 if not small else 2
            ]
        }
    section = {
        **raw,
        "parameters": {
            **{k: v for k, v in raw["parameters"].items() if not isinstance(v, dict)},
            **small,
        },
    }
    sec = config.resolve({"studies": [study], study: section})[study]
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    store.write(pipeline.run_study(sec), path)


ROOT = Path(__file__).resolve().parents[1]


def without_robust(section: dict) -> dict:
    """A study section of a config without its robust keys (noise, noise_samples, robust, roles):
    the grid alone, each operating condition ranked on its own (robust studies:
    tests/test_robust.py)."""
    out = {k: v for k, v in section.items() if k not in ("noise", "noise_samples", "robust")}
    out["parameters"] = {
        k: {f: x for f, x in v.items() if f != "role"} if isinstance(v, dict) else v
        for k, v in (section.get("parameters") or {}).items()
    }
    return out


# The tests that take longest (minutes each: Snakemake runs, the cluster), longest first as
# measured in a full run on 2 cores: pytest-xdist hands out the tests in collection order, and
# one of these started last kept one worker busy minutes after the other had finished. The
# cluster test of the small config makes the session's small run first (tests/test_slurm.py);
# the others, which do not read it, run meanwhile.
LONG_FIRST = (
    "tests/test_slurm.py::test_small_config_on_slurm_equals_the_local_run",
    "tests/test_slurm.py::test_a_chunk_job_cancelled_by_slurm",
    "tests/test_provenance.py::test_snakemake_finds_a_foreign_chunk_and_a_hand_edited_result",
    "tests/test_pipeline.py::test_every_config_runs_with_any_chunk_count[refine.yaml",
    "tests/test_pipeline.py::test_killed_run_unlock_and_resume",
    "tests/test_pipeline.py::test_interrupt_and_resume",
    "tests/test_pipeline.py::test_same_config_twice_gives_identical_files",
    "tests/test_pipeline.py::test_every_config_runs_with_any_chunk_count[million.yaml",
    "tests/test_pipeline.py::test_every_config_runs_with_any_chunk_count[config.yaml",
    "tests/test_pipeline.py::test_every_config_runs_with_any_chunk_count[seed000.yaml",
    "tests/test_pipeline.py::test_every_config_runs_with_any_chunk_count[small.yaml",
    "tests/test_pipeline.py::test_malformed_configs_are_refused_before_any_job",
    "tests/test_report_pages.py::test_every_page_is_legible_and_shows_the_runs_design",
    "tests/test_slurm.py::",
    "tests/test_pipeline.py::test_every_config_runs_with_any_chunk_count",
    "tests/test_compliant.py::test_seed_design_exact_and_integrated_agree",
    "tests/test_hang.py::test_every_input_ends_in_bounded_time_with_a_status[engagement.simulate",
    "tests/test_pipeline.py::test_a_changed_chunk_is_found_by_the_merge_and_recomputed",
)


def pytest_xdist_auto_num_workers(config):
    """``-n auto`` (pyproject's addopts): one pytest-xdist worker more than the cores this process
    may use. The longest tests mostly wait (on their Snakemake subprocesses, on a SLURM status
    check, on a run to interrupt), which a third worker on 2 cores can use (measured: within the
    scatter between runs, docs/benchmarks.md)."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return (cores or 1) + 1


def pytest_collection_modifyitems(config, items):
    """The tests of ``LONG_FIRST`` first, in its order; the others in collection order (the same
    on every pytest-xdist worker, as xdist requires)."""

    def rank(item):
        for i, prefix in enumerate(LONG_FIRST):
            if item.nodeid.startswith(prefix):
                return i
        return len(LONG_FIRST)

    items.sort(key=rank)  # (stable: each rank keeps collection order)


def snakemake_workdir(tmp_path: Path) -> Path:
    """A working folder with the workflow (Snakefile, workflows, config) as a user's clone has it."""
    import shutil

    for item in ("Snakefile", "workflows", "config"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp_path / item)
    (tmp_path / "profiles").symlink_to("workflows/profiles")
    return tmp_path


def run_snakemake(cwd, *args, check=True, **kw):
    import subprocess
    import sys

    cmd = [sys.executable, "-m", "snakemake", "--cores", "2", *args]
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=1800, **kw)
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake failed:\n{proc.stdout}\n{proc.stderr}")
    return proc


def _session_folder(tmp_path_factory) -> Path:
    """The session's temporary folder that every pytest-xdist worker of the session shares (each
    worker's own is a subfolder of it); without xdist, the session's own."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


@pytest.fixture(scope="session")
def small_run(tmp_path_factory):
    """config/small.yaml run through Snakemake once for the session (pipeline, notebook, explorer
    and cluster tests), whichever pytest-xdist worker needs it first: the run is made under a lock
    in the folder the workers share, the other workers wait for it and read the same folder, so
    that its tests spread over the workers. Tests only read it: a test that runs Snakemake in the
    run's folder, or writes there, takes its own copy (``small_run_copy``)."""
    import fcntl

    shared = _session_folder(tmp_path_factory)
    wd, made, failed = shared / "small_run", shared / "small_run.made", shared / "small_run.failed"
    with open(shared / "small_run.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        if failed.exists():  # another worker's attempt failed: the same error, not a second run
            raise AssertionError(failed.read_text())
        if not made.exists():
            wd.mkdir()
            try:
                run_snakemake(snakemake_workdir(wd), "--configfile", "config/small.yaml")
            except BaseException as exc:
                failed.write_text(f"the session's small run failed:\n{exc}")
                raise
            # one line for each run made (tests/test_suite_setup.py: one a session)
            with open(made, "a") as fh:
                fh.write(f"{os.environ.get('PYTEST_XDIST_WORKER', 'main')} {wd}\n")
    return wd


@pytest.fixture
def small_run_copy(small_run, tmp_path):
    """The test's own copy of the session's small run (every file with its modification time, and
    Snakemake's records in .snakemake/): for a test that reruns Snakemake in the run's folder or
    changes a file there, while other tests read the session's run."""
    import shutil

    return Path(shutil.copytree(small_run, tmp_path / "run", symlinks=True))

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


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Under pytest-xdist (``-n auto --dist loadgroup``, pyproject.toml) the tests that share the
    session's small Snakemake run go to one worker: the run is made once and its tests, some of
    which rerun Snakemake in its folder, run one after another. (First among the hooks: xdist's
    own, which turns the mark into the group a test is scheduled by, runs before a conftest's
    otherwise, and the mark came too late: each worker made the run.)"""
    for item in items:
        if "small_run" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.xdist_group("small_run"))


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


@pytest.fixture(scope="session")
def small_run(tmp_path_factory):
    """config/small.yaml run through Snakemake once for the session (pipeline and notebook tests)."""
    wd = snakemake_workdir(tmp_path_factory.mktemp("run"))
    run_snakemake(wd, "--configfile", "config/small.yaml")
    return wd

"""Issue 19: the SLURM path on a real cluster.

These tests need a SLURM cluster that this machine submits to (``sinfo`` shows a node up) and the
executor plugin (``pip install -e ".[slurm]"``). CI brings up a single-node cluster on its own
machine with ``.ci/slurm-up`` and sets ``CLUTCHLAB_REQUIRE_SLURM=1``, so that there a missing
cluster fails the tests instead of skipping them.
"""

import os
import re
import shutil
import subprocess
import sys
import time

import pytest

from conftest import snakemake_workdir

pytestmark = pytest.mark.slow

SUBMITTED = re.compile(r"Job (\d+) has been submitted with SLURM jobid (\d+) \(log: (\S+)\)")
PROFILE = ("--workflow-profile", "workflows/profiles/slurm")


def _why_no_cluster():
    if shutil.which("sinfo") is None or shutil.which("sbatch") is None:
        return "no SLURM client (sinfo, sbatch) on this machine"
    try:
        import snakemake_executor_plugin_slurm  # noqa: F401
    except ImportError:
        return 'the SLURM executor plugin is not installed (pip install -e ".[slurm]")'
    proc = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True)
    states = proc.stdout.split()
    if not {"idle", "mixed", "allocated"} & set(states):
        return f"no SLURM node up (sinfo: {(proc.stdout + proc.stderr).strip() or 'no answer'})"
    return None


@pytest.fixture(scope="module")
def cluster():
    why = _why_no_cluster()
    if why:
        if os.environ.get("CLUTCHLAB_REQUIRE_SLURM"):
            pytest.fail(f"{why}; CI brings one up with .ci/slurm-up")
        pytest.skip(f"{why} (as root, `bash .ci/slurm-up` brings up a single-node cluster)")


def _snakemake(cwd, *args, check=True, timeout=900):
    proc = subprocess.run(
        [sys.executable, "-m", "snakemake", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake failed:\n{proc.stdout}\n{proc.stderr}")
    return proc


def _job_states(slurm_ids) -> dict:
    """SLURM's state of each job id (the CI cluster keeps finished jobs for an hour: MinJobAge)."""
    out = subprocess.run(
        ["squeue", "--states=all", "--noheader", "--format=%i|%T", "--jobs", ",".join(slurm_ids)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return dict(line.split("|") for line in out.split())


def _job_stats(log: str) -> dict:
    """Snakemake's "Job stats" table of a run: rule -> jobs."""
    table = log.split("Job stats:", 1)[1].split("total", 1)[0]
    return {m.group(1): int(m.group(2)) for m in re.finditer(r"^(\w+)\s+(\d+)$", table, re.M)}


def test_small_config_on_slurm_equals_the_local_run(cluster, small_run, tmp_path):
    """The documented cluster command (docs/scaling.md), as written, on config/small.yaml: every job but the local
    target went through sbatch and completed on the cluster, the SLURM logs are under
    logs/slurm/, and every result file equals the local run's (values, status, attributes)."""
    import xarray as xr

    wd = snakemake_workdir(tmp_path)
    proc = _snakemake(wd, *PROFILE, "--configfile", "config/small.yaml")
    log = proc.stdout + proc.stderr
    submitted = SUBMITTED.findall(log)
    stats = _job_stats(log)
    assert len(submitted) == sum(stats.values()) - stats["all"] > 20, stats
    states = _job_states([s for _, s, _ in submitted])
    assert set(states.values()) == {"COMPLETED"}, states
    for _, _, path in submitted:
        assert path.startswith(str(wd / "logs" / "slurm")) and os.path.exists(path), path

    local, cluster_results = small_run / "results", wd / "results"
    files = sorted(
        p.relative_to(local) for p in local.rglob("*") if p.is_file() and "work" not in p.parts
    )
    compared = 0
    for rel in files:
        if rel.suffix == ".h5":
            with (
                xr.open_dataset(local / rel, engine="h5netcdf") as a,
                xr.open_dataset(cluster_results / rel, engine="h5netcdf") as b,
            ):
                xr.testing.assert_identical(a.load(), b.load())
            compared += 1
        elif rel.suffix == ".csv" and rel.parts[0] != "numerics":  # numerics/*.csv hold timings
            assert (local / rel).read_text() == (cluster_results / rel).read_text(), rel
            compared += 1
    assert compared >= 15
    assert (cluster_results / "report/report.pdf").stat().st_size > 0


CANCEL_CONFIG = """\
# one study in 4 chunk jobs of about 10 s each (roller wedging dynamics, 80 us a scenario)
studies: [roller]
chunks: 4
report: {hard_cases: false, numerics: false}
roller:
  design: sobol
  samples: 524288
  seed: 1
  options: {mode: bidirectional_lock, stress_reading: one_flank}
  parameters:
    rollers: {values: [6, 8, 10, 12]}
    wedge_angle: {min: 7 deg, max: 15 deg}
    roller_diameter: {min: 8 mm, max: 12 mm}
"""


def _stop_leftovers(root, timeout=30.0):
    """Kill the processes still working in ``root`` (their working directory below it) and wait
    until they are gone; return how many there were. The CI cluster tracks a job's processes by
    parentage (proctrack/linuxproc, no cgroups): a cancelled job's Snakemake, orphaned when its
    step ends, outlives the cancel and would write into the rerun's working directory."""
    root = os.path.realpath(root)
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            cwd = os.readlink(f"/proc/{pid}/cwd")
        except OSError:
            continue
        if int(pid) != os.getpid() and (cwd == root or cwd.startswith(root + os.sep)):
            found.append(int(pid))
    for pid in found:
        try:
            os.kill(pid, 9)
        except ProcessLookupError:
            pass
    deadline = time.time() + timeout
    while time.time() < deadline and any(_alive(p) for p in found):
        time.sleep(0.1)
    return len(found)


def _alive(pid):
    """Whether process pid runs (a zombie waiting for its parent does not)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_a_chunk_job_cancelled_by_slurm_is_reported_and_the_rerun_keeps_finished_chunks(
    cluster, tmp_path
):
    wd = snakemake_workdir(tmp_path)
    (wd / "cancel.yaml").write_text(CANCEL_CONFIG)
    target = "results/roller/roller.h5"
    work = wd / "results/work/roller"
    cmd = [sys.executable, "-m", "snakemake", target, *PROFILE, "--configfile", "cancel.yaml"]
    with open(tmp_path / "first.log", "w") as out:
        first = subprocess.Popen(cmd, cwd=wd, stdout=out, stderr=subprocess.STDOUT, text=True)
        cancelled, deadline = [], time.time() + 300
        while time.time() < deadline and first.poll() is None:
            # once a chunk has finished, cancel every chunk job SLURM runs at that moment
            log = (tmp_path / "first.log").read_text()
            chunk_jobs = [s for _, s, p in SUBMITTED.findall(log) if "rule_chunk" in p]
            running = (
                [j for j, st in _job_states(chunk_jobs).items() if st == "RUNNING"]
                if chunk_jobs
                else []
            )
            if list(work.glob("chunk_*.h5")) and running:
                subprocess.run(["scancel", *running], check=True)
                cancelled = running
                break
            time.sleep(0.5)
        assert cancelled, "no chunk job was running after the first chunk finished"
        first.wait(timeout=300)
    log = (tmp_path / "first.log").read_text()
    assert first.returncode != 0, log
    assert "Error in rule chunk" in log and "CANCELLED" in log, log
    assert not (wd / target).exists()
    states = _job_states(cancelled)
    assert set(states.values()) == {"CANCELLED"}, states
    _stop_leftovers(wd)

    finished = {p.name: p.stat().st_mtime_ns for p in work.glob("chunk_*.h5")}
    assert 0 < len(finished) < 4, finished
    rerun = _snakemake(wd, target, *PROFILE, "--configfile", "cancel.yaml")
    log2 = rerun.stdout + rerun.stderr
    rerun_chunks = sorted(re.findall(r"rule_chunk/roller_(\d{4})/", log2))
    assert rerun_chunks == sorted(
        f"{i:04d}" for i in range(4) if f"chunk_{i:04d}.h5" not in finished
    ), log2
    for name, mtime in finished.items():  # not recomputed
        assert (work / name).stat().st_mtime_ns == mtime, name
    from clutchlab import store

    ds = store.load(wd / target)
    # every scenario computed (the default roller damping makes most wedgings dynamic_overstress,
    # so engaged ones are counted, not ok ones)
    assert ds.sizes["run"] == 524288 and int(ds["engagement_time"].notnull().sum()) > 0


def test_a_site_sets_the_partition_on_the_command_line(cluster, tmp_path):
    """The documented per-run partition command (docs/scaling.md), as written (`main` is the CI cluster's partition):
    one study's result, each of its jobs submitted to that partition."""
    wd = snakemake_workdir(tmp_path)
    proc = _snakemake(
        wd,
        "results/sprag/sprag.h5",
        *PROFILE,
        "--configfile",
        "config/small.yaml",
        "--default-resources",
        "slurm_partition=main",
    )
    ids = [s for _, s, _ in SUBMITTED.findall(proc.stdout + proc.stderr)]
    assert len(ids) == 4  # design, 2 chunks, merge
    out = subprocess.run(
        ["squeue", "--states=all", "--noheader", "--format=%P|%T", "--jobs", ",".join(ids)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    assert out == ["main|COMPLETED"] * 4, out
    assert (wd / "results/sprag/sprag.h5").stat().st_size > 0

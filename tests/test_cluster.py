"""Issue 19: what each Snakemake job asks a cluster for (clutchlab.cluster), and the SLURM profile as
shipped. The runs on a real cluster are in test_slurm.py."""

import re
import subprocess
import sys

import yaml

from clutchlab import cluster, config
from conftest import ROOT


def _resolved(name="million.yaml", **top):
    return config.resolve({**config.read_file(ROOT / "config" / name), **top})


def test_chunk_requests_follow_the_chunk_size_and_the_measured_cost():
    res = _resolved()
    for s in res["studies"]:
        n = cluster.chunk_scenarios(res[s])
        assert n == 524288  # chunk_size of config/million.yaml
        r = cluster.chunk_resources(res[s])
        fixed_s, per_s, fixed_mb, per_mb = cluster.CHUNK_COST[s]
        assert r["mem_mb"] >= cluster.MEMORY_MARGIN * (
            fixed_mb + per_mb * n
        )  # the measurement with its margin
        assert r["runtime"] * 60 >= cluster.TIME_MARGIN * (fixed_s + per_s * n)
        assert r["cpus_per_task"] == 1
        assert r["mem_mb"] <= 4000  # a 2^19 chunk fits a common 4 GB-per-core node
    # a quarter of the chunk size: at most the memory, at least the minimum
    small = _resolved(chunk_size=65536)
    for s in res["studies"]:
        a, b = cluster.chunk_resources(small[s]), cluster.chunk_resources(res[s])
        assert cluster.MIN_MEM_MB <= a["mem_mb"] <= b["mem_mb"] and a["runtime"] <= b["runtime"]
    # the centrifugal chunk (4.6 kB a scenario) grows most: 2^19 scenarios ask for more than 2^16
    assert (
        cluster.chunk_resources(small["centrifugal"])["mem_mb"]
        < cluster.chunk_resources(res["centrifugal"])["mem_mb"]
    )


def test_merge_and_pages_requests_grow_with_the_study():
    res, tiny = _resolved(), _resolved("small.yaml")
    for s in tiny["studies"]:
        for jobs in (cluster.merge_resources, cluster.pages_resources):
            assert jobs(tiny[s])["mem_mb"] <= jobs(res[s])["mem_mb"]
    # a 2^20 study's pages job peaked at 0.78 GB (the million run; 2.3 GB asked)
    assert cluster.pages_resources(res["engagement"])["mem_mb"] >= 1.2e3
    # the report joins files and draws the run's own pages: a fixed size, one core
    assert cluster.report_resources(tiny) == cluster.report_resources(res)


def test_the_rules_ask_for_what_clutchlab_cluster_computes(tmp_path):
    """A dry run of config/million.yaml prints each job's resources: the chunk jobs' mem_mb and
    runtime are clutchlab.cluster's, for every study."""
    from conftest import snakemake_workdir

    wd = snakemake_workdir(tmp_path)
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "snakemake",
            "--cores",
            "2",
            "--configfile",
            "config/million.yaml",
            "--dry-run",
        ],
        cwd=wd,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    res = _resolved()
    seen = 0
    for block in out.split("\nrule chunk:")[1:]:
        study = re.search(r"wildcards: study=(\w+)", block).group(1)
        want = cluster.chunk_resources(res[study])
        assert f"runtime={want['runtime']}," in block and f"mem_mb={want['mem_mb']}," in block, (
            block
        )
        assert "cpus_per_task=1" in block
        i = int(re.search(r"wildcards: study=\w+, i=(\d+)", block).group(1))
        priority = int(re.search(r"priority: (\d+)", block).group(1))
        assert priority == cluster.chunk_priority(res, study, i), block
        seen += 1
    assert seen == sum(res[s]["chunks"] for s in res["studies"])
    for block in out.split("\nrule pages_")[1:]:
        study = block.split(":")[0]
        want = cluster.pages_resources(res[study])
        assert f"mem_mb={want['mem_mb']}," in block and "cpus_per_task=1" in block, block
    report = out.split("\nrule report:")[1].split("\n\n")[0]
    assert "cpus_per_task=1" in report and "threads:" not in report, report


def test_first_chunks_first_and_the_longest_first():
    """Every study's first chunk (it compiles the study's kernels) before any later chunk; among
    first (and among later) chunks the longest study first; the designs before every chunk."""
    res = _resolved()
    names = res["studies"]
    first = {s: cluster.chunk_priority(res, s, 0) for s in names}
    later = {s: cluster.chunk_priority(res, s, 1) for s in names}
    assert min(first.values()) > max(later.values()) >= min(later.values()) >= 2
    assert max(first.values()) < cluster.DESIGN_PRIORITY
    by_length = sorted(names, key=lambda s: cluster.chunk_seconds(res[s]))
    assert sorted(names, key=first.get) == by_length == sorted(names, key=later.get)
    assert by_length[-1] == "engagement"  # three engagements a scenario: the longest chunk


def test_the_slurm_profile_has_no_site_placeholders():
    """Partition and account are the cluster's defaults unless a site sets them (docs/scaling.md); the
    profile once shipped 'compute' and 'your_account', which a real cluster rejects."""
    text = (ROOT / "workflows/profiles/slurm/config.yaml").read_text()
    prof = yaml.safe_load(text)
    assert "default-resources" not in prof and not any(
        k.startswith("slurm-partition") or k.startswith("slurm-account") for k in prof
    )
    assert prof["executor"] == "slurm" and prof["slurm-status-command"] == "squeue"
    assert prof["slurm-logdir"] == "logs/slurm"


def test_the_slurm_extra_installs_the_tested_plugin():
    """The documented `pip install -e ".[slurm]"`: the extra exists and asks for the plugin version the
    cluster tests ran (the test extra installs the same requirement)."""
    from importlib import metadata

    from packaging.requirements import Requirement

    reqs = [Requirement(r) for r in metadata.requires("clutchlab")]
    slurm = [r for r in reqs if r.marker and r.marker.evaluate({"extra": "slurm"})]
    assert [r.name for r in slurm] == ["snakemake-executor-plugin-slurm"]
    assert metadata.version("snakemake-executor-plugin-slurm") in slurm[0].specifier


def test_benchmark_helpers():
    """benchmark_slurm's share of the wall time with no job running, and one chunk job of
    benchmark_resources (a fresh process, as the chunk rule runs it)."""
    from clutchlab.bench import resources as benchmark_resources
    from clutchlab.bench import slurm as benchmark_slurm

    assert benchmark_slurm.idle_share([(0, 1), (2, 3)], 0, 4) == 0.5
    assert (
        benchmark_slurm.idle_share([(1, 3), (0, 2), (5, 9)], 0, 4) == 0.25
    )  # overlaps, one past the end
    row = benchmark_resources.measure_one(ROOT / "config/million.yaml", "sprag", 64)
    assert 0 < row["seconds"] < 60 and 50 < row["max_rss_mb"] < 4000

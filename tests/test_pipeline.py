"""End to end through Snakemake, as a user would run it (slow: each run starts Snakemake)."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from clutchlab.published import CENTRIFUGAL_CLUTCH, ROLLER_CLUTCH, SPRAG_TABLE2

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


from conftest import run_snakemake as _snakemake  # noqa: E402
from conftest import snakemake_workdir as _workdir  # noqa: E402


def test_outputs_exist_and_open(small_run):
    for f in (
        "results/diaphragm_spring/diaphragm_spring.h5",
        "results/report/report.pdf",
        "results/report/validation.csv",
        "results/report/diaphragm_spring_load_curves.png",
        "results/report/diaphragm_spring_reserve_map.png",
        "results/centrifugal/centrifugal.h5",
        "results/report/centrifugal_capacity_curves.png",
        "results/report/centrifugal_release_map.png",
        "results/report/centrifugal_traces.png",
        "results/sprag/sprag.h5",
        "results/report/sprag_stress_vs_torque.png",
        "results/report/sprag_pass_map.png",
        "results/report/sprag_impact_torque.png",
        "results/roller/roller.h5",
        "results/report/roller_stress_engagement.png",
        "results/report/roller_feasible_region.png",
        "results/report/roller_engagement_trace.png",
        "results/report/hard_cases.png",
    ):
        assert (small_run / f).stat().st_size > 0, f
    # issue 17: the hard cases of the studies run, computed in this run, every one passing
    import csv

    with open(small_run / "results/report/hard_cases.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert {r["study"] for r in rows} == {"diaphragm_spring", "centrifugal", "sprag", "roller"}
    assert all(r["passed"] == "1" and r["right_answer"] and r["source"] for r in rows)
    with xr.open_dataset(
        small_run / "results/diaphragm_spring/diaphragm_spring.h5", engine="h5netcdf"
    ) as ds:
        for name, var in {**ds.coords, **ds.data_vars}.items():
            assert var.attrs.get("units") is not None and var.attrs.get("long_name"), name
        assert ds["clamp_load"].dims == (
            "sheet_thickness",
            "cone_height_ratio",
            "radius_ratio",
            "operating_point_factor",
        )
        seed = ds.sel(
            sheet_thickness=2.334e-3,
            cone_height_ratio=1.5,
            radius_ratio=1.294,
            operating_point_factor=0.9,
            method="nearest",
        )
        assert 2300 < float(seed["clamp_load"]) < 2700
    with xr.open_dataset(small_run / "results/centrifugal/centrifugal.h5", engine="h5netcdf") as ds:
        for name, var in {**ds.coords, **ds.data_vars}.items():
            assert var.attrs.get("units") is not None and var.attrs.get("long_name"), name
        seed = ds.sel(
            pressure_angle=np.deg2rad(38.84), friction_coefficient=0.4046, method="nearest"
        )
        m = CENTRIFUGAL_CLUTCH["forward_capacity"].value  # seed 001 section 2.3
        assert abs(float(seed["capacity_forward"]) - m) < 0.2
        assert (
            ds["status"].sel(pressure_angle=np.deg2rad(65)).values[-2:] == 5
        ).all()  # f tan(alpha) >= 1: jammed
    with xr.open_dataset(small_run / "results/sprag/sprag.h5", engine="h5netcdf") as ds:
        for name, var in {**ds.coords, **ds.data_vars}.items():
            assert var.attrs.get("units") is not None and var.attrs.get("long_name"), name
        seed = ds.sel(torque=750.0, sprags=18, sprag_length=16.891e-3)
        v = SPRAG_TABLE2[750.0].gripping_angle  # seed 002 Table 2, the fit target
        assert abs(np.rad2deg(float(seed["gripping_angle"])) - v) < 1e-6
        assert int(seed["status"]) == 10  # pop_out_risk: V above 5 deg (seed 002 section 2.2)
    with xr.open_dataset(small_run / "results/roller/roller.h5", engine="h5netcdf") as ds:
        for name, var in {**ds.coords, **ds.data_vars}.items():
            assert var.attrs.get("units") is not None and var.attrs.get("long_name"), name
        assert ds["status"].dims == ("rollers", "wedge_angle")
        assert (
            ds["status"].sel(wedge_angle=np.deg2rad(15)).values == 11
        ).all()  # tan 7.5 deg > 0.12: not self-locking
        seed = ds.sel(rollers=12, wedge_angle=np.deg2rad(11))
        sigma = ROLLER_CLUTCH["contact_stress"].value  # seed 003 section 2.2 [MPa]
        assert abs(float(seed["contact_stress"]) / 1e6 - sigma) < 3
        assert 0.1e-3 < float(seed["engagement_time"]) < 0.3e-3
    assert "yes" in (small_run / "results/report/validation.csv").read_text()
    # the traces of the design each study's pages show, computed after the merge
    for study in ("centrifugal", "sprag", "roller"):
        with xr.open_dataset(small_run / f"results/{study}/traces.h5", engine="h5netcdf") as tr:
            assert int(tr.attrs["shown_index"]) >= 0 and tr.attrs["shown_design"], study
    for f in (
        "diaphragm_spring/diaphragm_spring.h5",
        "centrifugal/centrifugal.h5",
        "sprag/sprag.h5",
        "roller/roller.h5",
    ):
        with xr.open_dataset(
            small_run / "results" / f, engine="h5netcdf"
        ) as ds:  # design answers (issue 15)
            assert ds["feasible"].dims == ds["status"].dims == ds["pareto_rank"].dims, f
            assert (
                ":" in ds["pareto_rank"].attrs["objectives"]
                and "constraint" in ds["constraint_margin"].dims
            )
    for name in (
        "diaphragm_spring",
        "centrifugal",
        "sprag",
        "roller",
    ):  # the answers page and front table
        assert (small_run / f"results/report/{name}_answers.png").stat().st_size > 0
        rows = (small_run / f"results/report/{name}_pareto.csv").read_text().splitlines()
        if name == "roller":  # every simulated design's wedging impact is far over the allowable
            status = xr.load_dataset(small_run / "results/roller/roller.h5", engine="h5netcdf")
            assert len(rows) == 1 and (status["status"].values == 16).any(), rows  # no front
        else:
            assert rows[0].count("[") >= 3 and 1 <= len(rows) - 1 <= 15, (name, rows)
        with xr.open_dataset(small_run / f"results/{name}/sensitivity.h5", engine="h5netcdf") as se:
            assert se["total"].dims == ("output", "factor") and "failure" in se["output"].values
        assert (small_run / f"results/report/{name}_sensitivity.png").stat().st_size > 0


def test_bad_config_fails_before_any_job(small_run_copy):
    target = small_run_copy / "results/diaphragm_spring/diaphragm_spring.h5"
    before = (target.read_bytes(), target.stat().st_mtime_ns)
    bad = small_run_copy / "bad.yaml"
    bad.write_text(
        (small_run_copy / "config/small.yaml")
        .read_text()
        .replace("radius_ratio:", "radius_ration:")
    )
    proc = _snakemake(small_run_copy, "--configfile", "bad.yaml", "--forceall", check=False)
    assert proc.returncode != 0
    assert "diaphragm_spring.parameters.radius_ration" in proc.stdout + proc.stderr
    assert "Execute" not in proc.stdout + proc.stderr
    assert (target.read_bytes(), target.stat().st_mtime_ns) == before


def _tree(root):
    return {
        p: (p.read_bytes(), p.stat().st_mtime_ns) for p in sorted(root.rglob("*")) if p.is_file()
    }


def test_malformed_configs_are_refused_before_any_job(small_run_copy):
    """Every file of tests/malformed/ through Snakemake: one line 'clutchlab: config key ...' naming
    the key (or the file), no traceback, no job, results/ untouched. The files Snakemake's own
    loader would choke on (not UTF-8, not YAML, not a mapping, empty) or evaluate (a YTE template)
    are refused by the default workflow profile's precheck before Snakemake opens them."""
    from concurrent.futures import ThreadPoolExecutor

    # (a file marked '# snakemake: no' is refused by resolve like one Snakemake passes on: read in
    # process by tests/test_config.py only, each Snakemake start costs seconds. Through Snakemake
    # go the files its own loader might read otherwise (encoding, YAML 1.1, duplicates, aliases,
    # tags, templates, not a mapping) and one or two of each kind of key.)
    files = [
        p
        for p in sorted((ROOT / "tests/malformed").glob("*.yaml"))
        if b"\n# snakemake: no\n" not in p.read_bytes()[:400]
    ]
    before = _tree(small_run_copy / "results")

    def run(path):
        return path, _snakemake(small_run_copy, "--configfile", str(path), check=False)

    with ThreadPoolExecutor(2) as pool:
        outcomes = list(pool.map(run, files))
    wrong = []
    for path, proc in outcomes:
        out = "\n".join(
            line
            for line in (proc.stdout + proc.stderr).strip().splitlines()
            if not line.startswith("Using workflow specific profile")
        )
        key = path.read_text(errors="replace").split("\n", 1)[0].removeprefix("# expect:").strip()
        ok = (
            len(out.splitlines()) == 1
            and out.startswith("clutchlab: config ")
            and (f"'{key}'" in out or f"{key}'" in out)
        )
        if proc.returncode == 0 or "Execute" in out or not ok:
            wrong.append((path.name, out))
    assert not wrong, wrong
    assert _tree(small_run_copy / "results") == before


def test_a_template_config_is_never_evaluated(small_run_copy):
    """A config file starting with `__use_yte__: true` used to run its Python expressions inside
    Snakemake's loader, even in a dry run; the default profile refuses it before that."""
    bad = small_run_copy / "template.yaml"
    bad.write_text(
        '__use_yte__: true\nstudies: ?open("evaluated", "w").write("x") and ["sprag"]\n'
        "sprag: {design: factorial}\n"
    )
    proc = _snakemake(small_run_copy, "--configfile", str(bad), "--dry-run", check=False)
    assert (
        proc.returncode != 0 and "clutchlab: config key '__use_yte__'" in proc.stderr + proc.stdout
    )
    assert not (small_run_copy / "evaluated").exists()


def test_a_json_config_indented_with_tabs_is_accepted(small_run_copy):
    """JSON is a config's other form: Snakemake reads it as JSON, and so does clutchlab (YAML
    refuses tabs; this used to be refused as 'not valid YAML')."""
    import json

    cfg = small_run_copy / "tabs.json"
    body = {
        "results": "results/tabs",
        "studies": ["sprag"],
        "sprag": {"design": "factorial", "parameters": {"torque": "500 N*m"}},
    }
    cfg.write_text(json.dumps(body, indent="\t"))
    proc = _snakemake(small_run_copy, "--configfile", str(cfg), "--dry-run", check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "merge_sprag" in proc.stdout


def test_same_config_twice_gives_identical_files(small_run, tmp_path):
    wd = _workdir(tmp_path)
    _snakemake(wd, "--configfile", "config/small.yaml")
    for f in (
        "results/diaphragm_spring/diaphragm_spring.h5",
        "results/diaphragm_spring/validation.h5",
        "results/report/validation.csv",
        "results/report/diaphragm_spring_reserve_map.png",
    ):
        assert (wd / f).read_bytes() == (small_run / f).read_bytes(), f


def _without_solver_pages(wd) -> str:
    """config/small.yaml in ``wd`` without the pages that run solvers of their own (benchmark,
    numerics, hard cases; the small run draws them): the interrupt and kill tests are about the
    workflow's files, not those pages. Returns the config's path relative to ``wd``."""
    import yaml

    cfg = yaml.safe_load((wd / "config/small.yaml").read_text())
    cfg.setdefault("report", {}).update(benchmark=False, numerics=False, hard_cases=False)
    (wd / "config/small_lite.yaml").write_text(yaml.safe_dump(cfg, sort_keys=False))
    return "config/small_lite.yaml"


# the chunks a study of the interrupt and kill tests: the run is stopped at its first chunk file,
# with the other chunks, the merges and the report still to come
STOP_CHUNKS = "chunks=3"


def _default_sigint():
    """In the child before it runs Snakemake: SIGINT handled again (a shell's background job, as a
    CI script may run the tests, inherits it ignored, and Python then never raises
    KeyboardInterrupt)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _interrupt(proc, log):
    """Ctrl-C to a running Snakemake, again until it says it stops: Snakemake drops an interrupt
    that arrives while it writes a log line (its log handler swallows KeyboardInterrupt), as a
    user would press Ctrl-C again."""
    for _ in range(10):
        proc.send_signal(signal.SIGINT)
        until = time.time() + 3
        while time.time() < until:
            if proc.poll() is not None or "on user request" in log.read_text(errors="replace"):
                return
            time.sleep(0.05)


def test_interrupt_and_resume(tmp_path):
    wd = _workdir(tmp_path)
    lite = _without_solver_pages(wd)
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "--cores",
        "1",
        "--configfile",
        lite,
        "--config",
        STOP_CHUNKS,
    ]
    log = tmp_path / "snakemake.log"
    with open(log, "w") as fh:  # (Ctrl-C reaches it also where the test runs with it ignored)
        proc = subprocess.Popen(
            cmd, cwd=wd, stdout=fh, stderr=subprocess.STDOUT, preexec_fn=_default_sigint
        )
    work = wd / "results/work/diaphragm_spring"
    deadline = time.time() + 120
    while time.time() < deadline and not list(work.glob("chunk_*.h5")):
        time.sleep(0.05)
    _interrupt(proc, log)  # Ctrl-C mid-run
    try:  # Snakemake lets the running job finish: on an empty kernel cache it may be compiling
        proc.wait(timeout=900)  # one of the kernels (minutes on a loaded 2-core machine)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert not (wd / "results/report/report.pdf").exists(), (
        "run finished before it could be interrupted"
    )
    for f in wd.rglob("*.h5"):  # whatever exists is complete and readable
        xr.open_dataset(f, engine="h5netcdf").close()
    _snakemake(wd, "--configfile", lite, "--config", STOP_CHUNKS)
    assert (wd / "results/report/report.pdf").exists()
    assert not [p for p in wd.rglob("*.tmp")]


def test_killed_run_unlock_and_resume(tmp_path):
    """The documented recovery after a hard kill (docs/outputs.md): the lock left behind, `snakemake --unlock`, rerun;
    no temporary file of the killed jobs survives the rerun."""
    wd = _workdir(tmp_path)
    lite = _without_solver_pages(wd)
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "--cores",
        "2",
        "--configfile",
        lite,
        "--config",
        STOP_CHUNKS,
    ]
    proc = subprocess.Popen(
        cmd, cwd=wd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True
    )
    work = wd / "results/work/centrifugal"
    deadline = time.time() + 120
    while time.time() < deadline and not list(work.glob("chunk_*.h5")):
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)  # kill -9 of Snakemake and its jobs
    proc.wait(timeout=60)
    assert not (wd / "results/report/report.pdf").exists(), "run finished before it could be killed"
    locked = _snakemake(wd, "--configfile", lite, "--config", STOP_CHUNKS, check=False)
    assert locked.returncode != 0 and "cannot be locked" in locked.stdout + locked.stderr
    _snakemake(wd, "--unlock", "--configfile", lite)
    _snakemake(wd, "--configfile", lite, "--config", STOP_CHUNKS)
    assert (wd / "results/report/report.pdf").exists()
    assert not [p for p in wd.rglob("*.tmp")]


def _tiny_variant(path):
    """A config file cut to two scenarios per study: its first factor keeps two values, every other
    factor one (still a dimension: the figures draw over them); no benchmark, numerics or hard-case
    pages (solver runs of their own that do not depend on the config's grid: the small run draws
    them)."""
    import yaml

    cfg = yaml.safe_load(path.read_text())
    cfg.setdefault("report", {}).update(benchmark=False, numerics=False, hard_cases=False)
    cfg.pop("chunk_size", None)  # the test sets the chunk count (--config chunks=N)
    for name in cfg["studies"]:
        sec = cfg[name]
        sec.pop("chunks", None)
        sec.pop("chunk_size", None)
        if "noise_samples" in sec:  # a robust study: the fewest noise draws
            sec["noise_samples"] = 2
        first = True
        for key, spec in list((sec.get("parameters") or {}).items()):
            if not isinstance(spec, dict):
                continue
            if "values" in spec:
                vals = spec["values"]
            elif sec["design"] == "factorial":
                vals = [spec["min"], spec["max"]]
            else:
                continue  # a sampled design keeps its bounds; its size is `samples`
            sec["parameters"][key] = {"values": vals[:2] if first else vals[:1]}
            first = False
        if sec["design"] != "factorial":
            sec["samples"] = 2
    return cfg


_CONFIGS = sorted(p.name for p in (ROOT / "config").glob("*.yaml"))


@pytest.mark.parametrize(
    "name, chunking",
    [(name, ("one", "more than scenarios")[i % 2]) for i, name in enumerate(_CONFIGS)],
)
def test_every_config_runs_with_any_chunk_count(name, chunking, tmp_path, monkeypatch):
    """Every file in config/ runs end to end (tiny variant), every other one with one chunk and the
    others with more chunks than scenarios (empty chunk jobs; config.yaml's own 4 is that here):
    each run costs a minute, and that a result does not depend on the chunk count is checked
    value by value in tests/test_provenance.py. seed000.yaml used to fail (validation outputs
    declared without a validated study), a one-value factor used to crash the map pages."""
    import yaml

    from clutchlab import config, doe, pipeline
    from conftest import refine_sources

    wd = _workdir(tmp_path)
    cfg = _tiny_variant(ROOT / "config" / name)
    own = int(
        yaml.safe_load((ROOT / "config" / name).read_text()).get("chunks", config.DEFAULT_CHUNKS)
    )
    (wd / "tiny.yaml").write_text(yaml.safe_dump(cfg))
    if refine_sources(cfg):  # a second stage: the first stage (the default config, tiny) runs first
        (wd / "first.yaml").write_text(
            yaml.safe_dump(_tiny_variant(ROOT / "config" / "config.yaml"))
        )
        # only the results the second stage reads (its merge jobs): the first stage's other
        # studies and its report are config.yaml's own run here (targets before --configfile,
        # which takes every word after it)
        _snakemake(wd, *refine_sources(cfg), "--configfile", "first.yaml")
        assert all((wd / s).exists() for s in refine_sources(cfg))
    monkeypatch.chdir(wd)  # relative paths of the config (refine.from) as Snakemake reads them
    resolved = config.resolve(cfg)
    sizes = {s: pipeline.n_scenarios(doe.build_design(resolved[s])) for s in resolved["studies"]}
    chunks = 1 if chunking == "one" else max(own, max(sizes.values()) + 1)
    _snakemake(wd, "--configfile", "tiny.yaml", "--config", f"chunks={chunks}", "--forceall")
    out = wd / resolved["results"]
    assert (out / "report/report.pdf").stat().st_size > 0
    from clutchlab import store, studies

    for s, n in sizes.items():
        ds = store.load(out / studies.get(s).output)
        assert int(ds["status"].size) == n, (s, chunks)


def test_editing_the_physics_reruns_the_studies(small_run_copy, tmp_path):
    """Issue 14: results say what produced them (the package's source hash, also a param of every
    physics rule); an edited physics constant makes the next run recompute, where it used to say
    'Nothing to be done'."""
    import clutchlab
    from clutchlab import store

    ds = store.load(small_run_copy / "results/diaphragm_spring/diaphragm_spring.h5")
    assert ds.attrs["clutchlab_source"] == clutchlab.source_hash()
    same = _snakemake(small_run_copy, "--configfile", "config/small.yaml", "--dry-run")
    assert "Nothing to be done" in same.stdout + same.stderr
    src = tmp_path / "src"
    shutil.copytree(
        ROOT / "src" / "clutchlab", src / "clutchlab", ignore=shutil.ignore_patterns("__pycache__")
    )
    mod = src / "clutchlab" / "diaphragm.py"
    mod.write_text(mod.read_text() + "\n_EDITED_CONSTANT = 1.0  # an edit to the physics\n")
    assert clutchlab.source_hash(src / "clutchlab") != clutchlab.source_hash()
    env = {**os.environ, "PYTHONPATH": str(src)}
    edited = _snakemake(small_run_copy, "--configfile", "config/small.yaml", "--dry-run", env=env)
    out = edited.stdout + edited.stderr
    assert "Nothing to be done" not in out and "chunk" in out and "merge_diaphragm_spring" in out


def test_a_changed_chunk_is_found_by_the_merge_and_recomputed(small_run_copy):
    """Issue 14: a chunk file whose data changed after it was written used to be merged silently;
    the merge checks each chunk's checksum, names and removes the bad one, the next run recomputes."""
    import h5py

    result = small_run_copy / "results/sprag/sprag.h5"
    before = xr.load_dataset(result, engine="h5netcdf")
    chunk = small_run_copy / "results/work/sprag/chunk_0001.h5"
    with h5py.File(chunk, "r+") as f:
        f["gripping_angle"][0] = 0.0
    proc = _snakemake(small_run_copy, "--configfile", "config/small.yaml", check=False)
    assert proc.returncode != 0
    assert (
        "results/work/sprag/chunk_0001.h5 does not match its checksum" in proc.stdout + proc.stderr
    )
    assert not chunk.exists()
    _snakemake(small_run_copy, "--configfile", "config/small.yaml")
    xr.testing.assert_identical(xr.load_dataset(result, engine="h5netcdf"), before)


def test_every_file_of_a_run_verifies_against_its_config(small_run):
    """Item 8: `clutchlab verify --config` on every study result, sensitivity file, design and
    chunk a run wrote: each matches its checksum, its study config and this source (one ok line
    each, exit 0)."""
    res = small_run / "results"
    files = sorted(
        str(p.relative_to(small_run))
        for p in res.rglob("*.h5")
        if p.parent.name not in ("validation", "numerics")  # (seed numbers, solver runs)
    )
    assert len([f for f in files if "chunk_" in f]) == 8 and len(files) > 16, files
    proc = subprocess.run(
        [sys.executable, "-m", "clutchlab.verify", "--config", "config/small.yaml", *files],
        cwd=small_run,
        capture_output=True,
        text=True,
        timeout=300,
    )
    lines = proc.stdout.splitlines()
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert [line.split(": ")[0] for line in lines] == files
    assert all(line.split(": ")[1].startswith("ok") for line in lines), lines


def test_every_report_page_keeps_its_text_on_the_page(small_run, tmp_path, monkeypatch):
    """Issue 18 item 3: the summary page names each study's best design and its pages; no text of
    any page (titles, labels, legends, tables, notes) runs off the page."""
    import glob

    from clutchlab import report, store, studies
    from clutchlab.report.common import texts_outside, texts_overprinted, texts_too_small

    res = small_run / "results"
    names = ["diaphragm_spring", "centrifugal", "sprag", "roller"]
    import matplotlib

    figures = []
    monkeypatch.setattr(report.plt, "close", figures.append)
    monkeypatch.setitem(matplotlib.rcParams, "figure.max_open_warning", 0)  # (kept to check them)
    report.build(
        {n: res / studies.get(n).output for n in names},
        sorted(glob.glob(str(res / "*/validation.h5"))),
        tmp_path,
        hard_cases_file=res / "numerics/hard_cases.h5",
        numerics_dir=res / "numerics",
        traces_files={n: res / n / "traces.h5" for n in names if (res / n / "traces.h5").exists()},
    )
    assert len(figures) >= 20
    for fig in figures:
        assert not texts_outside(fig), texts_outside(fig)
        assert not texts_too_small(fig), texts_too_small(fig)[:5]
        assert not texts_overprinted(fig), texts_overprinted(fig)
    # the summary: drawn after the studies' and the run's parts, the report's first page
    (title,) = [f for f in figures if f.texts and f.texts[0].get_text() == "clutchlab report"]
    summary = " ".join(" ".join(t.get_text() for t in title.texts).split())
    assert summary.count("best compromise: ") == len(names)
    assert "stress_engagement, feasible_region, engagement_trace, answers" in summary
    from clutchlab.report.common import study_summary, title_page

    sprag = study_summary("sprag", store.load(res / "sprag/sprag.h5"))
    page = title_page("t", "v", [sprag], [], None, {"sprag": (3, 12.5)})
    assert "3 jobs, 12.5 s of job time" in " ".join(t.get_text() for t in page.texts)


def test_snakemakes_own_report_holds_every_page_with_its_caption(small_run_copy):
    """Issue 18 item 2: `snakemake --report` gives one HTML with every report file, each with its
    caption (clutchlab.report.captions), and the run's provenance (version, source hash, config)."""
    import clutchlab
    from clutchlab.report import captions

    _snakemake(
        small_run_copy, "--configfile", "config/small.yaml", "--report", "results/report.html"
    )  # as docs/outputs.md
    html = (small_run_copy / "results/report.html").read_text()
    names = ["diaphragm_spring", "centrifugal", "sprag", "roller"]
    files = sorted(p.name for p in (small_run_copy / "results/report").iterdir())
    assert len(files) >= 25
    for name in files:
        assert name in html, name
        words = [
            w
            for w in captions.caption(name, names).split()
            if w.isascii() and w.isalpha() and len(w) > 4
        ]
        assert all(w in html for w in words[:6]), (
            name,
            words[:6],
        )  # its caption (non-ASCII is escaped)
    assert clutchlab.__version__ in html and clutchlab.source_hash() in html
    assert "Studies run: diaphragm_spring, centrifugal, sprag, roller" in html
    # it opens on a description of the run pointing to its own results folder, not a config dump
    assert "Start with the summary page" in html and "results/report/report.pdf" in html
    import zipfile

    _snakemake(
        small_run_copy, "--configfile", "config/small.yaml", "--report", "results/report.zip"
    )
    with zipfile.ZipFile(small_run_copy / "results/report.zip") as z:
        assert any(n.endswith("report.html") for n in z.namelist()) and len(z.namelist()) > len(
            files
        )


def test_every_report_file_has_a_caption():
    from clutchlab.report import captions, figure_stems

    names = ["diaphragm_spring", "engagement", "centrifugal", "sprag", "roller"]
    stems = figure_stems(names, True, names, names, True, True)
    for stem in stems:
        assert captions.caption(f"{stem}.png", names)
    for f in (
        "report.pdf",
        "validation.csv",
        "hard_cases.csv",
        "roller_pareto.csv",
        "sprag_refinement.csv",
    ):
        assert captions.caption(f, names)
    with pytest.raises(KeyError):
        captions.caption("nothing.png", names)

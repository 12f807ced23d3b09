"""Chunk provenance and verifiable results: a chunk computed by another config (same grid, another
Young's modulus), an attribute edited in a chunk and a result edited by hand are each found and
named (through the API, the ``clutchlab verify`` command and Snakemake); good chunks still merge
to the in-memory concatenation; the checksum of a million-scenario result is computed a block at a
time."""

import shutil
import subprocess
import sys
import tomllib

import h5py
import numpy as np
import pytest
import xarray as xr

from clutchlab import config, doe, explore, pipeline, store, verify
from clutchlab.config import resolve, study_config_text
from conftest import ROOT, run_snakemake, snakemake_workdir

STUDY = "diaphragm_spring"
GRID = {
    "sheet_thickness": {"values": ["2 mm", "2.3 mm", "2.6 mm"]},
    "cone_height_ratio": {"values": [1.5, 1.9]},
}


def _section(**fixed) -> dict:
    raw = {
        "studies": [STUDY],
        "chunks": 2,
        STUDY: {"design": "factorial", "parameters": {**GRID, **fixed}},
    }
    return resolve(raw)[STUDY]


def _write_chunks(sec, folder, chunks=2) -> list:
    """design.h5 and chunk_NNNN.h5 of ``sec`` in ``folder`` as the workflow writes them."""
    folder.mkdir(parents=True, exist_ok=True)
    design = doe.build_design(sec)
    store.write(design, folder / "design.h5", with_checksum=True)
    paths = []
    for i in range(chunks):
        paths.append(folder / f"chunk_{i:04d}.h5")
        store.write(
            pipeline.run_chunk(design, sec["options"], chunks, i),
            paths[-1],
            with_checksum=True,
            complevel=0,
        )
    return paths


@pytest.fixture
def own(tmp_path):
    sec = _section()
    return sec, doe.build_design(sec), _write_chunks(sec, tmp_path / "work" / STUDY)


def _merge(sec, design, paths, out, **kw):
    pipeline.merge_to_file(design, paths, out, sec["objectives"], sec["constraints"], **kw)


def test_a_chunk_says_what_produced_it(own):
    """Each chunk carries its study's config text, the design's hash (of its values and
    attributes), the source hash, and which chunk of how many it is."""
    import clutchlab

    sec, design, paths = own
    for i, p in enumerate(paths):
        a = store.load(p).attrs
        assert a["config"] == study_config_text(sec)
        assert a["clutchlab_design_hash"] == store.checksum(design)
        assert a["clutchlab_source"] == clutchlab.source_hash()
        assert (int(a["chunk_index"]), int(a["chunk_count"])) == (i, 2)


def test_a_foreign_chunk_is_named_removed_and_recomputed(own, tmp_path):
    """A chunk of another config (the same grid, E = 200 GPa instead of 206 GPa) in the place of
    chunk 2 used to be merged into a 50/50 mix; the merge names it and the key that differs,
    removes it and writes no result; with the chunk recomputed the merge equals the in-memory
    concatenation of good chunks."""
    sec, design, paths = own
    other = _write_chunks(_section(youngs_modulus="200 GPa"), tmp_path / "other")
    shutil.copy(other[1], paths[1])
    out = tmp_path / "spring.h5"
    with pytest.raises(store.ForeignChunk) as err:
        _merge(sec, design, paths, out, config=study_config_text(sec))
    message = str(err.value)
    assert message.startswith(f"{paths[1]} was computed from another study config")
    assert "fixed.youngs_modulus 200000000000.0 (expected 206000000000.0)" in message
    assert "it has been removed, run snakemake again" in message
    assert not paths[1].exists() and not out.exists() and paths[0].exists()

    store.write(pipeline.run_chunk(design, sec["options"], 2, 1), paths[1], with_checksum=True)
    _merge(sec, design, paths, out, config=study_config_text(sec))
    want = explore.annotate(
        pipeline.merge(design, [store.load(p) for p in paths]),
        sec["objectives"],
        sec["constraints"],
    )
    got = store.load(out)
    assert got.attrs.pop("clutchlab_checksum") == store.checksum(want)
    assert (
        got.attrs.pop("clutchlab_checksum_variables")
        == store.checksum_attrs(want)["clutchlab_checksum_variables"]
    )
    xr.testing.assert_identical(got, want)
    assert verify.file_problems(out, config=study_config_text(sec), design=design) == []


def test_the_in_memory_merge_refuses_a_foreign_chunk_too(own):
    sec, design, _ = own
    other = _section(youngs_modulus="200 GPa")
    parts = [
        pipeline.run_chunk(design, sec["options"], 2, 0),
        pipeline.run_chunk(doe.build_design(other), other["options"], 2, 1),
    ]
    with pytest.raises(
        store.ForeignChunk, match="chunk 2 of the 2 given was computed from another"
    ):
        pipeline.merge(design, parts)


@pytest.mark.parametrize(
    "edit, message",
    [
        ({"clutchlab_source": "0123456789abcdef"}, "was computed by another clutchlab source"),
        ({"clutchlab_design_hash": "f" * 64}, "was computed from another design"),
        ({"config": None}, "has no config attribute"),
        ({"chunk_index": None}, "has no chunk_index attribute"),
    ],
)
def test_a_chunk_of_another_source_or_design_is_refused(own, tmp_path, edit, message):
    """A chunk whose checksum is right but whose provenance is not this study's (another source,
    another design, no provenance) is named with what differs and removed."""
    sec, design, paths = own
    ds = store.load_verified(paths[0])
    for key, value in edit.items():
        if value is None:
            del ds.attrs[key]
        else:
            ds.attrs[key] = value
    store.write(ds, paths[0], with_checksum=True)
    with pytest.raises(store.ForeignChunk, match=message) as err:
        _merge(sec, design, paths, tmp_path / "out.h5")
    assert str(paths[0]) in str(err.value) and not paths[0].exists()


@pytest.mark.parametrize(
    "where, edit, found",
    [
        ("clamp_load", ("units", "kN"), "clamp_load attributes"),
        ("clamp_load", ("long_name", "clamp load"), "clamp_load attributes"),
        (None, ("config", "edited"), "global attributes"),
    ],
)
def test_an_attribute_edit_in_a_chunk_is_found(own, tmp_path, where, edit, found):
    """A unit attribute edited in a chunk (clamp_load in kN) used to be carried into the result:
    the checksum covers every variable's and the global attributes; the merge names the chunk
    and what changed, and removes it."""
    sec, design, paths = own
    with h5py.File(paths[0], "r+") as f:
        (f[where] if where else f).attrs[edit[0]] = edit[1]
    assert verify.file_problems(paths[0]) == [
        f"does not match its checksum (changed after it was written: {found})"
    ]
    with pytest.raises(
        store.CorruptChunk, match=f"chunk_0000.h5 does not match its checksum .*{found}"
    ):
        _merge(sec, design, paths, tmp_path / "out.h5")
    assert not paths[0].exists() and not (tmp_path / "out.h5").exists()


@pytest.fixture
def result(own, tmp_path):
    """A merged result in the workflow's layout: results/diaphragm_spring/diaphragm_spring.h5 beside results/work."""
    sec, design, paths = own
    out = tmp_path / "diaphragm_spring" / "diaphragm_spring.h5"
    _merge(sec, design, paths, out, config=study_config_text(sec))
    return out


@pytest.mark.parametrize(
    "variable, found",
    [
        ("feasible", "feasible values"),
        ("pareto_rank", "pareto_rank values"),
        ("clamp_load", "clamp_load values"),
    ],
)
def test_a_hand_edited_result_is_found(result, variable, found, capsys):
    """A merged result edited by hand was not detected (the report reran on it, `feasible` and
    `pareto_rank` stale): it is sealed with its own checksum, which verify checks."""
    assert verify.file_problems(result) == []
    with h5py.File(result, "r+") as f:
        flat = f[variable][...].ravel()
        flat[1] = flat[1] + 1
        f[variable][...] = flat.reshape(f[variable].shape)
    assert verify.file_problems(result) == [
        f"does not match its checksum (changed after it was written: {found})"
    ]
    assert verify.main([str(result)]) == 1
    out = capsys.readouterr().out
    assert out.startswith(f"{result}: FAILED: does not match its checksum") and found in out
    with pytest.raises(verify.ProvenanceError, match=f"{result} does not match .* delete it"):
        verify.require({result: {}})


def test_a_result_loaded_and_checked_in_memory_says_what_the_file_check_says(result):
    """verify.load_checked (the pages job: one read of the file) returns the file's content where
    it verifies, and refuses it with file_problems' own words where it does not."""
    xr.testing.assert_identical(verify.load_checked(result), store.load(result))
    with h5py.File(result, "r+") as f:
        f["clamp_load"].attrs["units"] = "kN"
    (problem,) = verify.file_problems(result)
    with pytest.raises(verify.ProvenanceError) as err:
        verify.load_checked(result, action="do this")
    assert str(err.value) == f"{result} {problem}; do this"
    result.write_bytes(result.read_bytes()[:1000])  # cut
    with pytest.raises(verify.ProvenanceError, match="cannot be read"):
        verify.load_checked(result)


def test_a_result_without_checksum_or_provenance_fails(result):
    with h5py.File(result, "r+") as f:
        del f.attrs["clutchlab_checksum"]
    assert verify.file_problems(result) == ["has no checksum"]
    with h5py.File(result, "r+") as f:
        f.attrs["clutchlab_checksum"] = "0" * 64
    assert verify.file_problems(result)[0].startswith("does not match its checksum")
    store.write(store.load(result).drop_attrs(deep=False), result, with_checksum=True)
    assert verify.file_problems(result) == [f"has no {key} attribute" for key in verify.PROVENANCE]


def test_good_files_verify_ok_and_a_misplaced_chunk_is_found(own, result, tmp_path, capsys):
    """Result, chunks, design and sensitivity-free files of the layout verify ok (exit 0, one
    line each); a good chunk under another chunk's name, or checked against another design, is
    named."""
    sec, design, paths = own
    files = [result, *paths, paths[0].parent / "design.h5"]
    assert verify.main([str(p) for p in files]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(": ")[0] for line in lines] == [str(p) for p in files]
    assert all(": ok" in line for line in lines), lines
    shutil.copy(paths[1], paths[0])
    assert verify.file_problems(paths[0]) == ["holds chunk 2 of 2, not the chunk its name says"]
    other = doe.build_design(_section(youngs_modulus="200 GPa"))
    assert verify.file_problems(result, design=other)[0].startswith(
        "was computed from another design"
    )


def test_chunks_missing_duplicated_or_out_of_order_are_refused(own, tmp_path):
    sec, design, paths = own
    for given in ([paths[0]], [paths[0], paths[0]], [paths[1], paths[0]]):
        with pytest.raises(ValueError, match="missing or duplicated"):
            _merge(sec, design, given, tmp_path / "out.h5")
        assert all(p.exists() for p in paths) and not (tmp_path / "out.h5").exists()


def test_a_design_of_another_config_or_source_is_refused(own, tmp_path):
    """The merge checks the design too against the current study config and source."""
    sec, design, paths = own
    other = study_config_text(_section(youngs_modulus="200 GPa"))
    with pytest.raises(verify.ProvenanceError, match="the design was computed from another study"):
        _merge(sec, design, paths, tmp_path / "out.h5", config=other)
    with pytest.raises(verify.ProvenanceError, match="another clutchlab source"):
        _merge(sec, design, paths, tmp_path / "out.h5", source="0123456789abcdef")
    assert all(p.exists() for p in paths)


def test_verify_against_a_config_file(result, tmp_path, capsys):
    """`clutchlab verify --config FILE`: each file's study config must be that file's and its
    source the installed clutchlab's; another Young's modulus is named."""
    import yaml

    raw = {"studies": [STUDY], "chunks": 2, STUDY: {"design": "factorial", "parameters": GRID}}
    same, other = tmp_path / "same.yaml", tmp_path / "other.yaml"
    same.write_text(yaml.safe_dump(raw))
    raw[STUDY]["parameters"] = {**GRID, "youngs_modulus": "200 GPa"}
    other.write_text(yaml.safe_dump(raw))
    assert verify.main(["--config", str(same), str(result)]) == 0
    assert verify.main(["--config", str(other), str(result)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"{result}: ok (study {STUDY}")
    assert out[1] == (
        f"{result}: FAILED: was computed from another study config: fixed.youngs_modulus "
        "206000000000.0 (expected 200000000000.0)"
    )
    assert config.load(same)[STUDY]["chunks"] == 2


def test_the_console_script_and_the_module(result, tmp_path):
    """`clutchlab verify PATH...` (pyproject's console script) and `python -m clutchlab.verify`."""
    from importlib import import_module

    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    module, name = scripts["clutchlab"].split(":")
    cli = getattr(import_module(module), name)
    assert cli(["verify", str(result)]) == 0
    assert cli([]) == 2 and cli(["check", str(result)]) == 2
    missing = tmp_path / "missing.h5"
    proc = subprocess.run(
        [sys.executable, "-m", "clutchlab.verify", str(result), str(missing)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 1, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0].startswith(f"{result}: ok") and lines[1].startswith(
        f"{missing}: FAILED: does not exist"
    )


def test_a_million_scenario_checksum_is_read_a_block_at_a_time(tmp_path):
    """The checksum of a 10^6-scenario result (40 MB of columns) is computed from the file a block
    at a time: peak numpy/Python memory stays a small fraction of the file, and it equals the
    in-memory checksum (hash per variable per block in a fixed order)."""
    import tracemalloc

    n = 1_000_000
    rng = np.random.default_rng(0)
    cols = {f"x{k}": ("run", rng.random(n), {"units": "m", "long_name": f"x{k}"}) for k in range(4)}
    cols["status"] = (
        "run",
        rng.integers(0, 3, n).astype(np.int8),
        {"units": "1", "long_name": "s"},
    )
    ds = xr.Dataset(cols, coords={"run": ("run", np.arange(n), {"units": "1", "long_name": "i"})})
    ds["x0"][::7] = np.nan
    path = store.write(ds, tmp_path / "big.h5", complevel=0)
    want = store.checksum(ds)
    tracemalloc.start()
    got = store.seal(path)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert got == want
    assert peak < 0.15 * ds.nbytes, (peak, ds.nbytes)
    assert store.file_checksum_problem(path) is None


@pytest.mark.slow
def test_snakemake_finds_a_foreign_chunk_and_a_hand_edited_result(tmp_path):
    """Through Snakemake: a chunk of another config put in the place of one of this run's used to
    be merged and everything then called up to date; the merge job names it, removes it and
    fails, the next run recomputes it and gives the same result. A result edited by hand: the
    pages job refuses it, naming the file and what to do (delete it and rerun); after that, the
    run gives the original result again."""
    wd = snakemake_workdir(tmp_path)
    tiny = {
        "studies": [STUDY],
        "chunks": 2,
        "report": {
            "title": "provenance",
            "benchmark": False,
            "hard_cases": False,
            "numerics": False,
        },
        STUDY: {"design": "factorial", "parameters": GRID},
    }
    import yaml

    (wd / "tiny.yaml").write_text(yaml.safe_dump(tiny))
    run_snakemake(wd, "--configfile", "tiny.yaml")
    result = wd / "results" / "diaphragm_spring" / "diaphragm_spring.h5"
    before = xr.load_dataset(result, engine="h5netcdf")
    chunk = wd / "results" / "work" / STUDY / "chunk_0001.h5"
    foreign = _write_chunks(_section(youngs_modulus="200 GPa"), tmp_path / "other")[1]
    shutil.copy(foreign, chunk)  # newer than the result: the merge reruns
    proc = run_snakemake(wd, "--configfile", "tiny.yaml", check=False)
    log = proc.stdout + proc.stderr
    assert proc.returncode != 0
    assert (
        "results/work/diaphragm_spring/chunk_0001.h5 was computed from another study config: "
        "fixed.youngs_modulus 200000000000.0 (expected 206000000000.0)" in log
    ), log
    assert not chunk.exists()
    run_snakemake(wd, "--configfile", "tiny.yaml")
    xr.testing.assert_identical(xr.load_dataset(result, engine="h5netcdf"), before)

    pdf = wd / "results" / "report" / "report.pdf"
    built = pdf.stat().st_mtime_ns
    with h5py.File(result, "r+") as f:
        f["clamp_load"].attrs["units"] = "kN"
    proc = run_snakemake(wd, "--configfile", "tiny.yaml", check=False)
    log = proc.stdout + proc.stderr
    assert proc.returncode != 0
    assert (
        "results/diaphragm_spring/diaphragm_spring.h5 does not match its checksum (changed after it was written: "
        "clamp_load attributes); delete it and run snakemake again to recompute it" in log
    ), log
    # no page is drawn from the edited result (the job that reads it first refuses it: the report
    # of the earlier run stays as it was, or is removed where the report job itself refused)
    assert not pdf.exists() or pdf.stat().st_mtime_ns == built
    result.unlink()
    run_snakemake(wd, "--configfile", "tiny.yaml")
    xr.testing.assert_identical(xr.load_dataset(result, engine="h5netcdf"), before)
    same = run_snakemake(wd, "--configfile", "tiny.yaml", "--dry-run")
    assert "Nothing to be done" in same.stdout + same.stderr


def test_a_stored_result_is_identical_whatever_the_chunk_count(tmp_path):
    """The chunk count says how a study runs, not what it is: the stored result (values, attributes,
    checksums, config text) of one chunk and of five is the same file content."""
    got = []
    for chunks in (1, 5):
        sec = resolve(
            {
                "studies": [STUDY],
                "chunks": chunks,
                STUDY: {"design": "factorial", "parameters": GRID},
            }
        )[STUDY]
        paths = _write_chunks(sec, tmp_path / str(chunks), chunks=chunks)
        out = tmp_path / str(chunks) / "result.h5"
        design = store.load(tmp_path / str(chunks) / "design.h5")
        _merge(sec, design, paths, out, config=study_config_text(sec))
        got.append(store.load(out))
    xr.testing.assert_identical(got[0], got[1])
    assert got[0].attrs["clutchlab_checksum"] == got[1].attrs["clutchlab_checksum"]

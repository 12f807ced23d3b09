"""Designs of experiments, chunking and merging."""

import numpy as np
import pytest
import xarray as xr

from clutchlab import doe, explore, pipeline, store
from clutchlab.config import resolve


def _study(design="factorial", **params):
    sec = {"design": design, "parameters": params}
    if design != "factorial":
        sec.update(samples=params.pop("_samples", 64), seed=7)
    return resolve({"studies": ["diaphragm_spring"], "diaphragm_spring": sec})["diaphragm_spring"]


def test_factorial_dimensions():
    sec = _study(
        sheet_thickness={"values": ["2 mm", "2.5 mm"]},
        cone_height_ratio={"min": 1.2, "max": 2.0, "num": 5},
    )
    ds = pipeline.run_study(sec)
    assert ds["clamp_load"].dims == ("sheet_thickness", "cone_height_ratio")
    assert ds["curve_load"].dims == ("sheet_thickness", "cone_height_ratio", "deflection_ratio")
    assert float(ds["clamp_load"].sel(sheet_thickness=2.5e-3, cone_height_ratio=1.6)) > 0
    assert pipeline.n_scenarios(doe.build_design(sec)) == 10


def test_fixed_only_design_is_one_scenario():
    ds = pipeline.run_study(_study())
    assert ds["clamp_load"].dims == () and np.isfinite(float(ds["clamp_load"]))


@pytest.mark.parametrize("kind", ["lhs", "sobol"])
def test_sampled_design_reproducible_and_bounded(kind):
    params = dict(
        sheet_thickness={"min": "2 mm", "max": "3 mm"}, radius_ratio={"min": 1.2, "max": 1.4}
    )
    a = doe.build_design(_study(kind, **params))
    b = doe.build_design(_study(kind, **params))
    xr.testing.assert_identical(a, b)
    assert a.sizes["run"] == 64 and a["sheet_thickness"].dims == ("run",)
    assert float(a["sheet_thickness"].min()) >= 2e-3 and float(a["sheet_thickness"].max()) <= 3e-3


def test_lhs_is_stratified():
    a = doe.build_design(_study("lhs", sheet_thickness={"min": 0.0 + 1e-3, "max": 2e-3}))
    u = (a["sheet_thickness"].values - 1e-3) / 1e-3
    counts = np.bincount(np.floor(u * 64).astype(int), minlength=64)
    assert np.all(counts == 1)  # one sample per stratum


def _sealed_as(stored: xr.Dataset, want: xr.Dataset) -> xr.Dataset:
    """A streamed result's stored checksum (computed from the file a block at a time) is that of
    the in-memory result it must equal (values and attributes); returned without it, to compare."""
    sealed = store.checksum_attrs(want)
    for key, value in sealed.items():
        assert stored.attrs.pop(key) == value, key
    return stored


@pytest.mark.parametrize("chunks", [1, 3, 7, 40])
def test_chunked_equals_unchunked(chunks):
    sec = _study(
        sheet_thickness={"values": ["2 mm", "2.3 mm", "2.6 mm"]},
        radius_ratio={"values": [1.2, 1.3]},
        operating_point_factor={"values": [0.8, 0.9]},
    )
    design = doe.build_design(sec)
    merged = pipeline.merge(
        design, [pipeline.run_chunk(design, {}, chunks, i) for i in range(chunks)]
    )
    # the design answers (feasibility, Pareto rank) too do not depend on the chunk count
    merged = explore.annotate(merged, sec["objectives"], sec["constraints"])
    # (run_study adds the traces of the design the pages show, as the workflow's traces job does)
    from clutchlab import traces

    merged = traces.attach(merged, traces.compute(merged, sec["options"]))
    xr.testing.assert_identical(merged, pipeline.run_study(sec))


def test_merge_detects_missing_chunk():
    design = doe.build_design(_study(sheet_thickness={"values": ["2 mm", "2.3 mm", "2.6 mm"]}))
    with pytest.raises(ValueError, match="missing or duplicated"):
        pipeline.merge(design, [pipeline.run_chunk(design, {}, 3, i) for i in (0, 2)])


def test_chunk_slices_partition():
    for n, k in [(10, 3), (5, 8), (1_000_000, 200)]:
        sl = [pipeline.chunk_slice(n, k, i) for i in range(k)]
        assert sl[0].start == 0 and sl[-1].stop == n
        assert all(a.stop == b.start for a, b in zip(sl, sl[1:], strict=False))
        sizes = [s.stop - s.start for s in sl]
        assert max(sizes) - min(sizes) <= 1


def test_sampled_merge_keeps_run_dimension():
    sec = _study("sobol", sheet_thickness={"min": "2 mm", "max": "3 mm"}, _samples=32)
    design = doe.build_design(sec)
    merged = pipeline.merge(design, [pipeline.run_chunk(design, {}, 4, i) for i in range(4)])
    assert merged["clamp_load"].dims == ("run",)
    np.testing.assert_array_equal(
        merged["sheet_thickness"].values, design["sheet_thickness"].values
    )


def test_flat_ranges_as_grid_blocks():
    """store._flat_blocks: any flat C-order range of a grid is covered exactly once by its blocks."""
    from clutchlab.store import _flat_blocks

    rng = np.random.default_rng(0)
    for _ in range(300):
        shape = tuple(int(s) for s in rng.integers(1, 5, size=rng.integers(1, 5)))
        n = int(np.prod(shape))
        a, b = sorted(int(x) for x in rng.integers(0, n + 1, size=2))
        hit = np.zeros(shape, int)
        flat = np.arange(n).reshape(shape)
        for index, lo, hi in _flat_blocks(a, b, shape):
            assert (flat[index].reshape(-1) == np.arange(lo, hi)).all()
            hit[index] += 1
        assert (hit.reshape(-1) == ((np.arange(n) >= a) & (np.arange(n) < b))).all()


@pytest.mark.parametrize(
    "name, section, chunks",
    [
        (
            "diaphragm_spring",
            {
                "design": "factorial",
                "parameters": {  # chunk edges inside grid rows
                    "sheet_thickness": {"values": ["1.8 mm", "2.3 mm", "2.8 mm"]},
                    "cone_height_ratio": {"values": [1.3, 1.6, 1.9, 2.2]},
                    "radius_ratio": {"values": [1.2, 1.3]},
                },
            },
            5,
        ),
        (
            "sprag",
            {
                "design": "sobol",
                "samples": 8,
                "seed": 3,
                "parameters": {
                    "torque": {"min": "200 N*m", "max": "900 N*m"},
                    "sprag_length": {"min": "12 mm", "max": "20 mm"},
                },
            },
            10,
        ),
        (
            "engagement",
            {
                "design": "factorial",
                "options": {"driveline": "rigid"},
                "parameters": {
                    "ramp_time": {"values": ["0.05 s", "0.1 s", "0.2 s"]},
                    "load_torque": {"values": ["44 N*m", "80 N*m"]},
                },
            },
            4,
        ),
    ],
)
def test_streamed_merge_equals_the_in_memory_merge(tmp_path, name, section, chunks):
    """Issue 16 item 1: the merge that writes chunk by chunk into a pre-sized file gives the same
    Dataset (values, dims, coordinates, attributes) as concatenating every chunk in memory and
    annotating it, for grids (chunk edges inside grid rows), sampled designs with empty chunks
    (more chunks than scenarios) and the sensitivity file; a missing chunk is refused."""
    sec = resolve({"studies": [name], name: section})[name]
    design = doe.build_design(sec)
    paths = []
    for i in range(chunks):
        paths.append(tmp_path / f"chunk_{i}.h5")
        store.write(
            pipeline.run_chunk(design, sec["options"], chunks, i), paths[-1], with_checksum=True
        )
    want = explore.annotate(
        pipeline.merge(design, [store.load(p) for p in paths]),
        sec["objectives"],
        sec["constraints"],
    )
    sens = tmp_path / "sensitivity.h5" if sec["design"] == "factorial" else None
    pipeline.merge_to_file(
        design, paths, tmp_path / "out.h5", sec["objectives"], sec["constraints"], sens
    )
    xr.testing.assert_identical(_sealed_as(store.load(tmp_path / "out.h5"), want), want)
    if sens:
        outputs = [o.split(":")[0] for o in sec["objectives"]] + list(sec["constraints"])
        expected = explore.sensitivity(want, outputs)
        xr.testing.assert_identical(_sealed_as(store.load(sens), expected), expected)
    full = [p for p in paths if store.load(p).sizes["run"]]
    with pytest.raises(ValueError, match="missing or duplicated"):
        pipeline.merge_to_file(
            design,
            [p for p in paths if p != full[1]],
            tmp_path / "bad.h5",
            sec["objectives"],
            sec["constraints"],
        )
    assert not (tmp_path / "bad.h5").exists()


def test_streamed_merge_memory_follows_the_chunk_not_the_study(tmp_path):
    """Issue 16 item 1: the merge's peak memory (numpy and Python allocations, tracemalloc) stays a
    small multiple of one chunk's data, while the in-memory merge holds the whole study: here a
    diaphragm-spring study of 2^15 scenarios with an 81-point spring curve per scenario (47 MB)
    in 16 chunks of 2.9 MB; measured 7.5 MB peak (the in-memory merge: 188 MB)."""
    import tracemalloc

    sec = resolve(
        {
            "studies": ["diaphragm_spring"],
            "diaphragm_spring": {
                "design": "sobol",
                "samples": 2**15,
                "seed": 7,
                "curves": "all",
                "parameters": {
                    "sheet_thickness": {"min": "1.8 mm", "max": "2.8 mm"},
                    "cone_height_ratio": {"min": 1.3, "max": 2.2},
                },
            },
        }
    )["diaphragm_spring"]
    design = doe.build_design(sec)
    paths = []
    for i in range(16):
        paths.append(tmp_path / f"chunk_{i}.h5")
        store.write(
            pipeline.run_chunk(design, sec["options"], 16, i), paths[-1], with_checksum=True
        )
    chunk_bytes = store.load(paths[0]).nbytes
    explore.pareto_rank(
        np.random.default_rng(0).random((50, 2))
    )  # numba loads its compiled code once
    tracemalloc.start()
    pipeline.merge_to_file(
        design, paths, tmp_path / "out.h5", sec["objectives"], sec["constraints"]
    )
    streamed = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    study_bytes = store.load(tmp_path / "out.h5").nbytes
    assert study_bytes > 14 * chunk_bytes
    print(
        f"chunk {chunk_bytes / 1e6:.1f} MB, study {study_bytes / 1e6:.1f} MB, "
        f"streamed merge peak {streamed / 1e6:.1f} MB"
    )
    assert streamed < 4 * chunk_bytes, (streamed, chunk_bytes, study_bytes)


def test_sampled_designs_with_discrete_factors():
    """Issue 16 item 3: a count sampled between min and max takes every whole number in between
    (equal shares); a values list in a sampled design is a discrete factor drawn among its values;
    a count range that includes odd roller counts is refused for the one-flank reading."""
    from clutchlab.config import ConfigError

    sec = resolve(
        {
            "studies": ["sprag"],
            "sprag": {
                "design": "sobol",
                "samples": 1024,
                "seed": 2,
                "parameters": {
                    "torque": {"min": "200 N*m", "max": "900 N*m"},
                    "sprags": {"min": 14, "max": 22},
                },
            },
        }
    )["sprag"]
    ds = pipeline.run_study(sec)
    values, counts = np.unique(ds["sprags"].values, return_counts=True)
    assert values.tolist() == list(range(14, 23)) and counts.min() >= 1024 // 9 - 2
    assert np.isfinite(ds["margin_contact_inner"].values).any()
    sec = resolve(
        {
            "studies": ["roller"],
            "roller": {
                "design": "lhs",
                "samples": 60,
                "seed": 1,
                "parameters": {
                    "rollers": {"values": [6, 10, 14]},
                    "wedge_angle": {"min": "7 deg", "max": "15 deg"},
                },
            },
        }
    )["roller"]
    design = doe.build_design(sec)
    assert set(np.unique(design["rollers"].values)) == {6.0, 10.0, 14.0}
    with pytest.raises(ConfigError, match="roller.parameters.rollers"):
        resolve(
            {
                "studies": ["roller"],
                "roller": {
                    "design": "sobol",
                    "samples": 8,
                    "parameters": {"rollers": {"min": 6, "max": 12}},
                },
            }
        )


@pytest.mark.parametrize("name", ["diaphragm_spring", "centrifugal"])
def test_curves_of_a_subset_of_a_large_sampled_design(tmp_path, name):
    """Issue 16 item 5: a sampled design stores every scenario's scalars but the per-scenario
    curves of every N-th scenario only (dimension curve_run, its coordinate the scenario index), the
    same values as the full curves there; streamed and in-memory merges agree (chunk edges not on
    multiples of N); the curve pages draw from the subset. Default: all curves up to 20 000
    scenarios, about 1 000 designs' above; a factorial grid keeps all."""
    import matplotlib.pyplot as plt

    from clutchlab import config
    from clutchlab.report import study_pages

    base = {
        "design": "sobol",
        "samples": 64,
        "seed": 4,
        "parameters": {"friction_coefficient": {"min": 0.3, "max": 0.5}},
    }
    full = pipeline.run_study(resolve({"studies": [name], name: base})[name])
    sec = resolve({"studies": [name], name: {**base, "curves": 7}})[name]
    design = doe.build_design(sec)
    paths = []
    for i in range(3):
        paths.append(tmp_path / f"chunk_{i}.h5")
        store.write(pipeline.run_chunk(design, sec["options"], 3, i), paths[-1], with_checksum=True)
    want = explore.annotate(
        pipeline.merge(design, [store.load(p) for p in paths]),
        sec["objectives"],
        sec["constraints"],
    )
    pipeline.merge_to_file(
        design, paths, tmp_path / "out.h5", sec["objectives"], sec["constraints"]
    )
    got = _sealed_as(store.load(tmp_path / "out.h5"), want)
    xr.testing.assert_identical(got, want)
    assert got["curve_run"].values.tolist() == list(range(0, 64, 7))
    curves = [
        n
        for n, v in full.data_vars.items()
        if "run" in v.dims and v.ndim > 1 and "constraint" not in v.dims
    ]
    assert curves and all(got[n].dims[0] == "curve_run" for n in curves)
    for n in curves:
        np.testing.assert_array_equal(
            got[n].values, full[n].isel(run=got["curve_run"].values).values
        )
    for n, v in full.data_vars.items():
        if n not in curves and "run" in v.dims:
            np.testing.assert_array_equal(got[n].values, v.values)
    for _stem, fig in study_pages(name, got):
        fig.canvas.draw()
        plt.close(fig)
    # a shown design (the traces' best design) outside the subset: the curve pages draw the
    # stored design nearest it (the shown index is the whole run's, not the subset's)
    got.attrs.update(shown_index=60, shown_design="design 60", shown_reason="the run's best design")
    for _stem, fig in study_pages(name, got):
        fig.canvas.draw()
        plt.close(fig)
    big = {**base, "samples": 2**15}
    assert resolve({"studies": [name], name: big})[name]["curve_stride"] == 33  # ceil(32768 / 1000)
    assert resolve({"studies": [name], name: {**big, "curves": "all"}})[name]["curve_stride"] == 1
    assert resolve({"studies": [name], name: base})[name]["curve_stride"] == 1
    with pytest.raises(config.ConfigError, match=f"'{name}.curves'"):
        resolve({"studies": [name], name: {"design": "factorial", "curves": 5}})


def test_curve_subset_of_a_study_without_curves():
    """A study with no per-scenario curves (engagement) runs unchanged with a curve subset asked."""
    sec = resolve(
        {
            "studies": ["engagement"],
            "engagement": {
                "design": "sobol",
                "samples": 16,
                "seed": 1,
                "curves": 5,
                "options": {"driveline": "rigid"},
                "parameters": {"ramp_time": {"min": "0.05 s", "max": "0.3 s"}},
            },
        }
    )["engagement"]
    ds = pipeline.run_study(sec)
    assert "curve_run" not in ds.dims and ds.sizes["run"] == 16


@pytest.mark.parametrize(
    "name, factor",
    [
        ("engagement", {"ramp_time": {"min": "0.05 s", "max": "0.3 s"}}),
        ("centrifugal", {"spring_force": {"min": "380 N", "max": "480 N"}}),
        ("sprag", {"torque": {"min": "100 N*m", "max": "1000 N*m"}}),
        ("roller", {"wedge_angle": {"min": "7 deg", "max": "15 deg"}}),
    ],
)
def test_traces_once_per_study_after_the_merge(name, factor):
    """The traces are computed once per study, after the merge, for the design the pages show
    (clutchlab.traces): no chunk holds any, whatever its scenarios, and they are the study's own
    traces of that design (the same numbers as its traces function given the design's inputs)."""
    from clutchlab import explore, studies, traces

    sec = resolve(
        {"studies": [name], name: {"design": "lhs", "samples": 6, "seed": 2, "parameters": factor}}
    )[name]
    design = doe.build_design(sec)
    study = studies.get(name)
    parts = [pipeline.run_chunk(design, sec["options"], 3, i) for i in range(3)]
    assert all("run" in v.dims for p in parts for v in p.data_vars.values())
    merged = explore.annotate(pipeline.merge(design, parts), sec["objectives"], sec["constraints"])
    tr = traces.compute(merged, sec["options"])
    i, _ = traces.shown_design(merged)
    inputs, chosen = traces.design_inputs(merged, i)
    own = study.traces(inputs, study.full_options({**sec["options"], **chosen}))
    assert own.data_vars and int(tr.attrs["shown_index"]) == i
    xr.testing.assert_identical(tr.drop_attrs(), own.drop_attrs())


@pytest.mark.parametrize(
    "name, options, factor",
    [
        (
            "roller",
            {"mode": ["bidirectional_lock", "overrun_forward", "overrun_reverse"]},
            {
                "wedge_angle": {"min": "7 deg", "max": "15 deg"},
                "drive_direction": {"values": [1, -1]},
                # the paper's 3041 MPa: every wedging impact far above it (dynamic_overstress), no
                # feasible design to refine around; a high allowable keeps designs feasible here
                "contact_allowable": "20 GPa",
            },
        ),
        (
            "engagement",
            {"profile": ["ramp", "cubic", "quintic"]},
            {"ramp_time": {"min": "0.05 s", "max": "0.3 s"}},
        ),
        (
            "diaphragm_spring",
            {"friction_radius": ["uniform_pressure", "uniform_wear"]},
            {"sheet_thickness": {"min": "1.8 mm", "max": "2.8 mm"}},
        ),
    ],
)
def test_options_drawn_per_scenario(tmp_path, name, options, factor):
    """Issue 16 item 3: categorical options in a sampled design. Each scenario's outputs equal
    those of a run with that choice fixed (its own batch); the choice is stored per scenario as a
    flagged code; the chunk count does not change the result; a refinement keeps the choices."""
    from clutchlab import studies

    sec = resolve(
        {
            "studies": [name],
            name: {
                "design": "sobol",
                "samples": 16,
                "seed": 4,
                "parameters": factor,
                "options": {o: {"values": v} for o, v in options.items()},
            },
        }
    )[name]
    one = pipeline.run_study(sec)
    design = doe.build_design(sec)
    paths = []
    for i in range(3):
        paths.append(tmp_path / f"c{i}.h5")
        store.write(
            pipeline.run_chunk(design, sec["options"], 3, i),
            paths[-1],
            with_checksum=True,
            complevel=0,
        )
    pipeline.merge_to_file(
        design, paths, tmp_path / "out.h5", sec["objectives"], sec["constraints"]
    )
    from clutchlab import traces

    stored = store.load(tmp_path / "out.h5")
    tr = traces.compute(stored, sec["options"])  # the traces job's, as run_study adds them
    bare = one.drop_vars([v for v in tr.variables if v in one])
    bare.attrs = {k: v for k, v in one.attrs.items() if k not in (*traces.ATTRS, "shown_status")}
    xr.testing.assert_identical(_sealed_as(stored, bare), bare)
    xr.testing.assert_identical(traces.attach(stored, tr), one)
    study = studies.get(name)
    _, inputs = pipeline.chunk_inputs(design, 1, 0)
    codes = {o: inputs.pop(o) for o in options}
    within = one["pareto_rank"].attrs.get("ranked_within", "").split()
    for o, labels in options.items():
        assert one[o].attrs["flag_meanings"].split() == labels and one[o].dtype == np.int8
        assert (o in within) == (
            o in study.conditions
        )  # a condition's choices each get their own front
        assert set(np.unique(one[o].values)) == set(range(len(labels)))  # every choice drawn
    seen = 0
    for combo in {tuple(int(codes[o][k]) for o in options) for k in range(16)}:
        sel = np.flatnonzero(
            np.all([codes[o] == c for o, c in zip(options, combo, strict=False)], axis=0)
        )
        alone = study.compute(
            {k: (v[sel] if np.ndim(v) else v) for k, v in inputs.items()},
            {**sec["options"], **{o: options[o][c] for o, c in zip(options, combo, strict=False)}},
        )
        for var in study.outputs:
            np.testing.assert_array_equal(one[var].values[sel], alone[var].values)
        np.testing.assert_array_equal(one["status"].values[sel], alone["status"].values)
        seen += sel.size
    assert seen == 16
    (tmp_path / "r").mkdir()
    store.write(one, tmp_path / "r" / "first.h5")
    ref = resolve(
        {
            "studies": [name],
            "results": str(tmp_path / "new"),
            name: {
                "design": "refine",
                "samples": 6,
                "seed": 1,
                "refine": {"from": str(tmp_path / "r" / "first.h5")},
            },
        }
    )[name]
    second = pipeline.run_study(ref)
    front = explore.front_order(one)
    for o in options:
        assert set(second[o].values) <= set(explore.flat(one, o)[front])


def test_a_large_chunk_runs_in_batches_with_progress(monkeypatch):
    """Issue 18 item 5: a chunk above pipeline.PROGRESS_MIN scenarios runs in batches, a progress line
    (scenarios done, rate, time left) after each, and gives the numbers of one batch."""
    sec = _study(
        "sobol",
        sheet_thickness={"min": "1.8 mm", "max": "2.8 mm"},
        cone_height_ratio={"min": 1.2, "max": 2.2},
        _samples=64,
    )
    design = doe.build_design(sec)
    whole = pipeline.run_chunk(design, {}, 1, 0)
    monkeypatch.setattr(pipeline, "PROGRESS_MIN", 10)
    lines = []
    batched = pipeline.run_chunk(design, {}, 1, 0, progress=lines.append)
    xr.testing.assert_identical(batched.drop_attrs(), whole.drop_attrs())
    timings = ("compute_seconds", "compute_cpu_seconds")
    assert {k: v for k, v in batched.attrs.items() if k not in timings} == {
        k: v for k, v in whole.attrs.items() if k not in timings
    }
    assert (
        len(lines) == pipeline.PROGRESS_BATCHES
        and "6 of 64 scenarios" in lines[0]
        and "s left" in lines[0]
    )
    assert "64 scenarios computed" in lines[-1]


@pytest.mark.parametrize("name", ["diaphragm_spring", "centrifugal"])
def test_a_large_chunk_keeps_its_curve_subset_batch_by_batch(monkeypatch, name):
    """A chunk that runs in batches keeps each batch's share of the stored curves (every N-th
    scenario of the whole run, batch and chunk edges not on multiples of N): the same Dataset as
    the chunk in one batch, the curves those of the full computation there."""
    sec = resolve(
        {
            "studies": [name],
            name: {
                "design": "sobol",
                "samples": 64,
                "seed": 3,
                "curves": 5,
                "parameters": {"friction_coefficient": {"min": 0.3, "max": 0.5}},
            },
        }
    )[name]
    design = doe.build_design(sec)
    whole = pipeline.run_chunk(design, sec["options"], 2, 1)
    monkeypatch.setattr(pipeline, "PROGRESS_MIN", 10)
    batched = pipeline.run_chunk(design, sec["options"], 2, 1)
    xr.testing.assert_identical(batched.drop_attrs(), whole.drop_attrs())
    assert batched["curve_run"].values.tolist() == list(range(35, 64, 5))
    monkeypatch.setattr(pipeline, "PROGRESS_MIN", 10**9)
    design.attrs["curve_stride"] = 1
    every = pipeline.run_chunk(design, sec["options"], 2, 1)
    curves = [n for n, v in batched.data_vars.items() if "curve_run" in v.dims]
    assert curves
    for n in curves:
        np.testing.assert_array_equal(
            batched[n].values, every[n].sel(run=batched["curve_run"].values).values
        )


# every study over designs that reach each of its models and statuses (sampled from the ranges of
# config/million.yaml, widened where a status needs it): its result must not depend on the batch a
# scenario is computed in
_PER_SCENARIO = {
    "diaphragm_spring": (
        {"friction_radius": {"values": ["uniform_pressure", "uniform_wear"]}},
        {
            "sheet_thickness": {"min": "1.8 mm", "max": "2.8 mm"},
            "cone_height_ratio": {"min": 1.2, "max": 3.0},
            "radius_ratio": {"min": 1.2, "max": 1.4},
        },
    ),
    "engagement": (
        {"profile": {"values": ["ramp", "cubic", "quintic"]}},
        {
            "ramp_time": {"min": "0.02 s", "max": "0.3 s"},
            "load_torque": {"min": "44 N*m", "max": "250 N*m"},
            "driven_inertia": {"min": "0.021 kg*m^2", "max": "0.05 kg*m^2"},
            "engine_inertia": "inf",
        },
    ),
    # the rigid driveline's closed form (held engine, constant mu), Newton roots on the smooth steps
    "engagement:closed_form": (
        {"driveline": "rigid", "profile": {"values": ["ramp", "cubic", "quintic"]}},
        {
            "sheet_thickness": {"min": "2.1 mm", "max": "2.6 mm"},
            "ramp_time": {"min": "0.02 s", "max": "0.3 s"},
            "load_torque": {"min": "44 N*m", "max": "250 N*m"},
            "driven_inertia": {"min": "0.021 kg*m^2", "max": "0.05 kg*m^2"},
            "engine_inertia": "inf",
        },
    ),
    # the rigid event solver: free engines, a Stribeck law and an air gap
    "engagement:events": (
        {"driveline": "rigid", "profile": {"values": ["ramp", "cubic", "quintic"]}},
        {
            "ramp_time": {"min": "0.02 s", "max": "0.3 s"},
            "engine_inertia": {"min": "0.2 kg*m^2", "max": "2 kg*m^2"},
            "stribeck_speed": {"min": "5 rad/s", "max": "200 rad/s"},
            "static_ratio": {"min": 1.0, "max": 1.4},
            "air_gap": {"min": "0 mm", "max": "0.6 mm"},
        },
    ),
    "centrifugal": (
        {},
        {
            "pressure_angle": {"min": "20 deg", "max": "70 deg"},
            "friction_coefficient": {"min": 0.25, "max": 0.6},
            "spring_force": {"min": "380 N", "max": "900 N"},
        },
    ),
    "sprag": (
        {},
        {
            "torque": {"min": "100 N*m", "max": "1500 N*m"},
            "sprag_length": {"min": "12 mm", "max": "22 mm"},
            "centre_distance": {"min": "0.70 mm", "max": "0.85 mm"},
        },
    ),
    "roller": (
        {"mode": {"values": ["bidirectional_lock", "overrun_forward"]}},
        {
            "wedge_angle": {"min": "7 deg", "max": "15 deg"},
            "roller_diameter": {"min": "8 mm", "max": "12 mm"},
            "friction_coefficient": {"min": 0.10, "max": 0.14},
            "drive_direction": {"values": [1, -1]},
        },
    ),
}


@pytest.mark.parametrize("case", sorted(_PER_SCENARIO))
def test_every_study_is_identical_in_one_and_seven_chunks(case):
    """A scenario's numbers are its own: no convergence test, tolerance or scale over the batch it
    is computed in, so a study's result is identical (values and attributes) whether it runs as one
    chunk or seven (issue 30 item 9: the closed form's Newton iterations stopped on the whole
    batch's convergence and 187 of 5 344 rows moved by up to 2.7e-15 between 1 and 7 chunks)."""
    name = case.split(":")[0]
    options, params = _PER_SCENARIO[case]
    sec = resolve(
        {
            "studies": [name],
            name: {
                "design": "sobol",
                "samples": 64,
                "seed": 5,
                "options": options,
                "parameters": params,
            },
        }
    )[name]
    design = doe.build_design(sec)
    merged = {}
    for chunks in (1, 7):
        parts = [pipeline.run_chunk(design, sec["options"], chunks, i) for i in range(chunks)]
        merged[chunks] = explore.annotate(
            pipeline.merge(design, parts), sec["objectives"], sec["constraints"]
        )
    statuses = set(np.unique(merged[1]["status"].values))
    assert len(statuses) > 1 or name == "engagement"  # the design reaches more than one status
    xr.testing.assert_identical(merged[1], merged[7])

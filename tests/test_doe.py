"""Designs of experiments, chunking and merging."""
import numpy as np
import pytest
import xarray as xr

from clutchlab import doe, explore
from clutchlab.config import resolve


def _study(design="factorial", **params):
    sec = {"design": design, "parameters": params}
    if design != "factorial":
        sec.update(samples=params.pop("_samples", 64), seed=7)
    return resolve({"studies": ["diaphragm_spring"], "diaphragm_spring": sec})["diaphragm_spring"]


def test_factorial_dimensions():
    sec = _study(sheet_thickness={"values": ["2 mm", "2.5 mm"]}, cone_height_ratio={"min": 1.2, "max": 2.0, "num": 5})
    ds = doe.run_study(sec)
    assert ds["clamp_load"].dims == ("sheet_thickness", "cone_height_ratio")
    assert ds["curve_load"].dims == ("sheet_thickness", "cone_height_ratio", "deflection_ratio")
    assert float(ds["clamp_load"].sel(sheet_thickness=2.5e-3, cone_height_ratio=1.6)) > 0
    assert doe.n_scenarios(doe.build_design(sec)) == 10


def test_fixed_only_design_is_one_scenario():
    ds = doe.run_study(_study())
    assert ds["clamp_load"].dims == () and np.isfinite(float(ds["clamp_load"]))


@pytest.mark.parametrize("kind", ["lhs", "sobol"])
def test_sampled_design_reproducible_and_bounded(kind):
    params = dict(sheet_thickness={"min": "2 mm", "max": "3 mm"}, radius_ratio={"min": 1.2, "max": 1.4})
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


@pytest.mark.parametrize("chunks", [1, 3, 7, 40])
def test_chunked_equals_unchunked(chunks):
    sec = _study(sheet_thickness={"values": ["2 mm", "2.3 mm", "2.6 mm"]}, radius_ratio={"values": [1.2, 1.3]},
                 operating_point_factor={"values": [0.8, 0.9]})
    design = doe.build_design(sec)
    merged = doe.merge(design, [doe.run_chunk(design, {}, chunks, i) for i in range(chunks)])
    # the design answers (feasibility, Pareto rank) too do not depend on the chunk count
    merged = explore.annotate(merged, sec["objectives"], sec["constraints"])
    xr.testing.assert_identical(merged, doe.run_study(sec))


def test_merge_detects_missing_chunk():
    design = doe.build_design(_study(sheet_thickness={"values": ["2 mm", "2.3 mm", "2.6 mm"]}))
    with pytest.raises(ValueError, match="missing or duplicated"):
        doe.merge(design, [doe.run_chunk(design, {}, 3, i) for i in (0, 2)])


def test_chunk_slices_partition():
    for n, k in [(10, 3), (5, 8), (1_000_000, 200)]:
        sl = [doe.chunk_slice(n, k, i) for i in range(k)]
        assert sl[0].start == 0 and sl[-1].stop == n
        assert all(a.stop == b.start for a, b in zip(sl, sl[1:]))
        sizes = [s.stop - s.start for s in sl]
        assert max(sizes) - min(sizes) <= 1


def test_sampled_merge_keeps_run_dimension():
    sec = _study("sobol", sheet_thickness={"min": "2 mm", "max": "3 mm"}, _samples=32)
    design = doe.build_design(sec)
    merged = doe.merge(design, [doe.run_chunk(design, {}, 4, i) for i in range(4)])
    assert merged["clamp_load"].dims == ("run",)
    np.testing.assert_array_equal(merged["sheet_thickness"].values, design["sheet_thickness"].values)

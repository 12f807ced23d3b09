"""The status rule (issue 30 item 9): every per-scenario output of every study says under which
statuses it is valid (attribute ``valid_statuses``, from the study's table) and is NaN (an integer
one −1) under the others; applied in one place, :func:`clutchlab.studies.apply_valid_statuses`."""

import numpy as np
import pytest

from clutchlab import config, pipeline, studies
from clutchlab import status as st

# designs that reach several statuses of each study
DESIGNS = {
    "diaphragm_spring": {
        "sheet_thickness": {"min": "1.8 mm", "max": "2.8 mm"},
        "cone_height_ratio": {"min": 1.2, "max": 3.2},
    },
    "engagement": {
        "ramp_time": {"min": "0.02 s", "max": "0.3 s"},
        "load_torque": {"min": "44 N*m", "max": "250 N*m"},
        "cone_height_ratio": {"min": 1.3, "max": 3.0},
    },
    "centrifugal": {
        "pressure_angle": {"min": "20 deg", "max": "70 deg"},
        "friction_coefficient": {"min": 0.25, "max": 0.6},
        "spring_force": {"min": "380 N", "max": "900 N"},
    },
    "sprag": {
        "torque": {"min": "100 N*m", "max": "1500 N*m"},
        "sprag_length": {"min": "12 mm", "max": "22 mm"},
        "centre_distance": {"min": "0.70 mm", "max": "0.85 mm"},
    },
    "roller": {
        "wedge_angle": {"min": "7 deg", "max": "15 deg"},
        "friction_coefficient": {"min": 0.10, "max": 0.14},
        "roller_diameter": {"min": "8 mm", "max": "12 mm"},
        "rollers": {"values": [6, 12, 18]},
    },
}
ANSWERS = ("feasible", "constraint_margin", "pareto_rank")  # design answers, from the status


def _run(name):
    sec = config.resolve(
        {
            "studies": [name],
            name: {"design": "sobol", "samples": 64, "seed": 2, "parameters": DESIGNS[name]},
        }
    )[name]
    return pipeline.run_study(sec)


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_every_output_is_nan_outside_its_valid_statuses(name):
    """Every per-scenario output carries ``valid_statuses`` (known status names, or ``all``): a
    float output is NaN under every other status, an integer one −1; the study's table names only
    outputs it computes; a float output the table leaves out is valid under ok only."""
    ds = _run(name)
    study = studies.get(name)
    code = ds["status"].values
    assert len(np.unique(code)) >= 2, "the design reaches several statuses"
    outputs = [v for v in ds.data_vars if "run" in ds[v].dims and v != "status"]
    assert set(study.valid_statuses) <= set(outputs)
    for v in outputs:
        if v in ANSWERS:
            continue
        rule = ds[v].attrs["valid_statuses"]
        if rule == studies.ALL_STATUSES:
            assert v in study.valid_statuses or ds[v].dtype.kind != "f", v
            continue
        names = rule.split()
        assert set(names) <= set(st.CODE), v
        if v not in study.valid_statuses:
            assert names == ["ok"], v
        invalid = ~np.isin(code, [st.CODE[s] for s in names])
        vals = np.moveaxis(ds[v].values, ds[v].dims.index("run"), 0)[invalid]
        if ds[v].dtype.kind == "f":
            assert np.isnan(vals).all(), v
        else:
            assert (vals == -1).all(), v


def test_never_locked_rows_keep_only_what_they_mean():
    """Issue 30 item 9: never_locked engagement rows kept finite peak jerk, roller never_locked rows
    finite peak force, release time and dynamic factor. An engagement still slipping at end_time
    keeps the slip work up to it (PHYSICS.md: 'slip work up to t_end') and its heat, not a peak
    jerk or a count of engagements to the limit; a roller that never engaged keeps its statics
    only."""
    eng = _run("engagement")
    never = eng["status"].values == st.CODE["never_locked"]
    assert never.any() and (~never).any()
    for v in ("lockup_time", "peak_jerk", "accel_jump", "engagements_to_limit"):
        assert np.isnan(eng[v].values[never]).all(), v
    for v in ("slip_work", "bulk_temperature_rise", "peak_surface_temperature", "clamp_load"):
        assert np.isfinite(eng[v].values[never]).all(), v
    assert "never_locked" in eng["slip_work"].attrs["valid_statuses"].split()
    roller = _run("roller")
    never = roller["status"].values == st.CODE["never_locked"]
    assert never.any()
    for v in ("peak_contact_force", "release_time", "dynamic_factor", "engagement_time"):
        assert np.isnan(roller[v].values[never]).all(), v
    for v in ("contact_stress", "self_locking_margin", "spring_margin"):
        assert np.isfinite(roller[v].values[never]).all(), v


def test_the_rule_leaves_valid_numbers_untouched():
    """apply_valid_statuses changes nothing but the invalid entries (bit-identical elsewhere), on
    any scenario axis position."""
    import xarray as xr

    code = np.array([0, 4, 14, 0], np.int8)
    ds = xr.Dataset(
        {
            "status": ("run", code),
            "a": ("run", np.array([1.0, 2.0, 3.0, 4.0])),
            "b": (("point", "run"), np.arange(8.0).reshape(2, 4)),
            "n": ("run", np.array([5, 6, 7, 8], np.int32)),
            "k": ("run", np.array([1, 1, 1, 1], np.int8)),
        }
    )
    out = studies.apply_valid_statuses(
        ds.copy(deep=True), {"b": ("ok", "never_locked"), "k": ("ok",)}
    )
    np.testing.assert_array_equal(out["a"].values, [1.0, np.nan, np.nan, 4.0])
    np.testing.assert_array_equal(out["b"].values, [[0, 1, np.nan, 3], [4, 5, np.nan, 7]])
    np.testing.assert_array_equal(out["n"].values, [5, 6, 7, 8])
    np.testing.assert_array_equal(out["k"].values, [1, -1, -1, 1])
    assert out["n"].attrs["valid_statuses"] == "all" and out["a"].attrs["valid_statuses"] == "ok"
    with pytest.raises(KeyError, match="unknown statuses"):
        studies.apply_valid_statuses(ds.copy(deep=True), {"a": ("fine",)})

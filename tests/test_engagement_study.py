"""The engagement study: spring design -> clamp force -> capacity -> engagement."""

from pathlib import Path

import numpy as np
import pytest

from clutchlab import config, doe, pipeline, report, store
from clutchlab import status as st
from clutchlab.published import DIAPHRAGM_CLUTCH as PUB

ROOT = Path(__file__).resolve().parents[1]


def _study(options, **params):
    return config.resolve(
        {
            "studies": ["engagement"],
            "engagement": {"design": "factorial", "options": options, "parameters": params},
        }
    )["engagement"]


def test_seed000_through_the_whole_chain():
    """Seed spring (F_B = 2500 N) -> eq. (14) as printed (239.3 N m) -> rigid closed form, held engine:
    lock-up 0.150 s (tol 1 %) and slip work 5800 J (tol 2 %), seed 000 sections 5.2-5.3."""
    sec = _study(
        {"driveline": "rigid", "capacity_formula": "eq14_as_printed"},
        cone_height_ratio=3.5 / 2.334,
        stack_mass="4.757 kg",
        engine_inertia="inf",
    )
    ds = pipeline.run_study(sec)
    assert ds.attrs["model_used"] == "rigid two-inertia, closed form"
    assert float(ds["peak_capacity"]) == pytest.approx(
        PUB["capacity_eq14_as_printed"].value, rel=2e-3
    )
    assert float(ds["lockup_time"]) == pytest.approx(PUB["lockup_time"].value, rel=0.01)
    assert float(ds["slip_work"]) == pytest.approx(PUB["slip_work"].value, rel=0.02)
    # the seed design's traces (Figs. 7-11) are the same scenario: their end values agree with it
    assert float(ds["trace_lockup_time"]) == pytest.approx(float(ds["lockup_time"]), abs=1e-9)
    assert float(ds["trace_slip_work"][-1]) == pytest.approx(float(ds["slip_work"]), rel=1e-8)
    assert float(ds["trace_clamp_force"].max()) == pytest.approx(float(ds["clamp_load"]), rel=1e-12)


def test_default_study_energy_and_metadata(tmp_path):
    """Acceptance: energy_residual <= 1e-9 relative for every scenario of the default study."""
    sec = config.load(ROOT / "config" / "config.yaml")["engagement"]
    ds = pipeline.run_study(sec)
    ok = ds["status"] == st.CODE["ok"]
    # (worn_not_locked: the first engagement is ok, the clutch worn by the allowance does not lock:
    # the thin springs of the grid, a finding of the design, not of the solver)
    first_ok = ok | (ds["status"] == st.CODE["worn_not_locked"])
    assert int(first_ok.sum()) > 0.8 * ok.size and int(ok.sum()) > 0.6 * ok.size
    assert float(np.abs(ds["energy_residual"]).max()) <= 1e-9
    assert bool((ds["peak_jerk"].values[ok.values] > 0).all())
    path = store.write(ds, tmp_path / "engagement.h5")  # checks units and long_name everywhere
    written = report.build({"engagement": path}, [], tmp_path / "report")
    assert {p.stem for p in written} >= {
        "engagement_tradeoff",
        "engagement_maps",
        "engagement_traces",
    }


def test_work_precision_page_from_stored_benchmark(tmp_path):
    """The report's work-precision page is drawn from the benchmark's CSV (no solver re-run)."""
    from clutchlab.bench import engagement as benchmark

    rows = [
        dict(
            method=benchmark.CLUTCHLAB,
            rtol=r,
            seconds_per_scenario=5e-5 * (1 + i),
            max_lockup_error_s=r,
            scenarios=10_000,
        )
        for i, r in enumerate((1e-4, 1e-8))
    ]
    rows += [
        dict(
            method=benchmark.RK45,
            rtol=1e-6,
            seconds_per_scenario=2e-3,
            max_lockup_error_s=5e-3,
            scenarios=200,
        )
    ]
    benchmark.write_rows(rows, tmp_path / "engagement_benchmark.csv")
    assert benchmark.read_rows(tmp_path / "engagement_benchmark.csv") == rows
    written = report.build(
        {}, [], tmp_path / "report", benchmark_csv=tmp_path / "engagement_benchmark.csv"
    )
    assert {p.stem for p in written} == {"title", "engagement_work_precision", "report"}
    assert report.figure_stems([], benchmark=True) == ["title", "engagement_work_precision"]
    assert report.figure_stems(["engagement"]) == [
        "title",
        "engagement_tradeoff",
        "engagement_maps",
        "engagement_traces",
        "engagement_heat",
        "engagement_answers",
        "validation_table",  # (the source paper's engagement numbers)
    ]
    assert "engagement_sensitivity" in report.figure_stems(
        ["engagement"], sensitivity=["engagement"]
    )


def test_infinite_only_where_allowed():
    with pytest.raises(config.ConfigError, match="driven_inertia"):
        _study({}, driven_inertia="inf")


def test_model_chosen_per_scenario():
    """Issue 16 item 2: in one rigid study over the engine inertia (held: inf, or free) and the
    Stribeck speed, each scenario runs the cheapest exact model (closed form where the engine is held
    and mu constant, the event solver elsewhere) and says which (variable model); the metrics equal
    those of each model run alone (closed form against the event solver forced on the same
    scenarios: within the accuracy), and the solver statistics are 0 for the closed form."""
    from clutchlab.studies.engagement import MODEL

    params = dict(
        ramp_time={"values": ["0.05 s", "0.15 s", "0.3 s"]},
        engine_inertia={"values": ["inf", "0.5 kg*m^2"]},
        stribeck_speed={"values": ["inf", "20 rad/s"]},
        load_torque={"values": ["44 N*m", "80 N*m"]},
    )
    sec = _study({"driveline": "rigid"}, **params)
    sec["options"]["accuracy"] = 1e-8
    ds = pipeline.run_study(sec)
    closed = (
        ~np.isfinite(ds["engine_inertia"]) & ~np.isfinite(ds["stribeck_speed"])
    ).broadcast_like(ds["status"])
    assert ((ds["model"] == MODEL["closed_form"]) == closed).all()
    assert ((ds["model"] == MODEL["rigid_events"]) == ~closed).all()
    assert ds["model"].attrs["flag_meanings"] == "closed_form rigid_events compliant_events"
    assert (ds["n_steps"].where(closed, 0) == 0).all() and (
        ds["n_steps"].where(~closed, 1) > 0
    ).all()
    # each model alone: the closed-form scenarios by the event solver (forced by a negligible drag:
    # 1e-12 N m s², the smallest plausible, changes the load by < 1e-8)
    forced = _study({"driveline": "rigid"}, **params, aero_coefficient=1e-12)
    forced["options"]["accuracy"] = 1e-8
    ref = pipeline.run_study(forced)
    assert (ref["model"] == MODEL["rigid_events"]).all()
    for name in ("lockup_time", "slip_work", "peak_friction_torque"):
        np.testing.assert_allclose(ds[name].values, ref[name].values, rtol=1e-6)
    sec = _study({"driveline": "compliant"}, ramp_time={"values": ["0.1 s", "0.2 s"]})
    assert (pipeline.run_study(sec)["model"] == MODEL["compliant_events"]).all()


def test_an_empty_chunk_runs():
    """More chunks than scenarios: an empty chunk of a per-scenario-model study gives an empty result."""
    sec = _study({"driveline": "rigid"}, ramp_time={"values": ["0.1 s", "0.2 s"]})
    design = doe.build_design(sec)
    assert pipeline.chunk_slice(2, 5, 0) == slice(0, 0)
    empty = pipeline.run_chunk(design, sec["options"], 5, 0)
    assert empty.sizes["run"] == 0 and "model" in empty


@pytest.mark.parametrize(
    "inputs, options, says, not_says",
    [
        ({}, {}, "constant μ", "Stribeck"),
        ({"stribeck_speed": 20.0}, {}, "slip with Stribeck friction", "tabulated"),
        ({"fade_coefficient": np.array([0.0, 0.01])}, {}, "slip with fading friction", "Stribeck"),
        ({}, {"friction_table": {}}, "slip with tabulated friction", "fading"),
    ],
)
def test_model_used_names_the_friction_law_the_run_has(inputs, options, says, not_says):
    """The report's caption of the compliant model says the slip law the inputs give, not every
    law the solver has (a varying input's law wherever it is a factor: the same text a chunk)."""
    from clutchlab.studies.engagement import _model_used

    text = _model_used(inputs, {"driveline": "compliant", **options})
    assert says in text and not_says not in text

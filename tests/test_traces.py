"""The design a run's pages show (clutchlab.traces): its choice in one function, and its traces
computed by the study's own traces function for that design (the trace's own result equals the
stored scenario's, to the solvers' tolerances)."""

import numpy as np
import pytest

from clutchlab import explore, pipeline, traces
from clutchlab.config import resolve


def _study(name, section):
    return pipeline.run_study(resolve({"studies": [name], name: section})[name])


def test_traces_are_the_best_designs():
    """Engagement: the traces are of the best compromise, not the paper's design; the traced
    lock-up time is the stored one of that scenario (the same solver, 1e-9 s)."""
    ds = _study(
        "engagement",
        {
            "design": "factorial",
            "parameters": {
                "sheet_thickness": {"values": ["2.1 mm", "2.6 mm"]},
                "ramp_time": {"values": ["0.05 s", "0.2 s"]},
                "load_torque": "60 N*m",
            },
        },
    )
    i, why = traces.shown_design(ds)
    assert i == explore.best_compromise(ds) and why.startswith("the run's best")
    assert int(ds.attrs["shown_index"]) == i and not ds.attrs["shown_is_paper"]
    assert float(ds["trace_lockup_time"]) == pytest.approx(
        explore.flat(ds, "lockup_time")[i], abs=1e-9
    )
    v = explore.flat(ds, "sheet_thickness")[i] * 1e3, explore.flat(ds, "ramp_time")[i] * 1e3
    assert ds.attrs["shown_design"] == f"sheet_thickness = {v[0]:.4g} mm, ramp_time = {v[1]:.4g} ms"


def test_centrifugal_traces_release_as_the_closed_form():
    """Centrifugal: the engine-failure trace (DOP853 with a release event) of the design shown
    releases when the closed form stored for that scenario says (relative 1e-6)."""
    ds = _study(
        "centrifugal",
        {
            "design": "factorial",
            "parameters": {
                "pressure_angle": {"values": ["30 deg", "45 deg", "55 deg"]},
                "friction_coefficient": {"values": [0.3, 0.4]},
            },
        },
    )
    i = int(ds.attrs["shown_index"])
    assert float(ds["failure_release_time"]) == pytest.approx(
        explore.flat(ds, "release_time")[i], rel=1e-6
    )


def test_no_feasible_design_shows_the_one_nearest_the_ideal_point():
    """Roller (every simulated design dynamic_overstress): no front, so the design shown is, among
    the designs that meet every constraint, the front design nearest the ideal point; its trace
    engages when the stored scenario does (the trace's finer steps: 1e-9 s), and it is named
    with its status."""
    ds = _study(
        "roller",
        {
            "design": "factorial",
            "parameters": {
                "rollers": {"values": [8, 12]},
                "wedge_angle": {"values": ["9 deg", "11 deg", "13 deg"]},
            },
        },
    )
    assert (ds["pareto_rank"].values < 0).all()
    i, why = traces.shown_design(ds)
    assert why.startswith("no feasible design")
    margins = ds["constraint_margin"].values.reshape(ds.sizes["constraint"], -1)[:, i]
    assert (margins >= 0).all()
    met = (ds["constraint_margin"].values.reshape(ds.sizes["constraint"], -1) >= 0).all(axis=0)
    f = np.stack([explore.flat(ds, o) for o in ("engagement_time", "contact_stress")], axis=1)
    assert explore.pareto_rank(f, met)[i] == 0  # on the front of those designs
    assert ds.attrs["shown_status"] == "dynamic_overstress"
    assert float(ds["trace_engagement_time"]) == pytest.approx(
        explore.flat(ds, "engagement_time")[i], abs=1e-9
    )


def test_the_papers_design_is_recognised():
    """A scenario at every default (the source paper's values) is the paper's design; a grid
    holding it marks it, one that does not, not."""
    ds = _study(
        "sprag",
        {
            "design": "factorial",
            "parameters": {
                "torque": {"values": ["267.5 N*m", "750 N*m"]},
                "sprags": {"values": [16, 18]},
            },
        },
    )
    from clutchlab import studies

    at = studies.get("sprag").defaults  # the source paper's torque (750 N m) and 18 sprags
    paper = [
        k
        for k in range(ds["status"].size)
        if explore.flat(ds, "torque")[k] == at["torque"] and explore.flat(ds, "sprags")[k] == 18
    ]
    assert len(paper) == 1 and at["torque"] == 750.0
    assert [traces.is_paper_design(ds, k) for k in range(ds["status"].size)] == [
        k in paper for k in range(ds["status"].size)
    ]
    inputs, chosen = traces.design_inputs(ds, paper[0])
    assert inputs["torque"] == 750.0 and inputs["sprags"] == 18 and not chosen

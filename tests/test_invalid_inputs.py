"""Issue 14: every public solver screens its inputs per scenario.

Hypothesis mixes random non-physical and non-finite inputs into batches of good scenarios: the good
scenarios must come out bit-identical to a batch without the bad ones, every bad one must have a
non-ok status and no finite headline number.
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

from clutchlab import centrifugal as cf
from clutchlab import contact, diaphragm, engagement, roller, sprag
from clutchlab import status as st

RPM = np.pi / 30
NAN, INF = np.nan, np.inf

# per solver: good scenarios (arrays of 4), bad values per input, the call, its headline outputs
GOOD_ENGAGEMENT = dict(
    engine_speed=np.array([5500, 5000, 5800, 5500]) * RPM,
    engine_inertia=np.array([INF, 0.8, 1.2, INF]),
    engine_torque=np.array([0.0, 150.0, 173.0, 0.0]),
    driven_inertia=np.array([0.2, 0.25, 0.3, 0.2]),
    load_torque=np.array([5.0, 0.0, 20.0, 5.0]),
    peak_capacity=np.array([300.0, 350.0, 400.0, 250.0]),
    ramp_time=np.array([0.2, 0.1, 0.0, 0.3]),
    static_ratio=np.array([1.0, 1.2, 1.5, 1.0]),
    driven_speed=np.array([0.0, 10.0, 0.0, 0.0]),
)
BAD_ENGAGEMENT = dict(
    engine_speed=[NAN, -1.0, INF],
    engine_inertia=[NAN, 0.0, -0.1],
    engine_torque=[NAN, INF, -INF],
    driven_inertia=[NAN, 0.0, -1.0, INF],
    load_torque=[NAN, -1.0, INF],
    peak_capacity=[NAN, -1.0, INF],
    ramp_time=[NAN, -0.1, INF],
    static_ratio=[NAN, 0.5, INF],
    driven_speed=[NAN, -1.0, 1e6],
)
GOOD_DIAPHRAGM = dict(
    youngs_modulus=np.array([206e9, 200e9, 210e9, 206e9]),
    poisson_ratio=np.array([0.3, 0.29, 0.3, 0.31]),
    sheet_thickness=np.array([2.334e-3, 2.0e-3, 2.6e-3, 2.2e-3]),
    cone_height=np.array([3.5e-3, 3.0e-3, 4.5e-3, 2.8e-3]),
    outer_radius=np.full(4, 0.1),
    inner_radius=np.full(4, 0.03),
    load_radius_outer=np.full(4, 0.095),
    load_radius_inner=np.full(4, 0.035),
    operating_point_factor=np.array([0.9, 0.8, 1.0, 0.85]),
)
BAD_DIAPHRAGM = dict(
    youngs_modulus=[NAN, 0.0, -1e9, INF],
    poisson_ratio=[NAN, 0.5, 1.0, -1.0],
    sheet_thickness=[NAN, 0.0, -1e-3, INF],
    cone_height=[NAN, -1e-3],
    outer_radius=[NAN, INF, -0.1],
    operating_point_factor=[NAN, -0.9, INF],
)
GOOD_CENTRIFUGAL = dict(
    rated_speed=np.array([5500, 5000, 6000, 5500]) * RPM,
    shoes=np.array([3.0, 3.0, 4.0, 2.0]),
    friction_coefficient=np.array([0.4046, 0.3, 0.5, 0.35]),
    pressure_angle=np.deg2rad([38.84, 30, 45, 25]),
    shoe_mass=np.full(4, 0.178),
    shoe_radius=np.full(4, 0.034),
    drum_radius=np.full(4, 0.045),
    spring_force=np.array([430.0, 400.0, 450.0, 430.0]),
    engine_inertia=np.full(4, 0.02),
    rotor_inertia=np.array([0.5, 0.4, 0.6, 0.5]),
    rotor_load_torque=np.array([55.0, 50.0, 60.0, 55.0]),
    rated_passive_torque=np.array([65.5, 60.0, 70.0, 65.5]),
    static_fraction=np.array([0.3, 0.2, 0.4, 0.3]),
)
BAD_CENTRIFUGAL = dict(
    rated_speed=[NAN, -1.0, 0.0],
    shoes=[NAN, 2.5, 0.0, -3.0],
    friction_coefficient=[NAN, -0.4],
    pressure_angle=[NAN, -0.1, np.pi / 2, 2.0],
    shoe_mass=[NAN, 0.0],
    spring_force=[NAN, -10.0],
    rotor_inertia=[NAN, -0.5, INF],
    rated_passive_torque=[NAN, -65.5],
    static_fraction=[NAN, -0.1, 1.5],
    rotor_load_torque=[NAN, -55.0],
)
GOOD_SPRAG = dict(
    torque=np.array([267.5, 750.0, 500.0, 100.0]),
    compliance_factor=np.array([1.72, 1.0, 1.72, 1.3]),
    sprags=np.array([18.0, 16.0, 18.0, 20.0]),
    sprag_length=np.array([16.891e-3, 14e-3, 16.891e-3, 18e-3]),
)
BAD_SPRAG = dict(
    torque=[NAN, -5.0, INF],
    compliance_factor=[NAN, 0.0, -1.0],
    sprags=[NAN, -3.0, 16.5, 0.0],
    sprag_length=[NAN, 0.0, -1e-3, INF],
    youngs_modulus=[NAN, -1.0],
    poisson_ratio=[NAN, 0.5],
)
K = contact.hertz_stiffness(roller_diameter=0.010)
GOOD_ROLLER = dict(
    driving_speed=np.array([2000, 1800, 2200, 2000]) * RPM,
    load_torque=np.array([1848.0, 1500, 1848, 800]),
    wedge_inertia=np.full(4, 1e-5),
    driven_inertia=np.full(4, 1e-2),
    contact_radius=np.full(4, 0.15),
    rollers_loaded=np.array([6.0, 4.0, 6.0, 5.0]),
    wedge_angle=np.deg2rad([11.0, 9.0, 11.0, 15.0]),
    friction_coefficient=np.full(4, 0.12),
    spring_force=np.full(4, 3.7),
    stiffness=np.full(4, K),
    end_time=np.full(4, 3e-3),
)
BAD_ROLLER = dict(
    driving_speed=[NAN, -1.0, INF],
    load_torque=[NAN, -10.0],
    rollers_loaded=[NAN, 0.0, -2.0],
    wedge_angle=[NAN, 0.0, np.pi / 2],
    friction_coefficient=[NAN, -0.1],
    stiffness=[NAN, 0.0],
    end_time=[NAN, 0.0, INF],
    driven_inertia=[NAN, 0.0],
)

SOLVERS = {
    "engagement_closed_form": (
        GOOD_ENGAGEMENT,
        BAD_ENGAGEMENT,
        lambda kw: engagement.closed_form(**kw),
        ("lockup_time", "slip_work", "peak_slip_power"),
    ),
    "engagement_simulate_rigid": (
        GOOD_ENGAGEMENT,
        BAD_ENGAGEMENT,
        lambda kw: engagement.simulate(t_end=0.5, **kw),
        ("lockup_time", "slip_work", "peak_slip_power"),
    ),
    "engagement_simulate_compliant": (
        GOOD_ENGAGEMENT,
        {
            **BAD_ENGAGEMENT,
            "damper_stiffness": [NAN, 0.0, -1.0],
            "damping_ratio": [NAN, -0.1],
            "hub_fraction": [NAN, 0.0, 1.0],
        },
        lambda kw: engagement.simulate(
            t_end=0.5, compliant=True, **{"damper_stiffness": 3000.0, "damping_ratio": 0.1, **kw}
        ),
        ("lockup_time", "slip_work", "peak_jerk"),
    ),
    "diaphragm": (
        GOOD_DIAPHRAGM,
        BAD_DIAPHRAGM,
        lambda kw: diaphragm.characteristic_points(**kw),
        ("load_B", "deflection_B"),
    ),
    "centrifugal_release": (
        GOOD_CENTRIFUGAL,
        BAD_CENTRIFUGAL,
        lambda kw: cf.release_after_failure(**kw),
        ("release_time", "release_speed"),
    ),
    "centrifugal_status": (
        GOOD_CENTRIFUGAL,
        {
            k: v
            for k, v in BAD_CENTRIFUGAL.items()
            if k not in ("rotor_inertia", "rated_passive_torque", "static_fraction")
        },
        lambda kw: {
            "status": cf.design_status(
                **{
                    k: v
                    for k, v in kw.items()
                    if k
                    not in (
                        "engine_inertia",
                        "rotor_inertia",
                        "rated_passive_torque",
                        "static_fraction",
                    )
                }
            )
        },
        (),
    ),
    "sprag": (
        GOOD_SPRAG,
        BAD_SPRAG,
        lambda kw: sprag.statics(**kw),
        ("V", "contact_stress_inner", "vm_stress_inner"),
    ),
    "roller": (
        GOOD_ROLLER,
        BAD_ROLLER,
        lambda kw: roller.simulate(**kw),
        ("engagement_time", "peak_contact_force"),
    ),
}


def _take(out, idx):
    return {
        k: (_take(v, idx) if isinstance(v, dict) else np.asarray(v)[idx])
        for k, v in out.items()
        if k != "trace" and (isinstance(v, dict) or np.ndim(v) > 0)
    }


def _same(a, b):
    for k in a:
        if isinstance(a[k], dict):
            _same(a[k], b[k])
        else:
            assert a[k].dtype == b[k].dtype and np.array_equal(
                a[k], b[k], equal_nan=a[k].dtype.kind == "f"
            ), k


@hs.composite
def _mixed(draw, solver):
    good, bad, _, _ = SOLVERS[solver]
    n_good = len(next(iter(good.values())))
    n_bad = draw(hs.integers(1, 3))
    order = draw(hs.permutations(range(n_good + n_bad)))
    rows = []  # per bad scenario: (which good scenario it copies, the input made bad, the bad value)
    for _ in range(n_bad):
        name = draw(hs.sampled_from(sorted(bad)))
        rows.append((draw(hs.integers(0, n_good - 1)), name, draw(hs.sampled_from(bad[name]))))
    return order, rows


@pytest.mark.parametrize("solver", sorted(SOLVERS))
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=hs.data())
def test_bad_scenarios_never_disturb_good_ones(solver, data):
    good, bad, call, headline = SOLVERS[solver]
    order, rows = data.draw(_mixed(solver))
    n_good = len(next(iter(good.values())))
    names = sorted(set(good) | {name for _, name, _ in rows})
    base = {k: (np.asarray(good[k], float) if k in good else None) for k in names}
    columns = {}
    for k in names:
        col = [base[k][i] if base[k] is not None else None for i in range(n_good)]
        for src, name, value in rows:
            col.append(value if name == k else col[src])
        columns[k] = col
    # inputs with no good values (solver defaults) are only given when some scenario makes them bad
    mixed = {}
    for k, col in columns.items():
        if any(c is None for c in col):
            fill = {
                "damper_stiffness": 3000.0,
                "damping_ratio": 0.1,
                "hub_fraction": 0.5,
                "youngs_modulus": 206e9,
                "poisson_ratio": 0.3,
            }[k]
            col = [fill if c is None else c for c in col]
        mixed[k] = np.asarray(col, float)[list(order)]
    clean = call({k: np.asarray(v, float) for k, v in good.items()})
    out = call(mixed)
    pos = np.argsort(order)  # where each original row went
    _same(_take(out, pos[:n_good]), _take(clean, np.arange(n_good)))
    for j in range(len(rows)):
        i = pos[n_good + j]
        assert out["status"][i] == st.CODE["invalid_input"], (rows[j], out["status"][i])
        for h in headline:
            assert not np.isfinite(out[h][i]), (rows[j], h, out[h][i])


def test_held_engine_at_rest_is_a_lockup_not_a_spin():
    """Issue 14: a held engine at 0 rad/s used to spin the parked driven side up to thousands of
    rad/s with negative slip work in `simulate` (the closed form was right): the clutch that comes
    to carry the load holds the driven side, lock-up at C(t) = T_m = 5 N m, t = 5/300 · 0.2 s."""
    kw = dict(
        engine_speed=0.0,
        engine_inertia=INF,
        engine_torque=0.0,
        driven_inertia=0.2,
        load_torque=5.0,
        peak_capacity=300.0,
        ramp_time=0.2,
    )
    exact = engagement.closed_form(**kw)
    sim = engagement.simulate(t_end=0.5, **kw)
    assert int(sim["status"]) == st.CODE["ok"]
    assert float(sim["lockup_time"]) == pytest.approx(float(exact["lockup_time"]), rel=1e-12)
    assert float(exact["lockup_time"]) == pytest.approx(5.0 / 300.0 * 0.2, rel=1e-12)
    assert float(sim["slip_work"]) == 0.0 and float(sim["lockup_speed"]) == 0.0
    comp = engagement.simulate(
        t_end=0.5, compliant=True, damper_stiffness=2000.0, damping_ratio=0.1, **kw
    )
    # compliant: the unloaded hub is held by the clutch from t = 0 and the parked output never moves
    # (it moved under its load torque, then the run ended `truncated`)
    assert int(comp["status"]) == st.CODE["ok"] and float(comp["lockup_time"]) == 0.0
    assert float(comp["load_work"]) == 0.0 and float(comp["kinetic_energy_change"]) == 0.0


def test_jamming_within_rounding_is_jammed():
    """f = 1, α = 45°: tan 45° = 1 − 1.1e-16 in floating point; was ok with M ≈ 1e18 N m."""
    kw = {
        "shoes": 3,
        "shoe_mass": 0.178,
        "shoe_radius": 0.034,
        "drum_radius": 0.045,
        "spring_force": 430.0,
        "friction_coefficient": 1.0,
        "pressure_angle": np.deg2rad(45.0),
    }
    assert (
        int(cf.design_status(rated_speed=5500 * RPM, rotor_load_torque=55.0, **kw))
        == st.CODE["jammed"]
    )
    fwd, _ = cf.capacity(speed=5500 * RPM, **kw)
    assert np.isnan(fwd)


def test_unloaded_sprag_is_its_rest_geometry():
    """Issue 14: zero torque used to say invalid_geometry for a sprag that spans the races."""
    out = sprag.statics(0.0)
    rest = sprag.rest_geometry(**sprag.SEED_GEOMETRY)
    assert int(out["status"]) == st.CODE["ok"]
    assert float(out["V"]) == pytest.approx(float(rest["V"]), abs=1e-15)
    assert float(out["contact_stress_inner"]) == 0.0 and float(out["vm_stress_outer"]) == 0.0


def test_an_odd_count_loads_no_half_roller():
    assert (
        np.isnan(roller.loaded_rollers(13, "one_flank"))
        and roller.loaded_rollers(12, "one_flank") == 6.0
    )
    assert roller.loaded_rollers(13, "all") == 13.0 and np.isnan(roller.loaded_rollers(12.5, "all"))

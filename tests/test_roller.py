"""Roller-type controllable overrunning clutch (seed 003): statics (eqs. 1-4), self-locking, the
contact law against the analytic Hertz impact, the wedging dynamics against a tight scipy Radau
reference, working modes, the study."""

import numpy as np
import pytest

from clutchlab import _contact_kernel as _kernel
from clutchlab import _contact_systems as _sys
from clutchlab import _dop853, contact
from clutchlab import _dop853_tableau as _tableau
from clutchlab import roller as rl
from clutchlab import status as st
from clutchlab.bench import roller as bench
from clutchlab.published import ROLLER_CLUTCH as PUB
from clutchlab.studies import roller as study
from conftest import ROOT

K = contact.hertz_stiffness(roller_diameter=0.010)
SEED = dict(
    driving_speed=2000 * rl.RPM,
    load_torque=1848.0,
    wedge_inertia=1e-5,
    driven_inertia=1e-2,
    contact_radius=0.15,
    rollers_loaded=6.0,
    wedge_angle=np.deg2rad(11.0),
    friction_coefficient=0.12,
    spring_force=3.7,
    stiffness=K,
    damping=2.1e6,
    penetration_depth=1e-4,
    end_time=3e-3,
)


# ------------------------------------------------------------------ statics, seed 003 section 2


def test_seed003_statics():
    """Seed 003 section 2.2 / Table 1 (tolerance 0.1 %): T_c 1848 N m, N_A 8555.6 N (z = 12 as
    printed), sigma_H 2865.5 MPa with one flank loaded (z/2), contact stiffness 3.375e5 N/mm^1.5."""
    tc = rl.computed_torque(800.0)
    assert tc == pytest.approx(PUB["computed_torque"].value, rel=1e-3)
    assert rl.normal_force(
        tc, contact_radius=0.15, friction_coefficient=0.12, rollers=12
    ) == pytest.approx(PUB["normal_force"].value, rel=1e-3)
    n6 = rl.normal_force(
        tc, contact_radius=0.15, friction_coefficient=0.12, rollers=rl.loaded_rollers(12)
    )
    sigma = rl.contact_stress(n6, roller_length=0.015, radius=rl.equivalent_radius(0.010))
    assert sigma / 1e6 == pytest.approx(PUB["contact_stress"].value, rel=1e-3)
    every = rl.contact_stress(0.5 * n6, roller_length=0.015, radius=rl.equivalent_radius(0.010))
    assert sigma / every == pytest.approx(
        np.sqrt(2), rel=1e-9
    )  # the factor 2 under the root (PHYSICS.md)
    assert K * 1e-3**1.5 == pytest.approx(PUB["contact_stiffness"].value, rel=1e-3)  # N mm^-1.5
    assert rl.equivalent_radius(0.010, 0.050) == pytest.approx(0.5 * 0.05 * 0.01 / 0.04)


def test_seed003_spring_and_self_locking():
    """F_T = 3.7 N <=> m = 4.6 g by eq. 4 as printed (800 m); a solid 10 x 15 mm roller is 9.25 g;
    self-locking margin 1.25 at 11 deg (published, rounded), limit 13.69 deg for mu 0.12."""
    per_kg = rl.spring_preload(
        roller_mass=1.0,
        contact_radius=0.15,
        friction_coefficient=0.12,
        speed=2000 * rl.RPM,
        formula="eq4",
    )
    assert per_kg == pytest.approx(800.0, rel=1e-12)
    assert PUB["spring_preload"].value / per_kg == pytest.approx(4.625e-3, rel=1e-9)
    exact = rl.spring_preload(
        roller_mass=1.0, contact_radius=0.15, friction_coefficient=0.12, speed=2000 * rl.RPM
    )
    assert exact / per_kg == pytest.approx(np.pi**2 / 10, rel=1e-12)
    assert rl.roller_mass(roller_diameter=0.01, roller_length=0.015) == pytest.approx(
        9.25e-3, rel=2e-3
    )
    # seed 003 section 2.1: mu/tan(alpha/2) = 1.25 at 11 deg (rounded); the margin is that minus one
    assert 1.0 + rl.self_locking_margin(
        wedge_angle=np.deg2rad(11), friction_coefficient=0.12
    ) == pytest.approx(PUB["self_locking_margin"].value, rel=5e-3)
    limit = PUB["limit_wedge_angle"].value
    assert np.rad2deg(rl.limit_wedge_angle(0.12)) == pytest.approx(limit, abs=5e-3)


# ------------------------------------------------------------------ contact law


@pytest.mark.parametrize("mass,speed", [(0.05, 1.5), (2.0, 0.1), (1e-3, 5.0)])
def test_undamped_hertz_impact(mass, speed):
    """Johnson 11.4: delta_max = (5 m v^2 / (4 k))^(2/5), contact time 2.9432 delta_max / v, restitution
    1 (tolerance 0.1 %; measured ~1e-10)."""
    r = contact.hertz_impact(mass=mass, speed=speed, stiffness=K)
    d_max = (5 * mass * speed**2 / (4 * K)) ** 0.4
    assert contact.HERTZ_CONTACT_TIME_FACTOR == pytest.approx(2.9432, abs=1e-4)
    assert r["max_penetration"] == pytest.approx(d_max, rel=1e-3)
    assert r["contact_time"] == pytest.approx(
        contact.HERTZ_CONTACT_TIME_FACTOR * d_max / speed, rel=1e-3
    )
    assert r["time_of_max"] == pytest.approx(0.5 * r["contact_time"], rel=1e-6)
    assert r["restitution"] == pytest.approx(1.0, abs=1e-6)


def test_contact_force_never_pulls_and_is_continuous():
    d = np.linspace(-1e-4, 3e-4, 401)[:, None]
    v = np.linspace(-5.0, 5.0, 41)[None, :]
    f = contact.impact_force(d, v, stiffness=K, damping=2.1e6, depth=1e-4)
    assert np.all(f >= 0) and np.all(f[d[:, 0] <= 0] == 0)
    tiny = contact.impact_force(1e-12, 5.0, stiffness=K, damping=2.1e6, depth=1e-4)
    assert tiny < 1e-3  # continuous at first touch: the damping steps in with the penetration
    r = contact.hertz_impact(mass=0.05, speed=1.5, stiffness=K, damping=2e3, depth=1e-5)
    assert 0 < r["restitution"] < 1


# ------------------------------------------------------------------ wedging dynamics


def test_engagement_against_tight_radau():
    """clutchlab's SDIRK4 at rtol 1e-9 against scipy Radau at rtol 1e-12 (same equations, events per
    phase) on random scenarios: engagement time within 2e-9 s (benchmark measures ~2e-10 s)."""
    d = bench.design(4, seed=3)
    P, _ = rl.parameter_rows(**d)
    ref = np.array([bench.scipy_engagement(p, "Radau", 1e-12) for p in P])
    got = rl.simulate(rtol=1e-9, **d)["engagement_time"]
    assert np.all(np.isfinite(ref))
    np.testing.assert_allclose(got, ref, rtol=0, atol=2e-9)


# every output the roller study stores (its peak stress and dynamic factor follow from the peak
# force), within this relative error of the tight reference; measured 2026-11-26 on 400 random
# designs (200 of config/million.yaml's roller ranges, 200 of the default grid) at the study's
# rtol 1e-8, the slip at 10x and the phase after the engagement at 30x it: engagement time
# 3.2e-6, the others at most 2.2e-6 (all at rtol 1e-8: 3.0e-6 and 3.5e-7; the code before the
# explicit steps: 1.9e-5)
STUDY_TOLERANCE = 1e-5


def _against_radau(kw):
    """Largest relative error of each stored output against Radau rtol 1e-12, and whether every
    status agrees."""
    P, _ = rl.parameter_rows(**kw)
    ref = [bench.scipy_outputs(p) for p in P]
    got = rl.simulate(rtol=study.RTOL, **kw)
    status = [st.CODE[r["status"]] for r in ref]
    errors = {}
    for k in bench.OUTPUTS:
        a = np.array([r[k] for r in ref])
        assert (np.isfinite(a) == np.isfinite(got[k])).all(), k
        errors[k] = np.max(np.abs(got[k][np.isfinite(a)] / a[np.isfinite(a)] - 1.0), initial=0.0)
    return errors, list(got["status"]) == status, got


@pytest.mark.parametrize("configfile,samples", [("million.yaml", 1024), ("config.yaml", None)])
def test_study_outputs_against_tight_radau(configfile, samples):
    """The wedging at the study's tolerance (DOP853 steps with SDIRK4 where the contact is stiff,
    events on the continuous extension) against scipy Radau at rtol 1e-12, on random designs the
    study simulates (config/million.yaml's ranges; the default grid): stick time, backlash of the
    wedge ring, engagement time, total backlash, peak contact force and release time within
    STUDY_TOLERANCE (relative), the same statuses (ok or never_locked)."""
    kw = bench.study_scenarios(ROOT / "config" / configfile, samples)
    pick = np.random.default_rng(11).choice(kw["wedge_angle"].size, 3, replace=False)
    errors, same_status, _ = _against_radau({k: v[pick] for k, v in kw.items()})
    assert same_status
    assert max(errors.values()) < STUDY_TOLERANCE, errors


def test_stiff_contact_steps_implicitly_against_tight_radau():
    """A stiff contact (a light driven ring, J_o = 1e-3 kg m², on ten times the damping): the
    explicit steps would be unstable over the creep after the impact, so SDIRK4 takes over there
    (implicit steps counted); the outputs stay within STUDY_TOLERANCE of Radau at rtol 1e-12."""
    kw = {**SEED, "driven_inertia": 1e-3, "damping": 2e7, "control_stop_time": 1e-3}
    kw["claw_clearance"] = 1e-3
    errors, same_status, got = _against_radau({k: np.atleast_1d(v) for k, v in kw.items()})
    assert same_status and got["status"][0] == st.CODE["ok"]
    assert 0 < got["n_implicit"][0] < got["n_steps"][0]
    assert max(errors.values()) < STUDY_TOLERANCE, errors


def test_contact_rates_are_the_jacobians_eigenvalues():
    """The decay and growth rates the driver chooses its method by, in closed form from the
    contact's (δ, δ̇) dynamics, against numpy's eigenvalues of the full 4 × 4 Jacobian (relative
    1e-9) in each mode, at states of a wedging (slip: one mode grows; stick: both decay)."""
    P, _ = rl.parameter_rows(**{**SEED, "control_stop_time": 1e-3})
    p = P[0]
    f, jac = np.zeros(4), np.zeros((4, 4))
    rng = np.random.default_rng(2)
    for mode in (_sys.SLIP, _sys.SLIP | _sys.HELD, _sys.STICK, _sys.STICK | _sys.CLAWS):
        for _ in range(20):
            y = np.array([0.0, rng.uniform(0, 200), rng.uniform(0, 4e-3), rng.uniform(0, 200)])
            _sys.rhs(_sys.ROLLER, 1.1e-3, y, p, mode, f, jac, True)
            lam = np.linalg.eigvals(jac)
            decaying = lam[lam.real < -1e-9 * np.abs(lam).max()]
            decay = np.abs(decaying).max(initial=0.0)
            growth = max(lam.real.max(), 0.0)
            got = _sys.contact_rates(1.1e-3, y, p, mode)
            assert got[0] == pytest.approx(decay, rel=1e-9, abs=1e-9 * np.abs(lam).max())
            assert got[1] == pytest.approx(growth, rel=1e-9, abs=1e-9 * np.abs(lam).max())


def test_dop853_tableau_order_and_stability():
    """The copied tableau is scipy's, bit for bit. The compiled step on a linear spring (the
    impact system with exponent 1 and no damping: δ = 10·cos t) has the local error of a method of
    order 8 or more (halving h divides it by more than 2^8.5), its continuous extension that of
    order 7 (2⁸ within 2^±0.5, at mid-step). The stability function stays within 1 on the half-disc of radius
    STABILITY_RADIUS up to 85° from the negative real axis, beyond the driver's STIFF_LIMIT."""
    from scipy.integrate._ivp import dop853_coefficients as scipy_tableau

    for name in ("A", "B", "C", "E3", "E5", "D"):
        assert np.array_equal(getattr(_tableau, name), getattr(scipy_tableau, name)), name
    p = np.array([1.0, 1.0, 1.0, 0.0, 1.0])  # mass, stiffness, exponent, damping, depth
    y0, y1, mid = np.array([10.0, 0.0]), np.zeros(2), np.zeros(2)
    ws = _dop853.work(2)
    step_err, dense_err = [], []
    for h in (1.2, 0.6):
        _sys.rhs(_sys.IMPACT, 0.0, y0, p, 0, ws.k[0], ws.jac, False)
        _dop853.step(_sys.IMPACT, 0.0, y0, h, p, 0, 1e-8, np.ones(2), y1, ws)
        _dop853.prepare_dense(_sys.IMPACT, 0.0, y0, y1, h, p, 0, ws)
        _dop853.dense_state(ws, y0, 0.5, mid)
        step_err.append(abs(y1[0] - 10.0 * np.cos(h)))
        dense_err.append(abs(mid[0] - 10.0 * np.cos(0.5 * h)))
    assert step_err[0] / step_err[1] > 2.0**8.5  # 978 = 2^9.9: R(z) − e^z = O(z^10) here
    assert 2.0**7.5 < dense_err[0] / dense_err[1] < 2.0**8.5
    a, b = _tableau.A[:12, :12], _tableau.B
    radius = _dop853.STABILITY_RADIUS
    for angle in np.deg2rad(np.linspace(0, 85, 18)):
        for r in np.linspace(0.1, radius, 30):
            z = -r * np.exp(1j * angle)
            assert abs(1 + z * b @ np.linalg.solve(np.eye(12) - z * a, np.ones(12))) <= 1.0
    assert _kernel.STIFF_LIMIT < radius


def test_seed_engagement_of_published_order():
    """Seed 003 section 3.2 (ADAMS): wedging time 0.197 ms and total backlash 1.12 deg; with the
    assumed inertias and the passive load the model gives 0.195 ms and 1.31 deg (within a factor
    1.5; the paper's inertias are not printed). Once engaged, the contact force approaches the
    wedge's static value T / (z R_C tan(alpha/2))."""
    r = rl.simulate(**SEED)
    assert r["status"] == st.CODE["ok"]
    t_pub = PUB["engagement_time"].value * 1e-3  # ms -> s
    assert t_pub / 1.5 < r["engagement_time"] < 1.5 * t_pub
    backlash = PUB["backlash"].value  # deg
    assert backlash / 1.5 < np.rad2deg(r["backlash"]) < 1.5 * backlash
    assert 0 < r["slip_backlash"] < r["backlash"]
    assert r["stick_time"] < r["engagement_time"]
    static = 1848.0 / (6 * 0.15 * np.tan(np.deg2rad(5.5)))
    assert r["final_contact_force"] == pytest.approx(static, rel=0.1)
    assert r["peak_contact_force"] > static


def test_driven_ring_never_turns_backwards_under_a_passive_load():
    """The load torque is passive (drag): it holds the driven ring at rest exactly (speed 0.0, not
    merely small) until the wedge's drive torque z R_C tan(alpha/2) N reaches it, opposes its
    motion after that, and holds it again once it stops: the ring never turns backwards, neither
    before it engages nor after the control ring releases the rollers. (An active load of 1848 N m
    drove the seed design's ring to -7.8 rad/s before it engaged.)"""
    d = bench.design(12, seed=5)
    d["control_stop_time"] = np.full(12, 1.5e-3)  # release: the ring coasts down under the load
    engaged = 0
    for i in range(12):
        one = {k: v[i] for k, v in d.items()}
        r = rl.simulate(trace_index=0, max_step=2e-6, **one)
        tr = r["trace"]
        assert tr[:, 3].min() == 0.0  # never below rest, and at rest exactly while held
        held = tr[:, 3] == 0.0
        engaged += int(r["status"] == st.CODE["ok"])
        if held.all():  # (a heavy load and few rollers: not broken away by end_time)
            assert r["status"] == st.CODE["never_locked"]
            continue
        first = int(np.argmin(held))  # the first sample with the ring turning
        drive = one["rollers_loaded"] * 0.15 * np.tan(0.5 * one["wedge_angle"]) * tr[:, 4]
        # broke away where the drive torque reached the load (the event, located to 1e-14 s)
        assert held[0] and drive[first - 1] == pytest.approx(one["load_torque"], rel=1e-6)
        assert (drive[: first - 1] < one["load_torque"]).all()
    assert engaged >= 6
    # a load the wedge never overcomes: the ring stays at rest, never engaged
    r = rl.simulate(trace_index=0, **{**SEED, "load_torque": 1e7})
    assert r["status"] == st.CODE["never_locked"] and (r["trace"][:, 3] == 0.0).all()
    # no load: the preload alone turns the ring from t = 0
    r = rl.simulate(trace_index=0, **{**SEED, "load_torque": 0.0})
    assert r["status"] == st.CODE["ok"] and r["trace"][:, 3].min() >= 0.0


def test_release_after_control_stop():
    """Stopping the control ring frees the rollers no sooner than the claws cross their clearance."""
    r = rl.simulate(control_stop_time=1e-3, claw_clearance=1e-3, **SEED)
    travel = 1e-3 / (0.15 * 2000 * rl.RPM)
    assert travel < r["release_time"] < travel + 1e-4
    assert r["final_contact_force"] == 0.0


def test_not_self_locking_is_never_simulated():
    r = rl.simulate(**{**SEED, "wedge_angle": np.deg2rad([11.0, 15.0])})
    assert r["status"][0] == st.CODE["ok"] and r["status"][1] == st.CODE["not_self_locking"]
    assert np.isnan(r["engagement_time"][1]) and np.isnan(r["n_steps"][1])


def test_modes():
    assert list(rl.engages("bidirectional_lock", np.array([1, -1]))) == [True, True]
    assert list(rl.engages("bidirectional_overrun", np.array([1, -1]))) == [False, False]
    assert list(rl.engages("overrun_forward", np.array([1, -1]))) == [False, True]
    assert list(rl.engages("overrun_reverse", np.array([1, -1]))) == [True, False]
    with pytest.raises(ValueError):
        rl.engages("lock", 1)


# ------------------------------------------------------------------ study


def test_study_statuses_and_modes():
    inputs = {p.name: p.default for p in study.PARAMETERS}
    inputs["wedge_angle"] = np.deg2rad(np.array([11.0, 15.0, 11.0, 11.0]))
    inputs["drive_direction"] = np.array([1.0, 1.0, -1.0, 1.0])
    # the seed design's wedging impact peaks at 5.8 x the allowable (17.7 GPa): far out; with an
    # allowable of 20 GPa the same scenario is ok
    inputs["contact_allowable"] = np.array([20e9, 20e9, 20e9, 3041e6])
    ds = study.compute(inputs, {"mode": "overrun_reverse"})
    assert list(ds["status"].values) == [
        st.CODE["ok"],
        st.CODE["not_self_locking"],
        st.CODE["overrunning"],
        st.CODE["dynamic_overstress"],
    ]
    ratio = ds["peak_contact_stress"].values[3] / 3041e6
    assert ratio > study.DYNAMIC_STRESS_FACTOR and ratio == pytest.approx(5.84, rel=0.01)
    assert ds["peak_contact_stress"].values[0] == ds["peak_contact_stress"].values[3]  # kept
    assert (
        np.isfinite(ds["engagement_time"].values[[0, 3]]).all()
        and np.isnan(ds["engagement_time"].values[1:3]).all()
    )
    assert np.isfinite(ds["contact_stress"].values).all()  # statics for every scenario
    assert ds["contact_stress"].values[0] / 1e6 == pytest.approx(
        2867.0, rel=1e-3
    )  # exact 0.4182 vs printed 0.418
    for name in (
        "contact_stress",
        "self_locking_margin",
        "spring_preload",
        "engagement_time",
        "backlash_angle",
        "status",
    ):
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs
    assert (
        "trace_driven_speed" not in ds
    )  # the seed trace is the study's, computed once (study.traces)
    tr = study.STUDY.traces(inputs, study.STUDY.full_options({"mode": "overrun_reverse"}))
    assert tr["trace_driven_speed"].values.max() > 0.98 * 2000 * rl.RPM

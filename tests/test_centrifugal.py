"""Centrifugal clutch with overrunning linkage (seed 001 eqs. 1-2) and release after engine failure."""

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from clutchlab import centrifugal as cf
from clutchlab import status as st
from clutchlab.published import CENTRIFUGAL_CLUTCH as PUB
from clutchlab.studies import centrifugal as study

RPM = np.pi / 30
# seed 001 section 2.3: z = 3 (fits 2 * 248 N * sin 60 deg = 430 N), f = 0.4046, alpha = 38.84 deg
SEED = dict(
    shoes=3,
    friction_coefficient=0.4046,
    pressure_angle=np.deg2rad(38.84),
    shoe_mass=0.178,
    shoe_radius=0.034,
    drum_radius=0.045,
    spring_force=430.0,
)
DYN = dict(
    engine_inertia=0.02,
    rotor_inertia=0.5,
    rotor_load_torque=55.0,
    rated_passive_torque=65.5,
    static_fraction=0.3,
)


def test_seed001_capacities():
    """Seed 001 section 2.3: M = 127.84 N m, M' = 65.0 N m at 5500 rpm (tol 0.1 %), reserve 1.88."""
    m, m_rev = cf.capacity(speed=5500 * RPM, **SEED)
    assert m == pytest.approx(PUB["forward_capacity"].value, rel=1e-3)
    assert m_rev == pytest.approx(PUB["reverse_capacity"].value, rel=1e-3)
    assert m / PUB["engine_torque"].value == pytest.approx(PUB["reserve_factor"].value, rel=1e-3)


def test_seed001_engagement_speed_and_idle():
    """Engagement about 2545 rpm (tol 0.5 %); idle 1900-2100 rpm fully disengaged (seed 001 requirements)."""
    w0 = cf.engagement_speed(shoe_mass=0.178, shoe_radius=0.034, spring_force=430.0)
    assert w0 / RPM == pytest.approx(PUB["engagement_speed"].value, rel=5e-3)
    idle = np.linspace(PUB["idle_speed_min"].value, PUB["idle_speed_max"].value, 21) * RPM
    fwd, rev = cf.capacity(speed=idle, **SEED)
    assert np.all(fwd == 0) and np.all(rev == 0)
    fwd, _ = cf.capacity(speed=w0 * (1 + 1e-9), **SEED)
    assert 0 < fwd < 1e-4  # continuous from zero at the engagement speed


def test_design_inverse():
    """Eq. 1 / eq. 2 with M = 127.84, M' = 65 N m gives f tan(alpha) = 0.32587 (section 2.3), and
    the capacities rebuilt from it match the targets."""
    m_pub, m_rev_pub = PUB["forward_capacity"].value, PUB["reverse_capacity"].value
    x = cf.linkage_factor_from_targets(m_pub, m_rev_pub)
    assert x == pytest.approx(PUB["linkage_factor"].value, rel=1e-4)
    f = 0.4046
    m, m_rev = cf.capacity(speed=5500 * RPM, **{**SEED, "pressure_angle": np.arctan(x / f)})
    assert m / m_rev == pytest.approx(m_pub / m_rev_pub, rel=1e-12)


def test_jam_and_weak_springs_are_flagged():
    """f tan(alpha) >= 1 is a jam, springs stronger than the centrifugal force at rated speed a
    'not_engaged' status: never a number that looks valid."""
    alpha = np.arctan(np.array([0.5, 1.0 + 1e-9, 1.5]) / 0.4046)
    code = cf.design_status(
        rated_speed=5500 * RPM, rotor_load_torque=55.0, **{**SEED, "pressure_angle": alpha}
    )
    assert list(code) == [st.CODE["ok"], st.CODE["jammed"], st.CODE["jammed"]]
    fwd, _ = cf.capacity(speed=5500 * RPM, **{**SEED, "pressure_angle": alpha})
    assert np.isfinite(fwd[0]) and np.all(np.isnan(fwd[1:]))
    code = cf.design_status(
        rated_speed=5500 * RPM, rotor_load_torque=55.0, **{**SEED, "spring_force": 2500.0}
    )
    assert code == st.CODE["not_engaged"]
    inputs = {q.name: q.default for q in study.PARAMETERS}
    ds = study.compute(
        {**inputs, "pressure_angle": np.array([SEED["pressure_angle"], np.arctan(1.2 / 0.4046)])}
    )
    assert ds.status.values[1] == st.CODE["jammed"] and np.isnan(ds.capacity_forward.values[1])
    assert np.isnan(ds.reserve_factor.values[1]) and np.isnan(ds.release_time.values[1])


def test_reverse_capacity_falls_with_f_too():
    """PHYSICS.md: a lower f lowers M' as well, so 'f too small' cannot delay the release."""
    _, lo = cf.capacity(speed=5500 * RPM, **{**SEED, "friction_coefficient": 0.3})
    _, hi = cf.capacity(speed=5500 * RPM, **SEED)
    assert lo < hi


def _reference_release(p, w_r, rtol=1e-13):
    """DOP853 at rtol 1e-13 on the held phase with the release as an event (scipy)."""
    k = p["rotor_load_torque"] / w_r**2
    p0 = p["rated_passive_torque"] * p["static_fraction"]
    p2 = p["rated_passive_torque"] * (1 - p["static_fraction"]) / w_r**2
    j = p["engine_inertia"] + p["rotor_inertia"]
    cap = {k_: p[k_] for k_ in SEED}
    w0 = cf.engagement_speed(
        shoe_mass=p["shoe_mass"], shoe_radius=p["shoe_radius"], spring_force=p["spring_force"]
    )

    def g(t, y):  # needed reverse torque reaches M'
        need = cf.needed_reverse_torque(
            y[0],
            engine_inertia=p["engine_inertia"],
            rotor_inertia=p["rotor_inertia"],
            rotor_drag=k,
            p0=p0,
            p2=p2,
        )
        return need - cf.capacity(speed=y[0], **cap)[1]

    def lift(t, y):  # shoes off the drum
        return y[0] - w0

    g.terminal, g.direction, lift.terminal, lift.direction = True, 1, True, -1
    sol = solve_ivp(
        lambda t, y: [-(p0 + (p2 + k) * y[0] ** 2) / j],
        (0, 50.0),
        [w_r],
        method="DOP853",
        rtol=rtol,
        atol=1e-12,
        events=(g, lift),
    )
    i = 0 if sol.t_events[0].size else 1
    return sol.t_events[i][0], sol.y_events[i][0][0]


@pytest.mark.parametrize(
    "variant",
    [
        {},  # seed: held, releases at 5214 rpm
        {"rotor_inertia": 2.0, "rotor_load_torque": 30.0},
        {"spring_force": 300.0, "pressure_angle": np.deg2rad(25.0)},
        {"static_fraction": 0.0},
        {
            "rotor_inertia": 0.01,
            "rotor_load_torque": 200.0,
        },  # rotor drag carries the engine: held down to w0
    ],
)
def test_release_closed_form_against_tight_ode(variant):
    """Acceptance: release instant (an exact root, not a step) equals a DOP853 rtol 1e-13 event
    solution to 1e-9 relative, for releases at a speed root and at the engagement speed."""
    p = {**SEED, **DYN, **variant}
    w_r = 5500 * RPM
    r = cf.release_after_failure(rated_speed=w_r, **p)
    assert not r["released_at_once"]
    t_ref, w_ref = _reference_release(p, w_r)
    assert r["release_time"] == pytest.approx(t_ref, rel=1e-9)
    assert r["release_speed"] == pytest.approx(w_ref, rel=1e-9)


def test_release_at_once_when_needed_torque_beats_reverse_capacity():
    """With the engine alone on the clutch (J_r >> J_e, no rotor drag) the passive 65.5 N m beats
    M' = 65.0 N m: the paper's 'immediate release'."""
    r = cf.release_after_failure(
        rated_speed=5500 * RPM, **{**SEED, **DYN, "rotor_inertia": 1e5, "rotor_load_torque": 0.0}
    )
    assert r["released_at_once"] and r["release_time"] == 0.0 and r["release_speed"] == 5500 * RPM


def test_failure_trace_matches_closed_form():
    p = {**SEED, **DYN, "rated_speed": 5500 * RPM}
    tr = cf.engine_failure_trace(p, t_end=3.0)
    r = cf.release_after_failure(**{k: p[k] for k in p})
    assert tr["release_time"] == pytest.approx(float(r["release_time"]), rel=1e-8)
    assert np.all(np.diff(tr["engine_speed"]) <= 1e-9)  # the dead engine only slows down
    after = tr["time"] > tr["release_time"]
    assert np.all(
        tr["rotor_speed"][after] >= tr["engine_speed"][after]
    )  # overrunning: rotor runs free
    assert tr["engine_speed"][-1] == 0.0


def test_startup_trace_locks_and_engages_above_idle():
    p = {**SEED, **DYN, "rated_speed": 5500 * RPM}
    up = cf.startup_trace(p, idle_speed=2000 * RPM, startup_time=8.0)
    w0 = cf.engagement_speed(shoe_mass=0.178, shoe_radius=0.034, spring_force=430.0)
    assert np.isfinite(up["lockup_time"]) and up["lockup_speed"] > w0
    moving = up["rotor_speed"] > 0
    assert np.all(
        up["engine_speed"][moving] >= w0 * (1 - 1e-9)
    )  # picked up only above the engagement speed
    assert np.nanmax(up["rotor_speed"] - up["engine_speed"]) <= 1e-6


def test_study_validation_rows():
    v = study.validation()
    rows = dict(zip(v.quantity.values, v.passed.values, strict=True))
    for key in ("forward_capacity", "reverse_capacity", "engagement_speed", "idle_capacity"):
        assert rows[PUB[key].quantity] == 1


def test_near_jam_is_flagged_and_keeps_its_exact_numbers():
    """Issue 16 item 4: designs whose f tan(alpha) is within the friction scatter of 1 (the forward
    capacity ~ 1/(1 - f tan(alpha)) near-singular; in a 2^20 design a few reached 2e6 x the engine
    torque) carry the status near_jam; their numbers stay (they are exact); a jam stays a jam."""
    x = np.array([0.5, 0.79, 0.81, 0.99, 1.0 + 1e-9])  # f tan(alpha); near_jam from 1/1.25 = 0.8
    alpha = np.arctan(x / SEED["friction_coefficient"])
    kw = dict(rated_speed=5500 * RPM, rotor_load_torque=55.0, **{**SEED, "pressure_angle": alpha})
    want = ["ok", "ok", "near_jam", "near_jam", "jammed"]
    assert [st.FLAGS[c] for c in cf.design_status(**kw, friction_scatter=0.25)] == want
    assert [st.FLAGS[c] for c in cf.design_status(**kw)] == ["ok"] * 4 + [
        "jammed"
    ]  # no scatter asked
    inputs = {q.name: q.default for q in study.PARAMETERS}
    ds = study.compute({**inputs, "pressure_angle": alpha})
    assert [st.FLAGS[c] for c in ds.status.values] == want
    fwd, _ = cf.capacity(speed=5500 * RPM, **{**SEED, "pressure_angle": alpha})
    np.testing.assert_array_equal(ds.capacity_forward.values[:4], fwd[:4])
    assert ds.reserve_factor.values[3] > 20 * ds.reserve_factor.values[0] and np.isnan(
        ds.reserve_factor.values[4]
    )


@pytest.mark.parametrize(
    "a, c, lo, hi",
    [
        (20.0, 1e-4, 300.0, 575.0),
        (0.0, 2e-4, 300.0, 575.0),
        (5.0, 1e-9, 300.0, 575.0),
        (1.0, 2.0, 0.5, 3.0),
        (1e-310, 2.0, 0.5, 3.0),  # a denormal static passive torque (it overflowed to 2.6e161 s)
        (1e-320, 2e-3, 100.0, 600.0),
        (5.0, 0.0, 100.0, 600.0),  # no drag growing with speed (it gave NaN)
        (5.0, 1e-30, 100.0, 600.0),
        (3.0, 1e-4, 100.0, 600.0),
        (3.0, 1e-4, 100.0, 100.0 * (1 + 1e-12)),
    ],
)
def test_release_integral_against_quadrature(a, c, lo, hi):
    """∫ dω/(a + c·ω²) of the coast-down, in every regime of a and c, against scipy's quad."""
    want = quad(lambda w: 1.0 / (a + c * w * w), lo, hi, epsabs=0, epsrel=1e-13)[0]
    assert float(cf._inverse_quadratic_integral(a, c, lo, hi)) == pytest.approx(want, rel=1e-12)


def test_release_time_is_continuous_in_the_static_fraction():
    """A static fraction of 1e-310 releases as one of 0; one of 1 without rotor drag is finite."""
    p = dict(
        rated_speed=576.0,
        shoes=3.0,
        spring_force=400.0,
        engine_inertia=0.05,
        rotor_inertia=5.0,
        rotor_load_torque=50.0,
        rated_passive_torque=65.5,
        friction_coefficient=0.4,
        pressure_angle=0.68,
        shoe_mass=0.3,
        shoe_radius=0.07,
        drum_radius=0.09,
    )
    zero = cf.release_after_failure(**p, static_fraction=0.0)["release_time"]
    tiny = cf.release_after_failure(**p, static_fraction=1e-310)["release_time"]
    assert float(tiny) == pytest.approx(float(zero), rel=1e-12) and float(zero) > 1.0
    flat = cf.release_after_failure(**{**p, "rotor_load_torque": 0.0}, static_fraction=1.0)
    assert np.isfinite(flat["release_time"]) and int(flat["status"]) == 0


def test_failure_trace_of_a_release_at_once_starts_at_rated_speed():
    """Released at once (rated speed below engagement): the trace's first point is the rated speed
    of both sides, not NaN."""
    p = {**SEED, **DYN, "rated_speed": 10.0}
    tr = cf.engine_failure_trace(p, t_end=5.0, n=6)
    assert tr["release_time"] == 0.0
    assert tr["engine_speed"][0] == tr["rotor_speed"][0] == 10.0
    assert np.isfinite(tr["clutch_torque"]).all() and np.isfinite(tr["rotor_speed"]).all()


def test_without_any_drag_the_clutch_never_lets_go():
    """No rotor drag and no passive torque: release time inf and no release speed (it gave the
    speed it would release at), as the trace says."""
    p = {**SEED, **DYN, "rated_speed": 5500 * RPM, "rotor_load_torque": 0.0}
    p["rated_passive_torque"] = 0.0
    r = cf.release_after_failure(**p)
    assert np.isinf(r["release_time"]) and np.isnan(r["release_speed"])
    tr = cf.engine_failure_trace(p, t_end=1.0, n=5)
    assert np.isinf(tr["release_time"]) and np.isnan(tr["release_speed"])

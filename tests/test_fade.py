"""Issue 20 items 4 and 5: friction fade μ(T) with the friction face's temperature as a solver
state, and μ(slip) from a table — each against an analytic solution or an independent reference.

The face temperature state (clutchlab.engagement._fade): Duhamel's integral of the slip power
with the kernel 1/√s split into a smooth part (15 exponential modes, states) and a singular part
taken quasi-statically. References: the semi-infinite body's constant- and ramp-flux solutions,
and clutchlab.reference.rigid_fade (Picard iteration on the face temperature with the exact
kernel, solve_ivp DOP853 at rtol 1e-12)."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erf, erfc

from clutchlab import engagement, heat, reference
from clutchlab import status as st
from clutchlab.engagement import _fade as k
from clutchlab.engagement import _works

K_FACE = float(heat.face_temperature_rise(1.0, 0.1125, 0.075, 2))  # K per W s^0.5, seed 000 lining
SEED = dict(
    engine_speed=570.0,
    engine_inertia=np.inf,
    engine_torque=0.0,
    driven_inertia=0.021,
    load_torque=44.0,
    peak_capacity=200.0,
    ramp_time=0.15,
    t_end=0.5,
)
COMPLIANT = dict(compliant=True, damper_stiffness=4498.0, damping_ratio=0.05)


def test_kernel_modes_approximate_the_smooth_part_of_the_kernel():
    """Σ w_k e^{−λ_k s} = erf(√(λ_c s))/√s within 3.1e-4/√s on s ∈ [1e-7 s, 10 s]; weights ≥ 0; the
    quasi-static weight M0 = ∫ erfc(√(λ_c s))/√s ds = 2/√(π λ_c) (by quadrature, s = u²)."""
    s = np.geomspace(1e-7, k.SOE_TMAX, 20000)
    approx = np.exp(-np.outer(s, k.SOE_LAMBDA)) @ k.SOE_WEIGHT
    err = (approx - erf(np.sqrt(k.SOE_CUT * s)) / np.sqrt(s)) * np.sqrt(s)
    assert np.abs(err).max() < 3.1e-4
    assert np.all(k.SOE_WEIGHT > 0) and np.all(k.SOE_LAMBDA > 0)
    m0 = 2 * quad(lambda u: erfc(math.sqrt(k.SOE_CUT) * u), 0, np.inf)[0]
    assert m0 == pytest.approx(k.SOE_M0, rel=1e-10)
    # the stiffest mode is what bounds the step: DOPRI5's real stability interval is about 3.3
    assert 3.3 / k.SOE_LAMBDA.max() > 4e-4
    # the constants are the fit heat.kernel_modes makes
    lam, w = heat.kernel_modes(cut=k.SOE_CUT, span=k.SOE_TMAX)
    np.testing.assert_allclose(lam, k.SOE_LAMBDA, rtol=1e-12)
    np.testing.assert_allclose(w, k.SOE_WEIGHT, rtol=1e-8)


def _flux_run(ramp_time):
    """A held engine slipping on a driven side its static load (above the capacity) keeps parked:
    the slip power is C(t)·ω_e, constant (step clamp) or rising linearly (a ramp far longer than
    the window); fade negligible (β = 1e-9 /K: C changes by < 1e-6)."""
    times = np.linspace(0.0, 0.5, 501)
    r = engagement.simulate(
        **{**SEED, "load_torque": 1e3, "ramp_time": ramp_time},
        fade_coefficient=1e-9,
        face_temperature_factor=K_FACE,
        trace_times=times,
        rtol=1e-10,
        atol=1e-10,
    )
    return times, r["trace"]["face_temperature_rise"]


def test_face_temperature_state_under_a_constant_slip_power():
    """ΔT = K·2P√t (the semi-infinite body's constant-flux solution) within 3e-5 of itself from 5 ms on."""
    times, rise = _flux_run(0.0)
    exact = K_FACE * 2 * 200.0 * 570.0 * np.sqrt(times)
    m = times >= 5e-3
    np.testing.assert_allclose(rise[m], exact[m], rtol=3e-5)


def test_face_temperature_state_under_a_linearly_rising_slip_power():
    """P = b·t: ΔT = K·(4/3)·b·t^{3/2} plus the quasi-static part's lead K·M1·b (M1 = 2/(3√π λ_c^{3/2}):
    the singular part of the kernel taken at P(t) instead of the recent past; 1.5e-5 K here) within
    3e-5 of the rise from 5 ms on (the slow modes' fit error)."""
    times, rise = _flux_run(10.0)
    b = 200.0 / 10.0 * 570.0
    exact = K_FACE * 4 / 3 * b * times**1.5
    lead = K_FACE * 2 / (3 * math.sqrt(math.pi) * k.SOE_CUT**1.5) * b
    m = times >= 5e-3
    np.testing.assert_allclose(rise[m] - lead, exact[m], rtol=3e-5)
    assert lead < 1e-5 * exact[-1]


@pytest.mark.slow
@pytest.mark.parametrize("beta, onset", [(0.02, 0.0), (0.05, 10.0)])
def test_fade_against_the_exact_kernel_reference(beta, onset):
    """Rigid model, held engine, seed-000 design with fade: lock-up time and slip work within 1e-5
    of the Picard reference with the exact kernel; the peak face temperature from the solver's power
    history (exact kernel) within 1e-5, the face temperature state while slipping within 1e-4 of
    the peak. (Measured: 2.8e-6 / 6.0e-6 lock-up, 5e-7 slip work, 4e-5 state.)"""
    p = dict(SEED, fade_coefficient=beta, fade_onset=onset, face_temperature_factor=K_FACE)
    ref = reference.rigid_fade(p, samples=4001)
    times = np.linspace(0.0, 0.5, 2001)
    r = engagement.simulate(**p, rtol=1e-10, atol=1e-10, trace_times=times, power_history=True)
    assert r["status"] == 0
    assert r["lockup_time"] == pytest.approx(ref["lockup_time"], rel=1e-5)
    assert r["slip_work"] == pytest.approx(ref["slip_work"], rel=1e-5)
    assert K_FACE * r["flash_peak"] == pytest.approx(ref["peak_face_rise"], rel=1e-5)
    slipping = times <= ref["lockup_time"]
    err = np.abs(
        r["trace"]["face_temperature_rise"] - np.interp(times, ref["times"], ref["face_rise"])
    )
    assert err[slipping].max() < 1e-4 * ref["peak_face_rise"]
    # fade slows the engagement: later lock-up, more slip work than without
    r0 = engagement.simulate(**SEED, rtol=1e-10, atol=1e-10)
    assert r["lockup_time"] > r0["lockup_time"] * 1.1 and r["slip_work"] > r0["slip_work"]


@pytest.mark.parametrize("compliant", [False, True])
def test_negligible_fade_leaves_the_engagement_unchanged(compliant):
    """β = 1e-9 /K (the smallest plausible): the mechanical results equal the run without fade
    (which solves the compliant
    model's linear phases in closed form; with fade every slipping phase is integrated, 15 more
    states) to the tolerance; the state's peak face temperature equals the exact-kernel Duhamel
    integral of the solver's own power history within 1e-4."""
    ex = COMPLIANT if compliant else {}
    times = np.linspace(0.0, 0.5, 1001)  # (every trace time is a sample of the power history too)
    base = engagement.simulate(**SEED, **ex, rtol=1e-9, atol=1e-9, power_history=True)
    fade = engagement.simulate(
        **SEED,
        **ex,
        rtol=1e-9,
        atol=1e-9,
        power_history=True,
        fade_coefficient=1e-9,
        face_temperature_factor=K_FACE,
        trace_times=times,
    )
    for name in ("lockup_time", "slip_work", "peak_friction_torque"):
        assert fade[name] == pytest.approx(base[name], rel=1e-7), name
    assert fade["peak_jerk"] == pytest.approx(base["peak_jerk"], rel=1e-5)
    peak_state = np.nanmax(fade["trace"]["face_temperature_rise"])
    assert peak_state == pytest.approx(K_FACE * fade["flash_peak"], rel=1e-4)
    if compliant:
        assert base["n_linear"] > 0  # (the comparison is between two solvers)


@pytest.mark.parametrize("compliant", [False, True])
def test_fade_below_its_onset_is_left_out_and_the_rest_solved_with_it(compliant, monkeypatch):
    """Engine speeds 400-700 rad/s against an onset at the middle of their face temperature rises:
    a scenario whose rise stays below 0.99 of the onset without fade gets its fade-free results
    (the compliant model's linear phases in closed form: no step), equal to the fade solver's
    within 1e-9 (its μ is divided by 1 throughout; the flash peak within the history's 5e-4); the
    others are the fade solver's, bit for bit; with traces every scenario is solved with fade."""
    from clutchlab.engagement import _simulate

    ex = COMPLIANT if compliant else {}
    speed = np.linspace(400.0, 700.0, 8)
    kw = dict(**{**SEED, "engine_speed": speed}, **ex, rtol=1e-9, atol=1e-9, power_history=True)
    plain = engagement.simulate(**kw)
    rise = K_FACE * plain["flash_peak"]
    onset = float(np.median(rise))
    kw |= dict(fade_coefficient=0.05, fade_onset=onset, face_temperature_factor=K_FACE)
    short = engagement.simulate(**kw)
    with monkeypatch.context() as m:
        m.setattr(
            _simulate,
            "_batch_with_fade",
            lambda Q, batch, ph: _simulate.simulate_batch(Q, with_hist=ph, **batch),
        )
        full = engagement.simulate(**kw)
    cool = rise <= 0.99 * onset
    assert 0 < cool.sum() < cool.size
    for name in ("lockup_time", "slip_work", "peak_friction_torque", "peak_jerk"):
        np.testing.assert_allclose(short[name][cool], full[name][cool], rtol=1e-9, err_msg=name)
        np.testing.assert_array_equal(short[name][~cool], full[name][~cool], err_msg=name)
    np.testing.assert_allclose(short["flash_peak"][cool], full["flash_peak"][cool], rtol=5e-4)
    assert np.all(short["status"] == full["status"])
    hot = rise > onset
    assert np.all(short["lockup_time"][hot] > plain["lockup_time"][hot])  # (they fade)
    if compliant:
        assert np.all(short["n_steps"][cool] == 0) and np.all(full["n_steps"] > 0)
    traced = engagement.simulate(**kw, trace_times=[0.1])
    assert (
        np.all(traced["n_steps"] > 0)
        and np.isfinite(traced["trace"]["face_temperature_rise"]).all()
    )


@pytest.mark.parametrize("compliant", [False, True])
def test_the_bound_without_the_history_clears_only_cool_scenarios(compliant):
    """Without the slip-power history (the worn engagements) the face is first bounded by
    2·P_max·√t_L ≥ Duhamel's integral (P ≥ 0, zero after the last lock-up): 1.45-1.7 times the
    flash peak here. Onset at the median rise: some scenarios are cleared by the bound, some only
    by the history, the rest fade; every output but the flash peak is that of the run with the
    history, bit for bit."""
    from clutchlab.engagement import _simulate

    ex = COMPLIANT if compliant else {}
    d = {**SEED, "engine_speed": np.linspace(250.0, 700.0, 16)}
    d["peak_capacity"] = np.linspace(300.0, 120.0, 16)
    plain = engagement.simulate(**d, **ex, rtol=1e-9, atol=1e-9, power_history=True)
    bound = 2.0 * plain["peak_slip_power"] * np.sqrt(plain["lockup_time"])
    assert np.all(bound >= plain["flash_peak"])
    rise = K_FACE * plain["flash_peak"]
    onset = float(np.median(rise))
    by_bound, by_history = K_FACE * bound <= 0.99 * onset, rise <= 0.99 * onset
    assert 0 < by_bound.sum() < by_history.sum() < rise.size
    kw = dict(fade_coefficient=0.05, fade_onset=onset, face_temperature_factor=K_FACE)
    kw |= dict(rtol=1e-9, atol=1e-9, **ex)
    with_history = engagement.simulate(**d, **kw, power_history=True)
    without = engagement.simulate(**d, **kw)
    for name in without:
        if name not in ("flash_peak", "n_power_samples"):
            np.testing.assert_array_equal(without[name], with_history[name], err_msg=name)
    assert np.isnan(without["flash_peak"]).all()
    assert _simulate.FADE_MARGIN == 0.99  # (the margin the classes above are drawn with)


def test_fade_off_is_the_default_and_costs_nothing():
    """β = 0 gives exactly the results of a call without the fade arguments (the face temperature
    trace is NaN then)."""
    a = engagement.simulate(**SEED, **COMPLIANT, rtol=1e-7, atol=1e-9, trace_times=[0.1])
    b = engagement.simulate(
        **SEED,
        **COMPLIANT,
        rtol=1e-7,
        atol=1e-9,
        trace_times=[0.1],
        fade_coefficient=0.0,
        fade_onset=5.0,
        face_temperature_factor=K_FACE,
    )
    for name in ("lockup_time", "slip_work", "peak_jerk", "n_steps", "n_linear"):
        assert a[name] == b[name]
    assert np.isnan(a["trace"]["face_temperature_rise"]).all()


def test_fade_jerk_is_the_derivative_of_the_clutch_torque():
    """Rigid model, no load: the output jerk (chain rule through the fade factor, whose rate is
    solved for) equals the central difference of the traced clutch torque over J_v."""
    t0 = np.array([0.03, 0.06, 0.1, 0.14])
    h = 1e-6
    times = np.sort(np.concatenate([t0 - h, t0, t0 + h]))
    r = engagement.simulate(
        **{**SEED, "load_torque": 0.0},
        fade_coefficient=0.05,
        fade_onset=2.0,
        face_temperature_factor=K_FACE,
        trace_times=times,
        rtol=1e-12,
        atol=1e-12,
    )
    tq, jerk = r["trace"]["friction_torque"].reshape(-1, 3), r["trace"]["jerk"].reshape(-1, 3)[:, 1]
    fd = (tq[:, 2] - tq[:, 0]) / (2 * h) / SEED["driven_inertia"]
    np.testing.assert_allclose(jerk, fd, rtol=1e-6)
    assert np.all(
        r["trace"]["face_temperature_rise"].reshape(-1, 3)[:, 1] > 2.0
    )  # (fading at those times)


def test_fade_result_does_not_depend_on_the_tolerance():
    """Lock-up time and slip work with fade at rtol 1e-6 and 1e-9 agree within 1e-6; the compliant
    model's peak jerk within 1e-5."""
    kw = dict(**SEED, **COMPLIANT, fade_coefficient=0.03, face_temperature_factor=K_FACE)
    loose = engagement.simulate(**kw, rtol=1e-7, atol=1e-9)
    tight = engagement.simulate(**kw, rtol=1e-10, atol=1e-12)
    for name in ("lockup_time", "slip_work"):
        assert loose[name] == pytest.approx(tight[name], rel=1e-6), name
    assert loose["peak_jerk"] == pytest.approx(tight["peak_jerk"], rel=1e-5)


def test_fade_inputs_are_screened_per_scenario():
    """A negative β, fade without a face temperature factor, or fade beyond the kernel fit's 10 s
    window: status invalid_input and NaN for that scenario only."""
    beta = np.array([0.02, -0.01, 0.02, 0.02])
    factor = np.array([K_FACE, K_FACE, 0.0, K_FACE])
    t_end = np.array([0.5, 0.5, 0.5, 12.0])
    r = engagement.simulate(
        **{**SEED, "t_end": t_end},
        fade_coefficient=beta,
        face_temperature_factor=factor,
        rtol=1e-7,
        atol=1e-9,
    )
    assert list(r["status"]) == [0] + [st.CODE["invalid_input"]] * 3
    assert np.isfinite(r["lockup_time"][0]) and np.isnan(r["lockup_time"][1:]).all()
    alone = engagement.simulate(
        **SEED, fade_coefficient=0.02, face_temperature_factor=K_FACE, rtol=1e-7, atol=1e-9
    )
    assert r["lockup_time"][0] == alone["lockup_time"]


# ------------------------------------------------------------------------------------------------
# μ(slip) from a table (item 5)
# ------------------------------------------------------------------------------------------------

TABLE = ([0.0, 50.0, 150.0, 400.0, 700.0], [1.35, 1.2, 1.05, 0.97, 0.95])  # μ/μ_k over |Δω| [rad/s]


def test_friction_table_against_the_scipy_reference_compliant():
    """Compliant model with a tabulated μ(slip): lock-up time, slip work and peak jerk against
    per-mode solve_ivp (DOP853, rtol 1e-12) with np.interp of the same table."""
    p = dict(SEED, **{k_: v for k_, v in COMPLIANT.items() if k_ != "compliant"}, static_ratio=1.35)
    ref = reference.compliant(p | {"friction_table": TABLE})
    r = engagement.simulate(
        **SEED, **COMPLIANT, static_ratio=1.35, friction_table=TABLE, rtol=1e-9, atol=1e-11
    )
    assert r["status"] == 0 and ref["status"] == "ok"
    assert r["lockup_time"] == pytest.approx(ref["lockup_time"], rel=1e-7)
    assert r["slip_work"] == pytest.approx(ref["slip_work"], rel=1e-7)
    assert r["peak_jerk"] == pytest.approx(ref["peak_jerk"], rel=1e-5)
    # and the table matters: not the constant-μ result
    r0 = engagement.simulate(**SEED, **COMPLIANT, rtol=1e-9, atol=1e-11)
    assert abs(r["lockup_time"] / r0["lockup_time"] - 1) > 1e-2


def test_finely_tabulated_stribeck_law_gives_the_stribeck_result():
    """The Stribeck law tabulated at 4 001 slip speeds (linear interpolation error ≈ Δv²·f''/8 ≈ 1e-7)
    gives the Stribeck law's lock-up time and slip work within 1e-6."""
    vs, rs = 80.0, 1.3
    v = np.linspace(0.0, 800.0, 4001)
    table = (v, 1 + (rs - 1) * np.exp(-((v / vs) ** 2)))
    kw = dict(**SEED, static_ratio=rs, rtol=1e-10, atol=1e-10)
    a = engagement.simulate(**kw, stribeck_speed=vs)
    b = engagement.simulate(**kw, friction_table=table)
    for name in ("lockup_time", "slip_work", "peak_slip_power"):
        assert b[name] == pytest.approx(a[name], rel=1e-6), name


def test_a_flat_table_is_constant_mu():
    """A one-point table (μ/μ_k = 1) equals constant μ_k: the DOPRI5 path against the compliant
    model's closed-form linear phases."""
    a = engagement.simulate(**SEED, **COMPLIANT, rtol=1e-10, atol=1e-12)
    b = engagement.simulate(
        **SEED, **COMPLIANT, rtol=1e-10, atol=1e-12, friction_table=([0.0], [1.0])
    )
    assert a["n_linear"] > 0 and b["n_linear"] < a["n_linear"]
    for name in ("lockup_time", "slip_work"):
        assert b[name] == pytest.approx(a[name], rel=1e-8), name
    assert b["peak_jerk"] == pytest.approx(a["peak_jerk"], rel=1e-6)


@pytest.mark.parametrize(
    "table, match",
    [
        (([0.0, 10.0], [1.0]), "equal"),
        (([0.0, 10.0, 5.0], [1.0, 1.1, 1.2]), "increase"),
        (([-1.0, 10.0], [1.0, 1.1]), ">= 0"),
        (([0.0, 10.0], [1.0, 0.0]), "> 0"),
        (([0.0, np.nan], [1.0, 1.0]), "finite"),
        (([], []), "non-zero"),
        (([0.0, 10.0], [1.0, 1e300]), "implausible"),
        (([0.0, 1e300], [1.0, 1.1]), "implausible"),
    ],
)
def test_a_malformed_friction_table_is_refused(table, match):
    with pytest.raises(ValueError, match=match):
        engagement.simulate(**SEED, friction_table=table)


# ------------------------------------------------------------------------------------------------
# the engagement study with fade and a friction table
# ------------------------------------------------------------------------------------------------


def _study_tolerances():
    from clutchlab.studies.engagement import ACCURACY, tolerances

    rtol, atol = tolerances(ACCURACY)
    return dict(rtol=rtol, atol=atol)


def _study(extra=None, **params):
    from clutchlab import config

    section = {"design": "factorial", "options": {"driveline": "rigid"}, "parameters": params} | (
        extra or {}
    )
    return config.resolve({"studies": ["engagement"], "engagement": section})["engagement"]


def test_study_with_fade_runs_the_event_solver_and_fades():
    """fade_coefficient as a factor [0, 0.05/K] with the onset at the ambient temperature: the faded
    design locks later with more slip work and heat; the unfaded one keeps the closed form; heat
    into the parts still equals the slip work."""
    from clutchlab import pipeline

    ds = pipeline.run_study(
        _study(fade_coefficient={"values": [0.0, 0.05]}, fade_onset_temperature="313.15 K")
    )
    off, on = ds.sel(fade_coefficient=0.0), ds.sel(fade_coefficient=0.05)
    assert int(off["model"]) == 0 and int(on["model"]) == 1  # closed form, rigid event solver
    # the faded clutch locks new (0.37 s), but worn by the 1.5 mm allowance (16 % less clamp load)
    # it fades further and no longer locks within end_time: its first engagement's numbers stand
    assert int(off["status"]) == st.CODE["ok"]
    assert int(on["status"]) == st.CODE["worn_not_locked"]
    assert float(on["lockup_time"]) > 1.05 * float(off["lockup_time"])
    assert float(on["slip_work"]) > float(off["slip_work"])
    heat_sum = sum(float(on[f"heat_{p}"]) for p in ("flywheel", "pressure_plate", "driven_plate"))
    assert heat_sum == pytest.approx(float(on["slip_work"]), rel=1e-12)
    assert np.isfinite(float(on["peak_surface_temperature"]))
    # the study's number is simulate's with the study's face temperature factor
    ref = engagement.simulate(
        **{**SEED, "peak_capacity": float(on["peak_capacity"])},
        fade_coefficient=0.05,
        face_temperature_factor=K_FACE,
        **_study_tolerances(),
    )
    assert float(on["lockup_time"]) == pytest.approx(float(ref["lockup_time"]), rel=1e-12)


def test_study_reads_a_measured_friction_table():
    """friction_table in the config (μ over slip speed, units converted): the study's engagement is
    simulate's with the table divided by the fixed friction coefficient."""
    from clutchlab import pipeline

    table = {
        "slip_speed": ["0 rpm", "500 rpm", "3000 rpm", "6000 rpm"],
        "friction_coefficient": [0.5, 0.45, 0.4, 0.39],
    }
    sec = _study({"friction_table": table}, ramp_time={"values": [0.1, 0.2]})
    assert sec["options"]["friction_table"]["slip_speed"][1] == pytest.approx(
        500 * 2 * math.pi / 60
    )
    ds = pipeline.run_study(sec)
    assert (ds["model"] == 1).all() and (ds["status"] == 0).all()
    mu = 0.4  # the default friction coefficient
    x = np.array(sec["options"]["friction_table"]["slip_speed"])
    for tr in (0.1, 0.2):
        one = ds.sel(ramp_time=tr)
        ref = engagement.simulate(
            **{**SEED, "peak_capacity": float(one["peak_capacity"]), "ramp_time": tr},
            friction_table=(x, np.array(table["friction_coefficient"]) / mu),
            **_study_tolerances(),
        )
        assert float(one["lockup_time"]) == pytest.approx(float(ref["lockup_time"]), rel=1e-12)


# ------------------------------------------------------------------------------------------------
# the closed form's face temperature (its exact slip power, sampled on its pieces)
# ------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("profile", ["ramp", "cubic"])
def test_closed_form_flash_peak_converges_at_second_order(profile, monkeypatch):
    """flash_peak of the closed form on 40 random designs (held and free engine, step to 0.3 s
    ramps): samples per piece 24 → 48 → 96 divide the error by about 4 (second order), 96 within
    1.5e-4 of 1 300 per piece; the event solver's own history agrees within 5e-4 (measured 2.1e-4;
    1.3e-3 when it sampled every ramp time / 48 only: 21 samples before an early lock-up)."""
    rng = np.random.default_rng(2)
    n = 40
    kw = dict(
        engine_speed=rng.uniform(300, 600, n),
        engine_inertia=np.where(rng.random(n) < 0.5, np.inf, rng.uniform(0.05, 0.5, n)),
        engine_torque=rng.uniform(0, 150, n),
        driven_inertia=rng.uniform(0.01, 0.05, n),
        load_torque=rng.uniform(0, 80, n),
        peak_capacity=rng.uniform(150, 300, n),
        ramp_time=np.concatenate([[0.0], rng.uniform(0.0, 0.3, n - 1)]),
        t_end=0.5,
        profile=profile,
    )
    peaks = {}
    for m in (24, 48, 96, 1300):
        monkeypatch.setattr(_works, "CLOSED_FORM_POWER_SAMPLES", m)
        peaks[m] = engagement.closed_form(**kw, power_history=True)["flash_peak"]
    assert np.isfinite(peaks[1300]).all()
    err = {m: np.abs(peaks[m] / peaks[1300] - 1).max() for m in (24, 48, 96)}
    assert 3.0 < err[24] / err[48] < 5.0 and 3.0 < err[48] / err[96] < 5.0, err
    assert err[96] < 1.5e-4
    events = engagement.simulate(**kw, power_history=True, rtol=1e-9, atol=1e-9)["flash_peak"]
    assert np.abs(events / peaks[1300] - 1).max() < 5e-4


@pytest.mark.slow
@pytest.mark.parametrize("profile", ["ramp", "cubic"])
def test_compliant_fade_against_dop853_at_the_study_accuracy(profile):
    """Compliant model with fade (β 0.005-0.01 /K from the ambient temperature), held engine, on
    million.yaml's engagement ranges: the exponential collocation (its heat modes exact over each
    step) at accuracy 1e-6 against the same face-temperature model integrated by scipy DOP853 at
    rtol 1e-13 with the mechanics (clutchlab.reference.compliant): lock-up time, slip work and
    peak jerk within 1e-6, in at most 60 steps (DOPRI5 took about 900, bound by the stiffest mode)."""
    from clutchlab.studies.engagement import tolerances

    rng = np.random.default_rng({"ramp": 51, "cubic": 52}[profile])
    n = 3
    d = dict(
        SEED,
        **COMPLIANT,
        driven_inertia=rng.uniform(0.021, 0.05, n),
        load_torque=rng.uniform(44.0, 80.0, n),
        peak_capacity=rng.uniform(150.0, 290.0, n),
        ramp_time=rng.uniform(0.05, 0.3, n),
        t_end=0.6,
        fade_coefficient=rng.uniform(0.005, 0.01, n),
        face_temperature_factor=K_FACE,
    )
    rtol, atol = tolerances(1e-6)
    r = engagement.simulate(**d, profile=profile, rtol=rtol, atol=atol)
    assert np.all(r["n_steps"] < 60)
    for i in range(n):
        p = {k_: (v[i] if np.ndim(v) else v) for k_, v in d.items() if k_ != "compliant"}
        ref = reference.compliant(p, rtol=1e-13, atol=1e-13, profile=profile)
        assert (r["status"][i] == st.CODE["ok"]) == (ref["status"] == "ok")
        for k_ in ("lockup_time", "slip_work", "peak_jerk"):
            if ref["status"] == "ok" or k_ != "lockup_time":
                assert r[k_][i] == pytest.approx(ref[k_], rel=1e-6), (k_, i)

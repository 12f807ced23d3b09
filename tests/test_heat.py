"""Issue 20: clutchlab.heat — the flash temperature against the semi-infinite body's analytic
solutions, the Duhamel integral's order, the heat partition, lumped cooling and the sequence of
engagements against their closed forms."""

import math

import numpy as np
import pytest

from clutchlab import heat
from clutchlab import status as st

E_IRON = float(heat.effusivity(**heat.MATERIALS["cast_iron"]))


@pytest.mark.parametrize("n", [2, 7, 151])
def test_duhamel_equals_the_constant_flux_solution(n):
    """ΔT = 2q√(t/(πρck)) at every sample, to 1e-6 relative (acceptance; it is exact to rounding)."""
    t = np.linspace(0.0, 0.15, n)
    q = np.full(n, 2.3e6)
    num = heat.duhamel_surface_temperature(t, q, E_IRON)
    ana = 2 * 2.3e6 * np.sqrt(t / (math.pi * 7200 * 500 * 50))
    assert num[0] == 0
    np.testing.assert_allclose(num[1:], ana[1:], rtol=1e-6)
    np.testing.assert_allclose(heat.surface_temperature_constant(2.3e6, t, E_IRON), ana, rtol=1e-14)


def test_duhamel_equals_the_ramp_flux_solution_on_uneven_samples():
    """q = b·t: ΔT = (4/3)·b·t^{3/2}/√(πρck), on an uneven grid (as a solver's steps), to 1e-6."""
    rng = np.random.default_rng(3)
    t = np.concatenate([[0.0], np.sort(rng.uniform(0, 0.2, 200))])
    b = 3.0e7
    num = heat.duhamel_surface_temperature(t, b * t, E_IRON)
    ana = 4 / 3 * b * t**1.5 / math.sqrt(math.pi * 7200 * 500 * 50)
    np.testing.assert_allclose(num[1:], ana[1:], rtol=1e-6)
    np.testing.assert_allclose(heat.surface_temperature_ramp(b, t, E_IRON), ana, rtol=1e-14)


def test_duhamel_converges_at_second_order_for_a_smooth_flux():
    """q = c·t²: exact ΔT = (16/15)·c·t^{5/2}/(e√π); halving the spacing divides the error by 4."""
    c, T = 1e8, 0.15
    exact = 16 / 15 * c * T**2.5 / (E_IRON * math.sqrt(math.pi))
    errors = []
    for n in (21, 41, 81, 161, 321):
        t = np.linspace(0.0, T, n)
        errors.append(abs(heat.duhamel_surface_temperature(t, c * t**2, E_IRON)[-1] / exact - 1))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all((orders > 1.9) & (orders < 2.1)), orders
    assert errors[-1] < 1e-5


def test_duhamel_is_batched_over_scenarios():
    t = np.linspace(0.0, 0.1, 51)
    q = np.stack([np.full(51, 1e6), 2e7 * t])
    e = np.array([E_IRON, 2 * E_IRON])
    out = heat.duhamel_surface_temperature(t, q, e)
    np.testing.assert_allclose(out[0], heat.duhamel_surface_temperature(t, q[0], e[0]), rtol=1e-15)
    np.testing.assert_allclose(out[1], heat.duhamel_surface_temperature(t, q[1], e[1]), rtol=1e-15)


def test_heat_shares_sum_to_one_and_follow_the_effusivities():
    rng = np.random.default_rng(0)
    e = rng.uniform(100, 30000, (3, 1000))
    shares = heat.face_shares(*e)
    np.testing.assert_allclose(sum(shares), 1.0, rtol=1e-15)
    assert heat.face_shares(1.0, 1.0, 1.0) == (0.25, 0.25, 0.5)
    # cast iron against an organic lining: the metal takes about 93 % at each face
    fw, pp, dp = heat.face_shares(
        E_IRON, E_IRON, heat.effusivity(**heat.MATERIALS["organic_lining"])
    )
    assert fw == pp and 0.46 < fw < 0.47 and abs(dp - 0.0694) < 1e-3


def test_specific_loading_of_the_seed_lining_and_bad_scenarios():
    """Seed 000: W ≈ 5.8 kJ on two faces of a 225/150 mm lining (A = 2·π(0.1125² − 0.075²) =
    0.04418 m²): q_A = 131.3 kJ/m². A bad scenario gets invalid_input (swapped radii:
    invalid_geometry, as the diaphragm spring's) and NaN, the others not."""
    out = heat.specific_loading(
        np.array([5800.0, np.nan, 5800.0, 5800.0]), 1.0e5, np.array([0.1125] * 3 + [0.07]), 0.075, 2
    )
    np.testing.assert_allclose(
        out["friction_area"][0], 2 * math.pi * (0.1125**2 - 0.075**2), rtol=1e-14
    )
    np.testing.assert_allclose(out["specific_friction_work"][[0, 2]], 131285.144, rtol=1e-8)
    np.testing.assert_allclose(
        out["peak_specific_friction_power"][0], 1e5 / out["friction_area"][0], rtol=1e-14
    )
    assert list(out["status"]) == [0, 14, 0, 1]
    assert np.isnan(out["specific_friction_work"][[1, 3]]).all()


def test_lumped_cooling_matches_its_exponential_solution():
    """Newton cooling m c dT/dt = −h A (T − T_amb), integrated tightly by scipy, against the factor
    exp(−t/τ) the sequence uses."""
    from scipy.integrate import solve_ivp

    tau, dt, t0 = 412.0, 90.0, 37.0
    sol = solve_ivp(lambda t, y: -y / tau, (0, dt), [t0], rtol=1e-12, atol=1e-14)
    seq = heat.sequence_temperatures(t0, dt, tau, 2)  # [ΔT, ΔT·r + ΔT]
    np.testing.assert_allclose(seq[1] - t0, sol.y[0, -1], rtol=1e-9)


def test_sequence_reaches_the_periodic_state_of_the_geometric_sum():
    rise, interval, tau = np.array([4.0, 11.5]), np.array([30.0, 120.0]), np.array([300.0, 900.0])
    seq = heat.sequence_temperatures(rise[:, None], interval[:, None], tau[:, None], 400)[:, 0]
    n = np.arange(1, 401)
    r = np.exp(-interval / tau)
    np.testing.assert_allclose(
        seq, rise[:, None] * (1 - r[:, None] ** n) / (1 - r[:, None]), rtol=1e-12
    )
    np.testing.assert_allclose(
        seq[:, -1], heat.periodic_temperature(rise, interval, tau), rtol=1e-9
    )


def test_engagements_to_limit_agrees_with_the_sequence():
    rise, interval, tau = 10.0, 60.0, 600.0
    seq = heat.sequence_temperatures(rise, interval, tau, 400)
    for margin in (5.0, 10.0, 10.01, 50.0, 100.0, 104.9):
        n = int(heat.engagements_to_limit(rise, interval, tau, margin))
        assert seq[n - 1] >= margin and (n == 1 or seq[n - 2] < margin), (margin, n)
    assert (
        heat.engagements_to_limit(rise, interval, tau, 106.0) == np.inf
    )  # periodic state 105.08 K
    assert np.isnan(heat.engagements_to_limit(np.nan, interval, tau, 50.0))


def _default_engagement():
    import yaml

    from clutchlab import config, pipeline
    from conftest import ROOT, without_robust

    cfg = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    section = without_robust(cfg["engagement"])  # the grid at the nominal friction (seed design)
    return pipeline.run_study(
        config.resolve({"studies": ["engagement"], "engagement": section})["engagement"]
    )


def test_heat_into_the_parts_equals_the_slip_work_in_the_default_study():
    """Acceptance: in every scenario of the default engagement study the heat into flywheel,
    pressure plate and driven plate sums to the slip work within 1e-9 relative; the per-area
    loading is the slip work and peak power over the friction area of both faces."""
    ds = _default_engagement()
    # the first engagement's heat: every scenario whose first engagement is ok (worn_not_locked:
    # the clutch worn by the allowance no longer locks, its first engagement's numbers stand)
    ok = ds["status"].isin([0, st.CODE["worn_not_locked"]])
    assert int(ok.sum()) > 100
    total = ds["heat_flywheel"] + ds["heat_pressure_plate"] + ds["heat_driven_plate"]
    assert float(abs(total / ds["slip_work"] - 1).where(ok).max()) < 1e-9
    area = 2 * math.pi * (0.1125**2 - 0.075**2)
    np.testing.assert_allclose(
        ds["specific_friction_work"].where(ok), ds["slip_work"].where(ok) / area, rtol=1e-12
    )
    np.testing.assert_allclose(
        ds["peak_specific_friction_power"].where(ok),
        ds["peak_slip_power"].where(ok) / area,
        rtol=1e-12,
    )
    # the pressure plate (2.5 kg against the flywheel's 10.3 kg, the same share) is the hottest part
    assert set(np.unique(ds["hottest_part"].values[ok.values])) == {1}
    rise = ds["heat_pressure_plate"] / (2.5 * heat.MATERIALS["cast_iron"]["specific_heat"])
    np.testing.assert_allclose(ds["bulk_temperature_rise"].where(ok), rise.where(ok), rtol=1e-12)
    seed = ds.sel(
        sheet_thickness=2.334e-3,
        friction_coefficient=0.4,
        ramp_time=0.15,
        driven_inertia=0.021,
        load_torque=44.0,
    )
    assert float(seed["peak_surface_temperature"]) - 273.15 == pytest.approx(
        68.45, abs=0.01
    )  # docs/engagement.md
    temp = ds["peak_surface_temperature"].where(ok)
    assert float(temp.min()) > 313.15 and float(temp.max()) < 313.15 + 100
    for name in (
        "specific_friction_work",
        "bulk_temperature_rise",
        "heat_flywheel",
        "peak_surface_temperature",
    ):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]


def test_seed_design_heat_numbers_and_their_trace_resolution():
    """The seed design's numbers quoted in docs/engagement.md (default study options: compliant
    driveline, corrected capacity, ramp 0.15 s): slip work 6146 J, q_A = 139.1 kJ/m², peak slip
    power 56.0 kW, pressure plate bulk 40 -> 42.29 °C, friction-face peak 68.45 °C; the face peak
    changes by < 0.01 K from 401 to 3201 trace points (Duhamel's second order)."""
    from clutchlab.studies import engagement as es

    opts = {k: v[0] for k, v in es.OPTIONS.items()} | {"accuracy": 1e-6}
    tr = es.seed_traces({}, opts)
    work = float(tr["trace_slip_work"][-1])
    assert abs(work - 6146.1) < 0.5
    assert abs(work / (2 * math.pi * (0.1125**2 - 0.075**2)) - 139.12e3) < 50
    assert abs(float(tr["trace_slip_power"].max()) - 56.0e3) < 100
    assert abs(float(tr["trace_bulk_temperature"][-1]) - 273.15 - 42.288) < 1e-3
    peak = float(tr["trace_peak_surface_temperature"]) - 273.15
    assert abs(peak - 68.45) < 0.01
    old = es.TRACE_POINTS
    try:
        es.TRACE_POINTS = 3201
        fine = float(es.seed_traces({}, opts)["trace_peak_surface_temperature"]) - 273.15
    finally:
        es.TRACE_POINTS = old
    assert abs(fine - peak) < 0.01
    seq = tr["trace_sequence_temperature"].values - 273.15
    assert seq[0] == pytest.approx(42.288, abs=1e-3) and np.all(np.diff(seq) > 0) and seq[-1] < 53.1


def test_duhamel_peak_of_the_kernel_coarse_to_fine_equals_every_sample():
    """The event solver's peak search (every stride-th sample, then around the best) finds the
    same maximum as evaluating every sample (each evaluation equal to duhamel_at within 1e-13), on
    slip power histories with one and with two bursts; its integral at each sample equals
    heat.duhamel_surface_temperature's (the same exact segment integrals), and the peak between
    samples lies within 1 % above the best sample."""
    from clutchlab.engagement import _power as k

    rng = np.random.default_rng(5)
    for case in range(40):
        n = int(rng.integers(20, 700))
        t = np.cumsum(rng.uniform(0.2e-3, 2e-3, n))
        t -= t[0]
        burst = (
            np.sin(np.pi * t / t[-1]) ** 2
            if case % 2
            else np.sin(2 * np.pi * t / t[-1]) ** 2 * (1 + 0.3 * (t > t[-1] / 2))
        )
        p = 5e4 * burst * rng.uniform(0.9, 1.1)
        hist = np.stack([t, p, np.zeros(n)])  # (row 2: scratch)
        full = k.duhamel_peak(hist, n, 1)
        fast = k.duhamel_peak(hist, n, max(1, int(math.sqrt(n / 2))))
        assert fast == pytest.approx(full, rel=1e-12), case
        # the peak search's evaluation (over the kinks of P, their coefficients in row 2, summed in
        # any order) equals the segment by segment one to round-off
        kinks = [k._duhamel_kinks(hist, j) for j in range(1, n)]
        np.testing.assert_allclose(kinks, [k.duhamel_at(hist, j) for j in range(1, n)], rtol=1e-13)
        ref = heat.duhamel_surface_temperature(t, p, 1.0) * math.sqrt(math.pi)
        np.testing.assert_allclose([k.duhamel_at(hist, j) for j in range(n)], ref, rtol=1e-10)
        # the peak between samples (vertex of the parabola through the best sample and its neighbours)
        assert (
            ref.max() <= full <= ref.max() * (1 + 1e-2)
        )  # (20 samples of a burst: a coarse history)


@pytest.mark.parametrize(
    "case", ["ramp", "cubic", "quintic", "stribeck", "free_engine", "rigid_stribeck", "closed_form"]
)
def test_study_peak_surface_temperature_against_a_dense_trace(case):
    """peak_surface_temperature comes from the solver's own slip power history (sampled every ramp
    time / 48 and at least 64 times a slip while slipping, exact Duhamel segments; the closed form:
    its exact slip power at 96
    points a piece); the reference is Duhamel's integral of the same model's trace at 3 201 points:
    the rise above ambient within 5e-4 relative."""
    from clutchlab.studies import engagement as es

    inputs = {"ramp_time": 0.12}
    opts = {k_: v[0] for k_, v in es.OPTIONS.items()} | {"accuracy": 1e-6}
    if case in ("cubic", "quintic"):
        opts["profile"] = case
    if case in ("stribeck", "rigid_stribeck"):
        inputs.update(stribeck_speed=40.0, static_ratio=1.25)
    if case in ("rigid_stribeck", "closed_form"):
        opts["driveline"] = "rigid"
    if case == "free_engine":
        inputs.update(engine_inertia=0.3, engine_torque=150.0)
    from clutchlab.studies import seed_design

    ds = es.compute(
        {k_: np.atleast_1d(v) for k_, v in seed_design(es.PARAMETERS, inputs).items()}, opts
    )
    assert int(ds["status"][0]) == 0
    assert (int(ds["model"][0]) == es.MODEL["closed_form"]) == (case == "closed_form")
    old = es.TRACE_POINTS
    try:
        es.TRACE_POINTS = 3201
        tr = es.seed_traces(inputs, opts)
    finally:
        es.TRACE_POINTS = old
    ambient = 313.15
    got = float(ds["peak_surface_temperature"][0]) - ambient
    ref = float(tr["trace_peak_surface_temperature"]) - ambient
    assert got == pytest.approx(ref, rel=5e-4), (got, ref)
    assert 5 < got < 200


@pytest.mark.parametrize("profile", ["ramp", "cubic"])
def test_flash_peak_of_random_compliant_designs_against_dense_breakpoints(profile):
    """The study's default model (compliant driveline, linear phases) on 60 random designs, early
    and late lock-ups: flash_peak from its own history against the same model's history with 2 000
    breakpoints up to lock-up (converged: 3 800 breakpoints change it by 3e-7) within 6e-4
    (measured 2.3e-4 ramp, 4.0e-4 cubic; 5.1e-3 when a slip that ended early in a long ramp had
    ~18 samples)."""
    from clutchlab import engagement

    rng = np.random.default_rng(5)
    n = 60
    kw = dict(
        engine_speed=rng.uniform(300, 600, n),
        engine_inertia=np.inf,
        engine_torque=0.0,
        driven_inertia=rng.uniform(0.01, 0.05, n),
        load_torque=rng.uniform(0, 80, n),
        peak_capacity=rng.uniform(150, 600, n),
        ramp_time=rng.uniform(0.02, 0.6, n),
        t_end=1.0,
        compliant=True,
        hub_fraction=0.5,
        damper_stiffness=rng.uniform(2e3, 2e4, n),
        damping_ratio=rng.uniform(0.02, 0.2, n),
        rtol=1e-7,
        atol=1e-9,
        profile=profile,
    )
    got = engagement.simulate(**kw, power_history=True)
    lock = got["lockup_time"]
    assert (
        np.isfinite(lock).all() and (lock / kw["ramp_time"] < 0.5).sum() >= 3
    )  # early lock-ups among them
    ref = np.array(
        [
            engagement.simulate(
                **{k: (v[i] if np.ndim(v) else v) for k, v in kw.items()},
                power_history=True,
                trace_times=np.linspace(0.0, 1.02 * lock[i], 2000)[1:],
            )["flash_peak"]
            for i in range(n)
        ]
    )
    assert np.abs(got["flash_peak"] / ref - 1).max() < 6e-4


@pytest.mark.parametrize("faces", [2, 4, 6, 8])
def test_heat_of_a_stack_of_n_faces(faces):
    """A dry clutch of n faces (n/2 driven plates lined on both sides, n/2 − 1 intermediate plates):
    every face takes W/n, its metal γ of that (γ = e_m/(e_m + e_lining)), so the flywheel and the
    pressure plate take γW/n, each intermediate plate 2γW/n and each driven plate 2(1 − γ)W/n; the
    parts' heats sum to W (to rounding); two faces give face_shares' single-plate partition
    exactly. The hottest part: the pressure plate with two faces, an intermediate plate (both its
    faces heated, the pressure plate's mass) with more."""
    e_iron, _, e_lining = heat.part_effusivities()
    g = e_iron / (e_iron + e_lining)
    w = np.array([1000.0, 6146.0])
    out = heat.engagement_heat(w, 5.6e4 * np.ones(2), 0.1125, 0.075, faces)
    assert np.all(out["status"] == 0)
    np.testing.assert_allclose(out["heat_flywheel"], g * w / faces, rtol=1e-15)
    np.testing.assert_allclose(out["heat_pressure_plate"], g * w / faces, rtol=1e-15)
    np.testing.assert_allclose(out["heat_driven_plate"], 2 * (1 - g) * w / faces, rtol=1e-15)
    np.testing.assert_allclose(
        out["heat_intermediate_plate"], (2 * g * w / faces) if faces > 2 else 0.0, rtol=1e-15
    )
    total = (
        out["heat_flywheel"]
        + out["heat_pressure_plate"]
        + (faces / 2 - 1) * out["heat_intermediate_plate"]
        + faces / 2 * out["heat_driven_plate"]
    )
    np.testing.assert_allclose(total, w, rtol=1e-14)
    area = faces * math.pi * (0.1125**2 - 0.075**2)
    np.testing.assert_allclose(out["specific_friction_work"], w / area, rtol=1e-15)
    hottest = "pressure_plate" if faces == 2 else "intermediate_plate"
    assert {heat.PARTS[k] for k in out["hottest_part"]} == {hottest}
    if faces == 2:
        fw, pp, dp = heat.face_shares(e_iron, e_iron, e_lining)
        np.testing.assert_array_equal(out["heat_flywheel"], fw * w)
        np.testing.assert_array_equal(out["heat_driven_plate"], dp * w)


def test_an_odd_face_count_is_no_clutch_stack():
    """An odd count of friction faces has no stack of double-lined driven plates: status
    invalid_input and NaN heat (in the engagement study: status invalid_input, never NaN with ok;
    its config refuses it, tests/malformed/friction_faces_odd_engagement.yaml)."""
    out = heat.engagement_heat(np.full(3, 6146.0), np.full(3, 5.6e4), 0.1125, 0.075, [2, 3, 4])
    np.testing.assert_array_equal(out["status"], [0, 14, 0])
    assert np.isnan(out["heat_flywheel"][1]) and np.isfinite(out["heat_flywheel"][[0, 2]]).all()
    from clutchlab.studies import engagement as es

    inputs = {q.name: q.default for q in es.PARAMETERS}
    ds = es.compute({**inputs, "friction_faces": np.array([2.0, 3.0, 4.0])})
    np.testing.assert_array_equal(ds["status"].values, [0, 14, 0])
    for name in es.HEAT:
        if ds[name].dtype.kind == "f":
            assert np.isfinite(ds[name].values[[0, 2]]).all() or name == "engagements_to_limit"


def test_a_four_face_engagement_study_has_its_heat():
    """Issue 30 item 9: friction_faces: 4 was accepted and gave NaN heat with status ok. A
    twin-plate clutch (four faces) of the seed spring: double the capacity, so an earlier lock-up
    and less slip work; every heat output finite with status ok, the parts' heats summing to the
    slip work, and the friction-face peak from the same flux per face (P/n on A/n)."""
    from clutchlab import config, pipeline

    sec = config.resolve(
        {
            "studies": ["engagement"],
            "engagement": {
                "design": "factorial",
                "parameters": {
                    "friction_faces": {"values": [2, 4]},
                    "ramp_time": {"values": ["0.1 s", "0.3 s"]},
                },
            },
        }
    )["engagement"]
    ds = pipeline.run_study(sec)
    assert (ds["status"] == 0).all()
    for name in (*heat.PARTS, "bulk_temperature_rise", "peak_surface_temperature"):
        var = f"heat_{name}" if name in heat.PARTS else name
        assert np.isfinite(ds[var].values).all(), var
    two, four = ds.sel(friction_faces=2.0), ds.sel(friction_faces=4.0)
    np.testing.assert_allclose(four["peak_capacity"], 2 * two["peak_capacity"], rtol=1e-12)
    assert (four["slip_work"] < two["slip_work"]).all()
    total = (
        four["heat_flywheel"]
        + four["heat_pressure_plate"]
        + four["heat_intermediate_plate"]
        + 2 * four["heat_driven_plate"]
    )
    np.testing.assert_allclose(total, four["slip_work"], rtol=1e-13)
    assert list(np.unique(four["hottest_part"])) == [heat.PARTS.index("intermediate_plate")]


# ------------------------------------------------------------------------------------------------
# the friction face's temperature modes over a step, exactly (clutchlab.engagement._heat_modes)
# ------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("lam", [0.01, 0.87, 30.9, 449.9, 2683.0, 6551.8])
@pytest.mark.parametrize("h", [1e-5, 2e-3, 0.04, 0.6])
def test_a_mode_over_a_step_equals_its_closed_form(lam, h):
    """z' = a + b·τ − λ·z, z(0) = z₀ (a constant plus a linearly rising slip power):
    z = z₀e^(−λτ) + a(1 − e^(−λτ))/λ + b(τ/λ − (1 − e^(−λτ))/λ²), at four points of the step,
    for modes solved as a series (λh/2 ≤ 4) and by their particular solution (above): 1e-11
    relative (measured ≤ 3e-13)."""
    from clutchlab.engagement import _heat_modes as hm

    a, b, z0 = 3.0e4, 2.0e5, 7.0
    pc = np.array([a + b * h / 2, b * h / 2])  # the power in v = 2τ/h − 1
    tmp = np.zeros(hm.SERIES_MAX)
    for v in (-1.0, -0.3, 0.4, 1.0):
        tau = h * (1 + v) / 2
        em1 = math.expm1(-lam * tau)
        exact = z0 * (1 + em1) - a * em1 / lam + b * (tau / lam + em1 / lam**2)
        assert hm.mode_at(lam, z0, pc, 2, h, v, tmp) == pytest.approx(exact, rel=1e-11, abs=1e-300)


def test_the_modes_summed_at_the_nodes_equal_each_mode():
    """weighted_at_nodes (the modes' series and particular solutions summed before evaluation)
    equals Σ w_k·z_k of the modes one by one at every node, for a cubic slip power and steps of
    0.1 ms, 10 ms and 40 ms (every mode in either regime): 1e-13."""
    from clutchlab.engagement import _colloc as sp
    from clutchlab.engagement import _fade as k
    from clutchlab.engagement import _heat_modes as hm

    lam, w = k.SOE_LAMBDA, k.SOE_WEIGHT
    z0 = np.random.default_rng(1).uniform(0, 5, lam.size)
    pc = np.zeros(sp.NN)
    pc[:4] = [5e4, 2e3, -3e3, 500]
    enode = np.zeros((lam.size, sp.NN))
    out, comb, tmp = np.zeros(sp.NN), np.zeros(hm.SERIES_MAX), np.zeros(hm.SERIES_MAX)
    for h in (1e-4, 0.01, 0.04):
        hm.node_decay(lam, h, sp.NODES, enode)
        hm.weighted_at_nodes(lam, w, z0, pc, sp.NN, h, sp.NODES, enode, out, comb, tmp)
        one = [
            sum(w[j] * hm.mode_at(lam[j], z0[j], pc, sp.NN, h, v, tmp) for j in range(lam.size))
            for v in sp.NODES
        ]
        np.testing.assert_allclose(out, one, rtol=1e-13)


def test_the_step_grid_maps_equal_the_modes_solved_mode_by_mode():
    """On the collocation's step grid (fade) the face temperature's modes come from per-step maps
    (level_map) of the slip power's coefficients: the weighted sum at the nodes and every mode at
    the step's end equal weighted_at_nodes and advance for the same power and start values (1e-12;
    measured 5e-13), and the closed form of a linearly rising power (2e-12; measured 6e-13), for
    steps of 0.1 ms, 10 ms and 40 ms rounded down to the grid (every mode in either regime). The
    grid: steps at most 9 % below the asked one, found again by grid_level; others off it (-1)."""
    from clutchlab.engagement import _colloc as sp
    from clutchlab.engagement import _fade as k
    from clutchlab.engagement import _heat_modes as hm

    lam, w, nn, nz = k.SOE_LAMBDA, k.SOE_WEIGHT, sp.NN, k.SOE_LAMBDA.size
    rng = np.random.default_rng(3)
    z0 = rng.uniform(0, 5, nz)
    p = 5e4 * (1 + np.sin(3 * sp.NODES)) + rng.uniform(0, 1e3, nn)
    pc = sp.VINV @ p
    zero = np.zeros(nz)
    enode = np.zeros((nz, sp.NN))
    out, comb, tmp = np.zeros(nn), np.zeros(sp.LSER), np.zeros(sp.LSER)
    for asked in (1e-4, 0.01, 0.04):
        h = hm.grid_step(asked)
        assert asked * 2 ** (-1 / hm.LEVELS_PER_OCTAVE) < h <= asked
        assert hm.grid_level(h) >= 0 and hm.grid_level(asked * (1 + 1e-9)) == -1
        fmap, fdec, fend = np.zeros((nn, nn)), np.zeros((nz, nn)), np.zeros((nz, nn + 1))
        scratch = (np.zeros((nz, sp.LSER)), np.zeros(sp.LSER), np.zeros(sp.LSER), zero)
        hm.level_map(lam, w, h, sp.NODES, *scratch, comb, tmp, fmap, fdec, fend)
        hm.node_decay(lam, h, sp.NODES, enode)
        hm.weighted_at_nodes(lam, w, z0, pc, nn, h, sp.NODES, enode, out, comb, tmp)
        np.testing.assert_allclose(fmap @ pc + fdec.T @ z0, out, rtol=1e-12)
        z1 = np.zeros(nz)
        hm.advance(lam, z0, pc, nn, h, 1.0, z1, tmp)
        np.testing.assert_allclose(fend[:, :nn] @ pc + fend[:, nn] * z0, z1, rtol=1e-13)
        # a linearly rising power a + b·τ: the closed form of each mode
        a, b = 5e4, 2e6
        tau = 0.5 * h * (1 + sp.NODES)
        em1 = np.expm1(-np.outer(lam, tau))
        modes = z0[:, None] * (1 + em1) - (a * em1 - b * (tau + em1 / lam[:, None])) / lam[:, None]
        got = fmap @ (sp.VINV @ (a + b * tau)) + fdec.T @ z0
        np.testing.assert_allclose(got, w @ modes, rtol=2e-12)
    assert hm.grid_step(1e-12) == 1e-12 and hm.grid_level(1e-12) == -1  # below the grid
    assert math.isnan(hm.grid_step(math.nan)) and hm.grid_level(math.nan) == -1
    # every step the grid rounds to is found on it, from its shortest to its longest
    for h in np.geomspace(2.0**-31.9, 2.0**8, 997):
        g = hm.grid_step(h)
        assert g == h or 0 <= hm.grid_level(g) < hm.N_LEVELS, h
    for h in (0.0, -1.0, math.inf, 5e-324, 1e300):
        assert hm.grid_step(h) == h and hm.grid_level(h) == -1

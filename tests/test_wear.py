"""A clutch over its life (clutchlab.wear): the wear travel on the Almen–László curve against its
closed form, the life in engagements against the allowance volume over the wear of one engagement
and against the engagement-by-engagement sum, and the largest engagement rate against the periodic
temperature and a brute-force sequence of engagements."""

import math

import numpy as np
import pytest

from clutchlab import config, engagement, friction, heat, wear
from clutchlab import status as st
from clutchlab.studies import get
from clutchlab.studies.diaphragm_spring import seed_spring
from clutchlab.studies.engagement import PARAMETER_DEFAULTS, capacity_of

MM = 1e-3
SPRING = seed_spring()  # E 206 GPa, nu 0.3, R/r/R1/r1 110/85/108/86 mm, h 2.334, H 3.50 mm


def _by_hand(lam, s=SPRING):
    """Eq. (10) of seed 000 written out: F = c·λ·[(H − kλ)(H − kλ/2) + h²]."""
    c = (
        math.pi
        * s["youngs_modulus"]
        * s["sheet_thickness"]
        / (6 * (1 - s["poisson_ratio"] ** 2))
        * math.log(s["outer_radius"] / s["inner_radius"])
        / (s["load_radius_outer"] - s["load_radius_inner"]) ** 2
    )
    k = (s["outer_radius"] - s["inner_radius"]) / (s["load_radius_outer"] - s["load_radius_inner"])
    H, h = s["cone_height"], s["sheet_thickness"]
    return c * lam * ((H - k * lam) * (H - k * lam / 2) + h**2)


def _lam_b(factor):
    k = (SPRING["outer_radius"] - SPRING["inner_radius"]) / (
        SPRING["load_radius_outer"] - SPRING["load_radius_inner"]
    )
    return factor * SPRING["cone_height"] / k


@pytest.mark.parametrize("factor", [0.8, 0.9, 1.0])
def test_wear_travel_against_the_almen_laszlo_closed_form(factor):
    lam_b = _lam_b(factor)
    for worn in (0.0, 0.75 * MM, 1.5 * MM):
        got = wear.worn_clamp_load(worn, deflection_operating=lam_b, **SPRING)
        assert got == pytest.approx(_by_hand(lam_b - worn), rel=1e-12)
    assert wear.worn_deflection(lam_b, 1.5 * MM) == pytest.approx(lam_b - 1.5 * MM, rel=1e-15)


def test_the_diaphragm_study_reports_new_half_and_worn_states_to_rounding():
    study = get("diaphragm_spring")
    factor = np.array([0.8, 0.9, 1.0])
    ds = study.compute(study.defaults | {"operating_point_factor": factor})
    allowance = study.defaults["wear_allowance"]
    assert allowance == 1.5 * MM
    for i, f in enumerate(factor):
        lam_b = _lam_b(f)
        ds_i = ds.isel(run=i)
        assert float(ds_i.clamp_load) == pytest.approx(_by_hand(lam_b), rel=1e-12)
        assert float(ds_i.clamp_load_half) == pytest.approx(
            _by_hand(lam_b - allowance / 2), rel=1e-12
        )
        assert float(ds_i.clamp_load_worn) == pytest.approx(_by_hand(lam_b - allowance), rel=1e-12)
        cap = friction.torque_capacity(_by_hand(lam_b - allowance), 0.4, 112.5 * MM, 75 * MM)
        assert float(ds_i.torque_capacity_worn) == pytest.approx(cap, rel=1e-12)
        assert float(ds_i.reserve_factor_worn) == pytest.approx(cap / 173.0, rel=1e-12)
        dense = _by_hand(np.linspace(lam_b - allowance, lam_b, 20001))
        assert float(ds_i.clamp_load_least) == pytest.approx(dense.min(), rel=1e-9)
    assert (ds.status == st.CODE["ok"]).all()
    for name in ("reserve_factor_worn", "reserve_factor_least", "clamp_load_worn"):
        assert name in study.outputs


def test_a_spring_on_the_falling_branch_keeps_its_load_one_on_the_rising_branch_loses_it():
    """The reason for the falling branch (seed 000, Fig. 6): over the default 1.5 mm allowance, B
    at λ_C past the hump A keeps the clamp load within 8 % (measured: +1.6 % at A, −6.9 % at the
    end); B at 0.6 λ_C, before A, loses more than half (measured 66.7 %)."""
    pts = {k: float(v) for k, v in friction_free_points().items()}
    lam_a = pts["deflection_A"]
    falling, rising = _lam_b(1.0), _lam_b(0.6)
    assert falling > lam_a > rising
    travel = np.linspace(0.0, 1.5 * MM, 301)
    keep = wear.worn_clamp_load(travel, deflection_operating=falling, **SPRING)
    lose = wear.worn_clamp_load(travel, deflection_operating=rising, **SPRING)
    assert np.all(np.abs(keep / keep[0] - 1) < 0.08)
    assert lose[-1] / lose[0] < 0.5 and np.all(np.diff(lose) < 0)
    # past the hump the falling-branch spring first gains load (towards A), then loses it
    assert keep.max() == pytest.approx(pts["load_A"], rel=1e-6)


def friction_free_points():
    from clutchlab import diaphragm

    return diaphragm.characteristic_points(**SPRING, operating_point_factor=1.0)


def test_a_spring_worn_past_its_free_position_clamps_nothing_and_bad_inputs_are_nan():
    lam_b = _lam_b(0.9)
    load = wear.worn_clamp_load(
        np.array([1.0 * MM, lam_b + 0.1 * MM, np.nan, -1.0 * MM, 1.0]),
        deflection_operating=lam_b,
        **SPRING,
    )
    assert load[1] == 0.0 and load[4] == 0.0  # past the spring's free position: no load
    assert np.isnan(load[2:4]).all()  # NaN, a negative wear
    alone = wear.worn_clamp_load(1.0 * MM, deflection_operating=lam_b, **SPRING)
    assert load[0] == alone  # bit-identical beside the refused ones


def test_life_for_a_constant_clamp_load_is_the_allowance_volume_over_one_engagements_wear():
    """A hand calculation: 8 kJ an engagement, q_V = 0.2 cm³/kWh, lining 225/150 mm: each
    engagement wears q_V·W = 0.4444 mm³ of lining, the plates close up by that over one face's
    area 22 089.3 mm², 2.0120e-5 mm; 1.5 mm lasts 74 551.8 engagements."""
    q = 0.2e-6 / 3.6e6
    area = math.pi * (112.5**2 - 75**2) * 1e-6
    delta = wear.wear_per_engagement(8000.0, q, 112.5 * MM, 75 * MM)
    assert delta == pytest.approx(q * 8000.0 / area, rel=1e-14)
    assert delta == pytest.approx(2.0120e-8, rel=1e-4)
    life = wear.life_engagements(1.5 * MM, delta, delta, delta)
    assert life == pytest.approx(1.5 * MM * area / (q * 8000.0), rel=1e-13)
    assert life == pytest.approx(74551.8, rel=1e-5)
    assert wear.life_engagements(0.0, delta, delta, delta) == 0.0
    assert wear.life_engagements(1.5 * MM, 0.0, 0.0, 0.0) == np.inf
    assert np.isnan(wear.life_engagements(1.5 * MM, np.nan, delta, delta))
    assert np.isnan(wear.wear_per_engagement(8000.0, q, 75 * MM, 112.5 * MM))  # swapped radii
    assert np.isnan(wear.wear_per_engagement(8000.0, 1.0, 112.5 * MM, 75 * MM))  # q_V in m³/J?


def _rigid(**extra):
    """The engagement study's inputs of a rigid, held-engine design (its closed form)."""
    return PARAMETER_DEFAULTS | {"engine_inertia": np.inf} | extra


def test_life_with_the_clamp_load_following_the_wear_against_the_engagement_by_engagement_sum():
    """The study's life (Simpson's rule over the new, half and fully worn engagements) against
    engaging the clutch one engagement after another, each at the clamp load of the wear so far
    (q_V raised to 2e-11 m³/J so that the allowance lasts some 260 engagements). Measured:
    Simpson's rule over three engagements is within 0.10 % of the sum for B at 0.8 λ_C (the slip
    work rising 11.5 % over the wear), 0.04 % at 0.9 λ_C, 0.014 % at λ_C."""
    study = get("engagement")
    q = 2e-11
    inputs = _rigid(specific_wear_rate=q, operating_point_factor=0.8)
    ds = study.compute(inputs, {"driveline": "rigid"}).isel(run=0)
    assert int(ds.status) == st.CODE["ok"]
    options = {"capacity_formula": "corrected"}
    p = {k: np.atleast_1d(float(v)) for k, v in inputs.items()}
    lam_b = _lam_b(0.8)
    allowance, worn, n = inputs["wear_allowance"], 0.0, 0
    area = math.pi * (inputs["lining_outer_radius"] ** 2 - inputs["lining_inner_radius"] ** 2)
    while worn < allowance:
        force = wear.worn_clamp_load(worn, deflection_operating=lam_b, **SPRING)
        cap = capacity_of(np.atleast_1d(force), p, options)
        r = engagement.closed_form(
            engine_speed=inputs["engine_speed"],
            engine_inertia=np.inf,
            engine_torque=inputs["engine_torque"],
            driven_inertia=inputs["driven_inertia"],
            load_torque=inputs["load_torque"],
            peak_capacity=cap,
            ramp_time=inputs["ramp_time"],
            t_end=inputs["end_time"],
        )
        step = q * float(r["slip_work"][0]) / area
        worn += step
        n += 1
    # the last engagement overshoots the allowance: count the fraction of it that was needed
    exact = n - (worn - allowance) / step
    assert float(ds.life_engagements) == pytest.approx(exact, rel=1.5e-3)
    assert float(ds.slip_work_worn) > float(ds.slip_work)  # less clamp load, more slip


def test_the_largest_engagement_rate_keeps_the_periodic_temperature_at_the_limit():
    rise = np.array([2.0, 10.0, 50.0, 209.0])
    tau, margin = 600.0, 210.0
    rate = heat.max_engagement_rate(rise, tau, margin)
    np.testing.assert_allclose(
        heat.periodic_temperature(rise, 1.0 / rate, tau), margin, rtol=1e-9, atol=0.0
    )
    # brute force: 20 000 engagements in a row at that rate stay under the limit and reach it;
    # 1 % more often they pass it
    for i in range(rise.size):
        seq = heat.sequence_temperatures(rise[i], 1.0 / rate[i], tau, 20000)
        assert seq.max() <= margin * (1 + 1e-12)
        assert seq[-1] == pytest.approx(margin, rel=1e-6)
        faster = heat.sequence_temperatures(rise[i], 0.99 / rate[i], tau, 20000)
        assert faster.max() > margin
    assert heat.max_engagement_rate(210.0, tau, margin) == 0.0  # one engagement reaches it
    assert heat.max_engagement_rate(0.0, tau, margin) == np.inf
    assert np.isnan(heat.max_engagement_rate(np.nan, tau, margin))
    assert np.isnan(heat.max_engagement_rate(5.0, -tau, margin))


def test_the_engagement_heat_rate_is_the_binding_parts():
    """Every part's periodic state at the reported rate is at or under the margin, the binding
    part's at it (to 1e-9)."""
    slip = np.array([6000.0, 40000.0])
    hot = heat.engagement_heat(slip, 1e5, 112.5 * MM, 75 * MM, engagement_interval=60.0)
    masses = {"flywheel": 10.3, "pressure_plate": 2.5, "driven_plate": 1.9}
    temps = []
    for part, m in masses.items():
        c = heat.MATERIALS[heat.BULK_MATERIAL[part]]["specific_heat"]
        rise = hot[f"heat_{part}"] / (m * c)
        temps.append(heat.periodic_temperature(rise, 1.0 / hot["max_engagement_rate"], m * c / 4.0))
    temps = np.array(temps)
    assert np.all(temps <= 210.0 * (1 + 1e-9))
    np.testing.assert_allclose(temps.max(axis=0), 210.0, rtol=1e-9)


def test_the_study_reports_life_and_rate_and_refuses_bad_wear_inputs():
    study = get("engagement")
    q = np.array([wear.SPECIFIC_WEAR_RATE, np.nan, wear.SPECIFIC_WEAR_RATE])
    allowance = np.array([1.5 * MM, 1.5 * MM, 6.0 * MM])
    ds = study.compute(
        _rigid(specific_wear_rate=q, wear_allowance=allowance), {"driveline": "rigid"}
    )
    code = ds.status.values
    assert code[0] == st.CODE["ok"] and code[1] == st.CODE["invalid_input"]
    # 6 mm of wear unloads the seed spring: the clutch no longer locks up at the end of its wear
    assert code[2] == st.CODE["worn_not_locked"]
    assert np.isnan(ds.life_engagements.values[1:]).all()
    assert np.isfinite(ds.lockup_time.values[2])  # the first engagement's numbers stand
    assert 1e4 < float(ds.life_engagements[0]) < 1e6
    assert float(ds.max_engagement_rate[0]) > 0
    assert ds.max_engagement_rate.attrs["units"] == "1/s"


@pytest.mark.parametrize(
    "key, value",
    [("wear_allowance", "25 mm"), ("wear_allowance", "-1 mm"), ("specific_wear_rate", 1.0)],
)
def test_a_wear_input_out_of_range_is_refused_naming_its_key(key, value):
    study = "diaphragm_spring" if key == "wear_allowance" else "engagement"
    with pytest.raises(config.ConfigError, match=f"{study}.parameters.{key}") as err:
        config.resolve(
            {"studies": [study], study: {"design": "factorial", "parameters": {key: value}}}
        )
    assert "unknown key" not in str(err.value)


def test_a_wear_rate_in_engineers_units_is_read_as_meant():
    section = config.resolve(
        {
            "studies": ["engagement"],
            "engagement": {
                "design": "factorial",
                "parameters": {"specific_wear_rate": "0.2 cm^3/(kW*h)", "wear_allowance": "1 mm"},
            },
        }
    )["engagement"]
    assert section["fixed"]["specific_wear_rate"] == pytest.approx(wear.SPECIFIC_WEAR_RATE)
    assert section["fixed"]["wear_allowance"] == pytest.approx(1e-3)


def test_a_refused_wear_allowance_is_invalid_input_and_leaves_the_others_bit_identical():
    study = get("diaphragm_spring")
    allowance = np.array([1.5 * MM, np.nan, 0.5 * MM])
    ds = study.compute(study.defaults | {"wear_allowance": allowance})
    assert list(ds.status.values) == [st.CODE["ok"], st.CODE["invalid_input"], st.CODE["ok"]]
    assert np.isnan(ds.reserve_factor_worn.values[1]) and np.isnan(ds.clamp_load.values[1])
    alone = study.compute(study.defaults | {"wear_allowance": np.array([0.5 * MM])})
    for name in ("clamp_load_worn", "reserve_factor_least", "clamp_load"):
        assert ds[name].values[2] == alone[name].values[0]


def test_the_load_curve_page_draws_the_wear_travel_from_b_to_the_worn_point():
    import matplotlib.pyplot as plt

    from clutchlab import pipeline
    from clutchlab.report import diaphragm_figures

    section = config.resolve(
        {
            "studies": ["diaphragm_spring"],
            "diaphragm_spring": {
                "design": "factorial",
                "parameters": {"cone_height_ratio": {"values": [1.5, 1.8]}},
            },
        }
    )["diaphragm_spring"]
    ds = pipeline.run_study(section)
    fig = diaphragm_figures.load_curves(ds)
    bands = [ln for ln in fig.axes[0].lines if ln.get_linewidth() == 6 and len(ln.get_xdata())]
    assert len(bands) == 2
    for band, ratio in zip(bands, (1.5, 1.8), strict=True):
        m = ds.sel(cone_height_ratio=ratio)
        x, y = band.get_xdata(), band.get_ydata()
        assert x[0] == pytest.approx(float(m.deflection_worn) * 1e3, rel=1e-12)
        assert x[-1] == pytest.approx(float(m.deflection_operating) * 1e3, rel=1e-12)
        assert y[0] == pytest.approx(float(m.clamp_load_worn) / 1e3, rel=1e-12)
        assert y[-1] == pytest.approx(float(m.clamp_load) / 1e3, rel=1e-12)
    plt.close(fig)


def test_life_outputs_are_objectives_and_constraints_in_engineers_units():
    section = config.resolve(
        {
            "studies": ["engagement"],
            "engagement": {
                "design": "factorial",
                "parameters": {},
                "objectives": ["life_engagements:max", "slip_work:min"],
                "constraints": {"max_engagement_rate": {"min": "100 1/h"}},
            },
        }
    )["engagement"]
    assert section["constraints"]["max_engagement_rate"][1] == pytest.approx(100 / 3600.0)
    assert display_unit("max_engagement_rate", "1/s")(1 / 36.0) == pytest.approx(100.0)
    assert display_unit("specific_wear_rate", "m^3/J")(wear.SPECIFIC_WEAR_RATE) == pytest.approx(
        0.2
    )


def display_unit(name, units):
    from clutchlab import display

    return display.unit(units, name)

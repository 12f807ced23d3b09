"""Almen-Laszlo curve (seed 000 eq. 10) and its characteristic points."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as hs
from scipy.optimize import minimize_scalar

from clutchlab import diaphragm
from clutchlab import status as st
from clutchlab.published import DIAPHRAGM_CLUTCH
from clutchlab.studies.diaphragm_spring import seed_spring

SEED = seed_spring()


def test_seed_operating_point_2500N():
    """Seed 000 section 5.1 / Fig. 7: F_B = 2500 N at lambda_B = 0.9 lambda_C (tolerance 0.5 %),
    with the PHYSICS.md spring (E 206 GPa, nu 0.3, R/r/R1/r1 = 110/85/108/86 mm, h 2.334, H 3.50 mm)."""
    pts = diaphragm.characteristic_points(**SEED, operating_point_factor=0.9)
    assert pts["load_B"] == pytest.approx(DIAPHRAGM_CLUTCH["clamp_load"].value, rel=5e-3)
    assert int(pts["status"]) == st.CODE["ok"]
    assert np.isfinite(pts["load_A"]) and np.isfinite(pts["load_D"])
    assert pts["load_A"] > pts["load_C"] > pts["load_D"] > 0
    assert pts["deflection_C"] == pytest.approx(
        0.5 * (pts["deflection_A"] + pts["deflection_D"]), rel=1e-12
    )


def test_points_against_numerical_optimisation():
    """Analytic A and D against a bounded scalar optimiser on eq. (10) itself."""
    pts = diaphragm.characteristic_points(**SEED)
    f = lambda lam: diaphragm.almen_laszlo_load(lam, **SEED)  # noqa: E731
    lam_c = float(pts["deflection_C"])
    a = minimize_scalar(
        lambda x: -f(x), bounds=(0, lam_c), method="bounded", options={"xatol": 1e-12}
    )
    d = minimize_scalar(f, bounds=(lam_c, 2 * lam_c), method="bounded", options={"xatol": 1e-12})
    assert a.x == pytest.approx(float(pts["deflection_A"]), rel=1e-5)
    assert d.x == pytest.approx(float(pts["deflection_D"]), rel=1e-5)
    assert -a.fun == pytest.approx(float(pts["load_A"]), rel=1e-10)
    assert d.fun == pytest.approx(float(pts["load_D"]), rel=1e-10)


def test_flat_point_load_closed_form():
    pts = diaphragm.characteristic_points(**SEED)
    c = diaphragm.spring_constant(**{k: v for k, v in SEED.items() if k != "cone_height"})
    k = diaphragm.radius_ratio_k(
        SEED["outer_radius"],
        SEED["inner_radius"],
        SEED["load_radius_outer"],
        SEED["load_radius_inner"],
    )
    assert pts["load_C"] == pytest.approx(
        c * SEED["cone_height"] * SEED["sheet_thickness"] ** 2 / k, rel=1e-12
    )


@pytest.mark.parametrize("ratio", [1.0, 1.3, np.sqrt(2.0)])
def test_monotone_spring_has_no_points(ratio):
    """PHYSICS.md hard case: H/h <= sqrt(2) gives a monotone curve - no A/D invented."""
    spring = dict(SEED, cone_height=ratio * SEED["sheet_thickness"])
    pts = diaphragm.characteristic_points(**spring)
    assert int(pts["status"]) == st.CODE["monotone_no_hump"]
    assert np.isnan(pts["load_A"]) and np.isnan(pts["load_D"])
    lam = np.linspace(0, 3 * float(pts["deflection_C"]), 2001)
    assert np.all(np.diff(diaphragm.almen_laszlo_load(lam, **spring)) >= -1e-9)
    assert np.isfinite(pts["load_B"])  # the flat position exists, so B is defined


def test_snap_through_flagged():
    spring = dict(SEED, cone_height=3.0 * SEED["sheet_thickness"])  # H/h > 2 sqrt 2: valley below 0
    pts = diaphragm.characteristic_points(**spring)
    assert pts["load_D"] < 0
    assert int(pts["status"]) == st.CODE["snap_through"]


def test_invalid_geometry_is_nan_with_status():
    spring = dict(SEED, load_radius_inner=0.120)  # fulcrum outside the pressure-plate radius
    pts = diaphragm.characteristic_points(**spring)
    assert int(pts["status"]) == st.CODE["invalid_geometry"]
    assert all(np.isnan(pts[k]) for k in ("load_A", "load_B", "load_C", "load_D"))


def test_broadcasting():
    h = np.array([2.0e-3, 2.334e-3, 2.6e-3])[:, None]
    factor = np.array([0.8, 0.9, 1.0])[None, :]
    pts = diaphragm.characteristic_points(
        **dict(SEED, sheet_thickness=h, cone_height=1.6 * h), operating_point_factor=factor
    )
    assert pts["load_B"].shape == (3, 3) and pts["status"].shape == (3, 3)
    for i in range(3):
        for j in range(3):
            hi = float(h[i, 0])
            one = diaphragm.characteristic_points(
                **dict(SEED, sheet_thickness=hi, cone_height=1.6 * hi),
                operating_point_factor=float(factor[0, j]),
            )
            assert pts["load_B"][i, j] == pytest.approx(float(one["load_B"]), rel=1e-14)


@settings(max_examples=200, deadline=None)
@given(ratio=hs.floats(1.45, 2.8), h=hs.floats(1e-3, 4e-3), rr=hs.floats(1.1, 1.6))
def test_stationary_points_property(ratio, h, rr):
    """dF/dlambda vanishes at A and D, F is a local max at A and a local min at D."""
    spring = dict(
        SEED,
        sheet_thickness=h,
        cone_height=ratio * h,
        inner_radius=0.110 / rr,
        load_radius_inner=0.110 / rr + 0.001,
    )
    pts = diaphragm.characteristic_points(**spring)
    for p, sign in (("A", -1), ("D", 1)):
        lam = float(pts[f"deflection_{p}"])
        eps = 1e-4 * lam
        left, mid, right = diaphragm.almen_laszlo_load(
            np.array([lam - eps, lam, lam + eps]), **spring
        )
        assert sign * (left - mid) >= 0 and sign * (right - mid) >= 0

"""Damper springs (seed 000 eqs. 4-9, with errata) and the hub spline check (section 3.2.2)."""

import pytest

from clutchlab import driven_plate as dp
from clutchlab.published import DIAPHRAGM_CLUTCH as PUB

T_EMAX = 173.0  # N m, seed 000 Table 1


def test_damper_chain_table2():
    """Seed 000 Table 2: T_j = 346 N m, P_total = 6654 N (R1 = 52 mm inferred), C_a = 4498 N m/rad,
    C = 415.9 N/mm (printed '416 N/m', erratum). Tolerance 1e-3."""
    tj = dp.damper_design_torque(T_EMAX)
    assert tj == pytest.approx(PUB["damper_design_torque"].value)
    p_total = dp.damper_total_force(tj, 0.052)
    assert p_total == pytest.approx(PUB["damper_total_force"].value, rel=1e-3)
    c_a = dp.damper_angular_stiffness(tj)
    assert c_a == pytest.approx(PUB["damper_angular_stiffness"].value, rel=1e-3)
    rate = dp.damper_spring_rate(c_a, 0.052, 4)
    assert rate == pytest.approx(PUB["damper_spring_rate"].value, rel=1e-3)


def test_wire_diameter_is_a_cube_root():
    """Eq. (6) erratum: tau = 8 P Dc / (pi d^3) must hold for the returned d."""
    d = dp.damper_wire_diameter(1663.5, 0.015, 400e6)
    assert 8 * 1663.5 * 0.015 / (3.141592653589793 * d**3) == pytest.approx(400e6, rel=1e-12)


def test_coil_count_six():
    """Table 2: i = 6 coils. tau and G are not printed; with tau = 400 MPa, G = 79 GPa (65Mn)
    eq. (6) gives d1 = 5.42 mm and eq. (9) i = 6.05 (PHYSICS.md: d1 = 5.34-5.40 mm for i = 6)."""
    coils = PUB["damper_coils"].value
    rate = dp.damper_spring_rate(PUB["damper_angular_stiffness"].value, 0.052, 4)
    d1 = dp.damper_wire_diameter(dp.damper_spring_force(6653.8, 4), 0.015, 400e6)
    assert d1 == pytest.approx(5.415e-3, rel=2e-3)
    assert round(float(dp.damper_coil_count(79e9, d1, 0.015, rate))) == coils
    assert dp.damper_coil_count(79e9, 5.40e-3, 0.015, rate) == pytest.approx(coils, rel=0.02)


def test_spline_stresses():
    """Section 3.2.2: 10 teeth, D 35, d 28, t 4, l 35 mm. Bearing 8.9 MPa at T_emax (tol 1 %);
    shear 15 MPa only at 2 T_emax (tol 5 %, load not stated in the paper)."""
    geo = dict(
        teeth=10, outer_diameter=0.035, inner_diameter=0.028, tooth_width=0.004, length=0.035
    )
    bearing, shear = dp.spline_stresses(T_EMAX, **geo)
    assert bearing == pytest.approx(PUB["spline_bearing_stress"].value, rel=0.01)
    assert shear == pytest.approx(7.85e6, rel=1e-3)
    at_tj = dp.spline_stresses(2 * T_EMAX, **geo)[1]
    assert at_tj == pytest.approx(PUB["spline_shear_stress"].value, rel=0.05)

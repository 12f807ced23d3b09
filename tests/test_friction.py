"""Lining size (eq. 3), torque capacity (eqs. 13-14 corrected and as printed), reserve factor."""

import numpy as np
import pytest
from scipy.integrate import quad

from clutchlab import friction
from clutchlab.published import DIAPHRAGM_CLUTCH as PUB

RO, RI = 0.1125, 0.075  # seed 000 Table 2: D = 225 mm, d = 150 mm


def test_lining_constant_A():
    """Seed 000 eq. (3): D = 225 mm with T_emax = 173 N m (Table 1) <=> A = 34.17 (tol 1e-3)."""
    a = PUB["lining_constant"].value
    assert friction.lining_coefficient(173.0, 0.225) == pytest.approx(a, rel=1e-3)
    assert friction.lining_outer_diameter(173.0, 34.17284) == pytest.approx(0.225, rel=1e-6)


def test_capacity_two_faces_uniform_pressure():
    """Corrected eqs. (13)-(14): 2 faces, mu = 0.4, F = 2500 N -> 190.0 N m (tol 1e-3)."""
    want = PUB["capacity_two_faces"].value
    assert friction.torque_capacity(2500.0, 0.4, RO, RI) == pytest.approx(want, rel=1e-3)


def test_capacity_with_stack_weight():
    """Same with the 4.757 kg stack weight (Table 3: 0.357 + 1.9 + 2.5 kg) -> 193.5 N m (tol 1e-3)."""
    assert friction.torque_capacity(2500.0, 0.4, RO, RI, stack_mass=4.757) == pytest.approx(
        PUB["capacity_two_faces_stack_weight"].value, rel=1e-3
    )


def test_eq14_as_printed_reproduces_paper():
    """Eq. (14) as printed (one face, mu on the weight only) -> 239.3 N m, the paper's value (tol 1e-3)."""
    assert friction.torque_capacity_eq14_as_printed(2500.0, 0.4, 4.757, RO, RI) == pytest.approx(
        PUB["capacity_eq14_as_printed"].value, rel=1e-3
    )


def test_effective_radius_against_quadrature():
    """Uniform pressure: R_eff = int r^2 dr / int r dr (eq. 13 integrated numerically)."""
    num = quad(lambda r: r**2, RI, RO)[0] / quad(lambda r: r, RI, RO)[0]
    assert friction.effective_radius(RO, RI) == pytest.approx(num, rel=1e-12)
    assert friction.effective_radius(RO, RI) == pytest.approx(0.095, rel=1e-12)
    assert friction.effective_radius(RO, RI, "uniform_wear") == pytest.approx(0.09375)
    with pytest.raises(ValueError):
        friction.effective_radius(RO, RI, "elliptic")


def test_ceiling_at_outer_radius():
    """PHYSICS.md: even at R2 on both faces the ceiling is 225 N m, so Fig. 11's 250-256 N m is impossible."""
    assert 2 * 0.4 * 2500 * RO == pytest.approx(225.0)
    assert friction.torque_capacity(2500.0, 0.4, RO, RI) < 225.0


def test_reserve_factor_vectorised():
    cap = friction.torque_capacity(np.array([2000.0, 2500.0]), 0.4, RO, RI)
    assert friction.reserve_factor(cap, 173.0) == pytest.approx(cap / 173.0)

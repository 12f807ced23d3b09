"""Clamp profiles p(x) of the capacity C(t) = C_max·p(t/t_r) and the release-bearing travel model.

Numpy, vectorised over scenarios; the compiled solver evaluates the same polynomials itself
(:func:`clutchlab.engagement._physics.capacity`).
"""

from __future__ import annotations

import numpy as np

from .. import status as st

PROFILES = ("ramp", "cubic", "quintic")
# profile p(x) on [0, 1] and its integral P(x) = ∫0^x p, as ascending polynomial coefficients
_P = {
    "ramp": np.array([0.0, 1.0]),
    "cubic": np.array([0.0, 0.0, 3.0, -2.0]),  # ADAMS STEP (cubic)
    "quintic": np.array([0.0, 0.0, 0.0, 10.0, -15.0, 6.0]),  # STEP5-like quintic
}


def _polyval(c, x):
    """The polynomial of ascending coefficients c at x (Horner; the rounding every caller relies on)."""
    out = np.zeros_like(x) + c[-1]
    for a in c[-2::-1]:
        out = out * x + a
    return out


def _integral_coeffs(c):
    """Ascending coefficients of ∫0^x of the polynomial c."""
    return np.concatenate([[0.0], c / np.arange(1, len(c) + 1)])


def _check_profile(kind):
    if kind not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES}, got {kind!r}")


def clamp_profile(x, kind="ramp"):
    """Clamp (capacity) profile p(x), x = t/t_r, clipped to [0, 1] outside [0, 1] [-].

    Parameters
    ----------
    x : array_like [-]
        Time over ramp time t/t_r; ±inf is before the start or after the end; NaN gives NaN.
    kind : {"ramp", "cubic", "quintic"}
        The profile (ValueError for another): the linear ramp x, the cubic smooth step
        3x² − 2x³ or the quintic smooth step 10x³ − 15x⁴ + 6x⁵.

    Returns
    -------
    numpy.ndarray [-]
        p(x); C(t) = C_max·p(t/t_r) is the kinetic torque capacity of eq. (13) as the clamp
        force rises.

    See Also
    --------
    bearing_travel_clamp : The clamp force when the profile is the release bearing's travel.

    References
    ----------
    .. [1] Zhao P. (2026), source paper (000), eqs. (1), (2), (13): the engagement under a
       rising clamp force.
    """
    _check_profile(kind)
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    return _polyval(_P[kind], x)


def bearing_travel_clamp(x, *, air_gap, cushion_travel, kind="ramp"):
    """Clamp force fraction F/F_B of the release-bearing travel model [-] at x = t/t_r.

    The bearing travel follows the profile p(x) from full release (p = 0) to engaged (p = 1);
    the pressure plate lifts by (1 − p)·(g + c) (rigid fingers: travel over lever ratio), g the
    air gap and c the travel of the lining cushion (a linear spring carrying F_B when fully
    compressed, F_B = the diaphragm spring's load at its operating point, eq. 10). The clamp force
    is the cushion force: F/F_B = max(0, 1 − κ(1 − p)), κ = (g + c)/c. The diaphragm curve sets F_B
    and the bearing force (:func:`clutchlab.studies.engagement.bearing_force`), not the shape.

    Parameters
    ----------
    x : array_like [-]
        Time over ramp time t/t_r (see :func:`clamp_profile`).
    air_gap : array_like [m]
        Air gap g ≥ 0 between pressure plate and lining at full release.
    cushion_travel : array_like [m]
        Travel c > 0 of the lining cushion from touch to full clamp.
    kind : {"ramp", "cubic", "quintic"}
        The bearing travel's profile (:func:`clamp_profile`).

    Returns
    -------
    numpy.ndarray [-]
        F/F_B; NaN where x is NaN or g, c are not finite, negative (c: not positive) or of
        an implausible magnitude (:mod:`clutchlab.plausible`).

    References
    ----------
    .. [1] Zhao P. (2026), source paper (000), eq. (10) (the diaphragm spring's load F_B) and
       eq. (13) (the capacity proportional to the clamp force).
    """
    _check_profile(kind)
    return st.nan_screened(
        _bearing_travel_clamp,
        dict(x=x, air_gap=air_gap, cushion_travel=cushion_travel),
        {
            "x": lambda v: ~np.isnan(v),
            "air_gap": st.nonnegative_in("m"),
            "cushion_travel": st.positive_in("m"),
        },
        extra={"kind": kind},
    )


def _bearing_travel_clamp(*, x, air_gap, cushion_travel, kind):
    kappa = (np.asarray(air_gap, float) + cushion_travel) / cushion_travel
    return np.maximum(0.0, 1.0 - kappa * (1.0 - clamp_profile(x, kind)))


def _invert_profile(q, kind):
    """x in [0, 1] with p(x) = q (p is monotone), vectorised bisection + Newton to round-off."""
    q = np.clip(q, 0.0, 1.0)
    if kind == "ramp":
        return q
    c, dc = _P[kind], np.polynomial.polynomial.polyder(_P[kind])
    lo, hi = np.zeros_like(q), np.ones_like(q)
    x = q.copy()
    done = np.zeros(q.shape, bool)  # per scenario: a converged x is frozen (batch-independent)
    for _ in range(60):
        f = _polyval(c, x) - q
        lo = np.where(f < 0, x, lo)
        hi = np.where(f >= 0, x, hi)
        d = _polyval(dc, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - f / d
        bad = ~((xn > lo) & (xn < hi))
        xn = np.where(bad, 0.5 * (lo + hi), xn)
        now = np.abs(xn - x) <= 4e-16
        x = np.where(done, x, xn)
        done = done | now
        if done.all():
            break
    return x

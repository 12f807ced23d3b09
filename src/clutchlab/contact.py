"""Contact force law for stiff impacts (ADAMS IMPACT-type), and the single Hertz impact.

F = k·δ^e + STEP(δ; 0, 0, d_max, c_max)·δ̇ for δ > 0, else 0, and never negative: the damping
coefficient rises from 0 at first touch to c_max at the penetration depth d_max through a cubic
step (so the force is continuous at first touch), and a separating contact whose damping would
pull is cut to zero (a contact can push, never pull).

References
----------
.. [1] The source paper (003), section 3.1.2: contact stiffness 3.375e5 N/mm^1.5
    (= (4/3)·E*·√(d/2) for a 10 mm steel roller on a flat), exponent 1.5, damping 2.1e3 N·s/mm.
.. [2] MSC ADAMS/Solver IMPACT function (cubic STEP of the damping over the penetration depth).
.. [3] Johnson, K. L., Contact Mechanics, 1985, section 11.4: Hertz impact of a mass m at speed v:
    δ_max = (5mv²/(4k))^(2/5), contact time 2.9432·δ_max/v, restitution 1.
"""

from __future__ import annotations

import math

import numpy as np

from . import _contact_kernel as _kernel
from . import status as st

__all__ = ["impact_force", "hertz_stiffness", "hertz_impact", "HERTZ_CONTACT_TIME_FACTOR"]

#: contact time of the undamped Hertz impact (e = 3/2) in units of δ_max / v:
#: 2·∫₀¹ dx/√(1−x^(5/2)) = (4/5)·B(2/5, 1/2) = 2.94328
HERTZ_CONTACT_TIME_FACTOR = 0.8 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)
MAX_EXPONENT = 10.0  # of k·δ^e (Hertz: 1.5; ADAMS models use 1 to about 3)
#: step attempts :func:`hertz_impact` may spend (an impact of the source paper (003) takes ~100)
IMPACT_MAX_STEPS = 1_000_000

# per-input rules (sign, finite, plausible magnitude: clutchlab.plausible); a penetration and its
# rate are states: any size near zero, finite and not absurd
_RULES = {
    "roller_diameter": st.positive_in("m"),
    "youngs_modulus": st.positive_in("Pa"),
    "poisson_ratio": st.between(-1.0, 0.5, lo_open=True, hi_open=True),
    "penetration": st.finite_in("m", lo=0.0),
    "rate": st.finite_in("m/s", lo=0.0, hi=1e5),
    "stiffness": st.positive_in("N/m^1.5"),
    "exponent": st.all_of(st.at_least(1.0), st.plausible("1", hi=MAX_EXPONENT)),
    "damping": st.nonnegative_in("N s/m"),
    "depth": st.positive_in("m"),
    "mass": st.positive_in("kg"),
    "speed": st.positive_in("m/s", lo=1e-9, hi=1e5),
}


def _domain(inputs):
    return {k: _RULES[k] for k in inputs}


def hertz_stiffness(*, roller_diameter, youngs_modulus=206e9, poisson_ratio=0.3):
    """Hertz stiffness k = (4/3)·E*·√(d/2) of a cylinder on a flat of one steel, E* = E/(2(1−ν²)).

    Parameters
    ----------
    roller_diameter : float or array_like [m]
        Roller diameter d.
    youngs_modulus : float or array_like [Pa]
        Young's modulus E of both bodies.
    poisson_ratio : float or array_like [-]
        Poisson's ratio ν ∈ (−1, 0.5).

    Returns
    -------
    numpy.ndarray [N/m^1.5]
        k (3.375e5 N/mm^1.5 for the 10 mm rollers of the source paper (003)); NaN where d or E is
        not positive, finite and plausible or ν lies outside (−1, 0.5).

    References
    ----------
    Source paper (003), section 3.1.2 ([1] in the module docstring).
    """
    inputs = dict(
        roller_diameter=roller_diameter, youngs_modulus=youngs_modulus, poisson_ratio=poisson_ratio
    )
    return st.nan_screened(_hertz_stiffness, inputs, _domain(inputs))


def _hertz_stiffness(*, roller_diameter, youngs_modulus, poisson_ratio):
    e_star = youngs_modulus / (2.0 * (1.0 - np.square(poisson_ratio)))
    return 4.0 / 3.0 * e_star * np.sqrt(0.5 * np.asarray(roller_diameter, float))


def impact_force(penetration, rate, *, stiffness, exponent=1.5, damping=0.0, depth=1e-5):
    """Contact force of the law in the module docstring, vectorised.

    F = k·δ^e + STEP(δ; 0, 0, d_max, c_max)·δ̇ for δ > 0, else 0, and never negative.

    Parameters
    ----------
    penetration : float or array_like [m]
        Penetration δ (> 0 in contact).
    rate : float or array_like [m/s]
        Penetration rate dδ/dt.
    stiffness : float or array_like [N/m^exponent]
        Contact stiffness k > 0 (:func:`hertz_stiffness`).
    exponent : float or array_like [-]
        Exponent e of k·δ^e, in [1, 10] (1.5: Hertz).
    damping : float or array_like [N s/m]
        Full damping coefficient c_max ≥ 0.
    depth : float or array_like [m]
        Penetration depth d_max > 0 over which the damping rises from 0 to c_max.

    Returns
    -------
    numpy.ndarray [N]
        F; NaN where k or d_max is not positive, c_max < 0, e outside [1, 10], or an input is not
        finite or plausible (:mod:`clutchlab.plausible`).

    References
    ----------
    Source paper (003), section 3.1.2 ([1]); MSC ADAMS IMPACT [2] (module docstring).
    """
    inputs = dict(
        penetration=penetration,
        rate=rate,
        stiffness=stiffness,
        exponent=exponent,
        damping=damping,
        depth=depth,
    )
    return st.nan_screened(_impact_force, inputs, _domain(inputs))


def _impact_force(*, penetration, rate, stiffness, exponent, damping, depth):
    d = np.asarray(penetration, float)
    x = np.clip(d / depth, 0.0, 1.0)
    step = x * x * (3.0 - 2.0 * x)
    f = stiffness * np.maximum(d, 0.0) ** exponent + step * damping * np.asarray(rate, float)
    return np.where(d > 0, np.maximum(f, 0.0), 0.0)


def hertz_impact(*, mass, speed, stiffness, exponent=1.5, damping=0.0, depth=1e-5, rtol=1e-10):
    """A mass hitting a rigid wall through the contact law, integrated with the compiled SDIRK4.

    Events are located by re-stepping. One scenario (scalars). Undamped, the result is checked
    against Hertz's closed form [3]: δ_max = (5mv²/(4k))^(2/5), contact time 2.9432·δ_max/v,
    restitution 1.

    Parameters
    ----------
    mass : float [kg]
        Impacting mass m.
    speed : float [m/s]
        Impact speed v > 0.
    stiffness : float or array_like [N/m^exponent]
        Contact stiffness k > 0 (:func:`hertz_stiffness`).
    exponent : float or array_like [-]
        Exponent e of k·δ^e, in [1, 10] (1.5: Hertz).
    damping : float or array_like [N s/m]
        Full damping coefficient c_max ≥ 0.
    depth : float or array_like [m]
        Penetration depth d_max > 0 over which the damping rises from 0 to c_max.
    rtol : float
        Integrator tolerance, in (0, 1).

    Returns
    -------
    dict
        ``max_penetration`` [m], ``time_of_max`` [s], ``contact_time`` [s], ``restitution`` [-]
        (exit over entry speed), ``nfev``, ``status``: ok; invalid_input (NaN, no integration)
        where an input is not physical, finite or plausible; not_converged (NaN) after
        :data:`IMPACT_MAX_STEPS` step attempts.

    Raises
    ------
    ValueError
        If ``rtol`` is out of range or the inputs are arrays.

    References
    ----------
    Johnson [3], section 11.4 (module docstring).
    """
    if not (np.isscalar(rtol) and np.isfinite(rtol) and 0 < rtol < 1):
        raise ValueError(f"rtol must be a number in (0, 1), got {rtol!r}")
    inputs = dict(
        mass=mass, speed=speed, stiffness=stiffness, exponent=exponent, damping=damping, depth=depth
    )
    _, ok = st.admissible(inputs, _domain(inputs))
    names = ("max_penetration", "time_of_max", "contact_time", "restitution", "nfev")
    if ok.ndim:
        raise ValueError("hertz_impact takes one scenario (scalars)")
    if not ok:
        return {**dict.fromkeys(names, np.nan), "status": st.CODE["invalid_input"]}
    p = np.array([mass, stiffness, exponent, damping, depth], float)
    d_ref = (5 * mass * speed**2 / (4 * stiffness)) ** (1 / (exponent + 1))
    atol = np.array([rtol * d_ref, rtol * speed])
    out = _kernel.impact(p, float(speed), rtol, atol, 1e-3 * d_ref / speed, IMPACT_MAX_STEPS)
    code = st.CODE["ok"] if np.isfinite(out[2]) else st.CODE["not_converged"]
    return {**dict(zip(names, out, strict=True)), "status": code}

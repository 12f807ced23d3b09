"""What the engagement solvers accept: the per-scenario input domains (a scenario outside gets status
``invalid_input`` and NaN outputs, :func:`clutchlab.status.screened`) and the checks of the options
shared by all scenarios (ValueError naming the argument)."""

from __future__ import annotations

import numpy as np

from .. import status as st
from ._fade import SOE_TMAX

# plausible limits of dimensionless inputs (beyond them a value is a slip, never a clutch)
MAX_STATIC_RATIO = 10.0  # μ_s/μ_k (dry friction: 1 to about 1.5)
MAX_DAMPING_RATIO = 100.0  # ζ of the damper springs (a clutch damper: 0.02 to about 1)
MAX_RELEASE_RATIO = 1e4  # κ = (air gap + cushion travel)/cushion travel
MIN_HUB_FRACTION = 1e-6  # share of J_v on the plate hub (and 1 − it on the output)
MAX_WORK = 1e9  # the largest work budget a scenario may be given (max_steps)

# admissible per-scenario inputs (anything else: status invalid_input, NaN outputs): sign, finite
# where inf means nothing, and a magnitude within clutchlab.plausible's range of the unit
DOMAIN = {
    "engine_speed": st.nonnegative_in("rad/s"),
    "engine_inertia": st.positive_or_inf_in("kg m^2"),
    "engine_torque": st.finite_in("N m"),
    "driven_inertia": st.positive_in("kg m^2"),
    "load_torque": st.nonnegative_in("N m"),
    "peak_capacity": st.nonnegative_in("N m"),
    "ramp_time": st.nonnegative_in("s"),
    "static_ratio": st.all_of(st.at_least(1.0), st.plausible("1", hi=MAX_STATIC_RATIO)),
    "driven_speed": st.nonnegative_in("rad/s"),
    "t_end": st.positive_or_inf_in("s"),
    None: lambda a: a["driven_speed"] <= a["engine_speed"],
}


def _simulate_relations(a):
    """Relations between simulate's inputs: ω_c(0) ≤ ω_e(0); the load after a step not negative
    (it is also the static torque that parks the output); fade needs the face temperature
    (factor > 0) and a window its kernel fit covers."""
    return (
        DOMAIN[None](a)
        & ((a["load_torque"] + a["load_step"] >= 0) | (a["load_step_time"] == np.inf))
        & (
            (a["fade_coefficient"] == 0)
            | ((a["face_temperature_factor"] > 0) & (a["t_end"] <= SOE_TMAX))
        )
    )


DOMAIN_SIMULATE = {
    **DOMAIN,
    "t_end": st.positive_in("s"),
    "stribeck_speed": st.positive_or_inf_in("rad/s"),
    "aero_coefficient": st.nonnegative_in("N m s^2"),
    "load_step": st.finite_in("N m"),
    "load_step_time": st.nonnegative_or_inf_in("s"),
    "hub_fraction": st.between(MIN_HUB_FRACTION, 1.0 - MIN_HUB_FRACTION),
    "damper_stiffness": st.positive_or_inf_in("N m/rad"),
    "damping_ratio": st.nonnegative_in("1", hi=MAX_DAMPING_RATIO),
    "release_ratio": st.all_of(st.at_least(1.0), st.plausible("1", hi=MAX_RELEASE_RATIO)),
    "fade_coefficient": st.nonnegative_in("1/K"),
    # a temperature difference [K]: any plausible rise, from a millikelvin
    "fade_onset": st.nonnegative_in("K", lo=1e-3),
    "face_temperature_factor": st.nonnegative_in("K/(W s^0.5)"),
    None: _simulate_relations,
}
#: the compliant model's: a finite damper spring (an infinitely stiff one is the rigid model,
#: ``compliant=False``; the compliant solver would spend its work budget on it)
DOMAIN_COMPLIANT = {**DOMAIN_SIMULATE, "damper_stiffness": st.positive_in("N m/rad")}


def check_solver_options(rtol, atol, max_step, first_step, max_steps, trace_times):
    """Refuse solver options that cannot be meant (shared by all scenarios: ValueError naming
    the argument)."""
    for name, v in (("rtol", rtol), ("atol", atol)):
        if not (np.isscalar(v) and np.isfinite(v) and 0 < v < 1):
            raise ValueError(f"{name} must be a number in (0, 1), got {v!r}")
    if not (np.isscalar(max_step) and max_step > 0):
        raise ValueError(f"max_step must be > 0 s (inf: no limit), got {max_step!r}")
    if first_step is not None and not (np.isscalar(first_step) and 0 < first_step < np.inf):
        raise ValueError(f"first_step must be None or a finite step > 0 s, got {first_step!r}")
    if not (np.isscalar(max_steps) and 1 <= max_steps <= MAX_WORK and max_steps == int(max_steps)):
        raise ValueError(
            f"max_steps must be a whole number in [1, {MAX_WORK:.0e}], got {max_steps!r}"
        )
    if trace_times is not None and not np.all(np.isfinite(np.asarray(trace_times, float))):
        raise ValueError("trace_times must be finite")


def check_table(table, name, x_name, y_name, y_positive):
    """(x, y) arrays of a shared table: at least one point, finite, x increasing (≥ 0 for the
    friction table), y > 0 where asked, every value of a plausible magnitude (speeds [rad/s];
    torques [N m], or friction ratios μ/μ_k ≤ MAX_STATIC_RATIO); else ValueError naming it."""
    try:
        tx, ty = (np.asarray(a, dtype=float).ravel() for a in table)
    except (TypeError, ValueError):
        raise ValueError(
            f"{name} must be a pair ({x_name}, {y_name}) of equal-length sequences"
        ) from None
    if (
        tx.size == 0
        or tx.size != ty.size
        or not (np.all(np.isfinite(tx)) and np.all(np.isfinite(ty)))
    ):
        raise ValueError(
            f"{name}: {x_name} and {y_name} must be finite and of equal, non-zero length"
        )
    if np.any(np.diff(tx) <= 0):
        raise ValueError(f"{name}: {x_name} must increase")
    if y_positive and (tx[0] < 0 or np.any(ty <= 0)):
        raise ValueError(f"{name}: {x_name} must be >= 0 and {y_name} > 0")
    y_rule = st.plausible("1", hi=MAX_STATIC_RATIO) if y_positive else st.plausible("N m")
    if not (np.all(st.plausible("rad/s")(tx)) and np.all(y_rule(ty))):
        raise ValueError(f"{name}: {x_name} or {y_name} of an implausible magnitude")
    return tx, ty

"""Parameter descriptions that :func:`~clutchlab.engagement.closed_form` and
:func:`~clutchlab.engagement.simulate` share, substituted into their docstrings (the manner of
scipy's ``doccer``): a line ``%(name)s`` of a docstring becomes the block ``name``, indented as
that line is.
"""

from __future__ import annotations

#: the driveline and clamp (the first nine parameters of both solvers, in their order)
DRIVELINE = """\
engine_speed : array_like [rad/s]
    Initial engine speed ω_e(0) ≥ 0.
engine_inertia : array_like [kg m²]
    Engine-side inertia J_e > 0 (eq. 1); ``inf`` holds the engine at ω_e(0) (as in the source
    paper (000)'s reproduction).
engine_torque : array_like [N m]
    Constant engine torque T_e (eq. 1; ignored for a held engine).
driven_inertia : array_like [kg m²]
    Driven-side inertia J_v > 0 (eq. 2).
load_torque : array_like [N m]
    Constant load torque T_m ≥ 0 (eq. 2); also the static torque that keeps a driven side at
    rest parked.
peak_capacity : array_like [N m]
    Kinetic torque capacity at full clamp C_max = z_f·μ_k·F_max·R_eff ≥ 0 (eqs. 13-14, z_f = 2
    faces).
ramp_time : array_like [s]
    Duration t_r ≥ 0 of the clamp profile; 0 is a step.
profile : {"ramp", "cubic", "quintic"}
    Clamp profile p of C(t) = C_max·p(t/t_r) (:func:`clamp_profile`); ValueError for another.
static_ratio : array_like [-]
    μ_s/μ_k ≥ 1: sticking holds up to (μ_s/μ_k)·C(t)."""

#: the initial driven speed
DRIVEN_SPEED = """\
driven_speed : array_like [rad/s]
    Initial driven speed 0 ≤ ω_c(0) ≤ ω_e(0)."""

#: the screening both solvers apply (the end of their Returns sections)
SCREENING = """\
A scenario with an input outside its domain (NaN; J ≤ 0; T_m, C_max, t_r or ω_e < 0;
μ_s/μ_k < 1; ω_c(0) outside [0, ω_e(0)]; any input outside the range stated above or of an
implausible magnitude, :mod:`clutchlab.plausible`) has status ``invalid_input`` and NaN outputs;
the others are computed as if it were not there."""

BLOCKS = {"driveline": DRIVELINE, "driven_speed": DRIVEN_SPEED, "screening": SCREENING}


def fill(func):
    """``func`` with every line ``%(name)s`` of its docstring replaced by :data:`BLOCKS` ``[name]``,
    indented as that line."""
    lines = []
    for line in func.__doc__.splitlines():
        key = line.strip()
        if key.startswith("%(") and key.endswith(")s"):
            indent = line[: len(line) - len(line.lstrip())]
            lines.extend(indent + b if b else b for b in BLOCKS[key[2:-2]].splitlines())
        else:
            lines.append(line)
    func.__doc__ = "\n".join(lines)
    return func

"""Friction fade: the friction face's temperature as a state, and the fade factor (compiled, numba).

While slipping μ_k is divided by 1 + β·(ΔT − ΔT_on)⁺, ΔT the friction face's temperature rise,
ΔT = K·I with I(t) = ∫ P(τ)/√(t − τ) dτ Duhamel's integral of the slip power P (the face as a
semi-infinite body, :mod:`clutchlab.heat`). The kernel is split as
1/√s = erf(√(λ_c s))/√s + erfc(√(λ_c s))/√s. The smooth first part is a sum of exponentials
Σ w_k e^{−λ_k s} (:func:`clutchlab.heat.kernel_modes`: non-negative least squares on
s ∈ [0, 10 s] weighted by √s, λ_k geometric with ratio 2.5 from 4λ_c down to 0.01/s, zero
weights dropped: 15 modes; max error 3.0e-4/√s), so I_slow = Σ w_k z_k with states
z_k' = P − λ_k z_k; the second part lives on s ≲ 1/λ_c and is taken quasi-statically,
∫ erfc(√(λ_c s))/√s · P(t − s) ds ≈ M0·P(t), M0 = 2/√(π λ_c) (error ≈ M1·P',
M1 = 2/(3√π λ_c^{3/2}) = 1.5e-6 s^1.5). λ_c = 4000/s: I within 7e-5 of its peak for a source
paper (000)-like slip power (1000/s: 6e-4), and the stiffest mode (6 552/s) within DOPRI5's
stability for steps up to 0.5 ms. Checked against a Picard iteration with the exact kernel in
tests/test_fade.py.

The modes are the state columns Z0 … Z0 + NZ − 1 (:mod:`clutchlab.engagement._layout`); these
functions are the only ones that know how the face temperature is represented.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._layout import FACE_K, FADE, FADE_ON, NZ, Z0

JIT = dict(cache=True, error_model="numpy", _nrt=False)

SOE_LAMBDA = np.array(
    [
        6551.82794011116,
        2682.9030848013267,
        1098.619961975734,
        449.87306015227944,
        184.21818031306321,
        75.43536380322267,
        30.889970264900256,
        12.64911064067352,
        5.179674782070132,
        2.121021122366016,
        0.8685353406927243,
        0.3556558820077846,
        0.14563725905021752,
        0.059636891435401344,
        0.01,
    ]
)
SOE_WEIGHT = np.array(
    [
        1.0530600051732957,
        23.723283392222843,
        16.97838879544467,
        10.605038794078247,
        6.868111310665909,
        4.362443640753169,
        2.805304573335715,
        1.7886805840332438,
        1.1483443174771812,
        0.7317541220924253,
        0.47246489841591777,
        0.29325528400612916,
        0.20871327506035586,
        0.11227925977551365,
        0.21804431165750585,
    ]
)
SOE_CUT = 4000.0  # λ_c [1/s]
SOE_M0 = 2.0 / math.sqrt(math.pi * SOE_CUT)
SOE_TMAX = 10.0  # [s]: the longest window the fit covers
assert SOE_LAMBDA.size == NZ


@njit(**JIT)
def face_rise(y, q):
    """Friction-face temperature rise [K] from the slow modes alone (the slip power's quasi-static
    part M0·P is added by :func:`fade_factor`)."""
    acc = 0.0
    for k in range(NZ):
        acc += SOE_WEIGHT[k] * y[Z0 + k]
    return q[FACE_K] * acc


@njit(**JIT)
def fade_factor(rise_slow, p0, q):
    """(fade factor g, face temperature rise ΔT) that solve ΔT = ΔT_slow + K·M0·P0·g(ΔT) with
    g = 1/(1 + β·(ΔT − ΔT_on)⁺) (β = q[FADE], ΔT_on = q[FADE_ON], K = q[FACE_K]; P0 ≥ 0 the
    slip power at g = 1): in closed form, a quadratic in u = ΔT − ΔT_on."""
    a = q[FACE_K] * SOE_M0 * p0
    c = rise_slow - q[FADE_ON]
    if c + a <= 0.0:
        return 1.0, rise_slow + a
    beta = q[FADE]
    b = 1.0 - beta * c
    root = math.sqrt(b * b + 4.0 * beta * (c + a))
    u = 2.0 * (c + a) / (b + root) if b >= 0.0 else (root - b) / (2.0 * beta)
    return 1.0 / (1.0 + beta * u), q[FADE_ON] + u


@njit(**JIT, inline="always")
def mode_rates(y, p, dy):
    """The modes' derivatives z_k' = P − λ_k z_k under the slip power p [W]."""
    for k in range(NZ):
        dy[Z0 + k] = p - SOE_LAMBDA[k] * y[Z0 + k]


@njit(**JIT, inline="always")
def fade_torque_rate(x0, b, slip, torque, slip_rate, dy):
    """d/dt of the slipping clutch torque X with fade [N m/s]: X' = x0 − b·ΔT'/K with
    ΔT' = K·(Σ w_k z_k' + M0·P'), P' = X'·Δω + T_c·Δω' (x0 the rate at constant g, b = s·f·C·β·g²·K),
    linear in X', solved for it."""
    s1 = 0.0
    for k in range(NZ):
        s1 += SOE_WEIGHT[k] * dy[Z0 + k]
    return (x0 - b * (s1 + SOE_M0 * torque * slip_rate)) / (1.0 + b * SOE_M0 * slip)


@njit(**JIT)
def decay_modes(y, q, dt):
    """The face temperature's modes over dt without slip power: z_k·exp(−λ_k dt)."""
    if q[FADE] > 0.0:
        for k in range(NZ):
            y[Z0 + k] *= math.exp(-SOE_LAMBDA[k] * dt)


@njit(**JIT, inline="always")
def face_rise_total(y, q, torque, slip):
    """The face temperature rise [K] with the slip power's quasi-static part (0 when locked: the
    slip is exactly 0 then)."""
    return face_rise(y, q) + q[FACE_K] * SOE_M0 * torque * slip

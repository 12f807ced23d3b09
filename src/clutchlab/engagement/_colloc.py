"""Exponential collocation of a slipping phase of the compliant engagement with a nonlinear friction
law (a Stribeck law, a friction table, friction fade): the linear part exactly, the friction
torque as the only nonlinear forcing.

While the clutch slips with a held engine, the compliant driveline (source paper (000) eqs. 1-2
with the damper springs between plate hub and output) is linear except for the clutch torque
D(t, ω_h) = s·f(|Δω|)·g·C(t) (f the slip law, g the fade factor, C the clamp profile's capacity).
With the output moving, the mass-weighted speed ω_m = (J_h·ω_h + J_r·ω_r)/J_v and the damper
twist θ obey (:mod:`clutchlab.engagement._linear_phase`)

    J_v·ω_m' = D − T_m,     m·θ'' + c·θ' + K·θ = ρ_r·D + ρ_a·T_m,     ω_h = ω_m + ρ_r·θ',

(m = J_h·J_r/J_v, ρ_r = J_r/J_v, ρ_a = J_h/J_v); with the output parked, J_h·θ'' + c·θ' + K·θ = D,
ω_h = θ'. The twist oscillates at ω₀ = √(K/m) (≈ 900 rad/s in the source paper's design): a
Runge-Kutta method must follow every period (DOPRI5: about 20 steps a period, 700-900 steps an
engagement). Here the oscillation is never stepped through. Each step [t₀, t₀ + h]:

* the friction torque's sensitivity to the hub speed, γ = ∂D/∂ω_h (the falling μ of a Stribeck
  law is a negative damping), is frozen at the step's start and joins the linear part exactly: the
  mean mode becomes ω_m' = κ·ω_m + …, κ = γ/J_v, the twist's damping c − ρ_r²·γ (parked: c − γ);
  the rest, N = D − γ·ω_h, and the cross terms are the forcing;
* the forcing is interpolated by a polynomial of degree ``NDEG`` on the step's Chebyshev–Lobatto
  nodes (in v = 2τ/h − 1 ∈ [−1, 1]), and the linear equations are solved exactly for it: the twist
  as a polynomial particular solution plus the free response e^(−aτ)(h₀·cos ω_dτ + …), the mean
  mode as a power series times e^(κτ);
* the node values are iterated to a fixed point (Picard; the frozen γ makes it contract), and the
  step is accepted when the interpolation error of the forcing, estimated by its last two
  Chebyshev coefficients, is below rtol of the forcing's size; the next step from that error's
  decay. The step follows the forcing's smoothness — the clamp profile, the slip law along the
  slip, the twist's small oscillation through f' — not the oscillation's period.

The solution is a closed form on the whole step (dense output): events (lock-up, break-away of the
output, its stop, a friction-table point crossed) are roots of it, placed by Illinois on the dense
solution (no re-integration); the peaks (slip power, clutch torque, output jerk) are taken at the
nodes and refined on the dense solution; the works are the exact integrals of the interpolated
node values (Clenshaw–Curtis). The friction face's temperature modes z_k' = P − λ_k·z_k of friction
fade (:mod:`clutchlab.engagement._heat_modes`) are integrated exactly for the step's slip power polynomial.

The method lives in four modules: this one (the nodes, polynomials and linear solutions, and the
step's named record :class:`Colloc`), :mod:`clutchlab.engagement._slip_step` (one step: the
Picard iteration of the clutch torque at the nodes), :mod:`clutchlab.engagement._slip_records`
(events, peaks, works and slip power samples of an accepted step) and
:mod:`clutchlab.engagement._slip_phase` (the step loop of a phase, called by the driver). No
allocation: every array lives in the batch's :class:`Colloc` record (:func:`new_colloc`), so the
functions are compiled without numba's reference counting like the rest of the solver.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from ._heat_modes import N_LEVELS
from ._layout import NZ

JIT = dict(cache=True, error_model="numpy", _nrt=False)

NDEG = 12  # degree of the forcing's interpolant (NDEG + 1 Chebyshev-Lobatto nodes)
NN = NDEG + 1
LSER = 72  # longest power series (particular solutions of short steps, the mean mode)
HW_TOPDOWN = 8.0  # ω₀·h above which the twist's particular solution is the top-down polynomial


def _node_tables(p):
    """Nodes v_i = −cos(πi/p) (ascending), the matrix taking node values to the coefficients of the
    interpolant in powers of v, its last two Chebyshev coefficients' rows, and the weights of
    ∫_{−1}^{1} (Clenshaw–Curtis), computed in extended precision."""
    ld = np.longdouble
    j = np.arange(p + 1)
    x = np.cos(np.pi * j.astype(ld) / ld(p))  # descending
    tk = np.cos(np.pi * np.outer(j, j).astype(ld) / ld(p))  # T_k(x_j)
    wgt = np.ones(p + 1, dtype=ld)
    wgt[0] = wgt[-1] = 0.5
    cheb = (ld(2) / ld(p)) * tk * wgt[None, :]
    cheb[0] *= 0.5
    cheb[-1] *= 0.5
    mono = np.zeros((p + 1, p + 1), dtype=ld)  # row k: monomial coefficients of T_k
    mono[0, 0] = 1
    mono[1, 1] = 1
    for k in range(2, p + 1):
        mono[k, 1:] = 2 * mono[k - 1, :-1]
        mono[k] -= mono[k - 2]
    vinv = (mono.T @ cheb)[:, ::-1]  # node values (ascending v) -> power coefficients
    tail = cheb[[p, p - 1]][:, ::-1]
    ints = np.array([(1 + (-1) ** n) / ld(n + 1) for n in range(p + 1)], dtype=ld)
    cc = ints @ vinv
    return (
        x[::-1].astype(float),
        vinv.astype(float),
        tail.astype(float),
        cc.astype(float),
    )


NODES, VINV, TAIL, CC_WEIGHTS = _node_tables(NDEG)
NODES[0], NODES[-1] = -1.0, 1.0

# ---- the step's named record ----------------------------------------------------------------

#: Arrays of one collocation step (each LSER long unless said; node values at the NN nodes, power
#: coefficients in v = 2τ/h − 1): ``tau`` node times from the step's start [s], ``cap`` capacity
#: C(t₀ + τ_i) [N m], ``cf``/``sf`` the free response's basis e^(−aτ)·cos ω_dτ and
#: e^(−aτ)·sin(ω_dτ)/ω_d at the nodes, ``eb`` e^(βv_i) of the mean mode, ``th``/``thd`` twist θ
#: [rad] and its rate θ' [rad/s], ``wm`` mean speed ω_m (0 parked), ``wh`` hub speed [rad/s],
#: ``d`` clutch torque D [N m] (the iterate), ``gnew`` the torque the law gives for the iterate's
#: solution (the fixed-point map G), ``fprev``/``gprev`` the previous iteration's residual and map
#: value (Anderson mixing), ``fo``/``fm`` the twist's and the mean mode's forcing, ``ao``/``am``
#: their power coefficients, ``xp`` the twist's particular solution (power coefficients), ``wser``
#: the mean mode's series W(v), ``g`` fade factor, ``rise`` face temperature rise ΔT [K], ``slow``
#: its slow part K·Σ w_k·z_k [K], ``p`` slip power [W], ``ap``/``ad`` slip power's and clutch
#: torque's power coefficients, ``thdp`` θ' less its free response, ``tmp``/``tmp2``/``ta``/``tb``
#: scratch, ``modes`` the face temperature's modes at the step's start (NZ), ``comb``/``htmp`` the
#: modes' summed and single series (scratch), ``enode`` e^(−Λ_k(1 + v_i)) of the modes (NZ × LSER),
#: ``zfree`` the modes' weighted free decay from the step's start at the nodes; the batch's maps
#: of the modes over the steps of the grid (:func:`clutchlab.engagement._heat_modes.level_map`,
#: N_LEVELS of each): ``fmap`` the forced response at the nodes to each power vʲ (NN × NN), ``fdec``
#: the free decay (NZ × NN), ``fend`` the modes at the step's end (NZ × (NN + 1)), ``fset`` 1 where
#: built; ``sc`` the step's scalars (a one-element array of :data:`STEP`).
Colloc = namedtuple(
    "Colloc",
    [
        "tau",
        "cap",
        "cf",
        "sf",
        "eb",
        "th",
        "thd",
        "wm",
        "wh",
        "d",
        "gnew",
        "fprev",
        "gprev",
        "fo",
        "fm",
        "ao",
        "am",
        "xp",
        "wser",
        "g",
        "rise",
        "slow",
        "p",
        "ap",
        "ad",
        "thdp",
        "tmp",
        "tmp2",
        "ta",
        "tb",
        "modes",
        "comb",
        "htmp",
        "enode",
        "zfree",
        "fmap",
        "fdec",
        "fend",
        "fset",
        "sc",
    ],
)

#: The scalars of one collocation step (and the step the controller proposes next).
STEP = np.dtype(
    [
        ("h", np.float64),  # step [s]
        ("t0", np.float64),  # start [s]
        ("gamma", np.float64),  # γ = ∂D/∂ω_h frozen at the start [N m s]
        ("a", np.float64),  # free response decay a [1/s]
        ("w2", np.float64),  # ω_d² [1/s²]
        ("h0", np.float64),  # free response h₀ [rad], h₁ [rad/s]
        ("h1", np.float64),
        ("mo", np.float64),  # oscillator mass [kg m²], damping with γ [N m s], stiffness [N m]
        ("co", np.float64),
        ("nxp", np.int64),  # length of the particular solution's coefficients
        ("beta", np.float64),  # β = κ·h/2 of the mean mode
        ("amp", np.float64),  # A of ω_m = A·e^(βv) + W(v) [rad/s]
        ("nws", np.int64),  # length of W
        ("parked", np.bool_),  # the output parked
        ("we", np.float64),  # engine speed (held) [rad/s]
        ("tm", np.float64),  # load torque (static, constant over the step) [N m]
        ("sign", np.float64),  # slip direction s
        ("h_next", np.float64),  # the step the controller proposes next [s] (0: none yet)
        ("iters", np.int64),  # Picard iterations of the step
        ("x_lo", np.float64),  # friction table: the step's segment [x_lo, x_hi] of s·Δω (±inf …
        ("x_hi", np.float64),  # … none) [rad/s]
        ("f_lo", np.float64),  # μ/μ_k at x_lo and its slope [s/rad] (the segment's line)
        ("slope", np.float64),
        ("n_scan", np.int64),  # dense jerk scans (a count, for the measurements)
        ("level", np.int64),  # fade: the step's index on the step grid (−1: off it)
    ]
)


def new_colloc():
    """The batch's :class:`Colloc` record (allocated once; every scenario reuses it)."""
    rows = [np.zeros(LSER) for _ in range(len(Colloc._fields) - 7)]
    maps = (
        np.zeros((N_LEVELS, NN, NN)),
        np.zeros((N_LEVELS, NZ, NN)),
        np.zeros((N_LEVELS, NZ, NN + 1)),
        np.zeros(N_LEVELS),
    )
    return Colloc(*rows, np.zeros((NZ, LSER)), np.zeros(LSER), *maps, np.zeros(1, STEP))


# ---- polynomials in v on the step's nodes ------------------------------------------------------


@njit(**JIT)
def poly_eval(c, n, v):
    """(value, d/dv) of Σ_{j<n} c_j·vʲ (Horner)."""
    p = 0.0
    dp = 0.0
    for j in range(n - 1, -1, -1):
        dp = dp * v + p
        p = p * v + c[j]
    return p, dp


@njit(**JIT)
def fit(values, coef):
    """Power coefficients (in v) of the interpolant of node values (ascending nodes)."""
    for n in range(NN):
        coef[n] = 0.0
    for i in range(NN):
        vi = values[i]
        for n in range(NN):
            coef[n] += VINV[n, i] * vi


@njit(**JIT)
def poly_nodes(c, n, val, der):
    """Values and d/dv at the NN nodes of Σ_{j<n} c_j·vʲ (Horner on every node at once: the nodes'
    chains are independent, so they run side by side; each node's arithmetic as
    :func:`poly_eval`'s)."""
    for i in range(NN):
        val[i] = 0.0
        der[i] = 0.0
    for j in range(n - 1, -1, -1):
        cj = c[j]
        for i in range(NN):
            der[i] = der[i] * NODES[i] + val[i]
            val[i] = val[i] * NODES[i] + cj


@njit(**JIT)
def tail_error(values):
    """|c_N| + |c_{N−1}| of the Chebyshev coefficients of the node values' interpolant: the size of
    its highest terms, an estimate of the interpolation error."""
    a = 0.0
    b = 0.0
    for i in range(NN):
        a += TAIL[0, i] * values[i]
        b += TAIL[1, i] * values[i]
    return abs(a) + abs(b)


@njit(**JIT)
def integral(coef, v_end):
    """∫_{−1}^{v_end} of the polynomial with power coefficients coef (length NN) in v."""
    acc = 0.0
    for n in range(NN - 1, -1, -1):
        acc = acc * v_end + coef[n] / (n + 1)
    acc *= v_end
    lo = 0.0
    for n in range(NN - 1, -1, -1):
        lo = lo * (-1.0) + coef[n] / (n + 1)
    lo *= -1.0
    return acc - lo


@njit(**JIT)
def taylor_at(coef, n, x, out):
    """Taylor coefficients at x of the polynomial Σ_{j<n} coef_j·vʲ (synthetic division):
    out_j = Q⁽ʲ⁾(x)/j!."""
    for j in range(n):
        out[j] = coef[j]
    for kk in range(n - 1):
        for j in range(n - 2, kk - 1, -1):
            out[j] += x * out[j + 1]


@njit(**JIT)
def free_basis(tau, a, w2):
    """(cf, sf) with the free response h = h₀·cf + (h₁ + a·h₀)·sf and
    h' = h₁·cf − (a·h₁ + (ω_d² + a²)·h₀)·sf (as :func:`clutchlab._linear_phase.hh`)."""
    if w2 > 0.0:
        w = math.sqrt(w2)
        e = math.exp(-a * tau)
        return e * math.cos(w * tau), e * math.sin(w * tau) / w
    if w2 < 0.0:
        b = math.sqrt(-w2)
        if b * tau < 1.0:
            e = math.exp(-a * tau)
            return e * math.cosh(b * tau), e * math.sinh(b * tau) / b
        e1 = math.exp((b - a) * tau)
        e2 = math.exp(-(a + b) * tau)
        return 0.5 * (e1 + e2), 0.5 * (e1 - e2) / b
    e = math.exp(-a * tau)
    return e, e * tau


@njit(**JIT)
def osc_particular(f, mv, cv, k, hw, xp):
    """A particular solution of mv·x'' + cv·x' + k·x = f(v) (f: NN power coefficients in v) as
    power coefficients in v; returns their count. For ω₀·h ≥ HW_TOPDOWN the polynomial one (top-down
    recurrence, from the highest degree: its terms shrink by (2/(ω₀h))² per two degrees); for
    shorter steps the power series with x(0) = x'(0) = 0 (upward recurrence: terms of the size of
    (ω₀h/2)ⁿ/n!), truncated where its terms fall below 1e-17 of the largest, at most LSER."""
    if hw >= HW_TOPDOWN:
        for j in range(NN - 1, -1, -1):
            acc = f[j]
            if j + 1 < NN:
                acc -= cv * (j + 1) * xp[j + 1]
            if j + 2 < NN:
                acc -= mv * (j + 2) * (j + 1) * xp[j + 2]
            xp[j] = acc / k
        return NN
    xp[0] = 0.0
    xp[1] = 0.0
    big = 0.0
    n = 0
    while n + 2 < LSER:
        fn = f[n] if n < NN else 0.0
        x2 = (fn - cv * (n + 1) * xp[n + 1] - k * xp[n]) / (mv * (n + 2) * (n + 1))
        xp[n + 2] = x2
        big = max(big, abs(x2))
        n += 1
        if n >= NN and abs(x2) + abs(xp[n]) <= 1e-17 * big:
            break
    return n + 2


@njit(**JIT)
def mean_series(f, beta, half_h, w):
    """The series W(v) = Σ w_n vⁿ with W(0) = 0 of W' = β·W + (h/2)·f(v) (f: NN power coefficients in
    v); returns its length (terms below 1e-17 of the largest dropped, at most LSER). The mean
    mode is then A·e^(βv) + W(v)."""
    w[0] = 0.0
    big = 0.0
    n = 0
    while n + 1 < LSER:
        fn = f[n] if n < NN else 0.0
        wn = (beta * w[n] + half_h * fn) / (n + 1)
        w[n + 1] = wn
        big = max(big, abs(wn))
        n += 1
        if n >= NN and abs(wn) <= 1e-17 * big:
            break
    return n + 1

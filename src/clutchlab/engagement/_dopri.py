"""The stepper of the numerical solver (compiled, numba): Dormand-Prince 5(4) with its controller.

One step (:func:`step`) integrates only the moving state components
(:func:`clutchlab.engagement._physics.n_active`); its error norm (:func:`err_norm`), Hairer's
starting step (:func:`initial_step`), the order-4 continuous extension (:func:`dense_coefficients`,
:func:`dense`), the cubic Hermite interpolant (:func:`hermite`) and Gustafsson's predictive
step-size control (:func:`control`, as in radau5.f: it anticipates the error growing towards
lock-up; 25-40 % fewer rejections than the PI control of dopri5.f here) are the whole interface
the driver uses: another one-step method with a continuous extension can replace this module.

References
----------
.. [1] Hairer E., Nørsett S.P., Wanner G. (1993), Solving Ordinary Differential Equations I,
   2nd ed., Springer, sections II.4-II.6 (dopri5.f, HINIT, the continuous extension).
.. [2] Gustafsson K. (1994), "Control-theoretic techniques for stepsize selection in implicit
   Runge-Kutta methods", ACM TOMS 20(4) (the predictive controller of radau5.f).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._layout import H, R
from ._physics import forces, n_active

JIT = dict(cache=True, error_model="numpy", _nrt=False)

# Dormand-Prince 5(4)
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = np.zeros((7, 6))
for _i, _row in enumerate(
    [
        [],
        [1 / 5],
        [3 / 40, 9 / 40],
        [44 / 45, -56 / 15, 32 / 9],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
        [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
    ]
):
    _A[_i, : len(_row)] = _row
_B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0])
_E = _B - np.array(
    [5179 / 57600, 0.0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40]
)
EPS = np.finfo(float).eps
_FAC_ACC_MIN = 0.01**0.2  # Gustafsson's controller: accepted errors below 1e-2 count as 1e-2
# DOPRI5 continuous extension of order 4 (Hairer, Norsett & Wanner, dopri5.f)
_D = np.array(
    [
        -12715105075 / 11282082432,
        0.0,
        87487479700 / 32700410799,
        -10690763975 / 1880347072,
        701980252875 / 199316789632,
        -1453857185 / 822651844,
        69997945 / 29380423,
    ]
)


@njit(**JIT)
def copy(dst, src):
    """dst[:] = src (no allocation)."""
    for i in range(dst.size):
        dst[i] = src[i]


@njit(**JIT)
def step(t, y, h, q, mode, d0, kk, yi, y_new, err):
    """One DOPRI5 step from (t, y) with first stage d0; fills y_new and err (only the moving
    components are integrated; the others are copied)."""
    n = n_active(q, mode)
    for m in range(n, y.size):
        yi[m] = y_new[m] = y[m]
        err[m] = 0.0
    for m in range(y.size):
        kk[0, m] = d0[m]
    for i in range(1, 7):
        for m in range(n):
            acc = y[m]
            for j in range(i):
                acc += h * _A[i, j] * kk[j, m]
            yi[m] = acc
        forces(t + _C[i] * h, yi, q, mode, kk[i])
    for m in range(n):
        a = y[m]
        e = 0.0
        for j in range(7):
            a += h * _B[j] * kk[j, m]
            e += h * _E[j] * kk[j, m]
        y_new[m] = a
        err[m] = e


@njit(**JIT)
def err_norm(y0, y1, err, rtol, atol, n, compliant):
    """RMS norm of the error estimate over the n moving components, scaled by atol + rtol·|y|. In
    the compliant model the output speed's entry is the error of the relative speed
    ω_h − ω_r scaled by its own size: the twist rate, and with it the output jerk K·θ' + c·θ'', is
    a small difference of large speeds whose error the output speed's scale would not control."""
    acc = 0.0
    for m in range(n):
        if m == R and compliant:
            e = err[H] - err[R]
            sc = atol + rtol * max(abs(y0[H] - y0[R]), abs(y1[H] - y1[R]))
        else:
            e = err[m]
            sc = atol + rtol * max(abs(y0[m]), abs(y1[m]))
        acc += (e / sc) ** 2
    return math.sqrt(acc / n)


@njit(**JIT)
def initial_step(t, y, d, q, mode, rtol, atol, hmax, y1, d1):
    """Starting step size (Hairer, Norsett & Wanner, dopri5.f HINIT): from the sizes of y, f and
    a difference estimate of f' so that the first step's error is about the tolerance; used at
    t = 0 and after every mode switch (the derivatives jump there). HINIT caps the step at 100
    times its probe; where the cap bites, the estimate is repeated once at the capped step."""
    n = n_active(q, mode)
    dnf = dny = 0.0
    for m in range(n):
        sk = atol + rtol * abs(y[m])
        dnf += (d[m] / sk) ** 2
        dny += (y[m] / sk) ** 2
    h = 1e-6 if (dnf <= 1e-10 or dny <= 1e-10) else 0.01 * math.sqrt(dny / dnf)
    h = min(h, hmax)
    for _ in range(2):  # HINIT, then once more with the difference taken at the proposed step
        for m in range(y.size):
            y1[m] = y[m] + h * d[m]
        forces(t + h, y1, q, mode, d1)
        der2 = 0.0
        for m in range(n):
            sk = atol + rtol * abs(y[m])
            der2 += ((d1[m] - d[m]) / sk) ** 2
        der12 = max(math.sqrt(der2) / h, math.sqrt(dnf))
        h1 = max(1e-6, h * 1e-3) if der12 <= 1e-15 else (0.01 / der12) ** 0.2
        h_new = min(100.0 * h, h1, hmax)
        if h_new <= h:
            return h_new
        h = h_new
    return h


@njit(**JIT, inline="always")
def control(sc, norm, h_try):
    """Gustafsson's predictive step-size control after a step of h_try with error ``norm``: the
    smaller of the elementary and the predicted step, factors in [0.2, 10], safety 0.9, no growth
    after a rejection. Sets the next step ``sc.h`` (``sc``: the scenario's record); returns whether
    the step is accepted (norm ≤ 1)."""
    fac11 = norm**0.2 if norm > 1e-6 else 0.0  # (below, growth is capped at 10 anyway)
    if norm > 1.0:
        sc.h = h_try / min(5.0, fac11 / 0.9)
        sc.rejected = True
        return False
    quot = fac11 / 0.9
    if sc.h_acc > 0.0:
        quot = max(quot, (sc.h_acc / h_try) * fac11 * fac11 / sc.fac_acc / 0.9)
    h = h_try / max(0.1, min(5.0, quot))
    if sc.rejected:
        h = min(h, h_try)
    sc.h = h
    sc.h_acc_prev, sc.fac_acc_prev = sc.h_acc, sc.fac_acc
    sc.h_acc, sc.fac_acc, sc.rejected = (
        h_try,
        max(_FAC_ACC_MIN, fac11),
        False,
    )  # max(1e-2, err)^(1/5)
    return True


@njit(**JIT, inline="always")
def retry_shorter(sc, tau, norm):
    """A step cut at an event (to tau) failed the tolerance (``norm`` > 1): retry it shorter, with
    the controller's memory as before that step's acceptance."""
    sc.h = tau / min(5.0, max(norm**0.2 / 0.9, 1.0 / 0.9))
    sc.h_acc, sc.fac_acc, sc.rejected = sc.h_acc_prev, sc.fac_acc_prev, True


@njit(**JIT, inline="always")
def restart(sc, h):
    """A fresh start (t = 0 or a mode switch) with the step h: the controller forgets."""
    sc.h = h
    sc.h_acc, sc.fac_acc, sc.rejected = 0.0, 1.0, False


@njit(**JIT)
def hermite(y0, d0, y1, d1, h, th, out):
    """The cubic Hermite interpolant of a step at the fraction th."""
    h00 = 2 * th**3 - 3 * th**2 + 1
    h10 = th**3 - 2 * th**2 + th
    h01 = -2 * th**3 + 3 * th**2
    h11 = th**3 - th**2
    for m in range(out.size):
        out[m] = h00 * y0[m] + h10 * h * d0[m] + h01 * y1[m] + h11 * h * d1[m]


@njit(**JIT)
def dense_coefficients(y0, y1, kk, h, rc):
    """Coefficients of the step's order-4 continuous extension (stages kk of the step from y0)."""
    for m in range(y0.size):
        ydiff = y1[m] - y0[m]
        bspl = h * kk[0, m] - ydiff
        acc = 0.0
        for j in range(7):
            acc += _D[j] * kk[j, m]
        rc[0, m] = y0[m]
        rc[1, m] = ydiff
        rc[2, m] = bspl
        rc[3, m] = ydiff - h * kk[6, m] - bspl
        rc[4, m] = h * acc


@njit(**JIT)
def dense(rc, th, out):
    """The state at the fraction ``th`` of the step (continuous extension)."""
    for m in range(out.size):
        out[m] = dense_component(rc, th, m)


@njit(**JIT)
def dense_component(rc, th, m):
    """Component m of the continuous extension at the fraction th."""
    u = 1.0 - th
    return rc[0, m] + th * (rc[1, m] + u * (rc[2, m] + th * (rc[3, m] + u * rc[4, m])))

"""Compiled explicit Runge-Kutta step of order 8 (DOP853) with its dense output of order 7.

Dormand & Prince's 12-stage method as in Hairer's DOP853 (Hairer, Nørsett & Wanner, Solving
Ordinary Differential Equations I, section II.10): the step of order 8, the error estimate that
blends its embedded 5th- and 3rd-order solutions, and the continuous extension of order 7 that
costs 3 more stages and is computed only for a step in which an event is located. The tableau
(:mod:`clutchlab._dop853_tableau`) is the one scipy's ``solve_ivp(method="DOP853")`` uses.
Stages are the named fields of a :data:`Dop853Work` record (:func:`work`); nothing here
allocates.

The method is explicit: its steps are stable while h·|λ| ≤ :data:`STABILITY_RADIUS` for every
decaying eigenvalue λ of the Jacobian (the stability region contains the half-disc of that
radius up to 85° from the negative real axis; ``tests/test_roller.py`` checks it). The roller's
driver (:mod:`clutchlab._contact_kernel`) uses it where the contact is not stiff at the step it
takes, and the L-stable SDIRK4 (:mod:`clutchlab._sdirk4`) where it is.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from . import _dop853_tableau as _tableau
from ._contact_systems import JIT, rhs

N_STAGES = 12  # stages of the step; stage 12 is f at the step's end (the next step's first)
N_DENSE_STAGES = 16  # with the 3 stages of the continuous extension
A = np.ascontiguousarray(_tableau.A)
B = np.ascontiguousarray(_tableau.B)
C = np.ascontiguousarray(_tableau.C)
E3 = np.ascontiguousarray(_tableau.E3)
E5 = np.ascontiguousarray(_tableau.E5)
D = np.ascontiguousarray(_tableau.D)
ERROR_ORDER = 7  # the step-size controller's exponent is −1/(ERROR_ORDER + 1)
STABILITY_RADIUS = 6.2
# step-size controller: safety factor, largest growth and largest cut of a step
SAFETY, MAX_FACTOR, MIN_FACTOR = 0.9, 6.0, 0.2

#: scratch of one step: the stage derivatives k (16 × n; k[0] = f at the step's start, set by the
#: caller, k[12] = f at its end), the stage state y_stage, the dense-output coefficients dense
#: (7 × n) and a Jacobian the right-hand side may fill
Dop853Work = namedtuple("Dop853Work", ["k", "y_stage", "dense", "jac"])


@njit(cache=True, error_model="numpy")
def work(n):
    """A fresh :data:`Dop853Work` for systems of size n."""
    return Dop853Work(
        np.zeros((N_DENSE_STAGES, n)), np.zeros(n), np.zeros((7, n)), np.zeros((n, n))
    )


@njit(**JIT)
def _stages(system, t, y, h, p, mode, ws, first, last):
    """Stages first … last − 1 of the extended tableau from the ones before."""
    n = y.size
    for s in range(first, last):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += A[s, j] * ws.k[j, i]
            ws.y_stage[i] = y[i] + h * acc
        rhs(system, t + C[s] * h, ws.y_stage, p, mode, ws.k[s], ws.jac, False)


@njit(**JIT)
def step(system, t, y, h, p, mode, rtol, atol, y_new, ws):
    """One DOP853 step from (t, y) of size h into ``y_new``; ``ws.k[0]`` must hold f(t, y).
    Returns (error norm, f evals); ``ws.k[12]`` holds f(t + h, y_new) after it."""
    n = y.size
    _stages(system, t, y, h, p, mode, ws, 1, N_STAGES)
    # the order-8 solution and f at its end
    for i in range(n):
        acc = 0.0
        for j in range(N_STAGES):
            acc += B[j] * ws.k[j, i]
        y_new[i] = y[i] + h * acc
    rhs(system, t + h, y_new, p, mode, ws.k[N_STAGES], ws.jac, False)
    # the error estimate: the 5th-order one, corrected by the 3rd-order one (Hairer's err·err5 /
    # √(err5² + 0.01·err3²)) in the weights atol + rtol·max(|y|, |y_new|)
    e5, e3 = 0.0, 0.0
    for i in range(n):
        a5, a3 = 0.0, 0.0
        for j in range(N_STAGES + 1):
            a5 += E5[j] * ws.k[j, i]
            a3 += E3[j] * ws.k[j, i]
        scale = atol[i] + rtol * max(abs(y[i]), abs(y_new[i]))
        e5 += (a5 / scale) ** 2
        e3 += (a3 / scale) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0, N_STAGES
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n), N_STAGES


@njit(**JIT)
def new_step(h, err_norm, after_reject):
    """The next step size after a step of size h with error norm ``err_norm`` (no growth right
    after a rejected step)."""
    if err_norm == 0.0:
        factor = MAX_FACTOR
    else:
        factor = min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err_norm ** (-1.0 / (ERROR_ORDER + 1))))
    if after_reject:
        factor = min(1.0, factor)
    return h * factor


@njit(**JIT)
def prepare_dense(system, t, y, y_new, h, p, mode, ws):
    """The continuous extension of the step just taken (its stages still in ``ws.k``): 3 more
    stages and the 7 coefficient rows ``ws.dense``. Returns the f evals (3)."""
    n = y.size
    _stages(system, t, y, h, p, mode, ws, N_STAGES + 1, N_DENSE_STAGES)
    for i in range(n):
        dy = y_new[i] - y[i]
        ws.dense[0, i] = dy
        ws.dense[1, i] = h * ws.k[0, i] - dy
        ws.dense[2, i] = 2.0 * dy - h * (ws.k[N_STAGES, i] + ws.k[0, i])
        for r in range(4):
            acc = 0.0
            for j in range(N_DENSE_STAGES):
                acc += D[r, j] * ws.k[j, i]
            ws.dense[3 + r, i] = h * acc
    return N_DENSE_STAGES - N_STAGES - 1


@njit(**JIT)
def dense_state(ws, y, x, out):
    """The continuous extension at θ = x ∈ [0, 1] of the step from y (:func:`prepare_dense`)."""
    for i in range(y.size):
        acc = 0.0
        for r in range(6, -1, -1):
            acc = (acc + ws.dense[r, i]) * (x if r % 2 == 0 else 1.0 - x)
        out[i] = y[i] + acc

"""The closed form's integrals and peaks: exact works, peak slip power, slip jerk, slip power samples.

The speeds of :class:`clutchlab.engagement._lockup.Drive` are polynomials on each piece between
the knots (0, parking, start of motion, the profile's end, the stop), so the works over [0, t_stop]
(slip work, eq. 11 of source paper (000); load and input work) are exact Gauss-Legendre sums, and
the slip jerk (eq. 12) is the largest dC/dt while the driven side moves, over J_v.
"""

from __future__ import annotations

import numpy as np

from ._power import flash_peaks
from ._profile import _P, _polyval

CLOSED_FORM_POWER_SAMPLES = 96  # slip power samples on each polynomial piece (flash_peak)


def knots(d, ramp_end, t_stop):
    """The ends of the polynomial pieces of [0, t_stop], sorted: list of arrays [s]."""
    return list(
        np.sort(
            np.stack(
                [
                    np.zeros_like(t_stop),
                    np.minimum(d.t_p, t_stop),
                    np.minimum(d.t0, t_stop),
                    np.minimum(ramp_end, t_stop),
                    t_stop,
                ]
            ),
            axis=0,
        )
    )


def works(d, pieces):
    """(slip, load, input) work over the pieces [J]: Gauss-Legendre with just enough nodes on
    each polynomial piece (exact: integrands of degree 2n − 1)."""
    nodes = {"ramp": 2, "cubic": 4, "quintic": 6}[d.profile]
    gx, gw = np.polynomial.legendre.leggauss(nodes)
    w_slip = w_in = w_load = 0.0
    for a, b in zip(pieces[:-1], pieces[1:], strict=False):
        half, mid = 0.5 * (b - a), 0.5 * (b + a)
        for xg, wg in zip(gx, gw, strict=False):
            c, dw, we, wc = d.state(mid + half * xg)
            wt = wg * half
            w_slip = w_slip + wt * c * dw
            w_load = w_load + wt * d.tm * wc
            w_in = w_in + wt * np.where(d.held, c * d.we0, d.te * we)
    return w_slip, w_load, w_in


def peak_power(d, pieces, a_coef, b_coef):
    """max of the slip power C·Δω over [0, t_stop] [W].

    Linear ramp: the power is a cubic on each ramp piece, so its stationary points are quadratic
    roots (evaluated with the end points). Smooth steps: golden-section search (unimodal).
    """
    t_stop = pieces[-1]
    if d.profile != "ramp":
        return _peak_power_golden(d.state, pieces)
    a_r, inv_je, te, we0, t0, state = d.cmax / d.trs, d.inv_je, d.te, d.we0, d.t0, d.state
    cands = list(pieces)
    with np.errstate(divide="ignore", invalid="ignore"):
        # parked piece: P = a t (ω_e0 + J_e⁻¹(T_e t − a t²/2)) -> P' = a(ω_e0 + 2J_e⁻¹T_e t − 1.5 J_e⁻¹ a t²)
        qa, qb, qc = 1.5 * inv_je * a_r, -2.0 * inv_je * te, -we0
        cands.append(
            np.where(qa > 0, (-qb + np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0))) / (2 * qa), 0.0)
        )
        # moving ramp piece: P = a t (K + A t − B a t²/2) -> P' = a(K + 2A t − 1.5 B a t²)
        k0 = state(t0)[1] - a_coef * t0 + 0.5 * b_coef * a_r * t0**2
        qa, qb, qc = 1.5 * b_coef * a_r, -2.0 * a_coef, -k0
        cands.append((-qb + np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0))) / (2 * qa))
        # moving from t = 0 (driven initially turning): same form with K = Δω(0)
        qc = -state(np.zeros_like(t0))[1]
        cands.append((-qb + np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0))) / (2 * qa))
    best = np.zeros_like(t_stop)
    for t in cands:
        t = np.clip(np.nan_to_num(t, nan=0.0), 0.0, t_stop)
        c, dw, _, _ = state(t)
        best = np.maximum(best, c * dw)
    return best


def _peak_power_golden(state, pieces):
    """max of C·Δω over [0, t_stop] of a smooth clamp step: golden section (unimodal), and the
    knots."""
    t_stop = pieces[-1]
    lo, hi = np.zeros_like(t_stop), t_stop.copy()
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    for _ in range(48):
        x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
        c1, d1, _, _ = state(x1)
        c2, d2, _, _ = state(x2)
        better = c1 * d1 >= c2 * d2
        hi, lo = np.where(better, x2, hi), np.where(better, lo, x1)
    c, dw, _, _ = state(0.5 * (lo + hi))
    best = c * dw
    for t in pieces:
        c, dw, _, _ = state(t)
        best = np.maximum(best, c * dw)
    return np.maximum(best, 0.0)


def _peak_rate(a, b, c_max, t_r, kind):
    """max of dC/dt over [a, b] (p' is constant for the ramp, unimodal with its top at x = 1/2 else)."""
    tr = np.where(t_r > 0, t_r, 1.0)
    xa, xb = np.clip(a / tr, 0, 1), np.clip(b / tr, 0, 1)
    dp = np.polynomial.polynomial.polyder(_P[kind])
    cand = np.maximum(_polyval(dp, xa), _polyval(dp, xb))
    cand = np.where(
        (xa <= 0.5) & (xb >= 0.5), np.maximum(cand, _polyval(dp, np.full_like(xa, 0.5))), cand
    )
    return np.where((t_r > 0) & (xb > xa), c_max * cand / tr, np.where(t_r > 0, 0.0, np.inf))


def slip_jerk(d, t_stop):
    """max of dC/dt while the driven side moves [N m/s]: from t0 to the stop, and for a driven side
    that first decelerates to rest (it parks at t_p) over [0, t_p] too."""
    t0, t_p, parks_later, kind = d.t0, d.t_p, d.parks_later, d.profile
    rate = _peak_rate(t0, t_stop, d.cmax, d.tr, kind)
    if np.any(parks_later):
        early = _peak_rate(
            np.zeros_like(t0),
            np.where(parks_later, np.minimum(t_p, t_stop), 0.0),
            d.cmax,
            d.tr,
            kind,
        )
        rate = np.where(parks_later, np.maximum(rate, early), rate)
    return rate


def flash_peak(d, pieces, t_stop, locked):
    """The peak of Duhamel's integral of the exact slip power [W s^0.5], sampled at
    ``CLOSED_FORM_POWER_SAMPLES`` points on each piece (zero-length pieces give repeated times,
    which the history skips); 0 from lock-up on."""
    frac = np.linspace(0.0, 1.0, CLOSED_FORM_POWER_SAMPLES + 1)[:-1]
    times = np.concatenate(
        [
            a[:, None] + (b - a)[:, None] * frac[None, :]
            for a, b in zip(pieces[:-1], pieces[1:], strict=False)
        ]
        + [t_stop[:, None]],
        axis=1,
    )
    power = np.empty_like(times)
    for j in range(times.shape[1]):
        c, dw, _, _ = d.state(times[:, j])
        power[:, j] = c * dw
    power[:, -1] = np.where(locked, 0.0, power[:, -1])
    return flash_peaks(times, power)

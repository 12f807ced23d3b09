"""The slip power history of a linear slipping segment (clutchlab.engagement._power.hist_linear):
its samples carried by the free response's transition equal the form evaluated anew at every
sample (the closed form's exact slip power)."""

import numpy as np
import pytest

from clutchlab.engagement import _linear_forms as lf
from clutchlab.engagement._power import EXACT_EVERY, hist_linear

FREE_RESPONSES = {  # (a [1/s], ω² [1/s²]): the twist's damped oscillation, over- and critically
    # damped
    "underdamped": (17.9, 358.0**2),
    "overdamped": (300.0, -(200.0**2)),
    "critical": (250.0, 0.0),
}
T0, T1, DT = 0.0113, 0.0113 + 0.3, 1e-3  # 300 grid samples and the end: the exact start 10 times


def _samples(fr, ft):
    hist = np.zeros((4, 1000))
    n = hist_linear(hist, 0, T0, T1, DT, ft, fr)
    assert n == 301 > 9 * EXACT_EVERY
    times, powers = hist[0, :n], hist[1, :n]
    assert np.all(np.diff(times) > 0) and times[-1] == T1
    exact = np.array([lf.fval(ft, lf.F_POW, t - fr.t0, *lf.hh(fr, t - fr.t0)) for t in times])
    return powers, exact


@pytest.mark.parametrize("kind", FREE_RESPONSES)
@pytest.mark.parametrize("degree", [0, 3, 11])
def test_carried_samples_are_the_form_evaluated_at_each_sample(kind, degree):
    """The free response's terms (polynomial times h and h'), carried: within 1e-13 of the
    largest sample; the polynomial term alone: the same bits."""
    a, w2 = FREE_RESPONSES[kind]
    fr = lf.FreeResponse(a, w2, 2e-3, -0.4, T0)
    rng = np.random.default_rng(degree)
    r = 3 * lf.F_POW
    ft = np.zeros((lf.N_FROWS, lf.NP))
    ft[r + 1, : degree + 1] = rng.normal(size=degree + 1) * 1e5
    ft[r + 2, : degree + 1] = rng.normal(size=degree + 1) * 1e3
    powers, exact = _samples(fr, ft)
    assert np.max(np.abs(powers - exact)) <= 1e-13 * np.max(np.abs(exact))
    ft[:] = 0.0
    ft[r, : degree + 1] = rng.normal(size=degree + 1) * 1e4
    powers, exact = _samples(fr, ft)
    np.testing.assert_array_equal(powers, exact)

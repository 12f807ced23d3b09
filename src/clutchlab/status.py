"""Per-scenario status codes shared by every study (CF ``flag_values`` / ``flag_meanings``).

A scenario that fails never stops a study and never hides as a number: its outputs are NaN and
its ``status`` says why.
"""

from __future__ import annotations

import numpy as np

from . import plausible as _plausible

#: code -> meaning; codes are stable (stored in files), append only.
FLAGS = {
    0: "ok",
    1: "invalid_geometry",
    2: "monotone_no_hump",
    3: "snap_through",
    4: "never_locked",
    5: "jammed",
    6: "not_converged",
    7: "above_allowable",
    8: "not_engaged",
    9: "roll_over",
    10: "pop_out_risk",
    11: "not_self_locking",
    12: "overrunning",
    13: "truncated",
    14: "invalid_input",
    15: "near_jam",
    16: "dynamic_overstress",
    17: "worn_not_locked",
}
CODE = {meaning: code for code, meaning in FLAGS.items()}
DTYPE = np.int8


def attrs(description: str = "") -> dict:
    """CF attributes of a ``status`` variable (``flag_values``, ``flag_meanings``).

    Parameters
    ----------
    description : str
        A comment for the attributes (none if empty).

    Returns
    -------
    dict
        ``long_name``, ``units``, ``flag_values``, ``flag_meanings`` and ``comment``.
    """
    out = {
        "long_name": "scenario status",
        "units": "1",
        "flag_values": np.array(sorted(FLAGS), dtype=DTYPE),
        "flag_meanings": " ".join(FLAGS[k] for k in sorted(FLAGS)),
    }
    if description:
        out["comment"] = description
    return out


# ---- per-scenario input screening ---------------------------------------------------------------
# A public physics function declares the domain of each per-scenario input; a scenario with any
# input outside it (NaN, an infinity where none is meaningful, a negative mass, ...) gets status
# ``invalid_input`` and NaN outputs, and the others are computed as a batch of their own, so they
# are bit-identical to a batch without the bad ones.


def finite(x):
    """Predicate: finite (any sign).

    Parameters
    ----------
    x : numpy.ndarray
        Values of one input, one per scenario.

    Returns
    -------
    numpy.ndarray of bool
        True where the value is admissible.
    """
    return np.isfinite(x)


def positive(x):
    """Predicate: finite and > 0.

    Parameters
    ----------
    x : numpy.ndarray
        Values of one input, one per scenario.

    Returns
    -------
    numpy.ndarray of bool
        True where the value is admissible.
    """
    return np.isfinite(x) & (x > 0)


def nonnegative(x):
    """Predicate: finite and ≥ 0.

    Parameters
    ----------
    x : numpy.ndarray
        Values of one input, one per scenario.

    Returns
    -------
    numpy.ndarray of bool
        True where the value is admissible.
    """
    return np.isfinite(x) & (x >= 0)


def positive_or_inf(x):
    """Predicate: > 0, inf allowed (a held engine, a constant μ, no release); NaN is not.

    Parameters
    ----------
    x : numpy.ndarray
        Values of one input, one per scenario.

    Returns
    -------
    numpy.ndarray of bool
        True where the value is admissible.
    """
    return x > 0


def nonnegative_or_inf(x):
    """Predicate: ≥ 0, inf allowed; NaN is not.

    Parameters
    ----------
    x : numpy.ndarray
        Values of one input, one per scenario.

    Returns
    -------
    numpy.ndarray of bool
        True where the value is admissible.
    """
    return x >= 0


def at_least(lo):
    """Rule: finite and ≥ ``lo``.

    Parameters
    ----------
    lo : float
        The least admissible value, in the input's unit.

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    return lambda x: np.isfinite(x) & (x >= lo)


def between(lo, hi, *, lo_open=False, hi_open=False):
    """Rule: finite and within [lo, hi] (either end open on request).

    Parameters
    ----------
    lo, hi : float
        The ends of the interval, in the input's unit.
    lo_open, hi_open : bool
        Whether ``lo`` and ``hi`` themselves are excluded.

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """

    def check(x):
        return (
            np.isfinite(x)
            & ((x > lo) if lo_open else (x >= lo))
            & ((x < hi) if hi_open else (x <= hi))
        )

    return check


def whole(minimum):
    """Rule: a finite whole number ≥ ``minimum``.

    Parameters
    ----------
    minimum : int
        The least admissible value.

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    return lambda x: np.isfinite(x) & (x >= minimum) & (x == np.round(x))


def all_of(*rules):
    """Rule true where every one of ``rules`` is.

    Parameters
    ----------
    *rules : callable
        Predicates (at least one).

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """

    def check(x):
        ok = rules[0](x)
        for rule in rules[1:]:
            ok = ok & rule(x)
        return ok

    return check


def apart(larger, smaller, unit="m"):
    """Whether ``larger`` exceeds ``smaller`` by at least the smallest plausible magnitude of
    ``unit`` (:func:`clutchlab.plausible.bounds`): two radii a model divides by their difference
    are a plausible length apart (radii equal to 1e-15 gave a spring load of 1e18 N).

    Parameters
    ----------
    larger, smaller : array_like
        Values in SI ``unit``.
    unit : str
        Their SI unit, as :data:`clutchlab.plausible.RANGES` spells it.

    Returns
    -------
    numpy.ndarray of bool
        True where they are far enough apart.
    """
    return np.asarray(larger) - np.asarray(smaller) >= _plausible.bounds(unit)[0]


def plausible(unit, *, lo=None, hi=None):
    """Rule: finite, and zero or of a magnitude within the plausible range of SI ``unit``.

    The range is :func:`clutchlab.plausible.bounds`; ``lo``/``hi`` replace it where an input's own
    physics narrows it (a friction coefficient ≤ 2, a count ≤ COUNT_MAX) or where the unit stands
    for another kind of quantity (a temperature difference in K). Zero is judged by each input's
    own sign rule (combine with :func:`positive`, :func:`nonnegative`).

    Parameters
    ----------
    unit : str
        SI unit of the input, as :data:`clutchlab.plausible.RANGES` spells it.
    lo, hi : float or None
        Smallest non-zero and largest magnitude, replacing the table's.

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    lo0, hi0 = _plausible.bounds(unit)
    lo = lo0 if lo is None else lo
    hi = hi0 if hi is None else hi

    def check(x):
        a = np.abs(x)
        return (a == 0) | (np.isfinite(a) & (a >= lo) & (a <= hi))

    return check


def positive_in(unit, **bounds):
    """Rule: > 0, finite and plausible (:func:`plausible`).

    Parameters
    ----------
    unit : str
        SI unit of the input, as :data:`clutchlab.plausible.RANGES` spells it.
    **bounds : float
        ``lo`` and ``hi``, replacing the table's bounds (:func:`plausible`).

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    return all_of(positive, plausible(unit, **bounds))


def nonnegative_in(unit, **bounds):
    """Rule: ≥ 0, finite and plausible (:func:`plausible`).

    Parameters
    ----------
    unit : str
        SI unit of the input, as :data:`clutchlab.plausible.RANGES` spells it.
    **bounds : float
        ``lo`` and ``hi``, replacing the table's bounds (:func:`plausible`).

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    return all_of(nonnegative, plausible(unit, **bounds))


def finite_in(unit, **bounds):
    """Rule: any sign, finite and plausible (:func:`plausible`).

    Parameters
    ----------
    unit : str
        SI unit of the input, as :data:`clutchlab.plausible.RANGES` spells it.
    **bounds : float
        ``lo`` and ``hi``, replacing the table's bounds (:func:`plausible`).

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    return plausible(unit, **bounds)


def positive_or_inf_in(unit, **bounds):
    """Rule: inf (a held engine, a constant μ, no release), or > 0 and plausible; NaN is not.

    Parameters
    ----------
    unit : str
        SI unit of the input, as :data:`clutchlab.plausible.RANGES` spells it.
    **bounds : float
        ``lo`` and ``hi``, replacing the table's bounds (:func:`plausible`).

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    rule = positive_in(unit, **bounds)
    return lambda x: rule(x) | (x == np.inf)


def nonnegative_or_inf_in(unit, **bounds):
    """Rule: inf, or ≥ 0 and plausible; NaN is not.

    Parameters
    ----------
    unit : str
        SI unit of the input, as :data:`clutchlab.plausible.RANGES` spells it.
    **bounds : float
        ``lo`` and ``hi``, replacing the table's bounds (:func:`plausible`).

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    rule = nonnegative_in(unit, **bounds)
    return lambda x: rule(x) | (x == np.inf)


def count(minimum=1, maximum=None):
    """Rule: a whole number in [minimum, maximum].

    Parameters
    ----------
    minimum : int
        The least count.
    maximum : int or None
        The largest count (default :data:`clutchlab.plausible.COUNT_MAX`).

    Returns
    -------
    callable
        A predicate: an array of values to a boolean mask of the admissible ones.
    """
    top = _plausible.COUNT_MAX if maximum is None else maximum
    return lambda x: np.isfinite(x) & (x >= minimum) & (x <= top) & (x == np.round(x))


def admissible(inputs: dict, domain: dict):
    """The inputs broadcast together and the mask of scenarios whose inputs all lie in ``domain``.

    Parameters
    ----------
    inputs : dict
        Input name -> per-scenario values (broadcast together).
    domain : dict
        Input name -> predicate, and optionally ``None`` -> a predicate of all inputs (see
        :func:`screened`).

    Returns
    -------
    arrays : dict of numpy.ndarray
        The inputs as float arrays of the broadcast shape.
    ok : numpy.ndarray of bool
        True where every rule holds.
    """
    arrays = dict(
        zip(
            inputs,
            np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in inputs.values())),
            strict=False,
        )
    )
    shape = next(iter(arrays.values())).shape if arrays else ()
    return arrays, _mask(arrays, domain, shape)


def _mask(arrays, domain, shape):
    ok = np.ones(shape, dtype=bool)
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        for name, rule in domain.items():
            ok &= rule(arrays) if name is None else rule(arrays[name])
    return ok


def screened(compute, inputs: dict, domain: dict, *, extra=None, geometry=None) -> dict:
    """Run ``compute(**inputs)`` on the scenarios whose inputs lie in ``domain`` only.

    A scenario with an input outside the domain gets NaN outputs and status ``invalid_input`` (or
    ``invalid_geometry``); the others are computed as a batch of their own, so they are
    bit-identical to a batch without the bad ones.

    Parameters
    ----------
    compute : callable
        The unscreened computation, called with the inputs (and ``extra``) as keywords; returns a
        dict of arrays (nested dicts allowed), optionally with ``status``.
    inputs : dict
        Input name -> per-scenario array (broadcast together).
    domain : dict
        Input name -> predicate giving True where the value is admissible; the key ``None`` may
        hold a predicate of all inputs (e.g. a relation between two of them).
    extra : dict or None
        Scalars and options passed to ``compute`` unchanged.
    geometry : dict or None
        Relations of a part's geometry (radii in order, a shoe inside its drum), in the form of
        ``domain``, checked where the inputs are admissible; a scenario that breaks one gets status
        ``invalid_geometry``.

    Returns
    -------
    dict
        ``compute``'s dict with every array (nested dicts too) shaped like the broadcast inputs
        (plus its own trailing axes), NaN (integers: 0) and the status ``invalid_input`` (or
        ``invalid_geometry``) where an input was bad.
    """
    extra = extra or {}
    arrays, ok = admissible(inputs, domain)
    shape = ok.shape
    code = np.where(ok, CODE["ok"], CODE["invalid_input"])
    if geometry:
        fits = _mask(arrays, geometry, shape)
        code = np.where(ok & ~fits, CODE["invalid_geometry"], code)
        ok = ok & fits
    if ok.all():
        return compute(**_sequences_as_arrays(inputs), **extra)
    good = ok.ravel()
    out = compute(**{k: a.reshape(-1)[good] for k, a in arrays.items()}, **extra)
    return _scatter(out, good, shape, code.ravel())


def nan_screened(compute, inputs: dict, domain: dict, *, extra=None):
    """:func:`screened` for a helper that returns a plain array (or a tuple of them).

    Parameters
    ----------
    compute : callable
        The unscreened computation, called with the inputs (and ``extra``) as keywords; returns an
        array or a tuple of arrays.
    inputs : dict
        Input name -> per-scenario array (broadcast together).
    domain : dict
        As in :func:`screened`.
    extra : dict or None
        Scalars and options passed to ``compute`` unchanged.

    Returns
    -------
    numpy.ndarray or tuple of numpy.ndarray
        ``compute``'s result, NaN (integers 0, booleans False) where an input lies outside
        ``domain``; a numpy scalar for scalar inputs.
    """
    extra = extra or {}
    arrays, ok = admissible(inputs, domain)
    if ok.all():
        return compute(**_sequences_as_arrays(inputs), **extra)
    good = ok.ravel()
    res = compute(**{k: a.reshape(-1)[good] for k, a in arrays.items()}, **extra)
    parts = res if isinstance(res, tuple) else (res,)
    full = _scatter({str(i): v for i, v in enumerate(parts)}, good, ok.shape, None)
    back = tuple(full[str(i)][()] if ok.ndim == 0 else full[str(i)] for i in range(len(parts)))
    return back if isinstance(res, tuple) else back[0]


def _sequences_as_arrays(inputs: dict) -> dict:
    """The inputs with each list or tuple as an array (as the bad scenarios' path passes them);
    arrays and scalars unchanged."""
    return {k: np.asarray(v) if isinstance(v, (list, tuple)) else v for k, v in inputs.items()}


def _scatter(out, good, shape, code):
    full = {}
    for name, v in out.items():
        if isinstance(v, dict):
            full[name] = _scatter(v, good, shape, code)
            continue
        v = np.asarray(v)
        if v.ndim == 0:  # a shared scalar (not per scenario)
            full[name] = v
            continue
        if name == "status":
            a = np.empty((good.size,) + v.shape[1:], dtype=v.dtype)
            a[...] = code.reshape((good.size,) + (1,) * (v.ndim - 1))
        elif v.dtype.kind == "f":
            a = np.full((good.size,) + v.shape[1:], np.nan, dtype=v.dtype)
        else:
            a = np.zeros((good.size,) + v.shape[1:], dtype=v.dtype)
        a[good] = v.reshape((int(good.sum()),) + v.shape[1:]) if v.size else v
        full[name] = a.reshape(shape + v.shape[1:])
    return full

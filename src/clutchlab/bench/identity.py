"""Bit-identity check of the engagement solvers: a restructuring must not change one output bit.

``python -m clutchlab.bench.identity save FILE.npz [--tests [TEST_FILE ...]]`` runs a fixed set of
calls of :mod:`clutchlab.engagement`'s public functions and stores their inputs and every output
array; ``python -m clutchlab.bench.identity compare FILE.npz`` repeats those calls with the
stored inputs on the code as it is now and compares every output bit for bit (same keys, dtype,
shape and values, np.array_equal with equal_nan; then the bytes: a NaN whose sign bit differs is
listed but passes, as IEEE 754 and the compiler leave a NaN's sign open; a signed zero fails). It
exits 1 on any difference. Save from the code before a change, compare after it. A call made
while a test had patched a module constant of the package (e.g. the closed form's power samples)
is replayed with that constant patched again, wherever the package keeps it.

The calls (recorded as they are made, so that the comparison replays exactly those inputs):

* :func:`~clutchlab.engagement.closed_form` on random designs of every clamp profile, held and free
  engine, driven side at rest or turning, step clamps, finite and infinite windows, with and
  without the slip power history, invalid scenarios mixed in, and one batch larger than its
  block size;
* :func:`~clutchlab.engagement.simulate`, rigid and compliant driveline, on random designs of every
  friction law (constant μ, Stribeck, μ(slip) table, fade), clamp profile, held and free engine,
  with load steps, rotor drag, an engine torque table, the release-bearing travel, driven sides
  turning at the start (up to the engine's speed), traces, slip power histories, loose and tight
  tolerances, a step limit and a largest step, invalid scenarios mixed in;
* the benchmark designs of :mod:`clutchlab.bench.engagement` (Stribeck, held engine, at several
  tolerances) and :mod:`clutchlab.bench.compliant` (constant μ and Stribeck);
* every call the engagement hard cases (:func:`clutchlab.hardcases.engagement_cases`) make;
* with ``--tests``, every call the given test files make (default: the engagement solver's tests),
  run in this process with pytest.
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import hashlib
import pickle
import sys
import time

import numpy as np

PUBLIC = (
    "closed_form",
    "simulate",
    "clamp_profile",
    "bearing_travel_clamp",
    "ramp_time_for_lockup",
)
TESTS = (
    "tests/test_engagement.py",
    "tests/test_compliant.py",
    "tests/test_fade.py",
    "tests/test_heat.py",
    "tests/test_hardcases.py",
    "tests/test_invalid_inputs.py",
    "tests/test_friction.py",
    "tests/test_engagement_study.py",
    "tests/test_wear.py",
)
PROFILES = ("ramp", "cubic", "quintic")
FRICTION_TABLE = (np.array([0.0, 5.0, 20.0, 60.0, 400.0]), np.array([1.3, 1.18, 1.05, 1.0, 0.97]))
ENGINE_TABLE = (np.array([0.0, 200.0, 400.0, 700.0]), np.array([120.0, 150.0, 140.0, 90.0]))
K_FACE = 8.858406279259717e-4  # K/(W s^0.5): the source paper (000)'s lining, one face
#: the solver's modules besides clutchlab.engagement.*: the kernel and linear phases of the code
#: before the engagement subpackage (a baseline saved from that code records their patches too)
PACKAGE_MODULES = (
    "clutchlab.engagement",
    "clutchlab._engagement_kernel",
    "clutchlab._linear_phase",
)


def _constants():
    """The module constants of the engagement package as they are now: (module, NAME) -> value
    (numbers and strings; a test may patch one, e.g. the closed form's power samples)."""
    out = {}
    for mod_name, mod in list(sys.modules.items()):
        if mod is None or not (
            mod_name in PACKAGE_MODULES or mod_name.startswith("clutchlab.engagement.")
        ):
            continue
        for name, value in vars(mod).items():
            if name.isupper() and isinstance(value, (int, float, str)):
                out[(mod_name, name)] = value
    return out


def _patched(base):
    """The constants that differ from ``base`` now: NAME -> value."""
    return {name: v for (mod, name), v in _constants().items() if base.get((mod, name), v) != v}


@contextlib.contextmanager
def _patches(patches):
    """Set each patched constant in every engagement module that has it (wherever the code
    keeps it now), and restore them after."""
    saved = []
    for (mod_name, name), value in _constants().items():
        if name in patches:
            saved.append((sys.modules[mod_name], name, value))
            setattr(sys.modules[mod_name], name, patches[name])
    try:
        yield
    finally:
        for mod, name, value in saved:
            setattr(mod, name, value)


class Recorder:
    """Replaces the public functions of :mod:`clutchlab.engagement` by ones that record each call
    (a deep copy of its keyword arguments, and the module constants a test patched for it) and
    its outputs (or the error it raised); identical calls are kept once."""

    def __init__(self):
        self.calls = []  # (function name, kwargs, patches, outputs or None, error text or None)
        self._seen = set()
        self._base = _constants()

    @contextlib.contextmanager
    def active(self):
        from clutchlab import engagement

        saved = {name: getattr(engagement, name) for name in PUBLIC}
        for name, fn in saved.items():
            setattr(engagement, name, self._wrap(name, fn))
        try:
            yield self
        finally:
            for name, fn in saved.items():
                setattr(engagement, name, fn)

    def _wrap(self, name, fn):
        def recorded(*args, **kwargs):
            if args:  # (only ramp_time_for_lockup and the profiles take positional arguments)
                kwargs = dict(zip(_positional(name), args, strict=False), **kwargs)
            inputs = (copy.deepcopy(kwargs), _patched(self._base))
            try:
                out = fn(**kwargs)
            except Exception as exc:  # a refused input is an output too
                self._add(name, inputs, None, f"{type(exc).__name__}: {exc}")
                raise
            self._add(name, inputs, copy.deepcopy(out), None)
            return out

        return recorded

    def _add(self, name, inputs, out, error):
        key = hashlib.sha256(pickle.dumps((name, inputs))).hexdigest()
        if key not in self._seen:
            self._seen.add(key)
            self.calls.append((name, *inputs, out, error))


def _positional(name):
    return {
        "ramp_time_for_lockup": ("target_lockup_time",),
        "clamp_profile": ("x", "kind"),
        "bearing_travel_clamp": ("x",),
    }.get(name, ())


def flatten(out, prefix=""):
    """The output arrays of one call, ``trace/…`` for the trace's (name -> numpy array)."""
    if not isinstance(out, dict):
        return {prefix or "value": np.asarray(out)}
    flat = {}
    for k, v in out.items():
        if isinstance(v, dict):
            flat.update(flatten(v, f"{prefix}{k}/"))
        else:
            flat[f"{prefix}{k}"] = np.asarray(v)
    return flat


# ---- the fixed calls ---------------------------------------------------------------------------


def _base(rng, n, held):
    """A random design of the common inputs (plausible ranges of the engagement study and beyond)."""
    we = rng.uniform(150.0, 650.0, n)
    d = dict(
        engine_speed=we,
        engine_inertia=np.full(n, np.inf) if held else rng.uniform(0.05, 1.0, n),
        engine_torque=rng.uniform(0.0, 200.0, n),
        driven_inertia=rng.uniform(0.01, 0.1, n),
        load_torque=np.where(rng.random(n) < 0.1, 0.0, rng.uniform(0.0, 120.0, n)),
        peak_capacity=rng.uniform(100.0, 400.0, n),
        ramp_time=np.where(rng.random(n) < 0.06, 0.0, rng.uniform(0.01, 0.4, n)),
        static_ratio=rng.uniform(1.0, 1.4, n),
        driven_speed=np.where(
            rng.random(n) < 0.8,
            0.0,
            np.where(rng.random(n) < 0.3, we, rng.uniform(0.0, 1.0, n) * we),
        ),
    )
    # a few invalid scenarios (screened: status invalid_input, NaN outputs)
    if n >= 10:
        d["engine_speed"][3] = np.nan
        d["driven_inertia"][7] = -1.0
    return d


def _closed_form_calls(eng, rng):
    for profile in PROFILES:
        for held in (True, False):
            for power in (False, True):
                d = _base(rng, 600, held)
                t_end = np.where(rng.random(600) < 0.5, np.inf, rng.uniform(0.05, 1.0, 600))
                eng.closed_form(**d, profile=profile, t_end=t_end, power_history=power)
    d = _base(rng, 20_000, False)  # more than one block of the vectorised closed form
    eng.closed_form(**d, profile="cubic")
    x = np.concatenate([np.linspace(-0.5, 1.5, 201), [np.nan, np.inf, -np.inf]])
    for profile in PROFILES:
        eng.clamp_profile(x, profile)
        eng.bearing_travel_clamp(
            x, air_gap=np.linspace(0.0, 2e-3, x.size), cushion_travel=1e-3, kind=profile
        )
    seed = dict(
        engine_speed=570.0,
        engine_inertia=np.inf,
        engine_torque=156.0,
        driven_inertia=0.021,
        load_torque=44.0,
        peak_capacity=239.3,
    )
    for target in (0.1, 0.2, 0.05):
        eng.ramp_time_for_lockup(target, **seed)


def _variant_inputs(rng, n, variant):
    kw = {}
    if variant == "stribeck":
        kw["stribeck_speed"] = rng.uniform(2.0, 60.0, n)
    elif variant == "table":
        kw["friction_table"] = FRICTION_TABLE
    elif variant == "fade":
        kw.update(
            fade_coefficient=rng.uniform(0.002, 0.03, n),
            fade_onset=rng.uniform(0.0, 40.0, n),
            face_temperature_factor=K_FACE * rng.uniform(0.5, 3.0, n),
            stribeck_speed=np.where(rng.random(n) < 0.3, rng.uniform(5.0, 50.0, n), np.inf),
        )
    elif variant == "drag":
        kw["aero_coefficient"] = rng.uniform(0.0, 5e-4, n)
    elif variant == "engine_table":
        kw["engine_torque_table"] = ENGINE_TABLE
    elif variant == "load_step":
        kw.update(load_step=rng.uniform(-20.0, 150.0, n), load_step_time=rng.uniform(0.0, 0.6, n))
    elif variant == "release":
        kw["release_ratio"] = np.where(rng.random(n) < 0.3, 1.0, rng.uniform(1.0, 4.0, n))
    return kw


def _compliant_inputs(rng, n):
    return dict(
        compliant=True,
        hub_fraction=rng.uniform(0.2, 0.8, n),
        damper_stiffness=np.where(rng.random(n) < 0.05, np.inf, rng.uniform(800.0, 30000.0, n)),
        damping_ratio=np.choose(
            rng.integers(0, 4, n), [0.0, 1.0, rng.uniform(0.0, 0.3, n), rng.uniform(0.3, 3.0, n)]
        ),
    )


VARIANTS = ("constant", "stribeck", "table", "fade", "drag", "engine_table", "load_step", "release")


def _simulate_calls(eng, rng):
    count = 0
    for compliant in (False, True):
        for variant in VARIANTS:
            for profile in PROFILES:
                for held in (True, False):
                    n = 12 if variant == "fade" else 30
                    d = _base(rng, n, held)
                    kw = dict(d, profile=profile, t_end=0.6, **_variant_inputs(rng, n, variant))
                    if compliant:
                        kw.update(_compliant_inputs(rng, n))
                    if count % 2 == 0:
                        kw["power_history"] = True
                    if count % 3 == 0:
                        kw["trace_times"] = np.linspace(0.0, 0.6, 25)
                    if count % 5 == 1:
                        kw.update(rtol=1e-5, atol=1e-7)
                    if count % 7 == 2:
                        kw.update(max_step=2e-3, first_step=1e-5)
                    count += 1
                    eng.simulate(**kw)
    # the work budget: scenarios that run out of steps (not_converged)
    d = _base(rng, 20, True)
    eng.simulate(**d, stribeck_speed=10.0, max_steps=40, t_end=0.6)
    eng.simulate(**d, **_compliant_inputs(rng, 20), max_steps=60, t_end=0.6, power_history=True)
    # a long window after lock-up and a window ending during slip
    for t_end in (3.0, 0.02):
        for compliant in (False, True):
            d = _base(rng, 20, False)
            extra = _compliant_inputs(rng, 20) if compliant else {}
            eng.simulate(**d, **extra, t_end=t_end, power_history=True)


def _benchmark_calls(eng):
    from clutchlab.bench import compliant as bc
    from clutchlab.bench import engagement as be
    from clutchlab.studies.engagement import tolerances

    d = be.design(2000)
    kw = dict(engine_inertia=np.inf, engine_torque=0.0, static_ratio=be.RS, t_end=2.0)
    for rtol in (1e-2, 10.0**-4.5, 1e-6, 1e-8, 1e-10, 1e-12):
        eng.simulate(**d, **kw, rtol=rtol, atol=rtol)
    eng.simulate(**bc.design(2000, "constant_mu"), compliant=True, power_history=True)
    eng.simulate(**bc.design(2000, "constant_mu"), compliant=True)
    ds = bc.design(200, "stribeck")
    for acc in (1e-3, 1e-5, 1e-7):
        rtol, atol = tolerances(acc)
        eng.simulate(**ds, compliant=True, power_history=True, rtol=rtol, atol=atol)


def _hard_case_calls():
    from clutchlab import hardcases

    hardcases.engagement_cases()


def _test_calls(files):
    import pytest

    code = pytest.main(["-q", "-p", "no:cacheprovider", "-x", *files])
    if code != 0:
        raise SystemExit(f"the tests failed (exit {code}): their calls are not a reference")


def record(tests=None):
    """Make every call under a :class:`Recorder`; return its calls."""
    from clutchlab import engagement as eng

    rec = Recorder()
    with rec.active():
        rng = np.random.default_rng(20261124)
        _closed_form_calls(eng, rng)
        _simulate_calls(eng, rng)
        _benchmark_calls(eng)
        _hard_case_calls()
        if tests:
            _test_calls(tests)
    return rec.calls


def save(path, tests=None):
    t0 = time.process_time()
    calls = record(tests)
    arrays = {"__calls__": np.frombuffer(pickle.dumps([c[:3] for c in calls]), dtype=np.uint8)}
    for i, (_, _, _, out, error) in enumerate(calls):
        if error is not None:
            arrays[f"{i}:__error__"] = np.array(error)
        else:
            for k, v in flatten(out).items():
                arrays[f"{i}:{k}"] = v
    np.savez_compressed(path, **arrays)
    n_scen = sum(v.size for k, v in arrays.items() if k.endswith(":lockup_time"))
    print(
        f"saved {len(calls)} calls, {len(arrays) - 1} arrays ({n_scen} scenarios with a lock-up "
        f"time) to {path} in {time.process_time() - t0:.0f} s CPU"
    )


def _same(a, b):
    """(equal, note): dtype, shape and every value (np.array_equal with equal_nan), then every
    byte: equal values whose bytes differ only in NaN bit patterns (the sign of a NaN is the
    compiler's choice, IEEE 754 leaves it open) pass with a note; a signed zero does not."""
    if a.dtype != b.dtype:
        return False, f"dtype {a.dtype} != {b.dtype}"
    if a.shape != b.shape:
        return False, f"shape {a.shape} != {b.shape}"
    if a.dtype.kind in "fc" and not np.array_equal(a, b, equal_nan=True):
        diff = ~((a == b) | (np.isnan(a) & np.isnan(b)))
        return False, f"{int(diff.sum())} values differ (first at {np.argwhere(diff)[0].tolist()})"
    if a.tobytes() == b.tobytes():
        return True, ""
    if a.dtype.kind in "fc":
        va, vb = a.reshape(-1).view(np.uint8), b.reshape(-1).view(np.uint8)
        item = a.dtype.itemsize
        differ = (va.reshape(-1, item) != vb.reshape(-1, item)).any(axis=1)
        if np.all(np.isnan(a.reshape(-1)[differ])):
            return True, f"{int(differ.sum())} NaN bit patterns differ"
    return False, "the bytes differ (signed zeros)"


def compare(path):
    from clutchlab import engagement as eng

    t0 = time.process_time()
    stored = np.load(path, allow_pickle=False)
    calls = pickle.loads(stored["__calls__"].tobytes())
    bad, notes, n_arrays, n_values = [], [], 0, 0
    keys = {}
    for k in stored.files:
        keys.setdefault(k.split(":", 1)[0], []).append(k)
    for i, (name, kwargs, *patched) in enumerate(calls):
        patches = patched[0] if patched else {}  # (files saved before patches were recorded)
        try:
            with _patches(patches):
                out = flatten(getattr(eng, name)(**copy.deepcopy(kwargs)))
        except Exception as exc:
            out = {"__error__": np.array(f"{type(exc).__name__}: {exc}")}
        want = {k.split(":", 1)[1]: stored[k] for k in keys.get(str(i), [])}
        if set(out) != set(want):
            bad.append(f"call {i} ({name}): outputs {sorted(set(out) ^ set(want))} added/missing")
            continue
        for k, v in want.items():
            ok, note = _same(v, out[k])
            n_arrays += 1
            n_values += v.size
            if not ok:
                bad.append(f"call {i} ({name}) {k}: {note}")
            elif note:
                notes.append(f"call {i} ({name}) {k}: {note}")
    print(
        f"compared {len(calls)} calls, {n_arrays} arrays, {n_values} values in "
        f"{time.process_time() - t0:.0f} s CPU: "
        + ("all bit-identical" if not bad else f"{len(bad)} differences")
        + (
            f" ({len(notes)} arrays with equal values whose NaN bit patterns differ)"
            if notes
            else ""
        )
    )
    for line in bad[:50] + notes[:20]:
        print("  " + line)
    return not bad


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("action", choices=("save", "compare"))
    p.add_argument("file")
    p.add_argument(
        "--tests",
        nargs="*",
        default=None,
        help="also record the calls of these test files (none given: the engagement tests)",
    )
    a = p.parse_args(argv)
    if a.action == "save":
        tests = None if a.tests is None else (a.tests or list(TESTS))
        save(a.file, tests)
        return 0
    return 0 if compare(a.file) else 1


if __name__ == "__main__":
    sys.exit(main())

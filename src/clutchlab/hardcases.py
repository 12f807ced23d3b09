"""Hard cases: the cases that break ordinary solvers, each with its right answer (analytic where one
exists, else a much tighter reference, with its source), what clutchlab computes for it, the error
and the verdict, and where instructive what an off-the-shelf solver (``scipy.integrate.solve_ivp``)
gives on the same case.

:func:`run` computes every case of the studies asked for (a few seconds in all); the Snakemake rule
``hard_cases`` stores the table as ``<results>/numerics/hard_cases.h5`` and the report writes it as a
page and as ``hard_cases.csv``. The tests assert that every case passes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from . import status as st

__all__ = ["Case", "run", "to_dataset", "to_csv", "COLUMNS"]

COLUMNS = [
    "study",
    "case",
    "right_answer",
    "source",
    "computed",
    "error",
    "error_kind",
    "error_unit",
    "tolerance",
    "passed",
    "off_the_shelf",
]

# the source paper (000)'s engagement: engine held at 570 rad/s, capacity ramped to 239.3 N m over
# 0.15 s, load 44 N m, driven inertia 0.021 kg m²
SEED = dict(
    engine_speed=570.0,
    engine_inertia=np.inf,
    engine_torque=156.0,
    driven_inertia=0.021,
    load_torque=44.0,
    peak_capacity=239.3,
)


@dataclass(frozen=True)
class Case:
    study: str
    case: str
    right_answer: str  # the right answer in words and numbers
    source: str  # where the right answer comes from
    computed: str  # what clutchlab computed in this run
    error: float  # |computed - right| (units in the right answer; NaN: a status check only)
    tolerance: float
    status_ok: bool  # the status (or the qualitative answer) is the right one
    off_the_shelf: str = ""
    relative: bool = (
        False  # error and tolerance relative to the right answer (else absolute, its units)
    )
    unit: str = ""  # the unit of an absolute error and its tolerance (as the right answer's)

    @property
    def error_kind(self) -> str:
        return "status" if np.isnan(self.error) else ("relative" if self.relative else "absolute")

    @property
    def passed(self) -> bool:
        return bool(self.status_ok and (np.isnan(self.error) or self.error <= self.tolerance))


def _name(code) -> str:
    return st.FLAGS.get(int(np.ravel(code)[0]), str(code))


def _f(x) -> float:
    return float(np.ravel(x)[0])


def _ms(t, fmt=".12g") -> str:
    """A time [s] as the pages give it: in ms."""
    return f"{float(t) * 1e3:{fmt}} ms"


def _num(x, fmt="g") -> str:
    """The first value of ``x`` as text, NaN spelled as the pages spell it."""
    v = _f(x)
    return "NaN" if np.isnan(v) else format(v, fmt)


def engagement_cases() -> list[Case]:
    """The engagement solver's hard cases, each against its right answer.

    Returns
    -------
    list of Case
        Start of motion with zero acceleration, step clamp, never locking, break-away and re-lock,
        tiny driven inertia, zero initial slip, held engine at rest, restart at an event, judder.
    """
    return [
        _start_of_motion(),
        _step_clamp(),
        _never_locking(),
        _breakaway_and_relock(),
        _tiny_driven_inertia(),
        _zero_initial_slip(),
        _held_engine_at_rest(),
        _restart_at_an_event(),
        _judder(),
    ]


def _start_of_motion() -> Case:
    """Start of motion with zero acceleration: the driven side starts when C(t) = T_m, with zero
    acceleration there; an integrator's first steps jump over it (the engagement benchmark's design,
    scenario 5: Stribeck friction, held engine)."""
    from . import engagement as eng
    from .bench import engagement as benchmark

    d = benchmark.design(200)
    i = 5
    right = benchmark.reference(d, i)
    sc = {k: float(v[i]) for k, v in d.items()}
    sim = eng.simulate(
        **{k: v for k, v in sc.items() if k != "stribeck_speed"},
        engine_inertia=np.inf,
        engine_torque=0.0,
        static_ratio=benchmark.RS,
        stribeck_speed=sc["stribeck_speed"],
        t_end=1.0,
    )
    shelf = [
        f"RK45 rtol {rtol:g}: error {abs(benchmark.rk45_per_scenario(d, i, rtol) - right) * 1e3:.1e} ms"
        for rtol in (1e-6, 1e-9)
    ]
    return Case(
        "engagement",
        "start of motion with zero acceleration (ramp clamp, Stribeck μ; benchmark scenario 5)",
        f"lock-up {_ms(right)}",
        "DOP853 at rtol 1e-12 from the analytic start of motion (clutchlab.bench.engagement.reference)",
        f"{_ms(_f(sim['lockup_time']))} ({int(sim['n_steps'])} steps)",
        abs(_f(sim["lockup_time"]) - right) * 1e3,
        1e-3,
        _name(sim["status"]) == "ok",
        "; ".join(shelf) + " (the first steps jump over the start of motion)",
        unit="ms",
    )


def _step_clamp() -> Case:
    """Step clamp: ramp time 0."""
    from . import engagement as eng

    right = 0.021 * 570.0 / (239.3 - 44.0)
    sim = eng.simulate(**SEED, ramp_time=0.0, t_end=0.5)
    return Case(
        "engagement",
        "step clamp (ramp time 0)",
        f"lock-up J ω/(C - T) = {_ms(right)}",
        "analytic (constant torques after the step)",
        _ms(_f(sim["lockup_time"])),
        abs(_f(sim["lockup_time"]) - right) * 1e3,
        1e-12 * right * 1e3,
        _name(sim["status"]) == "ok",
        unit="ms",
    )


def _never_locking() -> Case:
    """Load above the capacity: never locks, slip work over the window."""
    from . import engagement as eng

    right = 570.0 * 239.3 * (0.4 - 0.075)
    sim = eng.simulate(**dict(SEED, load_torque=300.0), ramp_time=0.15, t_end=0.4)
    return Case(
        "engagement",
        "never locking (load 300 N·m above the 239.3 N·m capacity)",
        f"status never_locked, lock-up NaN, slip work ω ∫C dt = {right / 1e3:.10g} kJ",
        "analytic (the driven side never moves)",
        f"{_name(sim['status'])}, lock-up {_num(sim['lockup_time'])}, slip work {_f(sim['slip_work']) / 1e3:.10g} kJ",
        abs(_f(sim["slip_work"]) - right) / right,
        1e-10,
        _name(sim["status"]) == "never_locked" and np.isnan(_f(sim["lockup_time"])),
        relative=True,
    )


def _breakaway_and_relock() -> Case:
    """Break-away after lock-up (load step at 0.35 s above the momentary capacity) and re-lock."""
    from scipy.optimize import brentq

    from . import engagement as eng

    def icap(t):  # ∫0^t C dt, C = 239.3 min(t/0.5, 1)
        return 239.3 * (t * t if t <= 0.5 else 0.25 + (t - 0.5))

    def dw(t):  # driven speed after the break-away at 0.35 s under 44 + 150 N m
        return 570.0 + (icap(t) - icap(0.35) - 194.0 * (t - 0.35)) / 0.021

    relock = brentq(lambda t: dw(t) - 570.0, 0.5 * 194.0 / 239.3 + 1e-6, 1.5, xtol=1e-14)
    sim = eng.simulate(**SEED, ramp_time=0.5, load_step=150.0, load_step_time=0.35, t_end=1.5)
    return Case(
        "engagement",
        "break-away after lock-up and re-lock (load step 150 N·m at 0.35 s)",
        f"break-away at 350 ms, re-lock at {_ms(relock)}",
        "exact integral of the driven side's equation, brentq at xtol 1e-14",
        f"break-away {_ms(_f(sim['breakaway_time']))}, re-lock {_ms(_f(sim['lockup_time']))}",
        max(abs(_f(sim["lockup_time"]) - relock), abs(_f(sim["breakaway_time"]) - 0.35)) * 1e3,
        1e-6,
        _name(sim["status"]) == "ok",
        unit="ms",
    )


def _tiny_driven_inertia() -> Case:
    """Tiny driven inertia."""
    from . import engagement as eng

    kw = dict(SEED, driven_inertia=1e-6)
    right = _f(eng.closed_form(**kw, ramp_time=0.15)["lockup_time"])
    sim = eng.simulate(**kw, ramp_time=0.15, t_end=0.3)
    return Case(
        "engagement",
        "tiny driven inertia (1e-6 kg·m²)",
        f"lock-up {_ms(right)}",
        "closed form",
        f"{_ms(_f(sim['lockup_time']))} in {int(sim['n_steps'])} steps",
        abs(_f(sim["lockup_time"]) - right) * 1e3,
        1e-9,
        _name(sim["status"]) == "ok" and sim["n_steps"] < 200,
        "a regularised (tanh) friction model is stiff as C/(J ε) here and never locks exactly",
        unit="ms",
    )


def _zero_initial_slip() -> Case:
    """Zero initial slip: stuck if the static capacity carries the needed torque."""
    from . import engagement as eng

    sim = eng.simulate(**SEED, ramp_time=0.0, driven_speed=570.0, t_end=0.2)
    return Case(
        "engagement",
        "zero initial slip (driven at engine speed, full clamp)",
        "stuck from t = 0: lock-up 0 ms",
        "capacity 239.3 N·m carries the 44 N·m needed (never sign(0))",
        f"{_ms(_f(sim['lockup_time']), 'g')}, {_name(sim['status'])}",
        abs(_f(sim["lockup_time"])) * 1e3,
        0.0,
        _name(sim["status"]) == "ok",
        unit="ms",
    )


def _held_engine_at_rest() -> Case:
    """A held engine at rest: the clutch holds the parked driven side."""
    from . import engagement as eng

    kw = dict(
        engine_speed=0.0,
        engine_inertia=np.inf,
        engine_torque=0.0,
        driven_inertia=0.2,
        load_torque=5.0,
        peak_capacity=300.0,
        ramp_time=0.2,
    )
    right = 5.0 / 300.0 * 0.2
    sim = eng.simulate(t_end=0.5, **kw)
    return Case(
        "engagement",
        "held engine at rest (0 rad/s, load 5 N·m)",
        f"lock-up where C(t) = T_m: {_ms(right)}, slip work 0",
        "analytic",
        f"{_ms(_f(sim['lockup_time']))}, slip work {_f(sim['slip_work']) / 1e3:g} kJ",
        abs(_f(sim["lockup_time"]) - right) * 1e3,
        1e-12 * right * 1e3,
        _name(sim["status"]) == "ok" and _f(sim["slip_work"]) == 0.0,  # (no slip: exactly 0)
        unit="ms",
    )


def _restart_at_an_event() -> Case:
    """Restart at an event (compliant driveline): the output unparks with zero speed and
    acceleration."""
    from . import engagement as eng
    from . import reference

    p = dict(
        engine_speed=570.0,
        engine_inertia=np.inf,
        engine_torque=0.0,
        driven_inertia=0.04478219675494552,
        load_torque=53.91347757013077,
        peak_capacity=175.34809669906292,
        ramp_time=0.2646604830414761,
        static_ratio=1.1104845505417242,
        damper_stiffness=4361.988757965115,
        damping_ratio=0.02798763262542414,
        hub_fraction=0.405630050395109,
        t_end=0.6,
    )
    ref = reference.compliant(p, rtol=1e-13, atol=1e-13)["lockup_time"]
    sim = eng.simulate(**p, compliant=True)
    return Case(
        "engagement",
        "restart at an event (compliant driveline: output unparks, g(t0) = 0)",
        f"lock-up {_ms(ref)} (not never_locked)",
        "clutchlab.reference.compliant: DOP853 per mode at rtol 1e-13",
        f"{_ms(_f(sim['lockup_time']))}, {_name(sim['status'])}",
        abs(_f(sim["lockup_time"]) - ref) / ref,
        1e-10,
        _name(sim["status"]) == "ok",
        "solve_ivp with an event function that is 0 at the restart fires at once "
        "(a zero-length segment): it needs mode logic",
        relative=True,
    )


def _judder() -> Case:
    """μ falling with slip on a compliant driveline: the friction's negative damping beats the
    damper's, and the hub-output mode grows at the linearised eigenvalue's rate."""
    from . import engagement as eng

    cap, rs, vs, s0, we = 100.0, 1.5, 10.0, 10.0, 300.0
    k, jv, zeta = 1e6, 0.1, 0.001
    jh = jr = 0.5 * jv
    f = 1 + (rs - 1) * np.exp(-((s0 / vs) ** 2))
    df = -(rs - 1) * 2 * s0 / vs**2 * np.exp(-((s0 / vs) ** 2))
    tm = cap * f
    c = 2 * zeta * np.sqrt(k * jh * jr / jv)
    g = -cap * df
    a = np.array([[(g - c) / jh, -k / jh, c / jh], [1.0, 0.0, -1.0], [c / jr, k / jr, -c / jr]])
    lam = np.linalg.eigvals(a)
    rate = float(lam[np.abs(lam.imag) > 0].real.max())
    tt = np.linspace(0.0, 0.03, 1501)
    s = eng.simulate(
        engine_speed=we,
        engine_inertia=np.inf,
        engine_torque=0.0,
        driven_inertia=jv,
        load_torque=tm,
        peak_capacity=cap,
        ramp_time=0.0,
        driven_speed=we - s0,
        static_ratio=rs,
        stribeck_speed=vs,
        compliant=True,
        hub_fraction=0.5,
        damper_stiffness=k,
        damping_ratio=zeta,
        t_end=0.03,
        trace_times=tt,
        rtol=1e-11,
        atol=1e-11,
    )
    rel = s["trace"]["hub_speed"] - s["trace"]["output_speed"]
    growth = np.abs(rel[tt > 0.025]).max() / np.abs(rel[tt < 0.005]).max()
    right = np.exp(rate * 0.025)
    return Case(
        "engagement",
        "μ falling with slip speed on a compliant driveline (judder)",
        f"oscillation grows: envelope ×{right:.4g} over 25 ms (Re λ = {rate:.4g} 1/s)",
        "eigenvalues of the linearised hub-twist-output system",
        f"envelope ×{growth:.4g}",
        abs(growth - right) / right,
        0.05,
        growth > 1.0,
        relative=True,
    )


def contact_cases() -> list[Case]:
    from scipy.integrate import solve_ivp

    from . import contact

    m, v, k = 0.05, 1.5, contact.hertz_stiffness(roller_diameter=0.010)
    d_max = (5 * m * v**2 / (4 * k)) ** 0.4
    t_c = contact.HERTZ_CONTACT_TIME_FACTOR * d_max / v
    r = contact.hertz_impact(mass=m, speed=v, stiffness=float(k))
    err = max(
        abs(_f(r["max_penetration"]) - d_max) / d_max,
        abs(_f(r["contact_time"]) - t_c) / t_c,
        abs(_f(r["restitution"]) - 1.0),
    )

    def f(t, y):
        return [y[1], -k * max(y[0], 0.0) ** 1.5 / m]

    sep = lambda t, y: y[0] if t > 0 else 1.0  # noqa: E731
    sep.terminal, sep.direction = True, -1
    sol = solve_ivp(
        f,
        (0.0, 10 * t_c),
        [0.0, v],
        method="RK45",
        rtol=1e-8,
        atol=1e-14,
        events=sep,
        dense_output=True,
    )
    t_rk = sol.t_events[0][0] if sol.t_events[0].size else np.nan
    return [
        Case(
            "roller",
            "stiff Hertz contact: undamped impact (0.05 kg at 1.5 m/s, d = 10 mm roller)",
            f"δ_max = (5mv²/4k)^(2/5) = {d_max * 1e6:.7g} µm, contact time 2.9432 δ_max/v = "
            f"{t_c * 1e6:.7g} µs, "
            "restitution 1",
            "Johnson, Contact Mechanics 11.4 (analytic)",
            f"δ_max {_f(r['max_penetration']) * 1e6:.7g} µm, contact "
            f"{_f(r['contact_time']) * 1e6:.7g} µs, "
            f"restitution {_f(r['restitution']):.9f} ({int(_f(r['nfev']))} f evals)",
            err,
            1e-6,
            True,
            f"RK45 rtol 1e-8: contact time error {abs(t_rk - t_c) / t_c:.1e} ({sol.nfev} f evals)",
            relative=True,
        )
    ]


def centrifugal_cases() -> list[Case]:
    from . import centrifugal as cf
    from .studies.centrifugal import RPM

    seed = dict(shoes=3, shoe_mass=0.178, shoe_radius=0.034, drum_radius=0.045, spring_force=430.0)
    out = []
    for f, deg, right, what in (
        (1.0, 45.0, "jammed", "f tan α = 1 within rounding (f = 1, α = 45°: tan = 1 - 1.1e-16)"),
        (0.99, 45.0, "near_jam", "f tan α = 0.99 (a 1 % friction rise jams it)"),
    ):
        code = cf.design_status(
            rated_speed=5500 * RPM,
            rotor_load_torque=55.0,
            friction_coefficient=f,
            pressure_angle=np.deg2rad(deg),
            friction_scatter=0.25,
            **seed,
        )
        fwd, _ = cf.capacity(
            speed=5500 * RPM, friction_coefficient=f, pressure_angle=np.deg2rad(deg), **seed
        )
        want_nan = right == "jammed"
        out.append(
            Case(
                "centrifugal",
                what,
                f"status {right}" + (", capacity NaN" if want_nan else ", capacity kept (exact)"),
                "paper 001 eq. 1: M ∝ 1/(1 - f tan α); friction scatter 25 % (assumed)",
                f"{_name(code)}, M = {_num(fwd, '.6g')} N·m",
                np.nan,
                0.0,
                _name(code) == right and bool(np.isnan(_f(fwd))) == want_nan,
            )
        )
    return out


def diaphragm_cases() -> list[Case]:
    from . import diaphragm
    from .studies.diaphragm_spring import seed_spring

    spring = dict(seed_spring(), operating_point_factor=0.9)
    spring["cone_height"] = np.sqrt(2.0) * spring["sheet_thickness"]
    pts = diaphragm.characteristic_points(**spring)
    return [
        Case(
            "diaphragm_spring",
            "monotone spring (H/h = √2)",
            "status monotone_no_hump, no points A/C/D",
            "Almen-László: a hump only for H/h > √2",
            f"{_name(pts['status'])}, load_A {_num(pts['load_A'])}",
            np.nan,
            0.0,
            _name(pts["status"]) == "monotone_no_hump" and bool(np.isnan(_f(pts["load_A"]))),
        )
    ]


def sprag_cases() -> list[Case]:
    from . import sprag as sp

    r = sp.statics(np.array([300.0, 5000.0]), compliance_factor=5.0)
    return [
        Case(
            "sprag",
            "sprag roll-over (5× compliance, 5000 N·m)",
            "status roll_over, no stresses (the loaded races open past the sprag's reach)",
            "paper 002 geometry: no gripping angle solves the deflected contact",
            f"{_name(r['status'][1])}, V {_num(r['V'][1])}; at 300 N·m: {_name(r['status'][0])}",
            np.nan,
            0.0,
            _name(r["status"][1]) == "roll_over"
            and bool(np.isnan(r["V"][1]))
            and _name(r["status"][0]) != "roll_over",
        )
    ]


CASES = {
    "engagement": engagement_cases,
    "roller": contact_cases,
    "centrifugal": centrifugal_cases,
    "diaphragm_spring": diaphragm_cases,
    "sprag": sprag_cases,
}


def run(study_names=None) -> list[Case]:
    """Every hard case of the studies named (default: all)."""
    names = list(CASES) if study_names is None else [s for s in study_names if s in CASES]
    return [case for s in names for case in CASES[s]()]


def to_dataset(cases: list[Case]) -> xr.Dataset:
    """Cases -> Dataset on dimension ``case`` with units and long_name on every variable."""

    def text(name, long_name):
        return (
            "case",
            np.array([getattr(c, name) for c in cases], dtype=object),
            {"long_name": long_name, "units": ""},
        )

    return xr.Dataset(
        {
            "study": text("study", "study the case belongs to"),
            "name": text("case", "hard case"),
            "right_answer": text("right_answer", "right answer"),
            "source": text("source", "source of the right answer"),
            "computed": text("computed", "what clutchlab computed"),
            "error": (
                "case",
                [c.error for c in cases],
                {
                    "long_name": "error against the right answer (NaN: a status check)",
                    "units": "row-wise: relative (1) or in error_unit (error_kind says which)",
                },
            ),
            "error_kind": text(
                "error_kind", "error relative to the right answer or absolute (in its units)"
            ),
            "error_unit": text("unit", "the unit of an absolute error and its tolerance"),
            "tolerance": (
                "case",
                [c.tolerance for c in cases],
                {"long_name": "tolerance", "units": "as the error"},
            ),
            "passed": (
                "case",
                np.array([c.passed for c in cases], np.int8),
                {"long_name": "passed (1) or not (0)", "units": "1"},
            ),
            "off_the_shelf": text(
                "off_the_shelf", "what an off-the-shelf solver gives on the same case"
            ),
        },
        coords={"case": ("case", np.arange(len(cases)), {"long_name": "case index", "units": "1"})},
        attrs={"title": "clutchlab hard cases"},
    )


def to_csv(ds: xr.Dataset, path) -> None:
    import csv

    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS)
        for i in range(ds.sizes["case"]):
            w.writerow(
                [
                    ds["name" if c == "case" else c].values[i] if c in ds or c == "case" else ""
                    for c in COLUMNS  # (a file of an older version has no error_unit)
                ]
            )

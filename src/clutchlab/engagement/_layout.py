"""The data of the compiled engagement solver: column layouts, codes and the named records.

Every scenario is one row ``q`` of the parameter table (read-only; columns below, built by
:func:`clutchlab.engagement._simulate.parameter_table`); its state ``y`` is a small array with
named columns; its results are one row of named result columns. The kernels pass the mode of
the stick/slip/park state machine as a :class:`Mode`, the forces at a state as a :class:`Forces`,
the solver options as an :class:`Options`, and the scenario's scratch arrays as a
:class:`Work`; the driver's mutable scalars (time, step size, counters) live in one record of
:data:`SCENARIO` (numpy structured dtype, fields by name). No positional offsets.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

# ---- parameter columns (one row per scenario) --------------------------------------------------
(
    WE0,  # initial engine speed ω_e(0) [rad/s]
    JE,  # engine inertia J_e [kg m²] (inf: held)
    TE,  # engine torque T_e [N m]
    JV,  # driven inertia J_v [kg m²]
    TM0,  # load torque T_m [N m]
    CMAX,  # peak capacity C_max [N m]
    TR,  # ramp time t_r [s]
    RS,  # static ratio μ_s/μ_k [-]
    VS,  # Stribeck speed v_s [rad/s] (inf: constant μ_k)
    WC0,  # initial driven speed ω_c(0) [rad/s]
    KA,  # rotor drag coefficient k_a [N m s²]
    DTM,  # load step ΔT_m [N m]
    TSTEP,  # load step time t_s [s]
    PHI,  # hub share of J_v [-]
    K,  # damper stiffness [N m/rad]
    ZETA,  # damping ratio ζ [-]
    TEND,  # end of the window [s]
    HELD,  # 1 for a held engine (J_e = inf), else 0
    INV_JE,  # 1/J_e [1/(kg m²)] (0 held)
    JH,  # hub inertia φ·J_v [kg m²]
    JR,  # output inertia (1 − φ)·J_v [kg m²]
    CD,  # damper viscous coefficient 2ζ√(K·J_h·J_r/J_v) [N m s/rad]
    KAPPA,  # release ratio κ [-]
    TCON,  # time the lining cushion is touched (κ > 1) [s]
    FADE,  # fade coefficient β [1/K]
    FADE_ON,  # fade onset ΔT_on [K]
    FACE_K,  # face temperature factor K [K/(W s^0.5)]
    FTAB,  # column of the friction table (0: none)
) = range(28)
N_PARAM = 28
# the engine torque table from column NTAB: count, then speeds, then torques (shared, on every
# row); the friction table (column FTAB, if any) after it, laid out alike: count, slip speeds, μ/μ_k
NTAB = N_PARAM

# ---- state columns ----------------------------------------------------------------------------
# hub (rigid: driven side) speed, slip/load/input work, engine speed, output speed, damper twist,
# damping work; rigid held engine: the first 4 move, rigid free: 5, compliant: all 8
H, WS, WL, WI, E, R, TH, WD = range(8)
N_MECH = 8
NZ = 15  # modes of the friction face's temperature (clutchlab.engagement._fade; only with fade)
Z0 = N_MECH  # their first column
N_STATE = N_MECH + NZ

# ---- events (switching functions falling through zero from > 0) --------------------------------
LOCK, BREAK, UNPARK, PARK, PEAK = range(5)
N_EVENTS = 5
NO_EVENT = -1
OUT_OF_WORK = -2  # a linear segment that ran out of its work budget (not an event)
# how following a locked scenario after the window ended
FOLLOW_SETTLED, FOLLOW_EVENT, FOLLOW_OUT_OF_WORK = range(3)
EVENT_TIME_TOL = 1e-13  # s: bracket width at which an event time is final (Illinois method)

# ---- running maxima of a scenario (slots of the array ``pk``) ----------------------------------
MAX_POWER, MAX_TORQUE, MAX_JERK = range(3)  # slip power, |friction torque|, |output jerk|
N_MAXIMA = 3

# ---- result columns ---------------------------------------------------------------------------
RESULTS = (
    "lockup_time",
    "breakaway_time",
    "capacity_at_lockup",
    "accel_jump",
    "lockup_speed",
    "peak_slip_power",
    "peak_friction_torque",
    "peak_jerk",
    "slip_work",
    "load_work",
    "input_work",
    "kinetic_energy_change",
    "damping_work",
    "energy_residual",
    "n_steps",
    "final_locked",
    "hit_step_limit",
    "n_rejected",
    "n_locate",
    "n_false_alarms",
    "n_event_steps",
    "truncated",
    "n_linear",
    "flash_peak",
    "n_power_samples",
)
(
    LOCKUP_TIME,
    BREAKAWAY_TIME,
    CAPACITY_AT_LOCKUP,
    ACCEL_JUMP,
    LOCKUP_SPEED,
    PEAK_SLIP_POWER,
    PEAK_FRICTION_TORQUE,
    PEAK_JERK,
    SLIP_WORK,
    LOAD_WORK,
    INPUT_WORK,
    KINETIC_ENERGY_CHANGE,
    DAMPING_WORK,
    ENERGY_RESIDUAL,
    N_STEPS,
    FINAL_LOCKED,
    HIT_STEP_LIMIT,
    N_REJECTED,
    N_LOCATE,
    N_FALSE_ALARMS,
    N_EVENT_STEPS,
    TRUNCATED,
    N_LINEAR,
    FLASH_PEAK,
    N_POWER_SAMPLES,
) = range(len(RESULTS))
N_RESULTS = len(RESULTS)

# ---- trace columns ----------------------------------------------------------------------------
TRACES = (
    "engine_speed",
    "hub_speed",
    "output_speed",
    "friction_torque",
    "capacity",
    "slip_work",
    "jerk",
    "face_temperature_rise",
)
(
    T_ENGINE,
    T_HUB,
    T_OUTPUT,
    T_TORQUE,
    T_CAPACITY,
    T_SLIP_WORK,
    T_JERK,
    T_FACE_RISE,
) = range(len(TRACES))
N_TRACES = len(TRACES)

# ---- the slip power history (only when asked for) ----------------------------------------------
# sampled while slipping every ramp time / POWER_SAMPLES_PER_RAMP (a ramp shorter than window / 48,
# or a step: every window / 48²) and at every step end and event, at most POWER_SAMPLES_MAX
# samples a scenario; its Duhamel integral's peak, max over t of ∫ P(τ)/√(t − τ) dτ [W s^0.5]
# (P linear between samples, each segment integrated exactly), is the result FLASH_PEAK (NaN if
# the history overflowed). A slip that ends early in the ramp would get few samples (second
# order: 18 samples gave 5e-3): within a slip phase the spacing is also at most (time slipped by
# the segment's end) / POWER_SAMPLES_PER_SLIP, but not below the ramp spacing /
# POWER_SAMPLES_DENSER (at most POWER_SAMPLES_PER_SLIP · POWER_SAMPLES_DENSER more samples a slip
# phase)
POWER_SAMPLES_PER_RAMP = 48
POWER_SAMPLES_PER_SLIP = 64
POWER_SAMPLES_DENSER = 8
POWER_SAMPLES_MAX = 4096

# ---- records ----------------------------------------------------------------------------------
#: The mode of the stick/slip/park state machine and the model (numba named tuple, passed by value):
#: ``locked`` (engine and hub stuck together), ``parked`` (output held at rest by its static
#: load), ``sign`` (±1: direction of slip), ``compliant`` (damper springs between hub and output;
#: a constant of each compiled batch loop) and ``profile`` (clamp profile 0 ramp, 1 cubic, 2
#: quintic).
Mode = namedtuple("Mode", ["locked", "parked", "sign", "compliant", "profile"])

#: The forces at a state (:func:`clutchlab.engagement._physics.forces`): ``capacity`` C(t) [N m],
#: ``torque`` the clutch torque T_c [N m], ``load`` T_m [N m], ``spring`` the damper torque T_s
#: [N m], ``needed`` the clutch torque that keeps the locked sides together [N m], ``slip`` Δω
#: [rad/s], ``law`` μ(|Δω|)/μ_k [-], ``output_accel`` [rad/s²], ``fade`` the fade factor g [-]
#: and ``law_slope`` d(μ/μ_k)/d|Δω| [s/rad].
Forces = namedtuple(
    "Forces",
    [
        "capacity",
        "torque",
        "load",
        "spring",
        "needed",
        "slip",
        "law",
        "output_accel",
        "fade",
        "law_slope",
    ],
)

#: The solver options, shared by all scenarios of a batch (``peaks``: whether the exact linear
#: phases track the peak friction torque and output jerk; the slip power's peak always).
Options = namedtuple(
    "Options", ["rtol", "atol", "max_step", "first_step", "max_steps", "with_hist", "peaks"]
)

#: A scenario's scratch arrays (views of the batch's, of the scenario's state length): the state
#: ``y`` and its derivative ``d`` at the step's left end, ``y1``/``d1`` at its right end, ``dm``
#: derivatives at a trial state, ``ym`` an interpolated state, ``err`` the error estimate, ``yi``
#: a stage state, ``ya``/``yb`` located and trial states, ``y_best`` the earliest located event's
#: state, ``kk`` the 7 stages, ``g``/``g1``/``gm`` the event functions at the left end, the right
#: end and inside, ``tau_hi`` the events' brackets, ``pk`` the running maxima (MAX_POWER …),
#: ``ths`` the step fractions where the events are sampled, ``rc`` the continuous extension's
#: coefficients, ``da`` the derivative at a located state, ``y_end`` the state at the window's end.
Work = namedtuple(
    "Work",
    [
        "y",
        "d",
        "d1",
        "dm",
        "y1",
        "ym",
        "err",
        "yi",
        "ya",
        "yb",
        "y_best",
        "kk",
        "g",
        "g1",
        "gm",
        "tau_hi",
        "pk",
        "ths",
        "rc",
        "da",
        "y_end",
    ],
)

#: The driver's mutable scalars of one scenario (a one-element structured array).
SCENARIO = np.dtype(
    [
        ("t", np.float64),  # time [s]
        ("locked", np.bool_),  # the mode (see Mode)
        ("parked", np.bool_),
        ("sign", np.float64),
        ("h", np.float64),  # next step size [s]
        ("h_acc", np.float64),  # last accepted step and its error factor (step-size control)
        ("fac_acc", np.float64),
        ("h_acc_prev", np.float64),  # the same before the last acceptance (undone on a retry)
        ("fac_acc_prev", np.float64),
        ("rejected", np.bool_),  # the last step was rejected: no growth
        (
            "j_left",
            np.float64,
        ),  # output jerk [rad/s³] and clutch torque [N m] at the step's left end
        ("tc_left", np.float64),
        ("n_hist", np.int64),  # slip power samples
        ("t_slip", np.float64),  # start of the current slip phase [s]
        ("dt_s", np.float64),  # the power samples' spacing [s]
        ("n_steps", np.int64),  # integrator steps attempted
        ("effort", np.int64),  # work spent (steps, mode switches, linear root-search passes)
        ("out_of_work", np.bool_),
        ("t_stop", np.float64),  # where the integration stops [s]
        ("past", np.bool_),  # past the window's end (following a locked scenario)
    ]
)

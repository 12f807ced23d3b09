"""Clutch engagement of a two-inertia driveline (source paper (000), eqs. 1-2, 11-13), batched.

Engine side (eq. 1) J_e·dω_e/dt = T_e − T_c; driven side (eq. 2) J_v·dω_c/dt = T_c − T_m.
While slipping T_c = sign(Δω)·μ(abs(Δω))/μ_k · C(t) with the kinetic capacity
C(t) = C_max·p(t/t_r) (p a clamp profile: linear ramp, cubic or quintic smooth step, 1 after
t_r); while stuck T_c is whatever keeps both sides together, as long as it stays within the
static capacity (μ_s/μ_k)·C(t). The driven side stays parked at rest while the clutch torque is
below the (static) load torque. An engine with ``engine_inertia = inf`` is held at its speed.

Two solvers, one contract (same inputs, same metrics):

* :func:`closed_form` — constant μ, constant torques, polynomial clamp profile, held or free
  engine: speeds are piecewise polynomials in t, lock-up is a polynomial root (bracketed, to
  machine precision), slip/load/input work are exact Gauss-Legendre integrals.
  ≈ 0.7 µs per scenario at 10⁶ scenarios; it is also the reference for the numerical solver.
* :func:`simulate` — everything else (Stribeck μ, rotor drag k·ω², engine torque table, load
  step, compliant driveline): a Dormand-Prince 5(4) integrator (compiled with numba) with per-scenario step
  sizes, breakpoints at the profile end and load step, and an event-driven stick/slip state
  machine whose events are located on the integrator's own solution (re-integration from the
  step's left end and a Newton correction), i.e. to the integrator's accuracy, not to the step
  size.

The package's modules (private; this one is the public API), in the manner of
``scipy.integrate._ivp``:

* ``_profile`` — clamp profiles and the release-bearing travel model;
* ``_domain`` — the admissible inputs (screening) and the checks of the shared options;
* ``_closed_form`` — :func:`closed_form`'s driver; ``_lockup`` its phases and the lock-up root;
  ``_works`` its work integrals, peaks and slip power samples;
* ``_simulate`` — :func:`simulate`'s driver: screening, the parameter table, the results;
* the compiled solver of :func:`simulate` (numba, allocation-free): ``_layout`` (the parameter,
  state, result and trace columns, event codes and the named records the kernels pass),
  ``_physics`` (forces, jerk, switching functions), ``_friction`` (the slipping friction law),
  ``_fade`` (the friction face's temperature modes and the fade factor), ``_dopri`` (the
  Dormand-Prince stepper and its step-size control), ``_events`` (event detection and
  location), ``_peaks`` (peak metrics inside steps), ``_power`` (the slip power history and its
  Duhamel integral), ``_linear_forms`` and ``_linear_phase`` (the compliant model's exact linear
  phases), ``_driver`` (one scenario's loop and the batch).

References
----------
.. [1] Zhao P. (2026), source paper (000), eqs. (1), (2), (11), (12), (13), Figs. 7-11.
.. [2] Otter M., Elmqvist H., Mattsson S.E. (1999), "Hybrid modeling in Modelica based on the
   synchronous data flow principle" (friction state machine of the Modelica Standard Library).
"""

from __future__ import annotations

# (the limits and constants the docstrings name are importable from here as before, re-exported
# as ``X as X``; __all__ lists the functions and profiles of the API reference)
from ._closed_form import closed_form, ramp_time_for_lockup
from ._domain import MAX_DAMPING_RATIO as MAX_DAMPING_RATIO
from ._domain import MAX_RELEASE_RATIO as MAX_RELEASE_RATIO
from ._domain import MAX_STATIC_RATIO as MAX_STATIC_RATIO
from ._domain import MAX_WORK as MAX_WORK
from ._domain import MIN_HUB_FRACTION as MIN_HUB_FRACTION
from ._profile import PROFILES, bearing_travel_clamp, clamp_profile
from ._simulate import EVENT_TIME_TOL as EVENT_TIME_TOL
from ._simulate import simulate
from ._works import CLOSED_FORM_POWER_SAMPLES as CLOSED_FORM_POWER_SAMPLES

__all__ = [
    "PROFILES",
    "clamp_profile",
    "bearing_travel_clamp",
    "closed_form",
    "simulate",
    "ramp_time_for_lockup",
]

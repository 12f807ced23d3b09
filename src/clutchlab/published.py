"""Numbers printed in the source papers that the studies, the report, the validation table and the
tests compare against: one place, each with its paper and the table, equation, section or figure
that prints it.

The papers are numbered as in the validation table's ``seed`` column:

* 000 — Zhao Peng (2026), design and engagement simulation of a diaphragm-spring clutch for an
  unmanned helicopter: :data:`DIAPHRAGM_CLUTCH`;
* 001 — Sun Rongzhe (2017), design and test of a multi-function (centrifugal, overrunning) clutch
  for small unmanned helicopters: :data:`CENTRIFUGAL_CLUTCH`;
* 002 — a sprag clutch under the transient impact of a turbine starter: :data:`SPRAG_CLUTCH` (its
  allowables) and :data:`SPRAG_TABLE2` (Table 2, theory column);
* 003 — Wang Peng, Li Pingkang, Li Wenguang, Kong Lingliang (2013), design of a new roller-type
  control-separated overrunning clutch: :data:`ROLLER_CLUTCH`.

Values are as the paper prints them, in the units it prints them (``units``, CF spelling; MPa,
rpm, deg and ms where the paper uses them), except where ``source`` names an erratum. A few
reference numbers are not printed but derived from the paper's equations as corrected
(``printed`` False, the derivation in ``source``): the validation table compares against them
like the printed ones. Design inputs a paper prints (dimensions, loads, speeds) are the studies'
parameter defaults, not repeated here.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "Published",
    "SpragTheory",
    "DIAPHRAGM_CLUTCH",
    "CENTRIFUGAL_CLUTCH",
    "SPRAG_CLUTCH",
    "SPRAG_TABLE2",
    "SPRAG_TABLE2_SOURCE",
    "SPRAG_TABLE2_UNITS",
    "ROLLER_CLUTCH",
]


@dataclass(frozen=True)
class Published:
    """One number of a source paper.

    Attributes
    ----------
    paper : str
        The paper's number ("000" to "003"), as the validation table's ``seed`` column.
    quantity : str
        What the number is, as the validation table names it.
    value : float
        The number [``units``].
    units : str
        Its units (CF spelling, as the paper prints them: "MPa", "rpm", "deg", "ms", ...).
    source : str
        Where the paper prints it (table, equation, section, figure).
    printed : bool
        False for a reference number derived from the paper's equations, not printed in it.
    """

    paper: str
    quantity: str
    value: float
    units: str
    source: str
    printed: bool = True


def _paper(paper):
    """A constructor of :class:`Published` records of ``paper``."""

    def number(quantity, value, units, source, printed=True):
        return Published(paper, quantity, float(value), units, source, printed)

    return number


_000 = _paper("000")
#: Paper 000, the diaphragm-spring clutch: statics (Tables 1-2, eqs. 3-14) and the engagement
#: simulation (section 5).
DIAPHRAGM_CLUTCH = {
    "lining_constant": _000(
        "lining design constant A (eq. 3, D = 225 mm)", 34.17, "1", "Table 1-2, eq. (3)"
    ),
    "damper_design_torque": _000("damper design torque T_j = 2 T_emax", 346.0, "N m", "Table 2"),
    "damper_total_force": _000("damper total spring force P_total (eq. 4)", 6654.0, "N", "Table 2"),
    "damper_angular_stiffness": _000(
        "damper angular stiffness C_a (eq. 7)", 4498.0, "N m rad-1", "Table 2"
    ),
    "damper_spring_rate": _000(
        "damper spring rate C (eq. 8)",
        415.9e3,
        "N m-1",
        "Table 2",  # printed as 416 'N/m': the value is in N/mm (erratum)
    ),
    "damper_coils": _000("damper coil count i (eqs. 6, 9)", 6.0, "1", "Table 2"),
    "spline_bearing_stress": _000("spline bearing stress at T_emax", 8.9e6, "Pa", "section 3.2.2"),
    "spline_shear_stress": _000("spline shear stress", 15e6, "Pa", "section 3.2.2"),
    "capacity_eq14_as_printed": _000(
        "friction torque, eq. (14) as printed", 239.3, "N m", "eq. (14), Fig. 11"
    ),
    "capacity_two_faces": _000(
        "capacity, 2 faces, uniform pressure, F = 2500 N",
        190.0,
        "N m",
        "eqs. (13)-(14) corrected",
        printed=False,
    ),
    "capacity_two_faces_stack_weight": _000(
        "capacity as above + 4.757 kg stack weight",
        193.5,
        "N m",
        "eqs. (13)-(14) corrected",
        printed=False,
    ),
    "clamp_load": _000(
        "clamp load F_B at lambda_B = 0.9 lambda_C (eq. 10)", 2500.0, "N", "section 5.1, Fig. 7"
    ),
    "lockup_time": _000("engagement: lock-up time", 0.150, "s", "section 5.2, Fig. 8"),
    "lockup_speed": _000(
        "engagement: driven speed at lock-up", 570.0, "rad s-1", "section 5.2, Fig. 8"
    ),
    "slip_work": _000("engagement: slip work (eq. 11)", 5800.0, "J", "section 5.3, Fig. 9"),
    "slip_work_lengthened": _000(
        "engagement: slip work, lock-up lengthened to 0.2 s (a lower bound: '> 7000 J')",
        7000.0,
        "J",
        "section 5.2",
    ),
}

_001 = _paper("001")
#: Paper 001, the centrifugal clutch with overrunning linkage: capacities at the rated 5500 rpm
#: (section 2.3) and the test after an engine cut.
CENTRIFUGAL_CLUTCH = {
    "forward_capacity": _001(
        "forward capacity M at 5500 rpm (eq. 1)", 127.84, "N m", "section 2.3"
    ),
    "reverse_capacity": _001("reverse capacity M' at 5500 rpm (eq. 2)", 65.0, "N m", "section 2.3"),
    "engine_torque": _001("engine torque at 5500 rpm", 68.0, "N m", "section 2.3"),
    "reserve_factor": _001("reserve factor M / 68 N m", 1.88, "1", "section 2.3"),
    "linkage_factor": _001(
        "f tan(alpha) from M, M' targets (eq. 1 / eq. 2)", 0.32587, "1", "section 2.3"
    ),
    "engagement_speed": _001("engagement speed", 2545.0, "rpm", "design inputs"),
    "idle_speed_min": _001(
        "idle speed, lower end (clutch disengaged)", 1900.0, "rpm", "requirements"
    ),
    "idle_speed_max": _001(
        "idle speed, upper end (clutch disengaged)", 2100.0, "rpm", "requirements"
    ),
    "idle_capacity": _001(
        "capacity at idle 1900-2100 rpm (disengaged)", 0.0, "N m", "requirements"
    ),
    "reserve_factor_53deg": _001(
        "alpha = 53 deg: reserve factor at 5500 rpm", 1.79, "1", "conclusions (final 1.79)"
    ),
    "release_speed": _001(
        "release speed after engine cut at 5500 rpm, alpha 38.84 deg",
        5400.0,
        "rpm",
        "test section (measured)",
    ),
}

_002 = _paper("002")
#: Paper 002, the sprag clutch: the allowables of Table 2 (its last line).
SPRAG_CLUTCH = {
    "contact_allowable": _002(
        "allowable Hertz contact stress", 3400.0, "MPa", "Table 2 (allowable)"
    ),
    "shaft_allowable": _002(
        "allowable shaft von Mises stress", 793.0, "MPa", "Table 2 (allowable)"
    ),
    "gripping_angle_allowable": _002(
        "allowable gripping angle V (pop-out beyond)",
        5.0,
        "deg",
        "Table 2 (allowable), section 2.2",
    ),
}


@dataclass(frozen=True)
class SpragTheory:
    """One torque of paper 002's Table 2, theory column (units: :data:`SPRAG_TABLE2_UNITS`).

    Attributes
    ----------
    torque : float
        Torque on the clutch [N m].
    gripping_angle : float
        Gripping angle V at the inner contact [deg].
    contact_stress_inner, contact_stress_outer : float
        Hertz contact stresses σ_ci, σ_co (eq. 7) [MPa].
    vm_stress_inner, vm_stress_outer : float
        Von Mises stresses σ_si of the inner shaft and σ_so of the outer race (eq. 8) [MPa].
    """

    torque: float
    gripping_angle: float
    contact_stress_inner: float
    contact_stress_outer: float
    vm_stress_inner: float
    vm_stress_outer: float


#: Where :data:`SPRAG_TABLE2` is printed.
SPRAG_TABLE2_SOURCE = "Table 2 (theory)"
#: Units of the fields of :class:`SpragTheory`.
SPRAG_TABLE2_UNITS = {
    "torque": "N m",
    "gripping_angle": "deg",
    "contact_stress_inner": "MPa",
    "contact_stress_outer": "MPa",
    "vm_stress_inner": "MPa",
    "vm_stress_outer": "MPa",
}
#: Paper 002, Table 2, theory column, by torque [N m]: the peak 750 N m and the rated 267.5 N m.
SPRAG_TABLE2 = {
    750.0: SpragTheory(
        torque=750.0,
        gripping_angle=5.097,
        contact_stress_inner=3482.0,
        contact_stress_outer=2928.0,
        vm_stress_inner=673.8,
        vm_stress_outer=582.0,
    ),
    267.5: SpragTheory(
        torque=267.5,
        gripping_angle=4.093,
        contact_stress_inner=2314.0,
        contact_stress_outer=1945.0,
        vm_stress_inner=295.2,
        vm_stress_outer=255.4,
    ),
}

_003 = _paper("003")
#: Paper 003, the roller-type controllable overrunning clutch: statics (sections 1.1-2.2, Table 1)
#: and the ADAMS engagement and release (sections 3.1-3.3).
ROLLER_CLUTCH = {
    "computed_torque": _003(
        "computed torque T_c = 2.31 x 800 N m (eq. 1)", 1848.0, "N m", "section 2.2"
    ),
    "normal_force": _003("normal force N_A (eq. 2, z = 12 as printed)", 8555.6, "N", "section 2.2"),
    "contact_stress": _003("contact stress sigma_H", 2865.5, "MPa", "section 2.2"),
    "contact_allowable_min": _003(
        "allowable contact stress, lower end (10^6 wedging cycles)", 3041.0, "MPa", "section 2.2"
    ),
    "contact_allowable_max": _003(
        "allowable contact stress, upper end (10^6 wedging cycles)", 3247.0, "MPa", "section 2.2"
    ),
    "spring_preload": _003("spring preload per roller F_T", 3.7, "N", "Table 1"),
    "self_locking_margin": _003(
        "self-locking margin mu / tan(alpha/2) at 11 deg", 1.25, "1", "section 2.1"
    ),
    "limit_wedge_angle": _003(
        "limiting wedge angle 2 atan(mu)",
        13.69,
        "deg",
        "section 1.1 step 4 (derived)",
        printed=False,
    ),
    "contact_stiffness": _003(
        "contact stiffness of a roller contact (Hertz)", 3.375e5, "N mm-1.5", "section 3.1.2"
    ),
    "engagement_time": _003("engagement (wedging) time", 0.197, "ms", "section 3.2 (ADAMS)"),
    "backlash": _003("total backlash angle", 1.12, "deg", "section 3.2 (ADAMS)"),
    "slip_backlash": _003("driving-ring / wedge-ring backlash", 0.11, "deg", "section 3.2 (ADAMS)"),
    "release_time": _003(
        "release time after stopping the control ring", 1.3, "ms", "section 3.3 (ADAMS)"
    ),
}

"""Captions of the report's files for Snakemake's own HTML report (``snakemake --report``).

Snakemake reads a caption from a reStructuredText file per output marked ``report(...)``; the
texts live here, next to the pages they describe, and :func:`write` puts one file per report file
in a folder of the working directory (``.snakemake/clutchlab_captions``) when the workflow is
parsed. Captions are Jinja templates: ``snakemake.params`` of the report rule is available
(clutchlab version, source hash, the run's resolved config).
"""

from __future__ import annotations

from pathlib import Path

from .explorer import MAX_DESIGNS

__all__ = ["caption", "category", "write"]

FIGURES = {
    "diaphragm_spring_load_curves": "Almen-László load-deflection curves of a spread of spring designs with their "
    "characteristic points A-D and the operating point B (paper 000 eq. 10).",
    "diaphragm_spring_reserve_map": "Reserve factor (torque capacity over the engine's maximum torque) over sheet "
    "thickness and cone-height ratio; designs without a hump or off the spring flagged.",
    "engagement_tradeoff": "The efficiency-smoothness trade-off: slip work against peak output jerk of every locked "
    "engagement, coloured by lock-up time, with the Pareto front of the feasible designs.",
    "engagement_maps": "Slip work and lock-up time over ramp time and clamp force.",
    "engagement_traces": "Traces of the run's best design (equivalents of the source paper's Figs. 7-11): clamp "
    "force, speeds, clutch torque, slip work and output jerk over time.",
    "engagement_heat": "Heat: the run's best design's friction-face (Duhamel) and bulk temperature over the "
    "engagement and over engagements in a row; the peak friction-face temperature over the design; the "
    "trade-off coloured by it (assumed materials, clutchlab.heat).",
    "centrifugal_capacity_curves": "Forward and reverse capacity of the run's best design over engine speed "
    "against the engine and passive torques (cf. the source paper's Fig. 5).",
    "centrifugal_release_map": "Release margin after an engine failure and forward reserve over pressure angle and "
    "friction coefficient, with the jam (f tan alpha >= 1) and near-jam regions.",
    "centrifugal_traces": "Start-up and engine-failure traces of the run's best design (DOP853 with lock-up and "
    "release events).",
    "sprag_stress_vs_torque": "Contact and shaft von Mises stresses and the gripping angle against torque, with the "
    "allowables (paper 002 Table 2 values marked).",
    "sprag_pass_map": "Which sprag geometries pass every allowable (contact, shaft, gripping angle).",
    "sprag_impact_torque": "Impact torque of the starter (paper 002 eqs. 1-5): T(t) and its peak against power, "
    "inertia, damping and initial speed.",
    "roller_stress_engagement": "Roller count: static contact stress and the engagement time and backlash of the "
    "wedging dynamics.",
    "roller_feasible_region": "Feasible region over roller count and wedge angle: ok, above the allowable, not "
    "self-locking, never engaged, overrunning, dynamic stress far above the allowable.",
    "roller_engagement_trace": "The run's best design: engagement from rest under the passive load and release "
    "after the control ring stops (speeds and contact force; cf. the source paper's Figs. 7 and 9).",
}
GENERIC = {
    "answers": "Design answers of study {study}: feasible share, the statuses and constraints that fail most, the "
    "Pareto front (per operating condition where ranked within one) with the run's best design, the front's "
    "designs, and a note where the best design sits at the edge of a factor's range.",
    "sensitivity": "First-order and total sensitivity indices of study {study}'s objectives, constrained outputs "
    "and failure indicator to each factor.",
    "refinement": "Refinement of study {study}: hypervolume of the first stage's front and of both stages' front "
    "per operating condition.",
    "pareto.csv": "The Pareto front designs of study {study}: factors, objectives, constrained outputs and "
    "constraint margins, in the units engineers read (each column header names its unit).",
    "explorer.html": "Interactive explorer of study {study} (open it in a browser; no network "
    "needed): every design on parallel coordinates of its factors, objectives, constrained and other "
    "outputs, status, feasibility and Pareto rank, in the units engineers read; drag along an axis to "
    "keep a range, the linked scatter of any two quantities (front marked) and the count follow; "
    "hover a design for its values; the selection downloads as CSV. A study above "
    f"{MAX_DESIGNS:,} designs shows a stated sample with every front design.",
    "refinement.csv": "Hypervolume before and after the refinement of study {study}.",
    "robust": "Robust answers of study {study}: every design's worst-case (or quantile) objectives over its "
    "operating conditions and the noise, the designs whose probability of failure is within the allowed at "
    "every condition, the robust front, and the best robust design's probability of failure at each condition "
    "with its 95 % Wilson interval and the condition where it binds.",
    "robust.csv": "The robust front designs of study {study}: factors, worst-case and quantile objectives, "
    "highest probability of failure with its interval and the binding condition and noise draw.",
    "numerics": "Work-precision of the solver study {study} runs, against per-scenario scipy, measured in this run "
    "on a small sample, with the speed ratio at equal error.",
}
SINGLE = {
    "title": "Summary: per study the scenarios, design, status counts, best compromise design, the factors it "
    "sits at the edge of and the pages. "
    "clutchlab {{ snakemake.params.version }}, source hash {{ snakemake.params.source }}.",
    "validation_table": "Numbers of the source papers reproduced: published value, clutchlab's value, relative "
    "error, tolerance (every row; paginated in the PDF).",
    "validation.csv": "The validation table as CSV.",
    "hard_cases": "Hard cases of the physics notes and since, computed in this run: right answer and its source, "
    "clutchlab's value, error, pass, and what an off-the-shelf solver gives.",
    "hard_cases.csv": "The hard cases as CSV.",
    "engagement_work_precision": "Work-precision of the engagement solvers (rigid driveline, Stribeck friction) "
    "against per-scenario solve_ivp RK45, from the engagement benchmark of this run.",
    "report.pdf": "The whole report as a PDF (every page above).",
}


def _split(name: str, study_names) -> tuple[str | None, str]:
    """(study, the rest of the file name) of a report file name."""
    for s in sorted(study_names, key=len, reverse=True):
        if name.startswith(f"{s}_"):
            return s, name[len(s) + 1 :]
        if name == f"numerics_{s}.png":
            return s, "numerics"
    return None, name


def caption(filename: str, study_names) -> str:
    """The caption text of a report file (its name, e.g. ``sprag_pass_map.png``)."""
    study, rest = _split(filename, study_names)
    stem = filename.rsplit(".", 1)[0] if filename.endswith(".png") else filename
    if stem in FIGURES:
        return FIGURES[stem]
    if filename.endswith(".png") and stem in SINGLE:
        return SINGLE[stem]
    if filename in SINGLE:
        return SINGLE[filename]
    key = rest[:-4] if rest.endswith(".png") else rest
    if study is not None and key in GENERIC:
        return GENERIC[key].format(study=study)
    raise KeyError(f"no caption for report file {filename!r}")


def category(filename: str, study_names) -> str:
    study, _ = _split(filename, study_names)
    return study or "summary and checks"


def write(folder, files, study_names) -> dict:
    """One caption file per report file in ``folder``; returns {file: caption path}."""
    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for f in files:
        name = Path(f).name
        path = folder / f"{name}.rst"
        text = caption(name, study_names) + "\n"
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
        out[f] = str(path)
    return out

"""Studies: a parameter table plus a pure function from a design chunk to a results Dataset.

A study never touches a file. ``compute(inputs)`` receives a mapping of parameter name to a
flat numpy array (one entry per scenario of the chunk, or a scalar for a fixed value) in SI
units and returns an :class:`xarray.Dataset` whose scenario dimension is ``run``; extra
dimensions (e.g. points of a curve) are allowed. :mod:`clutchlab.doe` builds the design,
:mod:`clutchlab.pipeline` runs and merges its chunks.

Which numbers a scenario of each status keeps (the status rule): every per-scenario output says
under which statuses it is valid, in its attribute ``valid_statuses`` (status names separated by
spaces, or ``all``), from the study's table :attr:`Study.valid_statuses`; elsewhere it is NaN (an
integer output: −1). A float output not in the table is valid under ``ok`` only; an integer one
(counts, flags, solver statistics) under every status. :func:`register` applies the table to
every study's ``compute`` (:func:`apply_valid_statuses`), so every path to a result — the
pipeline, a notebook, a test — gets it. Before it, every scenario with an input that its
:class:`Parameter` refuses (the rules the config is read with, per scenario: bounds, choices, a
whole count, a finite and plausible magnitude) gets the status ``invalid_input``
(:func:`refuse_inadmissible`), whether or not the study's own screening caught it.
"""

from __future__ import annotations

import dataclasses
import functools
import re
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .. import plausible
from .. import status as st

__all__ = [
    "Parameter",
    "Study",
    "REGISTRY",
    "get",
    "flat_inputs",
    "seed_design",
    "apply_valid_statuses",
    "inadmissible",
    "with_plausible",
    "refuse_inadmissible",
    "ALL_STATUSES",
    "units_metadata",
    "Relation",
    "value_range",
    "failed_relation",
]

ALL_STATUSES = "all"  # an output valid under every status (valid_statuses)
# the unit a bare number refused for a parameter of this SI unit was likely meant in (the hint)
BARE_HINT = {
    "m": (("mm", 1e-3),),
    "Pa": (("MPa", 1e6), ("GPa", 1e9)),
    "rad": (("deg", np.pi / 180),),
    "rad/s": (("rpm", np.pi / 30),),
    "s": (("ms", 1e-3),),
    "kg": (("g", 1e-3),),
}


@dataclass(frozen=True)
class Parameter:
    """An input of a study: SI unit, description, default (the seed design) and bounds.

    Besides its own bounds (``minimum``, ``maximum``, ``choices``, ``integer``) a value must have
    a plausible magnitude for its SI unit (:mod:`clutchlab.plausible`; a zero is judged by the
    parameter's own minimum, inf is allowed only with ``allow_infinite``), and a count at most
    :data:`clutchlab.plausible.COUNT_MAX`. A temperature (SI unit K) has a ``kind``: "absolute"
    (a temperature on the scale: ambient, a limit) or "difference" (a rise).
    """

    name: str
    units: str
    long_name: str
    default: float
    minimum: float | None = 0.0
    minimum_inclusive: bool = False
    maximum: float | None = None
    maximum_inclusive: bool = True
    allow_infinite: bool = (
        False  # e.g. engine inertia (inf = held engine), Stribeck speed (inf = constant mu)
    )
    integer: bool = False  # a count (sprags, rollers, shoes, friction faces)
    choices: tuple[float, ...] | None = None  # the only values allowed (e.g. drive direction +1/-1)
    kind: str | None = None  # temperatures: "absolute" or "difference" (see clutchlab.units)
    # (smallest non-zero, largest) magnitude [SI] a config's ``plausible`` key sets in place of
    # clutchlab.plausible.PARAMETERS' (within the unit's range): :func:`with_plausible`
    config_range: tuple[float, float] | None = None

    def __post_init__(self):
        if (self.units == "K") != (self.kind in ("absolute", "difference")):
            raise ValueError(f"{self.name}: a temperature (K), and only one, has a kind")

    @property
    def unit_kind(self) -> str | None:
        """The ``kind`` :func:`clutchlab.units.to_si` reads a value of this parameter with."""
        return "count" if self.integer or self.choices is not None else self.kind

    def attrs(self) -> dict:
        """CF attributes of this parameter stored as a variable or coordinate (a temperature in a
        compound unit, 1/K or W/(m^2*K), is a difference)."""
        kind = self.kind or ("difference" if re.search(r"\bK\b", self.units) else None)
        return {"long_name": self.long_name, "units": self.units, **units_metadata(kind)}

    def check(self, value: float, given=None) -> str | None:
        """Return why ``value`` [SI] is non-physical or implausible, or None if it is acceptable.

        ``given`` is the value as the user wrote it ("2.3 Mm"), quoted in the message.
        """
        u = "" if self.units == "1" else f" {self.units}"
        got = f"{value:g}{u}"
        if (
            given is not None
            and not isinstance(given, bool)
            and _text(given)
            not in (
                _text(value),
                got,
            )
        ):
            got = f"{_text(given)} = {got}"
        if self.choices is not None:
            if value not in self.choices:
                return f"must be one of {', '.join(f'{c:g}' for c in self.choices)}, got {got}"
            return None
        if np.isinf(value) and not self.allow_infinite:
            return f"must be finite, got {got}"
        if self.integer and not (np.isfinite(value) and value == round(value)):
            return f"must be a whole number (a count), got {got}"
        why = self._bounds(value, got, u) or self._plausible(value, got, u)
        return why + self._bare_hint(value, given) if why else None

    def _bare_hint(self, value, given) -> str:
        """Which units a refused bare number was likely meant in: those whose reading is
        admissible (none: no hint)."""
        if isinstance(given, str):  # a number as text (Snakemake's --config reads "0.6" so)
            try:
                given = float(given.strip())
            except ValueError:
                return ""
        if given is None or isinstance(given, bool) or not np.isfinite(given):
            return ""
        meant = [
            f"'{_text(given)} {unit}'"
            for unit, factor in BARE_HINT.get(self.units, ())
            if self.admissible(value * factor)
        ]
        if not meant:
            return ""
        return f" (a bare number is in {self.units}: write the unit, e.g. {' or '.join(meant)})"

    def _bounds(self, value, got, u) -> str | None:
        if self.minimum is not None:
            bad = value < self.minimum if self.minimum_inclusive else value <= self.minimum
            if bad:
                op = ">=" if self.minimum_inclusive else ">"
                return f"must be {op} {self.minimum:g}{u}, got {got}"
        if self.maximum is not None:
            bad = value > self.maximum if self.maximum_inclusive else value >= self.maximum
            if bad:
                op = "<=" if self.maximum_inclusive else "<"
                return f"must be {op} {self.maximum:g}{u}, got {got}"
        return None

    def _plausible(self, value, got, u) -> str | None:
        """A magnitude outside :mod:`clutchlab.plausible`'s range of the unit (a typing or unit
        slip: 2.3 Mm of sheet, 1e20 shoes); zero was judged by the bounds above."""
        if value == 0 or np.isinf(value):
            return None
        lo, hi = (1.0, float(plausible.COUNT_MAX)) if self.integer else self.plausible_range
        if lo <= abs(value) <= hi:
            return None
        what = " of a count" if self.integer else ""
        whose = ", with the config's plausible key" if self.config_range is not None else ""
        if self.kind == "absolute":  # (positive by its bound: read in °C as well)
            span = f"{lo:g} to {hi:g} K: {lo - 273.15:g} to {hi - 273.15:g} °C"
        else:
            signed = self.minimum is None or self.minimum < 0
            span = f"{lo:g} to {hi:g}{u}" + (" in magnitude" if signed else "")
        return (
            f"got {got}, outside the plausible range{what} ({span}{whose}): a typing or unit slip?"
        )

    def admissible(self, values) -> np.ndarray:
        """Which of ``values`` [SI] :meth:`check` accepts, per value (the same rules, vectorised).

        Parameters
        ----------
        values : array_like
            Values of this parameter [SI], one per scenario.

        Returns
        -------
        numpy.ndarray of bool
            True where the value is physical and plausible (NaN never is).
        """
        v = np.asarray(values, dtype=float)
        if self.choices is not None:
            return np.isin(v, self.choices)
        ok = ~np.isnan(v) & (np.isfinite(v) | self.allow_infinite)
        if self.integer:
            with np.errstate(invalid="ignore"):
                ok &= np.isfinite(v) & (v == np.round(v))
        if self.minimum is not None:
            ok &= (v >= self.minimum) if self.minimum_inclusive else (v > self.minimum)
        if self.maximum is not None:
            ok &= (v <= self.maximum) if self.maximum_inclusive else (v < self.maximum)
        lo, hi = (1.0, float(plausible.COUNT_MAX)) if self.integer else self.plausible_range
        a = np.abs(v)
        return ok & ((a == 0) | np.isinf(a) | ((a >= lo) & (a <= hi)))

    @property
    def plausible_range(self) -> tuple[float, float]:
        """(smallest non-zero, largest) plausible magnitude [SI] of this parameter: its unit's,
        narrowed by its own where :data:`clutchlab.plausible.PARAMETERS` names it, or by the
        range a config set (:attr:`config_range`)."""
        lo, hi = self.unit_range
        own_lo, own_hi = self.config_range or plausible.PARAMETERS.get(self.name, (lo, hi))
        return max(lo, own_lo), min(hi, own_hi)

    def widenable(self, value: float) -> bool:
        """Whether a config's ``plausible`` key could admit ``value`` [SI], refused as implausible:
        a magnitude within the unit's range and the parameter's own bounds, none set already."""
        ulo, uhi = self.unit_range
        inside = self._bounds(value, "", "") is None and ulo <= abs(value) <= uhi
        return inside and self.config_range is None and not self.integer and value != 0

    @property
    def unit_range(self) -> tuple[float, float]:
        """(smallest non-zero, largest) magnitude [SI] of any value of this parameter's unit
        (:func:`clutchlab.plausible.bounds`): no config widens it."""
        return plausible.bounds("delta_K" if self.kind == "difference" else self.units)


def with_plausible(parameters, ranges) -> tuple:
    """``parameters`` with the plausible ranges a config set (its study section's ``plausible``
    key, resolved into the study's ``options["plausible"]``).

    Parameters
    ----------
    parameters : sequence of Parameter
        A study's parameters.
    ranges : dict or None
        Parameter name -> (smallest non-zero, largest) magnitude [SI]; None or empty: none set.

    Returns
    -------
    tuple of Parameter
        The parameters, those named in ``ranges`` with that range as their plausible one.
    """
    ranges = ranges or {}
    return tuple(
        dataclasses.replace(p, config_range=tuple(map(float, ranges[p.name])))
        if p.name in ranges
        else p
        for p in parameters
    )


@dataclass(frozen=True)
class Relation:
    """A relation between parameters that the study's physics assumes for every scenario (a shoe
    inside its drum, the idle speed below the rated one).

    ``holds(**values)`` takes the parameters ``names`` in SI and is monotone in each, so that it
    holds for every scenario of a design wherever it holds at the design's worst corner: per name
    in ``worst``, "min" or "max" (the largest finite value: "max_finite") over the fixed value or
    the factor's values or range. ``text`` says the relation for the message.
    """

    names: tuple[str, ...]
    worst: tuple[str, ...]
    holds: Callable
    text: str


def value_range(section: dict, name: str, finite: bool = False) -> tuple[float, float]:
    """Smallest and largest value of a parameter over the scenarios of a resolved study section.

    Parameters
    ----------
    section : dict
        A resolved study section (:func:`clutchlab.config.resolve`): ``fixed`` values and
        ``factors``.
    name : str
        The parameter.
    finite : bool
        Whether to leave inf out.

    Returns
    -------
    (float, float)
        Its fixed value twice, or the minimum and maximum of its factor's values or range [SI].
    """
    if name in section["fixed"]:
        vals = [section["fixed"][name]]
    else:
        spec = section["factors"][name]
        vals = spec["values"] if "values" in spec else [spec["min"], spec["max"]]
    if finite:
        vals = [v for v in vals if np.isfinite(v)] or [-np.inf]
    return min(vals), max(vals)


def failed_relation(section: dict, relations) -> tuple[str, str] | None:
    """The first relation that fails for some scenario of a resolved study section.

    Checked at the worst corner of its design (:class:`Relation`), naming every parameter in it.

    Parameters
    ----------
    section : dict
        A resolved study section (:func:`clutchlab.config.resolve`).
    relations : sequence of Relation
        The study's relations.

    Returns
    -------
    (str, str) or None
        (config key, problem) of the first relation that fails, or None.
    """
    study = get(section["name"])
    for rel in relations:
        corner = {}
        for name, worst in zip(rel.names, rel.worst, strict=True):
            lo, hi = value_range(section, name, finite=worst == "max_finite")
            corner[name] = lo if worst == "min" else hi
        with np.errstate(all="ignore"):
            if bool(rel.holds(**corner)):
                continue
        at = ", ".join(
            f"'{section['name']}.parameters.{n}' = {corner[n]:g}"
            + ("" if study.parameter(n).units == "1" else f" {study.parameter(n).units}")
            for n in rel.names
        )
        key = f"{section['name']}.parameters.{rel.names[0]}"
        return key, f"must hold in every scenario: {rel.text}; it fails at {at}"
    return None


def units_metadata(kind: str | None) -> dict:
    """CF ``units_metadata`` of a temperature of ``kind`` (CF 1.11, section 3.1.2).

    Parameters
    ----------
    kind : str or None
        "absolute" (a temperature on the scale), "difference" (a rise), or anything else.

    Returns
    -------
    dict
        ``{"units_metadata": ...}`` for a temperature, else empty.
    """
    if kind == "absolute":
        return {"units_metadata": "temperature: on_scale"}
    if kind == "difference":
        return {"units_metadata": "temperature: difference"}
    return {}


def _text(v) -> str:
    return v.strip() if isinstance(v, str) else f"{float(v):g}"


@dataclass(frozen=True)
class Study:
    """A registered study: name, where its merged result goes, inputs and the compute function."""

    name: str
    output: str  # path of the merged result relative to the results folder
    description: str
    parameters: tuple[Parameter, ...]
    compute: Callable
    model: str  # which model runs, recorded in the results
    validation: Callable | None = None  # () -> validation Dataset (seed rows) or None
    options: dict = field(default_factory=dict)
    # default relative accuracy of the headline outputs (config key ``accuracy``, passed to compute
    # as options["accuracy"]); None: the study's models have no tolerance to set
    accuracy: float | None = None
    # resolved study section -> (key, problem) for a combination of values that cannot be read
    # physically (e.g. an odd roller count with the one-flank reading), or None
    check_config: Callable | None = None
    # relations between parameters the physics assumes for every scenario (a config whose design
    # breaks one for some scenario is refused, naming the parameters)
    relations: tuple[Relation, ...] = ()
    # design answers: the per-scenario outputs that objectives and constraints may name
    # (name -> units, or (units, kind) for a temperature: "absolute" or "difference"), the default
    # objectives ("name:min"/"name:max") and constraints (output -> ("max" or "min", limit in
    # SI)), as the seed papers suggest
    outputs: dict = field(default_factory=dict)
    objectives: tuple[str, ...] = ()
    constraints: dict = field(default_factory=dict)
    # operating conditions: parameters the engineer does not choose (loads, speeds, inertias of the
    # rest of the drivetrain). A factorial grid over one is ranked within each of its values, so
    # the front never answers "choose the lightest load"
    conditions: tuple[str, ...] = ()  # options too (a roller's commanded working mode)
    # options that choose a model or a reading of the paper, not a design or an operating
    # condition: never drawn per scenario (its choices ranked together would compare models)
    model_options: tuple[str, ...] = ()
    # (inputs, options) -> Dataset of one design's traces and curves (no ``run`` dimension): the
    # design a run's pages show, every input given as a scalar; computed once per study after the
    # merge (clutchlab.traces, the workflow's traces job)
    traces: Callable | None = None
    # a robust study's default noise (clutchlab.config: used where the config asks for a robust
    # study and gives no ``noise``): parameter -> noise spec as a config writes it, e.g.
    # {"friction_coefficient": {"scatter": "±20 %"}}
    noise: dict = field(default_factory=dict)
    # fixed values a robust study with a given noise uses unless the config gives them: noise
    # parameter -> {parameter: SI value} (the centrifugal's friction_scatter is 0 where the noise
    # draws the friction coefficient itself)
    noise_replaces: dict = field(default_factory=dict)
    # measured tables a study section may give (config key -> ((x name, x units), (y name, y units),
    # description)); resolved to SI lists and passed to compute as options[key]
    tables: dict = field(default_factory=dict)
    # the status rule (module docstring): output -> the statuses under which its value means what
    # its long_name says (tuple of status names, or ALL_STATUSES); a float output not listed: ok
    valid_statuses: dict = field(default_factory=dict)
    # where each parameter's default comes from (parameter -> "source paper (000) Table 3", or
    # "assumed: ..." with the reason); the reference pages show it
    sources: dict = field(default_factory=dict)

    def __post_init__(self):
        for name in self.outputs:
            units, kind = self.output_units(name)
            if (units == "K") != (kind in ("absolute", "difference")):
                raise ValueError(
                    f"{self.name} output {name}: a temperature (K), and only one, has a kind"
                )

    def output_units(self, name: str) -> tuple[str, str | None]:
        """(SI units, kind) of an output objectives and constraints may name (kind: "absolute" or
        "difference" for a temperature, else None)."""
        spec = self.outputs[name]
        return (spec, None) if isinstance(spec, str) else tuple(spec)

    def parameter(self, name: str) -> Parameter:
        """The parameter called ``name``.

        Parameters
        ----------
        name : str
            A parameter of the study.

        Returns
        -------
        Parameter
            Its definition.

        Raises
        ------
        KeyError
            If the study has no such parameter.
        """
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(name)

    def full_options(self, options=None) -> dict:
        """``options`` completed with the study's defaults (the first listed value; ``accuracy``)."""
        base = {k: v[0] for k, v in self.options.items()}
        if self.accuracy is not None:
            base["accuracy"] = self.accuracy
        return base | dict(options or {})

    @property
    def defaults(self) -> dict[str, float]:
        return {p.name: p.default for p in self.parameters}


def flat_inputs(inputs) -> dict:
    """Broadcast a chunk's inputs (flat arrays and scalars) to flat float arrays of one length.

    Parameters
    ----------
    inputs : dict
        Parameter name -> scalar or flat array [SI].

    Returns
    -------
    dict of numpy.ndarray
        Parameter name -> flat float array, all of one length (read-only broadcasts).

    Raises
    ------
    ValueError
        If two arrays have different lengths.
    """
    arrays = {k: np.asarray(v, dtype=float) for k, v in inputs.items()}
    sizes = {a.size for a in arrays.values() if a.ndim}
    if len(sizes) > 1:
        raise ValueError(f"inputs of a chunk have different lengths {sorted(sizes)}")
    n = sizes.pop() if sizes else 1
    return {k: np.broadcast_to(a.reshape(-1) if a.ndim else a, (n,)) for k, a in arrays.items()}


def seed_design(parameters, inputs) -> dict:
    """One design: the parameters' defaults (the source paper's), overridden by scalar inputs.

    A study's ``traces`` draw it (given every input of the design shown as a scalar,
    :mod:`clutchlab.traces`).

    Parameters
    ----------
    parameters : sequence of Parameter
        The study's parameters.
    inputs : dict
        Parameter name -> value [SI]; the scalars among them override the defaults.

    Returns
    -------
    dict
        Parameter name -> float [SI].
    """
    out = {p.name: p.default for p in parameters}
    out.update({k: float(v) for k, v in inputs.items() if np.ndim(v) == 0 and k in out})
    return out


REGISTRY: dict[str, Study] = {}


def apply_valid_statuses(ds, table: dict):
    """Each per-scenario output NaN where its scenario's status is not one of its valid statuses.

    An integer output is set to −1 instead. Every output gets the attribute ``valid_statuses``.
    Valid values are not touched (bit-identical).

    Parameters
    ----------
    ds : xarray.Dataset
        A study's compute result (scenario dimension ``run``, a ``status``); changed in place.
    table : dict
        Output -> status names or :data:`ALL_STATUSES`; a float output not listed: ``ok`` only, an
        integer one: every status.

    Returns
    -------
    xarray.Dataset
        ``ds``.

    Raises
    ------
    KeyError
        For a status name that does not exist.
    """
    code = np.asarray(ds["status"].values)
    for name, var in ds.data_vars.items():
        if name == "status" or "run" not in var.dims:
            continue
        floating = var.dtype.kind == "f"
        valid = table.get(name, ("ok",) if floating else ALL_STATUSES)
        if valid == ALL_STATUSES:
            var.attrs["valid_statuses"] = ALL_STATUSES
            continue
        unknown = set(valid) - set(st.CODE)
        if unknown:
            raise KeyError(f"valid_statuses of {name!r}: unknown statuses {sorted(unknown)}")
        keep = np.isin(code, [st.CODE[s] for s in valid])
        if not keep.all():
            values = np.moveaxis(var.values.copy(), var.dims.index("run"), 0)
            values[~keep] = np.nan if floating else -1
            var.values = np.moveaxis(values, 0, var.dims.index("run"))
        var.attrs["valid_statuses"] = " ".join(valid)
    return ds


def inadmissible(parameters, inputs) -> np.ndarray:
    """The scenarios with an input its parameter refuses (:meth:`Parameter.admissible`).

    Parameters
    ----------
    parameters : sequence of Parameter
        A study's parameters; inputs of other names are not judged.
    inputs : dict
        Parameter name -> scalar or flat array [SI] (a chunk's inputs).

    Returns
    -------
    numpy.ndarray of bool
        One entry per scenario (the inputs' length; 1 if every input is a scalar).
    """
    flat = flat_inputs(inputs)
    n = next(iter(flat.values())).size if flat else 1
    bad = np.zeros(n, dtype=bool)
    for p in parameters:
        if p.name in inputs:
            a = np.asarray(inputs[p.name], dtype=float)
            ok = p.admissible(a.reshape(-1) if a.ndim else a)
            bad |= ~ok
    return bad


def refuse_inadmissible(ds, parameters, inputs):
    """Status ``invalid_input`` for every scenario with an input its parameter refuses (one a
    study's own screening let through: a negative absolute temperature, an implausible magnitude,
    a value outside a parameter's choices); a scenario the study refused already keeps its status.

    Parameters
    ----------
    ds : xarray.Dataset
        A study's compute result (``status`` on dimension ``run``); changed in place.
    parameters : sequence of Parameter
        The study's parameters.
    inputs : dict
        The inputs ``ds`` was computed from.

    Returns
    -------
    xarray.Dataset
        ``ds``.
    """
    bad = inadmissible(parameters, inputs)
    if bad.any():
        code = np.array(ds["status"].values)
        refused = np.isin(code, [st.CODE["invalid_input"], st.CODE["invalid_geometry"]])
        mask = bad.reshape(code.shape) if bad.size == code.size else np.full(code.shape, True)
        code[mask & ~refused] = st.CODE["invalid_input"]
        ds["status"].values = code
    return ds


def _with_valid_statuses(compute: Callable, table: dict, parameters=()) -> Callable:
    @functools.wraps(compute)
    def valid_compute(inputs, options=None):
        # the plausible ranges the study's config set (key plausible): the config read its values
        # with them, so its scenarios are judged by them too
        own = with_plausible(parameters, (options or {}).get("plausible"))
        ds = refuse_inadmissible(compute(inputs, options), own, inputs)
        return apply_valid_statuses(ds, table)

    return valid_compute


def register(study: Study) -> Study:
    """Register ``study``, its ``compute`` wrapped so that each result follows the status rule.

    The wrapper gives status ``invalid_input`` to every scenario with an input its parameter
    refuses (:func:`refuse_inadmissible`), then applies :func:`apply_valid_statuses` with the
    study's :attr:`Study.valid_statuses`.

    Parameters
    ----------
    study : Study
        The study to register.

    Returns
    -------
    Study
        The registered study (with the wrapped ``compute``).
    """
    study = dataclasses.replace(
        study, compute=_with_valid_statuses(study.compute, study.valid_statuses, study.parameters)
    )
    REGISTRY[study.name] = study
    return study


def get(name: str) -> Study:
    """The registered study called ``name``.

    Parameters
    ----------
    name : str
        One of ``diaphragm_spring``, ``engagement``, ``centrifugal``, ``sprag``, ``roller``.

    Returns
    -------
    Study
        The study, its ``compute`` following the status rule.

    Raises
    ------
    KeyError
        For an unknown study, naming the known ones.
    """
    _load_all()
    try:
        return REGISTRY[name]
    except KeyError:
        raise KeyError(f"unknown study {name!r}; known: {sorted(REGISTRY)}") from None


def _load_all() -> None:
    from . import centrifugal, diaphragm_spring, engagement, roller, sprag  # noqa: F401  (register themselves)

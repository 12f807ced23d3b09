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
pipeline, a notebook, a test — gets it.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .. import status as st

__all__ = [
    "Parameter",
    "Study",
    "REGISTRY",
    "get",
    "flat_inputs",
    "seed_design",
    "apply_valid_statuses",
    "ALL_STATUSES",
]

ALL_STATUSES = "all"  # an output valid under every status (valid_statuses)


@dataclass(frozen=True)
class Parameter:
    """An input of a study: SI unit, description, default (the seed design) and bounds."""

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

    def check(self, value: float) -> str | None:
        """Return why ``value`` is non-physical, or None if it is acceptable."""
        if self.choices is not None:
            if value not in self.choices:
                return f"must be one of {', '.join(f'{c:g}' for c in self.choices)}, got {value:g}"
            return None
        if self.integer and value != round(value):
            return f"must be a whole number (a count), got {value:g}"
        u = "" if self.units == "1" else f" {self.units}"
        if self.minimum is not None:
            bad = value < self.minimum if self.minimum_inclusive else value <= self.minimum
            if bad:
                op = ">=" if self.minimum_inclusive else ">"
                return f"must be {op} {self.minimum:g}{u}, got {value:g}{u}"
        if self.maximum is not None:
            bad = value > self.maximum if self.maximum_inclusive else value >= self.maximum
            if bad:
                op = "<=" if self.maximum_inclusive else "<"
                return f"must be {op} {self.maximum:g}{u}, got {value:g}{u}"
        return None


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
    # design answers (issue 15): the per-scenario outputs that objectives and constraints may name
    # (name -> units), the default objectives ("name:min"/"name:max") and constraints
    # (output -> ("max" or "min", limit in SI)), as the seed papers suggest
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
    # measured tables a study section may give (config key -> ((x name, x units), (y name, y units),
    # description)); resolved to SI lists and passed to compute as options[key]
    tables: dict = field(default_factory=dict)
    # the status rule (module docstring): output -> the statuses under which its value means what
    # its long_name says (tuple of status names, or ALL_STATUSES); a float output not listed: ok
    valid_statuses: dict = field(default_factory=dict)

    def parameter(self, name: str) -> Parameter:
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
    """Broadcast a chunk's inputs (flat arrays and scalars) to flat float arrays of one length."""
    arrays = {k: np.asarray(v, dtype=float) for k, v in inputs.items()}
    sizes = {a.size for a in arrays.values() if a.ndim}
    if len(sizes) > 1:
        raise ValueError(f"inputs of a chunk have different lengths {sorted(sizes)}")
    n = sizes.pop() if sizes else 1
    return {k: np.broadcast_to(a.reshape(-1) if a.ndim else a, (n,)) for k, a in arrays.items()}


def seed_design(parameters, inputs) -> dict:
    """One design: the parameters' defaults (the source paper's design), overridden by the scalar
    ``inputs``; a study's ``traces`` draw it (given every input of the design shown as a scalar,
    :mod:`clutchlab.traces`)."""
    out = {p.name: p.default for p in parameters}
    out.update({k: float(v) for k, v in inputs.items() if np.ndim(v) == 0 and k in out})
    return out


REGISTRY: dict[str, Study] = {}


def apply_valid_statuses(ds, table: dict):
    """``ds`` (a study's compute result, scenario dimension ``run``) with every per-scenario output
    NaN (an integer one −1) where its scenario's status is not one of its valid statuses
    (``table``: output -> status names or :data:`ALL_STATUSES`; a float output not listed: ``ok``
    only, an integer one: every status), each carrying the attribute ``valid_statuses``. Valid
    values are not touched (bit-identical)."""
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


def _with_valid_statuses(compute: Callable, table: dict) -> Callable:
    @functools.wraps(compute)
    def valid_compute(inputs, options=None):
        return apply_valid_statuses(compute(inputs, options), table)

    return valid_compute


def register(study: Study) -> Study:
    """Register ``study``, its ``compute`` wrapped so that every result follows the status rule
    (:func:`apply_valid_statuses` with the study's :attr:`Study.valid_statuses`)."""
    study = dataclasses.replace(
        study, compute=_with_valid_statuses(study.compute, study.valid_statuses)
    )
    REGISTRY[study.name] = study
    return study


def get(name: str) -> Study:
    """The registered study called ``name``."""
    _load_all()
    try:
        return REGISTRY[name]
    except KeyError:
        raise KeyError(f"unknown study {name!r}; known: {sorted(REGISTRY)}") from None


def _load_all() -> None:
    from . import centrifugal, diaphragm_spring, engagement, roller, sprag  # noqa: F401  (register themselves)

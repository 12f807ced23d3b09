"""Studies: a parameter table plus a pure function from a design chunk to a results Dataset.

A study never touches a file. ``compute(inputs)`` receives a mapping of parameter name to a
flat numpy array (one entry per scenario of the chunk, or a scalar for a fixed value) in SI
units and returns an :class:`xarray.Dataset` whose scenario dimension is ``run``; extra
dimensions (e.g. points of a curve) are allowed. :mod:`clutchlab.doe` builds the design,
:mod:`clutchlab.pipeline` runs and merges its chunks.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

__all__ = ["Parameter", "Study", "REGISTRY", "get", "flat_inputs", "seed_design"]


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


def register(study: Study) -> Study:
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

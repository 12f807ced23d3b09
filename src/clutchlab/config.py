"""Config files: JSON-schema validation, unit conversion to SI and physical range checks.

:func:`resolve` turns a raw config (as Snakemake or ``yaml.safe_load`` reads it) into a
resolved config in which every quantity is a float in SI units, every study section lists
its ``fixed`` values and its ``factors``, and defaults are filled in. Any problem raises
:class:`ConfigError` whose message starts with the offending key, before any job runs.
"""
from __future__ import annotations

import copy
import functools
from importlib.resources import files

import numpy as np
import yaml

from . import studies
from .units import UnitError, to_si

__all__ = ["ConfigError", "SCHEMA_PATH", "schema", "load", "resolve", "study_config_text"]

SCHEMA_PATH = files("clutchlab") / "config.schema.yaml"
DEFAULT_CHUNKS = 4


class ConfigError(ValueError):
    """The config is invalid; the message names the key."""

    def __init__(self, key: str, problem: str):
        self.key = key
        super().__init__(f"config key '{key}': {problem}")


@functools.lru_cache(maxsize=1)
def schema() -> dict:
    return yaml.safe_load(SCHEMA_PATH.read_text())


def _key(path) -> str:
    return ".".join(str(p) for p in path) or "<top level>"


def validate_schema(cfg: dict) -> None:
    """Structural check against the JSON schema; raises ConfigError naming the key."""
    import jsonschema
    from jsonschema.exceptions import best_match

    validator = jsonschema.Draft202012Validator(schema())
    error = best_match(validator.iter_errors(cfg))
    if error is None:
        return
    path = list(error.absolute_path)
    if error.validator == "additionalProperties":
        extra = sorted(set(error.instance) - set(error.schema.get("properties", {})))
        if extra:
            path.append(extra[0])
            raise ConfigError(_key(path), "unknown key (allowed: "
                              + ", ".join(sorted(error.schema.get("properties", {}))) + ")")
    if error.validator == "required":
        missing = [k for k in error.validator_value if k not in error.instance]
        if missing:
            raise ConfigError(_key(path + [missing[0]]), "required key is missing")
    raise ConfigError(_key(path), error.message)


# relative accuracies a study can ask for: below 1e-7 the integrated peak jerk reaches its
# round-off floor (measured: 1.8e-8 at rtol 1e-10), above 1e-2 a number is no longer worth storing
ACCURACY_RANGE = (1e-7, 1e-2)


def _quantity(value, param, key) -> float:
    if param.allow_infinite and (value == float("inf") or str(value).strip().lower() in ("inf", ".inf")):
        return float("inf")
    try:
        v = to_si(value, param.units)
    except UnitError as exc:
        raise ConfigError(key, str(exc)) from None
    why = param.check(v)
    if why:
        raise ConfigError(key, why)
    return v


def _resolve_study(name: str, section: dict, default_chunks: int) -> dict:
    study = studies.get(name)
    design = section["design"]
    out = {
        "name": name,
        "design": design,
        "chunks": int(section.get("chunks", default_chunks)),
        "seed": int(section.get("seed", 0)),
        "options": {},
        "fixed": {},
        "factors": {},
    }
    for opt, allowed in study.options.items():
        out["options"][opt] = section.get("options", {}).get(opt, allowed[0])
    if study.accuracy is not None:
        acc = section.get("accuracy", study.accuracy)
        if not ACCURACY_RANGE[0] <= acc <= ACCURACY_RANGE[1]:
            raise ConfigError(f"{name}.accuracy", f"must be within {ACCURACY_RANGE[0]:g} to {ACCURACY_RANGE[1]:g} "
                              f"(relative), got {acc:g}")
        out["options"]["accuracy"] = float(acc)
    elif "accuracy" in section:
        raise ConfigError(f"{name}.accuracy", "this study has no tolerance to set (its models are closed forms "
                          "or fixed-point solutions to round-off)")
    if design != "factorial":
        if "samples" not in section:
            raise ConfigError(f"{name}.samples", f"required for design '{design}'")
        out["samples"] = int(section["samples"])
    given = section.get("parameters", {}) or {}
    for param in study.parameters:
        key = f"{name}.parameters.{param.name}"
        spec = given.get(param.name, param.default)
        if not isinstance(spec, dict):
            out["fixed"][param.name] = _quantity(spec, param, key)
            continue
        if "values" in spec:
            if set(spec) - {"values"}:
                raise ConfigError(key, "give either 'values' or 'min'/'max'[/'num'/'scale'], not both")
            if design != "factorial":
                raise ConfigError(key, f"design '{design}' samples between 'min' and 'max'; "
                                  "a 'values' list is for factorial designs")
            vals = [_quantity(v, param, f"{key}.values[{i}]") for i, v in enumerate(spec["values"])]
            if len(set(vals)) != len(vals):
                raise ConfigError(f"{key}.values", "values must be distinct")
            out["factors"][param.name] = {"values": vals}
            continue
        lo = _quantity(spec["min"], param, f"{key}.min")
        hi = _quantity(spec["max"], param, f"{key}.max")
        scale = spec.get("scale", "linear")
        if not lo < hi:
            raise ConfigError(key, f"min ({lo:g}) must be below max ({hi:g}) {param.units}")
        if scale == "log" and lo <= 0:
            raise ConfigError(f"{key}.min", "log scale needs min > 0")
        if design == "factorial":
            if "num" not in spec:
                raise ConfigError(f"{key}.num", "required for a factorial min/max factor")
            num = int(spec["num"])
            vals = np.geomspace(lo, hi, num) if scale == "log" else np.linspace(lo, hi, num)
            out["factors"][param.name] = {"values": [float(v) for v in vals]}
        else:
            if "num" in spec:
                raise ConfigError(f"{key}.num", f"not used by design '{design}' (use '{name}.samples')")
            out["factors"][param.name] = {"min": lo, "max": hi, "scale": scale}
    return out


def resolve(raw: dict) -> dict:
    """Validate ``raw`` and return the resolved config (SI floats, defaults filled in)."""
    cfg = copy.deepcopy(dict(raw))
    validate_schema(cfg)
    default_chunks = int(cfg.get("chunks", DEFAULT_CHUNKS))
    resolved = {"studies": list(cfg["studies"]), "chunks": default_chunks,
                "report": {"title": "clutchlab report", "dpi": 120, "benchmark": False, **cfg.get("report", {})}}
    for name in cfg["studies"]:
        if name not in cfg:
            raise ConfigError(name, "section missing for a study listed in 'studies'")
        resolved[name] = _resolve_study(name, cfg[name], default_chunks)
    return resolved


def load(path) -> dict:
    """Read a YAML config file and return the resolved config."""
    with open(path) as fh:
        return resolve(yaml.safe_load(fh) or {})


def study_config_text(resolved_study: dict) -> str:
    """YAML text of a resolved study section (stored as provenance in result files)."""
    return yaml.safe_dump(resolved_study, sort_keys=True)

"""Config files: JSON-schema validation, unit conversion to SI and physical range checks.

:func:`resolve` turns a raw config (as Snakemake or ``yaml.safe_load`` reads it) into a
resolved config in which every quantity is a float in SI units, every study section lists
its ``fixed`` values and its ``factors``, and defaults are filled in. Any problem raises
:class:`ConfigError` whose message starts with the offending key, before any job runs.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import math
import re
from importlib.resources import files

import numpy as np
import yaml

from . import plausible, studies
from .units import UnitError, to_si

__all__ = [
    "ConfigError",
    "SCHEMA_PATH",
    "schema",
    "load",
    "read_file",
    "resolve",
    "study_config_text",
    "stored_study",
    "scenario_count",
    "DEFAULT_MAX_SCENARIOS",
]

SCHEMA_PATH = files("clutchlab") / "config.schema.yaml"
DEFAULT_CHUNKS = 4  # of a study whose config gives neither chunks nor chunk_size (historical)
# scenarios per chunk job where a config gives chunk_size, and the most jobs it may make per study:
# a 10^7 design stays at 32 jobs a study (memory per job grows with the chunk, not the study)
MAX_CHUNKS_FROM_SIZE = 32
# scenarios a study may hold unless the config raises the ceiling on purpose (top-level key
# max_scenarios): a 2^21 design is about what one 2-core workstation finishes in an hour
DEFAULT_MAX_SCENARIOS = 2**21
# YAML nodes a config file may expand to (anchors and aliases counted as often as they are used):
# the largest shipped config has a few hundred; an alias bomb has billions
MAX_NODES = 100_000
# levels of mappings and lists a config may nest (the deepest shipped config nests 6: a study's
# friction_table or a factor's values list)
MAX_DEPTH = 16


class ConfigError(ValueError):
    """The config is invalid; the message names the key (or, for a file that cannot be read as a
    config at all, the file)."""

    def __init__(self, key: str, problem: str, what: str = "config key"):
        self.key, self.problem = key, problem
        super().__init__(f"{what} '{key}': {problem}")


class _StrictLoader(yaml.SafeLoader):
    """YAML 1.1 safe loader that refuses a key given twice in one mapping (PyYAML keeps the last)."""

    def construct_mapping(self, node, deep=False):
        seen = {}
        for key_node, _ in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                continue
            key = self.construct_object(key_node, deep=True)
            line = key_node.start_mark.line + 1
            try:
                if key in seen:
                    raise ConfigError(
                        str(key),
                        f"given twice in one mapping (lines {seen[key]} and {line}); "
                        "YAML would silently keep the last",
                    )
                seen[key] = line
            except TypeError:
                continue  # an unhashable key: SafeLoader refuses it below
        return super().construct_mapping(node, deep=deep)


def _expanded_size(obj, memo=None) -> int:
    """Nodes of ``obj`` with every alias expanded, counted without expanding (shared objects memoised)."""
    memo = {} if memo is None else memo
    if id(obj) in memo:
        return memo[id(obj)]
    memo[id(obj)] = 1  # guards recursive structures
    if isinstance(obj, dict):
        n = 1 + sum(_expanded_size(k, memo) + _expanded_size(v, memo) for k, v in obj.items())
    elif isinstance(obj, list):
        n = 1 + sum(_expanded_size(v, memo) for v in obj)
    else:
        n = 1
    memo[id(obj)] = n
    return n


def read_file(path) -> dict:
    """Read a config file as data: UTF-8 JSON or YAML, safe types only, no key twice, no template,
    no scalar that YAML 1.1 and YAML 1.2 read differently.

    Snakemake reads ``--configfile`` itself, as JSON if it can and else with PyYAML, a YAML 1.1
    reader (``010`` is 8, ``on`` a boolean, ``1e-4`` text; its loader also evaluates a file that
    starts with ``__use_yte__: true`` as a YTE template, and keeps the last of a duplicated key):
    the default workflow profile calls :func:`precheck_argv` before that, and the Snakefile reads
    every config file again through this function, so what it refuses stops the run before any
    job. A JSON file is read as JSON (tabs and all), like Snakemake does.

    Parameters
    ----------
    path : str or path-like
        The config file.

    Returns
    -------
    dict
        The file's data.

    Raises
    ------
    ConfigError
        Naming the file, or the key of a scalar read differently by YAML 1.1 and 1.2.
    """
    where = str(path)
    try:
        data = open(path, "rb").read()
    except OSError as exc:
        raise ConfigError(where, f"cannot be read: {exc.strerror}", "config file") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigError(
            where,
            f"is not UTF-8 text (byte {exc.start} is {data[exc.start : exc.start + 1]!r}); "
            "save it as UTF-8",
            "config file",
        ) from None
    try:
        raw = _read_json(text)
        if raw is _NOT_JSON:
            raw = _read_yaml(text, where)
    except RecursionError:
        raise ConfigError(
            where,
            "nests brackets or indentation too deep to be read (a clutchlab config nests "
            f"{MAX_DEPTH} levels at most)",
            "config file",
        ) from None
    _check_data(raw, where)
    return raw


_NOT_JSON = object()


def _read_json(text):
    """The data of a JSON text (a key twice refused), or _NOT_JSON where the text is not JSON."""
    import json

    from ._yaml_readings import path_text

    def pairs(items):
        seen = set()
        for key, _ in items:
            if key in seen:
                return _Twice(items, key)
            seen.add(key)
        return dict(items)

    try:
        data = json.loads(text, object_pairs_hook=pairs)
    except json.JSONDecodeError:
        return _NOT_JSON
    path = _twice_path(data, [])
    if path is not None:
        raise ConfigError(
            path_text(path), "given twice in one JSON object; JSON readers keep the last"
        )
    return data


class _Twice(dict):
    """A JSON object with a key given twice (``key``)."""

    def __init__(self, items, key):
        super().__init__(items)
        self.key = key


def _twice_path(obj, path):
    """The key path of the first key given twice in a JSON document's objects, or None."""
    if isinstance(obj, _Twice):
        return path + [str(obj.key)]
    children = (
        obj.items() if isinstance(obj, dict) else enumerate(obj) if isinstance(obj, list) else ()
    )
    for k, v in children:
        found = _twice_path(v, path + [k])
        if found is not None:
            return found
    return None


def _read_yaml(text, where):
    """The data of a YAML text; refuses invalid YAML and any scalar YAML 1.1 reads otherwise than
    YAML 1.2 (:mod:`clutchlab._yaml_readings`)."""
    from ._yaml_readings import duplicates, misreadings

    loader = None
    try:
        loader = _StrictLoader(text)
        node = loader.get_single_node()
        for key, problem in duplicates(node) if node is not None else ():
            raise ConfigError(key, problem)  # (named by its whole path)
        raw = loader.construct_document(node) if node is not None else None
    except ConfigError:
        raise
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        at = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(exc, "problem", None) or (str(exc).splitlines() or [""])[0]
        raise ConfigError(where, f"is not valid YAML{at}: {problem}", "config file") from None
    except (ValueError, TypeError, IndexError, OverflowError) as exc:  # a tag's value (!!int x)
        raise ConfigError(
            where,
            f"is not valid YAML: {type(exc).__name__}: {(str(exc).splitlines() or [''])[0]}",
            "config file",
        ) from None
    finally:
        if loader is not None:
            loader.dispose()
    if isinstance(raw, dict):  # (aliases are walked once: an alias bomb is refused below)
        for key, problem in misreadings(node):
            raise ConfigError(key, problem)
    return raw


def _check_data(raw, where) -> None:
    """A config file's data: a mapping, not an alias bomb, not nested deeper than MAX_DEPTH, not a
    template."""
    from ._yaml_readings import deepest, path_text

    if raw is None:
        raise ConfigError(
            where,
            "is empty: a config file needs at least 'studies' and a section for each",
            "config file",
        )
    if not isinstance(raw, dict):
        raise ConfigError(
            where,
            f"must be a mapping of keys at the top level, got {type(raw).__name__}",
            "config file",
        )
    deep = deepest(raw, MAX_DEPTH)
    if deep is not None:
        raise ConfigError(
            path_text(deep), f"nests deeper than {MAX_DEPTH} levels (a config needs 6)"
        )
    if _expanded_size(raw) > MAX_NODES:
        raise ConfigError(
            where,
            f"expands to more than {MAX_NODES} YAML nodes (anchors/aliases used as a "
            "bomb?); a clutchlab config needs a few hundred",
            "config file",
        )
    if "__use_yte__" in raw:
        raise ConfigError(
            "__use_yte__", "config files are data, not templates: clutchlab refuses YTE templating"
        )


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
            raise ConfigError(
                _key(path),
                "unknown key (allowed: "
                + ", ".join(sorted(error.schema.get("properties", {})))
                + ")",
            )
    if error.validator == "required":
        missing = [k for k in error.validator_value if k not in error.instance]
        if missing:
            raise ConfigError(_key(path + [missing[0]]), "required key is missing")
    raise ConfigError(_key(path), _schema_message(error))


def _schema_message(error) -> str:
    """jsonschema's message, with what to write where a value of the wrong type stands (YAML's
    null, ~ or an empty value; true/false/yes/no; a list where one value belongs)."""
    value = error.instance
    parameter = "parameters" in list(error.absolute_path)
    if value is None:
        return "has no value (null, ~ or nothing after the colon): " + (
            "give one, with its unit" if parameter else error.message
        )
    if isinstance(value, bool):
        return f"got the yes/no value {str(value).lower()}: " + (
            "give a number, with its unit" if parameter else error.message
        )
    if parameter and isinstance(value, list) and error.validator in ("anyOf", "oneOf", "type"):
        return (
            f"got the list {value!r}: several values of a factor are written "
            "{values: [...]}; one value alone, without brackets"
        )
    return error.message


# relative accuracies a study can ask for: below 1e-7 the integrated peak jerk reaches its
# round-off floor (measured: 1.8e-8 at rtol 1e-10), above 1e-2 a number is no longer worth storing
ACCURACY_RANGE = (1e-7, 1e-2)


def _quantity(value, param, key, finite=False) -> float:
    """A parameter's value (as given in the config at ``key``) in SI, read by its unit and kind
    and checked against its bounds and plausible magnitude."""
    infinite = value == float("inf") or str(value).strip().lower() in ("inf", ".inf", "+inf")
    if infinite and not param.allow_infinite:
        raise ConfigError(key, f"must be finite, got {value!r} (inf means nothing here)")
    if infinite:
        if finite:
            raise ConfigError(
                key,
                "a range needs finite bounds (inf is allowed as a fixed value or in a "
                "'values' list)",
            )
        return float("inf")
    try:
        v = to_si(value, param.units, param.unit_kind)
    except UnitError as exc:
        raise ConfigError(key, str(exc)) from None
    why = param.check(v, value)
    if why and "bare number" not in why and param.widenable(v):
        try:  # a number without its unit: its unit first (a plausible range would pass a slip)
            float(value)
            why += f" (a bare number is in {param.units}: write its unit)"
        except (TypeError, ValueError):
            why += " (if meant, set the study's key plausible)"
    if why:
        raise ConfigError(key, why)
    return v


def _table(study, tname, spec, key) -> dict:
    """A measured table of a study section in SI: {x name: [...], y name: [...]}, both finite and
    of plausible magnitude (a column named like a parameter within its bounds too), of equal
    length, x increasing from ≥ 0, y > 0."""
    if tname not in study.tables:
        raise ConfigError(key, f"not read by the {study.name} study")
    (xn, xu), (yn, yu), _ = study.tables[tname]
    cols = {}
    for col, units in ((xn, xu), (yn, yu)):
        vals = []
        for i, v in enumerate(spec[col]):
            try:
                vals.append(to_si(v, units))
            except UnitError as exc:
                raise ConfigError(f"{key}.{col}[{i}]", str(exc)) from None
            why = _column_check(study, col, units, vals[-1], v)
            if why:
                raise ConfigError(f"{key}.{col}[{i}]", why)
        cols[col] = vals
    x, y = np.array(cols[xn]), np.array(cols[yn])
    if x.size != y.size:
        raise ConfigError(
            key, f"'{xn}' and '{yn}' must be of equal length, got {x.size} and {y.size}"
        )
    if x[0] < 0 or np.any(np.diff(x) <= 0):
        raise ConfigError(f"{key}.{xn}", "must increase from a value >= 0")
    if np.any(y <= 0):
        raise ConfigError(f"{key}.{yn}", "must be > 0")
    return cols


def _column_check(study, col, units, value, given) -> str | None:
    """Why a table entry (SI ``value``, as ``given``) is implausible (a column named like one of
    the study's parameters: outside that parameter's bounds), or None."""
    try:
        param = study.parameter(col)
    except KeyError:
        param = studies.Parameter(col, units, col, 0.0, minimum=None)
    return param.check(value, given)


def _count(section, key, name):
    """An integer count of the config (samples, num, seed, chunks): a whole number, never coerced."""
    v = section[key]
    if isinstance(v, bool) or not (isinstance(v, int) or (isinstance(v, float) and v.is_integer())):
        raise ConfigError(name, f"must be a whole number, got {v!r}")
    return int(v)


def scenario_count(resolved_study: dict) -> int:
    """Scenarios of a resolved study: the grid's size (factorial), A, B and one AB matrix per
    factor and option choice (saltelli), else its samples."""
    design = resolved_study["design"]
    if design == "factorial":
        return math.prod(len(f["values"]) for f in resolved_study["factors"].values()) * (
            noise_count(resolved_study.get("robust"))
        )
    if design == "saltelli":
        d = len(resolved_study["factors"]) + len(resolved_study.get("option_factors", {}))
        return resolved_study["samples"] * (d + 2)
    robust = resolved_study.get("robust")
    if robust:  # sampled design points x the conditions' grid x the noise draws
        grid = [len(resolved_study["factors"][c]["values"]) for c in robust["conditions"]]
        return resolved_study["samples"] * math.prod(grid) * noise_count(robust)
    return resolved_study["samples"]


def _chunking(section, key) -> tuple[str, int] | None:
    """("chunks", N) or ("chunk_size", S) as a config level gives it (never both), or None."""
    given = [k for k in ("chunks", "chunk_size") if k in section]
    if len(given) == 2:
        raise ConfigError(
            f"{key}chunk_size",
            "give either 'chunks' (jobs) or 'chunk_size' (scenarios per job), not both",
        )
    return (given[0], _count(section, given[0], f"{key}{given[0]}")) if given else None


def chunk_count(n: int, chunking: tuple[str, int]) -> int:
    """Chunk jobs of a study of n scenarios: the given count, or ceil(n / chunk_size) capped at
    :data:`MAX_CHUNKS_FROM_SIZE` (at least 1)."""
    kind, value = chunking
    if kind == "chunks":
        return value
    return int(min(MAX_CHUNKS_FROM_SIZE, max(1, -(-n // value))))


# a sampled design stores every scenario's curves up to this size, else about CURVE_DESIGNS of them
CURVES_ALL_MAX = 20_000
CURVE_DESIGNS = 1000


def _curve_stride(name, section, design, n) -> int:
    """Every how many scenarios a design stores its per-scenario curves (1: all)."""
    given = section.get("curves")
    if given == "all":
        return 1
    if given is not None:
        if design == "factorial":
            raise ConfigError(
                f"{name}.curves",
                "a factorial grid stores every scenario's curves (its figures read "
                "them over the grid); a subset is for sampled designs",
            )
        stride = _count(section, "curves", f"{name}.curves")
        if not 1 <= stride <= max(n, 1):
            raise ConfigError(
                f"{name}.curves",
                f"every how many scenarios to store curves: a whole number from 1 to the design's "
                f"{n} scenarios, got {stride}",
            )
        return stride
    return 1 if design == "factorial" or n <= CURVES_ALL_MAX else -(-n // CURVE_DESIGNS)


def _resolve_study(
    name: str, section: dict, default_chunks, max_scenarios: int, results_dir: str = "results"
) -> dict:
    study = studies.get(name)
    design = section["design"]
    if design == "refine":
        return _resolve_refine(name, section, default_chunks, max_scenarios, results_dir)
    if "refine" in section:
        raise ConfigError(
            f"{name}.refine", f"only read by design 'refine' (this study's design is '{design}')"
        )
    study, ranges = _with_plausible(study, section, name)
    out = {
        "name": name,
        "design": design,
        "seed": _count(section, "seed", f"{name}.seed") if "seed" in section else 0,
        "options": {},
        "fixed": {},
        "factors": {},
    }
    _resolve_options(study, section, out)
    if ranges:  # (the chunks' screening judges each scenario by them too)
        out["options"]["plausible"] = ranges
    if design != "factorial":
        if "samples" not in section:
            raise ConfigError(f"{name}.samples", f"required for design '{design}'")
        out["samples"] = _count(section, "samples", f"{name}.samples")
        if out["samples"] > max_scenarios:
            raise _ceiling(name, out["samples"], max_scenarios)
    else:
        for key in ("samples", "seed"):
            if key in section:
                raise ConfigError(
                    f"{name}.{key}",
                    "not used by a factorial design (its scenarios are the "
                    "grid of the factors' values); remove it or choose design lhs/sobol",
                )
    roles = _resolve_parameters(study, section, out, max_scenarios)
    robust = _resolve_robust(study, section, out, roles)
    if robust is not None:
        out["robust"] = robust
    n = scenario_count(out)
    if n > max_scenarios:
        raise _ceiling(name, n, max_scenarios)
    out["chunks"] = chunk_count(n, _chunking(section, f"{name}.") or default_chunks)
    out["curve_stride"] = _curve_stride(name, section, design, n)
    out["objectives"], out["constraints"] = _answers(study, section)
    _check_window_limits(out, section)
    problem = studies.failed_relation(_noise_widened(out), study.relations) or (
        study.check_config(out) if study.check_config is not None else None
    )
    if problem and problem[0].startswith(f"{name}.noise.") and "noise" not in section:
        p = problem[0].rsplit(".", 1)[1]  # (the study's default noise: the user wrote none)
        raise ConfigError(_robust_key(name, section, roles), f"{_brought(study, p)}: {problem[1]}")
    if problem:
        raise ConfigError(*problem)
    return out


def _robust_key(name: str, section: dict, roles: dict) -> str:
    """The key that made a study robust: robust, noise_samples, or a factor's role."""
    return next(
        (f"{name}.{k}" for k in ("robust", "noise_samples") if k in section),
        f"{name}.parameters.{next(iter(roles), '')}.role",
    )


def _brought(study, p: str) -> str:
    """What the study's default noise of ``p`` is, in words."""
    spec = ", ".join(f"{k} {v}" for k, v in (study.noise or {}).get(p, {}).items())
    return f"the study's default noise ({p}: {spec})"


def _with_plausible(study, section: dict, name: str):
    """The study with the plausible ranges its section sets (``plausible: {parameter: {min, max}}``,
    magnitudes with their units, in place of :data:`clutchlab.plausible.PARAMETERS`' for that
    parameter, within its unit's range), and those ranges in SI ({} where none is set)."""
    given = section.get("plausible") or {}
    ranges = {}
    for pname, spec in given.items():
        key = f"{name}.plausible.{pname}"
        param = _continuous_parameter(study, pname, key, "has no magnitude range to set")
        lo, hi = param.plausible_range
        for end in ("min", "max"):
            if end in spec:
                v = _range_end(param, spec[end], f"{key}.{end}")
                lo, hi = (v, hi) if end == "min" else (lo, v)
        if not lo < hi:
            built_in = " (the built-in one; give both)" if len(spec) == 1 else ""
            raise ConfigError(
                key, f"min must be below max, got {lo:g} to {hi:g} {param.units}{built_in}"
            )
        ranges[pname] = [lo, hi]
    return dataclasses.replace(
        study, parameters=studies.with_plausible(study.parameters, ranges)
    ), ranges


def _range_end(param, value, key) -> float:
    """One end of a plausible range a config sets, in SI: written with its unit (the range
    overrides the check that catches a number written without one), a magnitude > 0 within the
    unit's range."""
    try:
        bare = float(value) if not isinstance(value, bool) else None  # (a number, or one as text)
    except (TypeError, ValueError):
        bare = None
    if bare is not None and not math.isfinite(bare):
        raise ConfigError(key, f"must be a finite magnitude, got {value!r}")
    if bare is not None and param.units != "1":
        raise ConfigError(
            key,
            f"write the unit ('{value} {param.units}' or another {param.units} unit): a plausible "
            "range overrides the check that catches a number written without its unit",
        )
    try:
        v = to_si(value, param.units, param.unit_kind)
    except UnitError as exc:
        raise ConfigError(key, str(exc)) from None
    ulo, uhi = param.unit_range
    u = "" if param.units == "1" else f" {param.units}"
    if not ulo <= v <= uhi:
        raise ConfigError(
            key,
            f"must be within {ulo:g} to {uhi:g}{u} (any{u or ' dimensionless'} value's range: "
            f"beyond it no model of a clutch holds), got {value!r} = {v:g}{u}",
        )
    got = repr(value) if str(value) == f"{v:g}" else f"{value!r} = {v:g}{u}"
    own = param._bounds(v, got, u)
    if own:  # (a parameter's own bound is the physics': no plausible range passes it)
        raise ConfigError(key, f"the parameter's own bound: it {own}")
    return v


def _resolve_parameters(study, section: dict, out: dict, max_scenarios: int) -> None:
    """A study section's parameters into ``out["fixed"]`` (SI; the seed design's value where not
    given) and ``out["factors"]``; a sampled design needs a factor to sample."""
    name, design = out["name"], out["design"]
    given = section.get("parameters", {}) or {}
    roles = {}
    for param in study.parameters:
        key = f"{name}.parameters.{param.name}"
        if param.name not in given:  # the seed design's value (SI, checked by the tests)
            out["fixed"][param.name] = float(param.default)
            if param.config_range is not None and param.check(param.default):
                raise ConfigError(
                    f"{name}.plausible.{param.name}",
                    f"leaves out the parameter's default ({param.default:g} {param.units}): "
                    "give the parameter's value too",
                )
            continue
        spec = given[param.name]
        if isinstance(spec, dict):
            if "role" in spec:
                roles[param.name] = spec["role"]
                spec = {k: v for k, v in spec.items() if k != "role"}
            out["factors"][param.name] = _factor(param, spec, design, key, name, max_scenarios)
        else:
            out["fixed"][param.name] = _quantity(spec, param, key)
    if design == "saltelli" and not out["factors"]:
        raise ConfigError(
            f"{name}.parameters", "design 'saltelli' needs at least one factor (min/max)"
        )
    if design != "factorial" and not out["factors"] and not out.get("option_factors"):
        raise ConfigError(
            f"{name}.parameters",
            f"design '{design}' samples factors and this section has none (a min/max or values "
            "for a parameter, or an option's values); for the one design of fixed values use "
            "design factorial",
        )
    return roles


ROBUST_KEYS = ("robust", "noise", "noise_samples")
ROBUST_DEFAULTS = {"quantile": 0.95, "max_failure_probability": 0.01, "objectives": "worst"}
DEFAULT_NOISE_SAMPLES = 64


def noise_count(robust) -> int:
    """Noise draws of a resolved robust section (None: not robust, one draw): the 2^k corners of
    the k noise parameters' box and the Sobol' samples, or the one nominal draw of no noise."""
    if not robust:
        return 1
    k = len(robust["noise"])
    return 2**k + robust["noise_samples"] if k else 1


def _resolve_robust(study, section: dict, out: dict, roles: dict) -> dict | None:
    """The robust settings of a study section (None where it asks for no robust answer: no
    ``robust``, ``noise``, ``noise_samples`` or ``role`` key): its operating conditions (factors
    of role condition, the study's conditions by default), noise (the config's, else the
    study's defaults; :func:`_noise`) and answer settings."""
    name = out["name"]
    asked = section.get("robust", None)
    if asked is False or (asked is None and not roles and not set(section) & set(ROBUST_KEYS)):
        for key in ("noise", "noise_samples"):
            if key in section:
                raise ConfigError(f"{name}.{key}", "read by a robust study only ('robust: false')")
        if roles:
            raise ConfigError(
                f"{name}.parameters.{next(iter(roles))}.role",
                "read by a robust study only ('robust: false')",
            )
        return None
    if out["design"] == "saltelli" or out.get("option_factors"):
        raise ConfigError(
            f"{name}.design",
            "a robust study crosses its designs (a factorial grid, or lhs/sobol samples) with "
            "its conditions and noise draws; saltelli designs and options drawn per scenario "
            "are not crossed",
        )
    settings = dict(ROBUST_DEFAULTS, **(asked if isinstance(asked, dict) else {}))
    conditions = [
        f
        for f in out["factors"]
        if roles.get(f, "condition" if f in study.conditions else "design") == "condition"
    ]
    for c in conditions:
        if "values" not in out["factors"][c]:
            raise ConfigError(
                f"{name}.parameters.{c}",
                "an operating condition of a sampled robust design is a grid every design point "
                "meets: give its 'values'",
            )
    own = [f for f in out["factors"] if f not in conditions]
    if out["design"] != "factorial" and not own:
        raise ConfigError(f"{name}.parameters", "a sampled robust design needs a design factor")
    if "noise" in section:
        given = section["noise"] or {}
        noise = {p: _noise(study, p, spec, out, f"{name}.noise.{p}") for p, spec in given.items()}
    else:  # (named at the key that made the study robust)
        noise = _default_noise(study, out, _robust_key(name, section, roles))
    samples = DEFAULT_NOISE_SAMPLES if noise else 0
    if "noise_samples" in section:
        samples = _count(section, "noise_samples", f"{name}.noise_samples")
        if not noise or samples < 2 or samples & (samples - 1):
            raise ConfigError(
                f"{name}.noise_samples",
                f"must be a power of 2 (a scrambled Sobol' sequence), at least 2, with a noise "
                f"to draw; got {samples}" + ("" if noise else " and no noise"),
            )
    for p in noise:
        for other, value in study.noise_replaces.get(p, {}).items():
            if other not in out["factors"] and other not in (section.get("parameters") or {}):
                out["fixed"][other] = float(value)
    return {**settings, "conditions": conditions, "noise": noise, "noise_samples": samples}


def _default_noise(study, out: dict, asked_by: str) -> dict:
    """The study's own noise (a robust section written without ``noise``), checked against the
    design; a refusal names the key that made the study robust (``asked_by``: robust,
    noise_samples or a role) and the noise it brought."""
    noise = {}
    for p, spec in (study.noise or {}).items():
        try:
            noise[p] = _noise(study, p, spec, out, f"{asked_by}.noise.{p}")
        except ConfigError as exc:
            raise ConfigError(
                asked_by,
                f"{_brought(study, p)}: {exc.problem}; change the design's {p} or write the "
                "study's noise key",
            ) from None
    return noise


_SCATTER = re.compile(
    r"^\s*(?:±|\+-|\+/-)\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(?:%|percent)\s*$"
)
_PERCENT = re.compile(r"^\s*([-+−]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(%|percent)?\s*$")


def _relative(value, key) -> float:
    """A relative deviation: a bare fraction (-0.2) or a percentage ("-20 %")."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ConfigError(key, f"a relative deviation: a fraction or 'N %', got {value!r}")
    if isinstance(value, str):
        m = _PERCENT.match(value)
        if not m:
            raise ConfigError(key, f"a relative deviation: a fraction or 'N %', got {value!r}")
        value = float(m.group(1).replace("−", "-")) / (100.0 if m.group(2) else 1.0)
    if not np.isfinite(value):
        raise ConfigError(key, f"must be finite, got {value!r}")
    return float(value)


def _continuous_parameter(study, name: str, key: str, what: str):
    """The study's parameter ``name``, refused at ``key`` where the study has none of that name
    or it is a count or a choice (which ``what``)."""
    try:
        param = study.parameter(name)
    except KeyError:
        raise ConfigError(key, f"not a parameter of the {study.name} study") from None
    if param.integer or param.choices is not None:
        raise ConfigError(key, f"a count or a choice {what}")
    return param


def _noise(study, p: str, spec: dict, out: dict, key: str) -> dict:
    """One noise parameter in SI: {"relative": bool, "min", "max", "dist", "centre", "sd"}
    (relative: fractions of the design's value; absolute: the parameter's SI value)."""
    param = _continuous_parameter(study, p, key, "cannot scatter continuously")
    kinds = [k for k in ("scatter", "relative", "min") if k in spec]
    if len(kinds) != 1 or ("min" in spec) != ("max" in spec):
        raise ConfigError(key, "give one of scatter: '±N %', relative: [lo, hi], or min and max")
    dist = spec.get("dist", "uniform")
    relative = kinds[0] != "min"
    if relative:
        lo, hi = _relative_bounds(spec, kinds[0], param, key)
        conv = spread = lambda v, k: _relative(v, k)  # noqa: E731
        _check_relative(param, out, lo, hi, key)
    else:
        lo, hi = _absolute_bounds(spec, param, p in out["factors"], key)
        conv = lambda v, k: _quantity(v, param, k, finite=True)  # noqa: E731
        spread = lambda v, k: _spread(v, param, k)  # noqa: E731
    if not lo < hi:
        raise ConfigError(key, f"the lower bound ({lo:g}) must be below the upper ({hi:g})")
    return {
        "relative": relative,
        "min": lo,
        "max": hi,
        "dist": dist,
        **_shape(spec, dist, lo, hi, conv, spread, key),
    }


def _absolute_bounds(spec: dict, param, is_factor: bool, key: str) -> tuple[float, float]:
    """A noise's min and max in SI (not on a design factor; a bare sd beside them refused where
    their unit scales it otherwise)."""
    if is_factor:
        raise ConfigError(
            key,
            "absolute bounds make the parameter the noise itself, and it is a factor of the "
            "design: give its scatter relative to the design's value (scatter or relative)",
        )
    lo = _quantity(spec["min"], param, f"{key}.min", finite=True)
    hi = _quantity(spec["max"], param, f"{key}.max", finite=True)
    if _bare_sd_beside_units(spec, param):
        raise ConfigError(
            f"{key}.sd",
            f"a bare number ({spec['sd']!r}) beside bounds written with their unit: write "
            "the sd's unit too (a bare number is SI)",
        )
    return lo, hi


def _relative_bounds(spec: dict, kind: str, param, key: str) -> tuple[float, float]:
    """A noise's bounds as fractions of the design's value (``kind`` scatter or relative):
    within -100 % and +100 %, not factors written as bare numbers, not of an absolute
    temperature."""
    if kind == "scatter":
        text = spec["scatter"]
        m = _SCATTER.match(text) if isinstance(text, str) else None
        if not m:
            raise ConfigError(f"{key}.scatter", f"write it as '±N %' (e.g. '±20 %'), got {text!r}")
        lo, hi = -float(m.group(1)) / 100.0, float(m.group(1)) / 100.0
    else:
        lo, hi = (_relative(v, f"{key}.relative[{i}]") for i, v in enumerate(spec["relative"]))
    if lo <= -1.0:
        raise ConfigError(
            key,
            f"a relative deviation below -100 % (got {lo:.4g}) changes the sign (write "
            "fractions (-0.2) or percent ('-20 %'))",
        )
    bare = kind == "relative" and all(map(_bare_number, spec["relative"]))
    if bare and lo >= 0.5:  # (bounds written as factors: [0.9, 1.0] would be +90 % to +100 %)
        raise ConfigError(
            key,
            f"relative bounds are deviations from the design's value, not factors: "
            f"{lo:.4g} to {hi:.4g} is {100 * lo:+.4g} % to {100 * hi:+.4g} %; as factors "
            f"they are written [{lo - 1:.4g}, {hi - 1:.4g}], or in percent with their sign",
        )
    if hi > 1.0:
        raise ConfigError(
            key,
            f"a relative deviation above +100 % (got {hi:.4g}, i.e. {100 * hi:.4g} %): write "
            "fractions (0.2) or percent ('20 %'); give min and max for a wider range",
        )
    if param.kind == "absolute":
        raise ConfigError(
            key,
            "a relative scatter of an absolute temperature depends on its scale (±20 % of "
            "313 K is ±63 K, of 40 degC ±8 K): give min and max (e.g. 20 degC and 60 degC)",
        )
    return lo, hi


_NUMBER_TEXT = re.compile(r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*$")


def _bare_number(value) -> bool:
    """Whether a config value is a number without a unit (a number, or a number in quotes)."""
    if isinstance(value, bool):
        return False
    return isinstance(value, (int, float)) or bool(
        isinstance(value, str) and _NUMBER_TEXT.match(value)
    )


def _bare_sd_beside_units(spec: dict, param) -> bool:
    """Whether a normal noise's sd is a bare number (SI) beside bounds written with a unit that
    scales it otherwise: any unit but a ratio's, or a temperature's in degF (a bare sd of a
    temperature, per K or per degC, reads as meant)."""
    if spec.get("dist") != "normal" or not _bare_number(spec.get("sd")):
        return False
    bounds = [spec["min"], spec["max"]]
    if param.units == "1" or all(map(_bare_number, bounds)):
        return False
    if re.search(r"\bK\b", param.units):
        return any(re.search(r"degF|°F|℉|delta_degF", str(b)) for b in bounds)
    return True


def _spread(value, param, key) -> float:
    """A spread of a parameter's values (a noise's sd) in SI: of the parameter's unit, a
    temperature as a difference ("5 degC" is 5 K), finite and of plausible magnitude, but not
    held to the parameter's own bounds (an sd of 0.1 for a ratio ≥ 1)."""
    kind = "difference" if param.units == "K" else param.unit_kind
    if param.units != "1" and isinstance(value, str) and ("%" in value or "percent" in value):
        other = (
            " (a temperature difference: K or degC)"
            if param.units == "K"
            else " (or another unit of it), or the noise relative (relative: ['-N %', 'N %'] or "
            "scatter: '±N %') with sd in %"
        )
        raise ConfigError(
            key,
            f"got {value!r}, a relative spread beside absolute bounds (min and max): give sd in "
            f"{param.units}{other}",
        )
    try:
        v = to_si(value, param.units, kind)
    except UnitError as exc:
        raise ConfigError(key, str(exc)) from None
    # (from the unit's smallest magnitude: a spread is not a value held to the parameter's)
    if param.units == "K":
        lo, hi = plausible.bounds("delta_K")
    else:
        lo, hi = param.unit_range[0], param.plausible_range[1]
    if not lo <= abs(v) <= hi:
        raise ConfigError(
            key,
            f"got {value!r}, outside the plausible range ({lo:g} to {hi:g} {param.units} in "
            "magnitude): a typing or unit slip?",
        )
    return v


def _shape(spec, dist, lo, hi, conv, spread, key) -> dict:
    """The centre (mode of a triangular, mean of a truncated normal) and sd of a noise."""
    if "sd" in spec and dist != "normal":
        raise ConfigError(f"{key}.sd", f"read by dist normal only (this noise is {dist})")
    if "mode" in spec and dist == "uniform":
        raise ConfigError(f"{key}.mode", "read by dist normal or triangular only")
    centre = conv(spec["mode"], f"{key}.mode") if "mode" in spec else 0.5 * (lo + hi)
    if not lo <= centre <= hi:
        raise ConfigError(
            f"{key}.mode", f"must lie within the bounds {lo:g} to {hi:g}, got {centre:g}"
        )
    out = {"centre": centre}
    if dist == "normal":
        if "sd" not in spec:
            raise ConfigError(f"{key}.sd", "required for dist normal (truncated at the bounds)")
        sd = spread(spec["sd"], f"{key}.sd")
        if not sd > 0:
            raise ConfigError(f"{key}.sd", f"must be > 0, got {sd:g}")
        if sd > hi - lo:  # (a number meant in another unit: the normal would be a uniform)
            raise ConfigError(
                f"{key}.sd",
                f"got {spec['sd']!r} = {sd:g}, wider than the noise's bounds ({hi - lo:g} from "
                "min to max): a unit slip? (a bare number is SI; write its unit)",
            )
        out["sd"] = sd
    return out


def _check_relative(param, out, lo, hi, key) -> None:
    """The design's values of ``param`` scattered by [lo, hi] stay physical and plausible."""
    a, b = studies.value_range(out, param.name, finite=True)
    for v in (a * (1 + lo), a * (1 + hi), b * (1 + lo), b * (1 + hi)):
        why = param.check(float(v))
        if why:
            raise ConfigError(key, f"the scattered value {why}")


def _noise_widened(out: dict) -> dict:
    """A resolved section whose noise parameters range over their scattered values (relations
    are checked at the worst corner of design, conditions and noise together)."""
    robust = out.get("robust")
    if not robust or not robust["noise"]:
        return out
    wide = {**out, "fixed": dict(out["fixed"]), "factors": dict(out["factors"])}
    for p, spec in robust["noise"].items():
        if spec["relative"]:
            a, b = studies.value_range(out, p)
            vals = [
                a * (1 + spec["min"]),
                a * (1 + spec["max"]),
                b * (1 + spec["min"]),
                b * (1 + spec["max"]),
            ]
        else:
            vals = [spec["min"], spec["max"]]
        wide["fixed"].pop(p, None)
        wide["factors"][p] = {"min": min(vals), "max": max(vals)}
    return wide


def _resolve_options(study, section: dict, out: dict) -> None:
    """A study section's options into ``out["options"]`` (a ``{values: [...]}`` choice drawn per
    scenario also into ``out["option_factors"]``), its measured tables and its accuracy."""
    name, design = out["name"], out["design"]
    for opt, allowed in study.options.items():
        given = (section.get("options") or {}).get(opt, allowed[0])
        if isinstance(given, dict):  # {values: [...]}: a categorical factor, drawn per scenario
            key = f"{name}.options.{opt}"
            if design == "factorial":
                raise ConfigError(
                    key,
                    "a list of choices is drawn per scenario by a sampled design (lhs, sobol, "
                    "saltelli); for a factorial design run one config per choice",
                )
            if opt in study.model_options:
                raise ConfigError(
                    key,
                    "chooses a model (or a reading of the paper), not a design or an operating "
                    "condition: its choices ranked together would compare models; run one config "
                    "per choice",
                )
            if len(set(given["values"])) != len(given["values"]):
                raise ConfigError(f"{key}.values", "values must be distinct")
            out.setdefault("option_factors", {})[opt] = list(given["values"])
            given = given["values"][0]  # the seed design's traces use the first choice
        out["options"][opt] = given
    for tname in ("friction_table",):  # (the tables the schema knows)
        if tname in section:
            out["options"][tname] = _table(study, tname, section[tname], f"{name}.{tname}")
    if study.accuracy is not None:
        acc = section.get("accuracy", study.accuracy)
        if not ACCURACY_RANGE[0] <= acc <= ACCURACY_RANGE[1]:
            raise ConfigError(
                f"{name}.accuracy",
                f"must be within {ACCURACY_RANGE[0]:g} to {ACCURACY_RANGE[1]:g} "
                f"(relative), got {acc:g}",
            )
        out["options"]["accuracy"] = float(acc)
    elif "accuracy" in section:
        raise ConfigError(
            f"{name}.accuracy",
            "this study has no tolerance to set (its models are closed forms "
            "or fixed-point solutions to round-off)",
        )


def _factor(param, spec: dict, design: str, key: str, name: str, max_scenarios: int) -> dict:
    """One parameter given as a factor (``key`` names it in errors): its grid values
    ``{"values": [...]}`` (a factorial grid, a values list, a sampled count's whole numbers) or a
    sampled range ``{"min", "max", "scale"}``, in SI."""
    if "values" in spec:
        return _values_factor(param, spec, key)
    if param.choices is not None:
        raise ConfigError(
            key,
            f"must be one of {param.choices}: give a fixed value or a 'values' list, not a range",
        )
    lo = _quantity(spec["min"], param, f"{key}.min", finite=True)
    hi = _quantity(spec["max"], param, f"{key}.max", finite=True)
    if param.integer and design != "factorial":  # a sampled count: every whole number in [min, max]
        return _sampled_count(spec, lo, hi, key)
    scale = spec.get("scale", "linear")
    if not lo < hi:
        raise ConfigError(key, f"min ({lo:g}) must be below max ({hi:g})")
    if scale == "log" and lo <= 0:
        raise ConfigError(f"{key}.min", "log scale needs min > 0")
    if design != "factorial":
        if "num" in spec:
            raise ConfigError(f"{key}.num", f"not used by design '{design}' (use '{name}.samples')")
        return {"min": lo, "max": hi, "scale": scale}
    return _factorial_range(param, spec, lo, hi, scale, key, name, max_scenarios)


def _values_factor(param, spec: dict, key: str) -> dict:
    """A factor given as a ``values`` list: a factorial grid's values, or a sampled design's
    discrete factor drawn uniformly among them."""
    if set(spec) - {"values"}:
        raise ConfigError(key, "give either 'values' or 'min'/'max'[/'num'/'scale'], not both")
    vals = [_quantity(v, param, f"{key}.values[{i}]") for i, v in enumerate(spec["values"])]
    if len(set(vals)) != len(vals):
        raise ConfigError(f"{key}.values", "values must be distinct")
    return {"values": vals}


def _sampled_count(spec: dict, lo: float, hi: float, key: str) -> dict:
    """A count factor of a sampled design: every whole number in [min, max]."""
    for bound, v in (("min", lo), ("max", hi)):
        if v != round(v):
            raise ConfigError(f"{key}.{bound}", f"a count: must be a whole number, got {v:g}")
    if set(spec) - {"min", "max"}:
        raise ConfigError(
            key, "a sampled count takes only 'min' and 'max' (every whole number between)"
        )
    if not lo < hi:
        raise ConfigError(key, f"min ({lo:g}) must be below max ({hi:g})")
    return {"values": [float(v) for v in range(int(lo), int(hi) + 1)]}


def _factorial_range(param, spec, lo, hi, scale, key, name, max_scenarios) -> dict:
    """A factorial factor given as min/max/num[/scale]: its ``num`` grid values."""
    if "num" not in spec:
        raise ConfigError(f"{key}.num", "required for a factorial min/max factor")
    num = _count(spec, "num", f"{key}.num")
    if num < 2:
        raise ConfigError(
            f"{key}.num",
            f"must be at least 2 to span min and max (got {num}); "
            "for one value give it as a fixed value",
        )
    if num > max_scenarios:
        raise _ceiling(name, num, max_scenarios)
    if param.integer:
        step = (hi - lo) / (num - 1)
        if lo != round(lo) or step != round(step):
            raise ConfigError(
                key,
                f"a count: min {lo:g}, max {hi:g} with num {num} gives non-whole "
                "values; give a 'values' list",
            )
    vals = np.geomspace(lo, hi, num) if scale == "log" else np.linspace(lo, hi, num)
    # between ends that are decimals (0.25, 0.6), the points to 15 digits: 0.45, not
    # 0.44999999999999996, so that .sel(x=0.45) finds it; the ends as given (np.deg2rad(65))
    decimal = all(float(f"{v:.15g}") == v for v in (lo, hi))
    inner = [float(f"{v:.15g}") if decimal else float(v) for v in vals[1:-1]]
    return {"values": [float(lo), *inner, float(hi)]}


REFINE_KEYS = ("design", "refine", "samples", "seed", "chunks", "chunk_size", "curves")
DEFAULT_SHRINK = 0.5


def stored_study(path, name=None, key="refine.from") -> dict:
    """The resolved study section a stored result was computed from (its ``config`` attribute),
    checked to be a clutchlab result of study ``name`` with a Pareto front."""
    import os

    import h5py

    if not os.path.isfile(path):
        raise ConfigError(key, f"no such file {path!r} (run the first stage first)")
    try:
        with h5py.File(path, "r") as fh:
            attrs = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in fh.attrs.items()}
            rank = fh["pareto_rank"][...] if "pareto_rank" in fh else None
    except (OSError, ValueError) as exc:
        raise ConfigError(key, f"cannot read {path!r} as a clutchlab result ({exc})") from None
    if attrs.get("source") != "clutchlab" or "config" not in attrs or rank is None:
        raise ConfigError(
            key,
            f"{path!r} is not a clutchlab study result with design answers "
            "(no config attribute or pareto_rank)",
        )
    section = yaml.safe_load(attrs["config"])
    if name is not None and section.get("name") != name:
        raise ConfigError(
            key, f"{path!r} is a result of study {section.get('name')!r}, not {name!r}"
        )
    if not (rank == 0).any():
        raise ConfigError(
            key, f"{path!r} has no feasible design on a Pareto front to refine around"
        )
    return section


def _check_refine_keys(name, section) -> None:
    """A 'design: refine' section has only the keys a refinement reads, and those it needs."""
    accuracy = " accuracy," if studies.get(name).accuracy is not None else ""
    for key in section:
        if key not in REFINE_KEYS:
            raise ConfigError(
                f"{name}.{key}",
                f"a 'design: refine' study takes its factors, fixed values, options,{accuracy} "
                "objectives and constraints from the result it refines (refine.from); "
                "remove this key",
            )
    for key in ("refine", "samples"):
        if key not in section:
            raise ConfigError(f"{name}.{key}", "required for design 'refine'")
    for key in ("samples", "seed"):
        if key in section:
            _count(section, key, f"{name}.{key}")
    _chunking(section, f"{name}.")


def _resolve_refine(name, section, default_chunks, max_scenarios, results_dir) -> dict:
    """A second stage: new samples near the Pareto fronts of a stored result, with everything
    else (factors and their ranges, fixed values, options, objectives, constraints) taken from it,
    so that the two stages' fronts are comparable."""
    import os

    _check_refine_keys(name, section)
    path = section["refine"]["from"]
    key = f"{name}.refine.from"
    own = os.path.join(results_dir, studies.get(name).output)
    if os.path.realpath(path) == os.path.realpath(own):
        raise ConfigError(
            key,
            f"is this run's own result file ({own}); write the refining run to another folder "
            "with the top-level key 'results: <folder>'",
        )
    first = stored_study(path, name, key)
    _check_first_stage(first, name, key)
    out = dict(first)
    out.update(
        {
            "design": "refine",
            "seed": _count(section, "seed", f"{name}.seed") if "seed" in section else 0,
            "samples": _count(section, "samples", f"{name}.samples"),
            # origin_design: the design the factor specs come from (a values list is a grid's levels
            # for a factorial origin, a discrete factor for a sampled one)
            "refine": {
                "from": path,
                "shrink": float(section["refine"].get("shrink", DEFAULT_SHRINK)),
                "first_design": first["design"],
                "origin_design": first.get("refine", {}).get("origin_design", first["design"]),
            },
        }
    )
    n = scenario_count(out)
    if n > max_scenarios:
        raise _ceiling(name, n, max_scenarios)
    out["chunks"] = chunk_count(n, _chunking(section, f"{name}.") or default_chunks)
    out["curve_stride"] = _curve_stride(name, section, "refine", n)
    return out


def _check_first_stage(first: dict, name: str, key: str) -> None:
    """The fixed values and factor bounds a refinement takes from its first stage pass today's
    parameter checks (with the first stage's own plausible ranges): a result made before a check
    was added is refused here, not turned into scenarios of status invalid_input."""
    own = studies.with_plausible(
        studies.get(name).parameters, first.get("options", {}).get("plausible")
    )
    by_name = {p.name: p for p in own}
    values = {p: [v] for p, v in first.get("fixed", {}).items()}
    for p, spec in first.get("factors", {}).items():
        values[p] = list(spec.get("values", [])) + [spec[e] for e in ("min", "max") if e in spec]
    for p, vals in values.items():
        param = by_name.get(p)
        why = next((w for v in vals if param and (w := param.check(float(v)))), None)
        if why:
            raise ConfigError(
                key,
                f"the first stage's {p} {why}; recompute the first stage with a config read "
                "by this version",
            )


# the units of outputs that are never negative (times, works, powers, stresses, lengths, rates,
# capacities and torque peaks, speeds, angles, jerk peaks; a temperature and its rise too): a
# negative constraint limit on one is a sign slip. Not forces (a snapping spring's valley load is
# negative), accelerations (a jump is signed) or ratios (margins are signed). An output of these
# units that can be negative must not be added without changing this (tests/test_config.py checks
# every scenario of the small config).
NEVER_NEGATIVE_UNITS = (
    "s", "J", "J/m^2", "W", "W/m^2", "Pa", "m", "1/s", "N m", "rad/s", "rad/s^3", "rad",
)  # fmt: skip


# the times a study finds only inside its simulated window [0, end_time] (a scenario that does not
# get there has a status that fails it): a maximum past the window's end adds nothing to that (a
# time written in ms without its unit is read in s); one at the end says "within the window"
WINDOWED_OUTPUTS = {
    "engagement": ("lockup_time", "lockup_time_worn"),
    "roller": ("engagement_time", "release_time"),
}


def _check_window_limits(out: dict, section: dict) -> None:
    """Refuse a constraint maximum the config gives on a windowed time past the longest window
    end (a study's default limit is left to its relation with end_time)."""
    for output in WINDOWED_OUTPUTS.get(out["name"], ()):
        given = (section.get("constraints") or {}).get(output, {}).get("max")
        if given is None:
            continue
        end = studies.value_range(out, "end_time")[1]
        if out["constraints"][output][1] > end:
            hint = (
                "a number meant in ms? write its unit"
                if not isinstance(given, str)
                else "lower the limit or lengthen end_time"
            )
            raise ConfigError(
                f"{out['name']}.constraints.{output}.max",
                f"a maximum of {given!r} never binds: {output} is found only within the simulated "
                f"window (end_time, at most {end:g} s here; a scenario past it fails by its "
                f"status); {hint}",
            )


def _answers(study, section):
    """The study's objectives and constraints: the config's, else the study's defaults."""
    name = study.name
    objectives = list(section.get("objectives", study.objectives))
    for i, item in enumerate(objectives):
        output = item.partition(":")[0]
        if output not in study.outputs:
            raise ConfigError(
                f"{name}.objectives[{i}]",
                f"unknown output {output!r} (choose from " + ", ".join(sorted(study.outputs)) + ")",
            )
    if len({o.partition(":")[0] for o in objectives}) != len(objectives):
        raise ConfigError(f"{name}.objectives", "an output given twice")
    given = section.get("constraints")
    if given is None:  # the study's defaults (SI)
        return objectives, {k: [op, float(v)] for k, (op, v) in study.constraints.items()}
    constraints = {}
    for output, limit in given.items():
        key = f"{name}.constraints.{output}"
        if output not in study.outputs:
            raise ConfigError(
                key, "unknown output (choose from " + ", ".join(sorted(study.outputs)) + ")"
            )
        ((op, value),) = limit.items()
        units, kind = study.output_units(output)
        try:
            v = to_si(value, units, kind)
        except UnitError as exc:
            raise ConfigError(f"{key}.{op}", str(exc)) from None
        # a limit of implausible magnitude for its unit (zero and negative margins are fine)
        why = studies.Parameter(output, units, output, 0.0, minimum=None, kind=kind).check(v, value)
        if why is None and v < 0 and (units in NEVER_NEGATIVE_UNITS or kind is not None):
            meets = "every scenario meets it" if op == "min" else "no scenario can meet it"
            why = f"{output} is never negative: a limit of {value} is a sign slip ({meets})"
        if why:
            raise ConfigError(f"{key}.{op}", why)
        constraints[output] = [op, v]
    return objectives, constraints


def _ceiling(name, n, max_scenarios) -> ConfigError:
    return ConfigError(
        name,
        f"the design has {n} scenarios, above the ceiling of {max_scenarios}; to run it "
        f"on purpose set the top-level key 'max_scenarios: {n}' (or more)",
    )


# folders of the workflow's source tree (relative to the working folder) results may not be in
SOURCE_FOLDERS = ("config", "workflows", "src")


def _check_results(path: str) -> None:
    """The results folder can be made and written, is not a file and not inside the source tree
    (``config/`` holds the configs: a report or result written there mixes with them)."""
    import os
    import tempfile

    full = os.path.realpath(path)
    for part in SOURCE_FOLDERS:
        src = os.path.realpath(part)
        if os.path.isdir(src) and (full == src or full.startswith(src + os.sep)):
            raise ConfigError(
                "results",
                f"{path!r} is inside the workflow's {part}/ folder; write results to a folder of "
                "their own, e.g. 'results/my_study'",
            )
    if os.path.exists(full) and not os.path.isdir(full):
        raise ConfigError("results", f"{path!r} is an existing file, not a folder")
    parent = full
    while not os.path.exists(parent):
        parent = os.path.dirname(parent)
    if not os.path.isdir(parent):
        raise ConfigError("results", f"{path!r} cannot be made: {parent!r} is a file")
    try:
        with tempfile.TemporaryFile(dir=parent):
            pass
    except OSError as exc:
        raise ConfigError(
            "results",
            f"{path!r} cannot be written: no file can be made in {parent!r} ({exc.strerror})",
        ) from None


def resolve(raw: dict) -> dict:
    """Validate ``raw`` and return the resolved config (SI floats, defaults filled in).

    Parameters
    ----------
    raw : dict
        The config as read (:func:`read_file`, or Snakemake's ``config`` with ``--config``
        overrides).

    Returns
    -------
    dict
        The resolved config: per study its design, options, fixed values and factors in SI,
        chunks, objectives and constraints.

    Raises
    ------
    ConfigError
        Naming the key of the first problem found.
    """
    from ._yaml_readings import deepest, path_text

    deep = deepest(raw, MAX_DEPTH)
    if deep is not None:
        raise ConfigError(
            path_text(deep), f"nests deeper than {MAX_DEPTH} levels (a config needs 6)"
        )
    cfg = copy.deepcopy(dict(raw))
    validate_schema(cfg)
    default_chunks = _chunking(cfg, "") or ("chunks", DEFAULT_CHUNKS)
    max_scenarios = (
        _count(cfg, "max_scenarios", "max_scenarios")
        if "max_scenarios" in cfg
        else DEFAULT_MAX_SCENARIOS
    )
    title = cfg.get("report", {}).get("title", "")
    if any(not ch.isprintable() for ch in title):
        raise ConfigError(
            "report.title",
            "must be one line of printable text (no newline, tab or control character)",
        )
    results_dir = cfg.get("results", "results")
    _check_results(results_dir)
    resolved = {
        "studies": list(cfg["studies"]),
        "max_scenarios": max_scenarios,
        "results": results_dir,
        "report": {
            "title": "clutchlab report",
            "dpi": 120,
            "benchmark": False,
            "hard_cases": True,
            "numerics": True,
            **cfg.get("report", {}),
        },
    }
    for name in cfg["studies"]:
        if name not in cfg:
            raise ConfigError(name, "section missing for a study listed in 'studies'")
        resolved[name] = _resolve_study(name, cfg[name], default_chunks, max_scenarios, results_dir)
    for name in studies.REGISTRY:
        if name in cfg and name not in resolved:
            # a section of a study not run is checked all the same (no ceiling: it is not run):
            # a mistake in it is refused now, not on the day the study is listed (of a refinement
            # its own keys: the result it refines need not exist yet)
            if cfg[name].get("design") == "refine":
                _check_refine_keys(name, cfg[name])
            else:
                _resolve_study(name, cfg[name], default_chunks, math.inf, results_dir)
    return resolved


def precheck_argv(argv=None) -> None:
    """Read every ``--configfile`` of a Snakemake command line with :func:`read_file`; exit with one
    line if one is not a clutchlab config file.

    Called by the default workflow profile, which Snakemake reads before it loads ``--configfile``
    itself: a file that is a YTE template (Snakemake's loader would evaluate its expressions, even
    in a dry run), not UTF-8, not YAML or not a mapping stops here, before Snakemake opens it.
    """
    import sys

    argv = sys.argv[1:] if argv is None else argv
    paths, taking = [], False
    for arg in argv:
        if arg.startswith("--configfile=") or arg.startswith("--configfiles="):
            paths.append(arg.split("=", 1)[1])
            taking = False
        elif arg in ("--configfile", "--configfiles"):
            taking = True
        elif taking and not arg.startswith("-"):
            paths.append(arg)
        else:
            taking = False
    try:
        for path in paths:
            read_file(path)
    except ConfigError as exc:
        sys.exit(f"clutchlab: {exc}")


def load(path) -> dict:
    """Read a YAML config file (:func:`read_file`) and return the resolved config."""
    return resolve(read_file(path))


# how a study is split into jobs: not part of what a result is (a result is identical whatever the
# chunk count; each chunk carries its index and count, checked at the merge)
EXECUTION_KEYS = ("chunks",)


def study_config_text(resolved_study: dict) -> str:
    """YAML text of a resolved study section (stored as provenance in result files), without the
    keys that only say how it is run (:data:`EXECUTION_KEYS`)."""
    science = {k: v for k, v in resolved_study.items() if k not in EXECUTION_KEYS}
    return yaml.safe_dump(science, sort_keys=True)

"""The parameter, output, config and API reference pages of the documentation, generated from the
code: the study tables (:mod:`clutchlab.studies`), one computed scenario of each study (its
outputs' units, long names and valid statuses), the config schema and the public modules'
``__all__``. The docs build (``docs/conf.py``) writes them before Sphinx reads the sources, so the
reference cannot drift from the code.

Run ``python -m clutchlab.reference_docs DIR`` to write the pages into ``DIR`` by hand.
"""

from __future__ import annotations

import importlib
import sys
from functools import cache
from pathlib import Path

import numpy as np
import yaml

from . import display, studies

__all__ = [
    "STUDIES",
    "PUBLIC_MODULES",
    "parameter_rows",
    "output_rows",
    "study_page",
    "config_page",
    "api_pages",
    "schema_parameter_description",
    "write_pages",
]

STUDIES = ("diaphragm_spring", "engagement", "centrifugal", "sprag", "roller")

#: modules whose ``__all__`` is the public API (the API reference lists every name in it)
PUBLIC_MODULES = (
    "clutchlab",
    "clutchlab.diaphragm",
    "clutchlab.friction",
    "clutchlab.driven_plate",
    "clutchlab.engagement",
    "clutchlab.heat",
    "clutchlab.wear",
    "clutchlab.centrifugal",
    "clutchlab.sprag",
    "clutchlab.roller",
    "clutchlab.contact",
    "clutchlab.units",
    "clutchlab.plausible",
    "clutchlab.display",
    "clutchlab.config",
    "clutchlab.doe",
    "clutchlab.studies",
    "clutchlab.pipeline",
    "clutchlab.store",
    "clutchlab.explore",
    "clutchlab.robust",
    "clutchlab.traces",
    "clutchlab.published",
    "clutchlab.validation",
    "clutchlab.hardcases",
    "clutchlab.verify",
    "clutchlab.report",
    "clutchlab.report.captions",
    "clutchlab.report.robust",
    "clutchlab.report.explorer",
    "clutchlab.reference_docs",
)

_SCHEMA = Path(__file__).with_name("config.schema.yaml")


def _num(value: float) -> str:
    if value is None:
        return ""
    if np.isinf(value):
        return "inf" if value > 0 else "−inf"
    return f"{value:.6g}"


def _cell(text) -> str:
    """``text`` safe inside a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def _range(p: studies.Parameter) -> str:
    """The allowed range of parameter ``p`` as an interval, in its SI unit."""
    if p.choices is not None:
        return "one of " + ", ".join(_num(c) for c in p.choices)
    lo = "(−∞" if p.minimum is None else ("[" if p.minimum_inclusive else "(") + _num(p.minimum)
    hi = "∞)" if p.maximum is None else _num(p.maximum) + ("]" if p.maximum_inclusive else ")")
    text = f"{lo}, {hi}"
    if p.integer:
        text += ", whole"
    if p.allow_infinite:
        text += ", inf allowed"
    return text


def _unit(units: str, kind: str | None = None) -> str:
    return f"{units} ({kind})" if kind else units


def _shown(p: studies.Parameter) -> str:
    """The default of ``p`` in the unit engineers read (:mod:`clutchlab.display`)."""
    if p.integer or p.choices is not None:
        return _num(p.default)
    return display.text(p.default, display.unit(p.units, p.name, p.kind), fmt=".6g")


def parameter_rows(name: str) -> list[dict]:
    """Per parameter of study ``name``: name, unit (SI), default (SI and as engineers read it),
    allowed range, meaning, source, role (design choice or operating condition)."""
    study = studies.get(name)
    return [
        {
            "name": p.name,
            "unit": _unit(p.units, p.kind),
            "default": _num(p.default),
            "shown": _shown(p),
            "range": _range(p),
            "meaning": p.long_name,
            "source": study.sources.get(p.name, ""),
            "role": "condition" if p.name in study.conditions else "design",
        }
        for p in study.parameters
    ]


@cache
def _one_scenario(name: str):
    """Study ``name`` computed for its default design (one scenario), for its outputs' attrs."""
    study = studies.get(name)
    inputs = {p.name: np.array([p.default]) for p in study.parameters}
    return study.compute(inputs, study.full_options())


def output_rows(name: str) -> list[dict]:
    """Per output of study ``name`` (every data variable of its result with the scenario
    dimension ``run``): name, unit (SI), meaning (``long_name``), valid statuses."""
    ds = _one_scenario(name)
    rows = []
    for var_name, var in ds.data_vars.items():
        if "run" not in var.dims:
            continue
        kind = var.attrs.get("units_metadata", "").removeprefix("temperature: ") or None
        rows.append(
            {
                "name": var_name,
                "unit": _unit(var.attrs.get("units", ""), kind),
                "meaning": var.attrs.get("long_name", ""),
                "valid": var.attrs.get("valid_statuses", "all"),
            }
        )
    return rows


def _table(rows: list[dict], columns: dict[str, str]) -> list[str]:
    lines = ["| " + " | ".join(columns.values()) + " |", "|" + "---|" * len(columns)]
    for row in rows:
        lines.append("| " + " | ".join(_cell(row[k]) for k in columns) + " |")
    return lines + [""]


def _options(study) -> list[str]:
    if not study.options:
        return ["This study has no options.", ""]
    lines = []
    for key, choices in study.options.items():
        role = (
            "chooses a model or a reading of the paper (one choice per run)"
            if key in study.model_options
            else "an operating condition (a front per choice)"
            if key in study.conditions
            else "a design choice (may be drawn per scenario in a sampled design)"
        )
        lines.append(
            f"- `{key}`: {', '.join(f'`{c}`' for c in choices)} (default `{choices[0]}`): {role}"
        )
    if study.accuracy is not None:
        lines.append(
            f"- `accuracy`: relative accuracy of the headline outputs, default {study.accuracy:g}"
        )
    return lines + [""]


def _answers(study) -> list[str]:
    objectives = ", ".join(f"`{o}`" for o in study.objectives) or "none"
    lines = [f"Default objectives: {objectives}.", "", "Default constraints:", ""]
    for out, (sense, limit) in study.constraints.items():
        units, _ = study.output_units(out)
        op = "≤" if sense == "max" else "≥"
        lines.append(f"- `{out}` {op} {_num(limit)} {'' if units == '1' else units}".rstrip())
    if not study.constraints:
        lines.append("- none")
    names = ", ".join(f"`{o}`" for o in study.outputs)
    conditions = ", ".join(f"`{c}`" for c in study.conditions) or "none"
    lines += [
        "",
        f"Outputs objectives and constraints may name: {names}.",
        "",
        f"Operating conditions (ranked within each value of a factorial grid): {conditions}.",
        "",
    ]
    return lines


def _tables(study) -> list[str]:
    lines = []
    for key, ((x, xu), (y, yu), text) in study.tables.items():
        lines.append(f"- `{key}`: {text} (`{x}` [{xu}] against `{y}` [{yu}])")
    return lines + [""] if lines else []


def study_page(name: str) -> str:
    """The reference page (MyST Markdown) of study ``name``."""
    study = studies.get(name)
    lines = [
        f"# Study `{name}`",
        "",
        f"{study.description}. Result: `results/{study.output}`; model: {study.model}.",
        "",
        "Values in SI units; a config may give any unit of the same kind "
        "([units](../config.md#units)).",
        "",
        "## Parameters",
        "",
        *_table(
            parameter_rows(name),
            {
                "name": "name",
                "unit": "unit",
                "default": "default",
                "shown": "default shown as",
                "range": "allowed",
                "meaning": "meaning",
                "source": "source",
                "role": "role",
            },
        ),
        "## Options",
        "",
        *_options(study),
    ]
    if study.tables:
        lines += ["## Measured tables", "", *_tables(study)]
    lines += [
        "## Outputs",
        "",
        "Each output is NaN (an integer one −1) under the statuses not listed as valid "
        "([statuses](../outputs.md#statuses-which-numbers-a-scenario-keeps)).",
        "",
        *_table(
            output_rows(name),
            {"name": "name", "unit": "unit", "meaning": "meaning", "valid": "valid statuses"},
        ),
        "## Design answers",
        "",
        *_answers(study),
    ]
    return "\n".join(lines)


def _schema_rows(props: dict, prefix: str = "") -> list[dict]:
    rows = []
    for key, spec in props.items():
        if key in STUDIES:
            continue
        rows.append({"key": f"`{prefix}{key}`", "meaning": spec.get("description", "")})
        if "properties" in spec and key != "parameters":
            rows += _schema_rows(spec["properties"], prefix=f"{prefix}{key}.")
    return rows


def config_page() -> str:
    """The config file reference (MyST Markdown): top-level keys and the keys of a study section,
    with the schema's descriptions."""
    schema = yaml.safe_load(_SCHEMA.read_text())
    study_keys = schema["$defs"]["study"]["properties"]
    lines = [
        "# Config file reference",
        "",
        "The keys of a config file, from its schema (`src/clutchlab/config.schema.yaml`, which "
        "editors read for completion and hover help). A study section (`diaphragm_spring`, "
        "`engagement`, `centrifugal`, `sprag`, `roller`) takes the keys below; its parameters "
        "and options are on the study's own [reference page](index.md).",
        "",
        "## Top-level keys",
        "",
        *_table(_schema_rows(schema["properties"]), {"key": "key", "meaning": "meaning"}),
        "## Keys of a study section",
        "",
        *_table(_schema_rows(study_keys), {"key": "key", "meaning": "meaning"}),
    ]
    return "\n".join(lines)


def schema_parameter_description(study: str, name: str) -> str:
    """The description the config schema carries for parameter ``name`` of ``study``: its
    meaning and SI unit, as the reference page gives them."""
    p = studies.get(study).parameter(name)
    unit = "" if p.units == "1" else f" [{p.units}]"
    return f"{p.long_name}{unit}"


def _kind(obj) -> str:
    if isinstance(obj, type):
        return "class"
    if callable(obj):
        return "function"
    return "data"


def api_pages() -> dict[str, str]:
    """File name -> reStructuredText of the API reference: an index and one page per public
    module listing every name in its ``__all__``."""
    pages = {}
    index = ["API reference", "=============", "", ".. toctree::", "   :maxdepth: 1", ""]
    for mod_name in PUBLIC_MODULES:
        module = importlib.import_module(mod_name)
        index.append(f"   {mod_name}")
        lines = [
            f"``{mod_name}``",
            "=" * (len(mod_name) + 4),
            "",
            f".. automodule:: {mod_name}",
            "",
        ]
        names = list(module.__all__)
        lines += [".. autosummary::", ""] + [f"   {n}" for n in names] + [""]
        for n in names:
            kind = _kind(getattr(module, n))
            directive = {"class": "autoclass", "function": "autofunction", "data": "autodata"}[kind]
            lines += [f".. {directive}:: {mod_name}.{n}"]
            if kind == "class":
                lines += ["   :members:"]
            if kind == "data":
                lines += ["   :no-value:"]
            lines += [""]
        pages[f"{mod_name}.rst"] = "\n".join(lines)
    pages["index.rst"] = "\n".join(index) + "\n"
    return pages


def _reference_index() -> str:
    lines = [
        "# Parameter and output reference",
        "",
        "Generated from the study tables and from one computed scenario of each study, so it "
        "always matches the code. Per study: every parameter (SI unit, default — the source "
        "paper's design —, allowed range, meaning, source, and whether it is a design choice or "
        "an operating condition), the options, the outputs (unit, meaning, the statuses under "
        "which the number is valid), the default objectives and constraints.",
        "",
        "```{toctree}",
        ":maxdepth: 1",
        "",
        *STUDIES,
        "config",
        "```",
        "",
    ]
    return "\n".join(lines)


def write_pages(reference_dir, api_dir) -> list[Path]:
    """Write the reference pages into ``reference_dir`` and the API pages into ``api_dir``;
    return the files written (a file whose text is unchanged is left as it is)."""
    pages = {Path(reference_dir) / f"{s}.md": study_page(s) for s in STUDIES}
    pages[Path(reference_dir) / "index.md"] = _reference_index()
    pages[Path(reference_dir) / "config.md"] = config_page()
    pages |= {Path(api_dir) / n: t for n, t in api_pages().items()}
    for path, text in pages.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    return list(pages)


if __name__ == "__main__":  # pragma: no cover
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "docs")
    for written in write_pages(out / "reference", out / "api"):
        print(written)

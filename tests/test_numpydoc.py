"""The public API's docstrings follow numpydoc, and every physical parameter states its unit.

numpydoc's own validator (``numpydoc.validate.validate``, the checks of ``numpydoc lint``) runs on
every public function of the physics, study and result modules: every name in a module's
``__all__`` that is a function, or, where a module has no ``__all__``, every function it defines
whose name does not start with an underscore. A test fails on

- GL08: no docstring;
- PR01 / PR02: a parameter of the signature not documented, or a documented one not in it;
- PR03: the parameters documented in another order than the signature's;
- PR04 / PR07: a parameter without a type or without a description;
- PR10: ``name: type`` (numpydoc needs a space before the colon);
- RT01 / RT03: a function that returns a value without a Returns section, or a return value
  without a description.

In the physics modules every parameter's type also carries its unit in brackets, the style of
pvlib-python: ``torque : float or array_like [N m]``, ``[-]`` for a dimensionless number or a
count. Arguments that are no physical quantity (a switch, a method name, a mapping of inputs, a
solver setting) are listed in :data:`NON_PHYSICAL`.
"""

from __future__ import annotations

import importlib
import inspect
import re

import pytest

numpydoc_validate = pytest.importorskip("numpydoc.validate")
docscrape = pytest.importorskip("numpydoc.docscrape")

#: the physics modules: numpydoc and a unit on every physical parameter
PHYSICS = (
    "clutchlab.diaphragm",
    "clutchlab.friction",
    "clutchlab.driven_plate",
    "clutchlab.heat",
    "clutchlab.centrifugal",
    "clutchlab.sprag",
    "clutchlab.roller",
    "clutchlab.contact",
    "clutchlab.wear",
    "clutchlab.engagement",
)

#: modules of the public API without physical parameters of their own: numpydoc only
SUPPORT = (
    "clutchlab.status",
    "clutchlab.plausible",
    "clutchlab.units",
    "clutchlab.explore",
    "clutchlab.robust",
    "clutchlab.store",
    "clutchlab.studies",
    "clutchlab.studies.centrifugal",
    "clutchlab.studies.diaphragm_spring",
    "clutchlab.studies.engagement",
    "clutchlab.studies.roller",
    "clutchlab.studies.sprag",
)

#: numpydoc validation codes that fail the test (numpydoc.validate.ERROR_MSGS)
REQUIRED = ("GL08", "PR01", "PR02", "PR03", "PR04", "PR07", "PR10", "RT01", "RT03")

#: arguments of physics functions that are no physical quantity: no unit expected
NON_PHYSICAL = {
    "assumption",  # a pressure distribution's name
    "formula",  # which printed formula
    "reading",  # which reading of a paper's formula
    "profile",  # a clamp profile's name
    "kind",  # a clamp profile's or a unit's kind
    "mode",  # an operating mode's name
    "direction",  # a load direction's name
    "geometry",  # a mapping of geometry arrays (each documented with its unit)
    "spring",  # a mapping of spring parameters (each documented with its unit)
    "scenario",  # a mapping of one scenario's inputs
    "p",  # a mapping of one scenario's inputs
    "rest",  # the other keys of a geometry dict, ignored (another name is refused)
    "trace_index",
    "trace_points",
    "power_history",  # a switch
    "peaks",  # a switch
    "compliant",  # a switch
    "rtol",  # solver tolerances, settings and iteration limits
    "atol",
    "tol",
    "max_iter",
    "max_steps",
    "first_step",
    "n",  # number of output points
    "kwargs",
}

_UNIT = re.compile(r"\[[^\]]+\]")


def public_functions(module_name: str) -> list[str]:
    """The module's public functions as import paths (``__all__``, or its own public functions)."""
    module = importlib.import_module(module_name)
    names = getattr(module, "__all__", None)
    if names is None:
        names = [
            n
            for n, obj in vars(module).items()
            if not n.startswith("_") and inspect.isfunction(obj) and obj.__module__ == module_name
        ]
    return [f"{module_name}.{n}" for n in names if inspect.isfunction(getattr(module, n))]


def _cases(modules):
    return [
        pytest.param(path, id=path.removeprefix("clutchlab."))
        for m in modules
        for path in public_functions(m)
    ]


def _problems(path: str) -> list[str]:
    result = numpydoc_validate.validate(path)
    return [f"{code}: {msg}" for code, msg in result["errors"] if code in REQUIRED]


@pytest.mark.parametrize("path", _cases(PHYSICS + SUPPORT))
def test_numpydoc(path):
    problems = _problems(path)
    assert not problems, f"{path}:\n  " + "\n  ".join(problems)


def _without_unit(func) -> list[str]:
    doc = docscrape.FunctionDoc(func)
    missing = []
    for param in doc["Parameters"]:
        for name in (n.strip().lstrip("*") for n in param.name.split(",")):
            if name and name not in NON_PHYSICAL and not _UNIT.search(param.type):
                missing.append(f"{name} : {param.type}")
    return missing


@pytest.mark.parametrize("path", _cases(PHYSICS))
def test_physical_parameters_have_units(path):
    module_name, _, name = path.rpartition(".")
    func = getattr(importlib.import_module(module_name), name)
    missing = _without_unit(func)
    assert not missing, f"{path}: parameters without a [unit] in their type: {missing}"


def test_checks_catch_what_they_should():
    """The validator and the unit check fail on an undocumented, misnamed or unit-less parameter
    and on a missing Returns section (the checks above are not vacuous)."""

    def undocumented(torque, speed):
        """Power.

        Parameters
        ----------
        torque : float [N m]
            Torque.
        sped : float
            Misnamed.
        """
        return torque * speed

    result = numpydoc_validate.validate(docscrape.get_doc_object(undocumented))
    codes = {code for code, _ in result["errors"]}
    assert {"PR01", "PR02", "RT01"} <= codes
    assert _without_unit(undocumented) == ["sped : float"]


def test_every_module_has_public_functions():
    for m in PHYSICS + SUPPORT:
        assert public_functions(m), m

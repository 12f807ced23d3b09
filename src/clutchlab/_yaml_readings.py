"""Plain YAML scalars that YAML 1.1 and YAML 1.2 read differently, and how deep a config nests.

Snakemake reads ``--configfile`` with PyYAML, a YAML 1.1 reader: ``010`` is 8 (octal), ``1:30``
is 90 (sexagesimal), ``on``/``off``/``yes``/``no`` are booleans, ``1_000`` is 1000, ``0b101`` is 5,
``2024-01-01`` a date, while ``1e-4`` and ``1.5e3`` (no dot or no sign in the exponent) and
``+.5`` are text. The YAML 1.2 core schema (the reading of YAML 1.2 tools and of most people) reads
``010`` as 10 and the others the other way round. :func:`misreadings` lists every plain scalar of
a composed YAML document whose two readings differ, so that a config can refuse it instead of
silently taking one of them.
"""

from __future__ import annotations

import datetime
import math
import re

import yaml

__all__ = ["yaml12", "spell", "misreadings", "deepest", "path_text"]

# the YAML 1.2 core schema (YAML 1.2.2, section 10.3.2): tag resolution of a plain scalar
_CORE = (
    (re.compile(r"(?:~|null|Null|NULL|)"), lambda t: None),
    (re.compile(r"(?:true|True|TRUE)"), lambda t: True),
    (re.compile(r"(?:false|False|FALSE)"), lambda t: False),
    (re.compile(r"[-+]?[0-9]+"), lambda t: int(t, 10)),
    (re.compile(r"0o[0-7]+"), lambda t: int(t[2:], 8)),
    (re.compile(r"0x[0-9a-fA-F]+"), lambda t: int(t[2:], 16)),
    (re.compile(r"[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"), float),
    (re.compile(r"[-+]?\.(?:inf|Inf|INF)"), lambda t: -math.inf if t[0] == "-" else math.inf),
    (re.compile(r"\.(?:nan|NaN|NAN)"), lambda t: math.nan),
)


_INF_WORD = re.compile(r"[-+]?\.(?:inf|Inf|INF)")


def yaml12(text: str):
    """The YAML 1.2 core-schema reading of the plain scalar ``text``."""
    for pattern, read in _CORE:
        if pattern.fullmatch(text):
            return read(text)
    return text


def _same(a, b) -> bool:
    if type(a) is not type(b):
        return False
    if isinstance(a, float) and math.isnan(a):
        return math.isnan(b)
    return a == b


def spell(value) -> str:
    """A spelling of ``value`` that YAML 1.1 and YAML 1.2 both read as ``value``."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        text = repr(value)
        mantissa, e, exponent = text.partition("e")
        if e:
            mantissa += "" if "." in mantissa else ".0"
            exponent = exponent if exponent[0] in "+-" else "+" + exponent
            return f"{mantissa}e{exponent}"
        return text
    if isinstance(value, (datetime.date, datetime.datetime)):
        value = value.isoformat()
    return "'" + str(value).replace("'", "''") + "'"


def _reading(value) -> str:
    """A reading for a message: a number or a boolean as such, text quoted."""
    if isinstance(value, bool):
        return f"the boolean {spell(value)}"
    if isinstance(value, (int, float)):
        return spell(value)
    if value is None:
        return "null (no value)"
    if isinstance(value, (datetime.date, datetime.datetime)):
        return f"the date {value.isoformat()}"
    return f"the text {spell(value)}"


def _key_text(node) -> str:
    return str(node.value) if isinstance(node, yaml.ScalarNode) else "<key>"


def _children(node, path):
    """(child node, its path, whether it is a mapping key) of a collection node."""
    if isinstance(node, yaml.MappingNode):
        for k, v in node.value:
            if k.tag == "tag:yaml.org,2002:merge":  # '<<': YAML 1.1 merge key (an anchor's keys)
                yield v, path, False
                continue
            key = _key_text(k)
            yield k, path + [key], True
            yield v, path + [key], False
    elif isinstance(node, yaml.SequenceNode):
        for i, v in enumerate(node.value):
            yield v, path + [i], False


def path_text(path) -> str:
    """A key path as config messages write it: ``roller.parameters.rollers.values[1]``."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "<top level>"


def duplicates(root):
    """(key path, message) of each key given twice in one mapping of the composed document
    ``root`` (PyYAML would keep the last), in document order; aliases are visited once."""
    constructor = yaml.constructor.SafeConstructor()
    seen, stack = set(), [(root, [])]
    while stack:
        node, path = stack.pop()
        if id(node) in seen or not isinstance(node, yaml.MappingNode | yaml.SequenceNode):
            continue
        seen.add(id(node))
        if isinstance(node, yaml.MappingNode):
            found = _duplicate_key(constructor, node)
            if found is not None:
                key, first, second = found
                yield (
                    path_text(path + [key]),
                    (
                        f"given twice in one mapping (lines {first} and {second}); YAML would "
                        "silently keep the last"
                    ),
                )
        children = [(child, p) for child, p, is_key in _children(node, path) if not is_key]
        stack.extend(reversed(children))


def _duplicate_key(constructor, node):
    """(key text, first line, second line) of the first key given twice in the mapping ``node``,
    or None (keys compared as read: ``1`` and ``1.0`` are one key)."""
    lines = {}
    for k, _ in node.value:
        if not isinstance(k, yaml.ScalarNode) or k.tag == "tag:yaml.org,2002:merge":
            continue
        try:
            key = constructor.construct_object(k)
            if key in lines:
                return _key_text(k), lines[key], k.start_mark.line + 1
            lines[key] = k.start_mark.line + 1
        except (TypeError, ValueError, yaml.YAMLError):
            continue  # (an unhashable or unreadable key: refused when the document is read)
    return None


def misreadings(root):
    """(key, message) of each plain scalar of the composed document ``root`` that YAML 1.1 and
    YAML 1.2 read differently; aliases are visited once."""
    constructor = yaml.constructor.SafeConstructor()
    resolver = yaml.resolver.Resolver()
    seen, stack = set(), [(root, [], False)]
    while stack:
        node, path, is_key = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, yaml.ScalarNode):
            implicit = resolver.resolve(yaml.ScalarNode, node.value, (True, False))
            explicit_text = node.tag != implicit and node.tag == "tag:yaml.org,2002:str"
            if node.style is None and not explicit_text:  # (plain, not tagged !!str)
                problem = _misread(constructor, node, is_key)
                if problem:
                    yield path_text(path), problem
            continue
        stack.extend(reversed(list(_children(node, path))))


def _misread(constructor, node, is_key) -> str | None:
    v11 = constructor.construct_object(node)
    v12 = yaml12(node.value)
    if _same(v11, v12):
        if isinstance(v12, float) and math.isinf(v12) and not _INF_WORD.fullmatch(node.value):
            # a number beyond a double's range (1.0e+400), not the word .inf: both readers
            # overflow to an infinity (a held engine, for an engine inertia)
            return (
                f"the value {node.value} is beyond the largest number a double holds (1.8e308) and "
                "would be read as infinite: write .inf if that is meant"
            )
        return None
    what = "the key" if is_key else "the value"
    ways = dict.fromkeys((spell(v11), spell(v12)))
    write = " or ".join(ways) + (", whichever you mean" if len(ways) > 1 else "")
    return (
        f"{what} {node.value} is read as {_reading(v11)} by YAML 1.1 (Snakemake's reader) and as "
        f"{_reading(v12)} by YAML 1.2: write {write}"
    )


def deepest(obj, limit: int):
    """The path (list of keys and indices) to the first container nested more than ``limit``
    deep in ``obj`` (dicts and lists), or None; iterative, so any depth is safe."""
    stack, seen = [(obj, [])], set()
    while stack:
        node, path = stack.pop()
        if not isinstance(node, (dict, list)) or id(node) in seen:
            continue
        if len(path) > limit:
            return path
        seen.add(id(node))
        items = node.items() if isinstance(node, dict) else enumerate(node)
        stack.extend((v, path + [k]) for k, v in items)
    return None

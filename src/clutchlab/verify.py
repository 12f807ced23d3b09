"""Is a stored result (or chunk) what it says it is? Its checksum and its provenance.

Every chunk file says what produced it: its study's resolved config text (``config``), the hash
of the design it was computed from (``clutchlab_design_hash``: :func:`clutchlab.store.checksum`
of the design Dataset's values and attributes), the package source that computed it
(``clutchlab_source``, :func:`clutchlab.source_hash`), and which chunk it is (``chunk_index`` of
``chunk_count``). The merge checks each of them against the design and the current config and
source (:func:`chunk_problems`), and a merged result keeps the first three and is sealed with its
own checksum of everything it holds (:func:`clutchlab.store.seal`).

``clutchlab verify PATH...`` (or ``python -m clutchlab.verify PATH...``) checks files against
their stored checksum and provenance and says per file ``ok`` or what differs; the exit code is
non-zero when any file fails. Each study's pages job checks its inputs the same way
(:func:`require`, and :func:`load_checked` for the result it draws from), so the report is not
built from a result that fails.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import numpy as np
import yaml

from . import store

__all__ = [
    "PROVENANCE",
    "ProvenanceError",
    "config_difference",
    "provenance_problems",
    "chunk_problems",
    "file_problems",
    "load_checked",
    "require",
    "main",
    "cli",
]

# the attributes that say what produced a chunk or a result (checked by the merge and by verify)
PROVENANCE = ("config", "clutchlab_source", "clutchlab_design_hash")
_CHUNK_FILE = re.compile(r"chunk_(\d+)\.h5$")
_SHOWN_KEYS = 3  # config keys named in a message (then "and N more")
# what a message tells the user to do with a result or chunk that fails
_RECOMPUTE = "delete it and run snakemake again to recompute it"


class ProvenanceError(ValueError):
    """A design, chunk or result was not produced by the config and source it is checked against,
    or fails its checksum (the message names the file and what differs)."""


def _flatten(value, prefix="") -> dict:
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            out.update(_flatten(item, f"{prefix}{key}."))
        return out
    return {prefix[:-1]: value}


def config_difference(text: str, expected: str) -> str:
    """The keys whose values differ between two study config texts, as one line.

    Parameters
    ----------
    text : str
        The resolved study config (YAML) a file was computed from (its ``config`` attribute).
    expected : str
        The one it is checked against (:func:`clutchlab.config.study_config_text`).

    Returns
    -------
    str
        e.g. ``fixed.youngs_modulus 200000000000.0 (expected 206000000000.0)``; the first
        ``_SHOWN_KEYS`` differing keys in key order, then how many more.
    """
    try:
        got, want = _flatten(yaml.safe_load(text) or {}), _flatten(yaml.safe_load(expected) or {})
    except yaml.YAMLError:
        return "its config text cannot be read"
    keys = sorted(k for k in set(got) | set(want) if got.get(k, None) != want.get(k, None))
    shown = [
        f"{k} {got[k] if k in got else '(absent)'} (expected {want[k] if k in want else 'absent'})"
        for k in keys[:_SHOWN_KEYS]
    ]
    more = f" and {len(keys) - _SHOWN_KEYS} more" if len(keys) > _SHOWN_KEYS else ""
    return ", ".join(shown) + more if shown else "the same values written differently"


def _text(value) -> str | None:
    if value is None:
        return None
    return value.decode() if isinstance(value, bytes) else str(np.asarray(value).ravel()[0])


def provenance_problems(
    attrs: dict,
    *,
    config: str | None = None,
    source: str | None = None,
    design_hash=None,
    required=PROVENANCE,
) -> list[str]:
    """What in a file's provenance attributes is missing or differs from what it must come from.

    Parameters
    ----------
    attrs : dict
        The file's (or in-memory chunk's) global attributes.
    config : str or None
        The study config text it must have been computed from; None: not checked.
    source : str or None
        The package source hash that must have computed it; None: not checked.
    design_hash : str or None
        :func:`clutchlab.store.checksum` of the design it must come from; None: not checked.
    required : tuple of str
        The provenance attributes it must carry (a design: ``config`` and ``clutchlab_source``).

    Returns
    -------
    list of str
        One phrase per problem (empty: none), to follow the file's name.
    """
    problems = [f"has no {key} attribute" for key in required if key not in attrs]
    got = {key: _text(attrs.get(key)) for key in PROVENANCE}
    if config is not None and got["config"] is not None and got["config"] != config:
        problems.append(
            "was computed from another study config: " + config_difference(got["config"], config)
        )
    if source is not None and got["clutchlab_source"] not in (None, source):
        problems.append(
            f"was computed by another clutchlab source ({got['clutchlab_source']}; "
            f"the current source is {source})"
        )
    if design_hash is not None and got["clutchlab_design_hash"] not in (None, design_hash):
        problems.append(
            f"was computed from another design (design hash {got['clutchlab_design_hash'][:16]}, "
            f"this study's design {design_hash[:16]})"
        )
    return problems


def chunk_problems(attrs: dict, design, *, config=None, source=None, design_hash=None) -> list:
    """What is wrong with a chunk's provenance, checked against the design it is merged into.

    Parameters
    ----------
    attrs : dict
        The chunk's global attributes.
    design : xarray.Dataset
        The study's design (its ``config`` attribute and its hash are what the chunk must carry).
    config : str or None
        The current study config text; it must be the design's and the chunk's. None: the
        design's own.
    source : str or None
        The current package source hash (default: :func:`clutchlab.source_hash`).
    design_hash : str or None
        :func:`clutchlab.store.checksum` of ``design``, if the caller has it already.

    Returns
    -------
    list of str
        One phrase per problem (empty: the chunk belongs to this design, config and source).
    """
    from . import source_hash

    return provenance_problems(
        attrs,
        config=config if config is not None else _text(design.attrs.get("config")),
        source=source if source is not None else source_hash(),
        design_hash=design_hash if design_hash is not None else store.checksum(design),
    ) + [f"has no {key} attribute" for key in ("chunk_index", "chunk_count") if key not in attrs]


def _design_beside(path: Path, attrs: dict) -> Path | None:
    """The design file of a chunk (``design.h5`` in its folder) or of a study result (the work
    folder of the results folder it sits in), if it is there."""
    if "chunk_index" in attrs:
        candidate = path.parent / "design.h5"
        return candidate if candidate.exists() else None
    from . import studies

    try:
        output = studies.get(_text(attrs["study"])).output
    except (KeyError, ValueError, TypeError):
        return None
    text = path.as_posix()
    if not text.endswith("/" + output) and text != output:
        return None
    root = Path(text[: -len(output)] or ".")
    candidate = root / "work" / _text(attrs["study"]) / "design.h5"
    return candidate if candidate.exists() else None


def _chunk_place_problems(path: Path, attrs: dict, design) -> list[str]:
    """A chunk's index against its file name (chunk_NNNN.h5) and its scenarios against the
    design's split into ``chunk_count`` chunks."""
    from . import pipeline

    index, count = int(np.ravel(attrs["chunk_index"])[0]), int(np.ravel(attrs["chunk_count"])[0])
    problems = []
    named = _CHUNK_FILE.search(path.name)
    if named and int(named.group(1)) != index:
        problems.append(f"holds chunk {index + 1} of {count}, not the chunk its name says")
    if design is not None:
        with store.open(path, indexes=False) as ds:
            run = ds["run"].values if "run" in ds.variables else np.zeros(0, np.int64)
        n = pipeline.n_scenarios(design)
        want = pipeline.chunk_slice(n, count, index) if 0 <= index < count else slice(0, -1)
        if not np.array_equal(run, np.arange(want.start, want.stop)):
            problems.append(f"does not hold the scenarios of chunk {index + 1} of {count}")
    return problems


def file_problems(path, *, config=None, source=None, design=None) -> list[str]:
    """Check one stored result, chunk or sensitivity file against its checksum and provenance.

    The checksum is recomputed a block at a time (:func:`clutchlab.store.file_checksum_problem`).
    A study result or chunk must carry its provenance (:data:`PROVENANCE`); it is compared with
    ``config`` and ``source`` where given, and with the design: ``design``, else the design file
    of the folder layout the workflow writes (``work/<study>/design.h5``) if present. A chunk's
    index must match its file name and its scenarios the design's split.

    Parameters
    ----------
    path : str or path
        The file.
    config : str or None
        The study config text it must come from (:func:`clutchlab.config.study_config_text`).
    source : str or None
        The package source hash it must have been computed by.
    design : xarray.Dataset, str, path, None or False
        The design it must come from (a Dataset or its file); None: the design file of the
        workflow's layout if present; False: none.

    Returns
    -------
    list of str
        One phrase per problem (empty: ok), each to follow the file's name.
    """
    path = Path(path)
    problem = store.file_checksum_problem(path)
    if problem:
        return [problem]
    with store.open(path, indexes=False) as ds:
        return _provenance_of(path, dict(ds.attrs), _kind(ds), config, source, design)


def load_checked(path, *, config=None, source=None, design=None, action=None):
    """Load a stored file and check it as :func:`file_problems` does, on the loaded Dataset (its
    checksum computed in memory: one read of the file instead of two, for a job that reads all of
    it anyway).

    Parameters
    ----------
    path : str or path
        The file.
    config, source, design
        As :func:`file_problems`.
    action : str or None
        What the error tells the user to do (default: delete it and run snakemake again).

    Returns
    -------
    xarray.Dataset
        The file's content, loaded.

    Raises
    ------
    ProvenanceError
        The file cannot be read, does not match its checksum or its provenance (one line: the
        file, what differs, what to do).
    """
    path = Path(path)
    todo = action or _RECOMPUTE
    try:
        ds = store.load(path)
    except Exception as exc:  # h5py/netCDF raise several types for a cut or damaged file
        raise ProvenanceError(f"{path} {store._unreadable(exc)}; {todo}") from None
    problem = store.checksum_problem(ds)
    problems = (
        [problem]
        if problem
        else _provenance_of(path, dict(ds.attrs), _kind(ds), config, source, design)
    )
    if problems:
        raise ProvenanceError(f"{path} {'; '.join(problems)}; {todo}")
    return ds


def _provenance_of(path, attrs, kind, config, source, design) -> list[str]:
    """:func:`file_problems` of a file whose checksum matched: its provenance."""
    if kind is None:
        return []  # a file without a study of its own (sensitivity indices): its checksum only
    if kind == "design":
        return provenance_problems(
            attrs, config=config, source=source, required=("config", "clutchlab_source")
        )
    design, problems, design_hash = _the_design(path, attrs, design)
    problems += provenance_problems(attrs, config=config, source=source, design_hash=design_hash)
    if kind == "chunk":
        problems += _chunk_place_problems(path, attrs, design)
    return problems


def _kind(ds) -> str | None:
    """The kind of a stored file: ``chunk``, ``result`` (scenario results: a ``status``
    variable), ``design`` (a study's file without them) or None (e.g. sensitivity indices)."""
    if "chunk_index" in ds.attrs:
        return "chunk"
    if "status" in ds.variables:
        return "result"
    return "design" if "study" in ds.attrs else None


def _the_design(path: Path, attrs: dict, design) -> tuple:
    """(the design Dataset to compare with or None, [problem], its hash or None): ``design`` as
    given (a Dataset or a file), None: the workflow layout's design file if present, False: none.
    A design file is read once and checked against its own checksum in memory; its hash is then
    the checksum it carries (the same value :func:`clutchlab.store.checksum` computes)."""
    if design is False:
        return None, [], None
    if design is None:
        design = _design_beside(path, attrs)
    if design is None:
        return None, [], None
    if hasattr(design, "attrs"):
        return design, [], store.checksum(design)
    try:
        loaded = store.load(design)
    except Exception as exc:  # h5py/netCDF raise several types for a cut or damaged file
        problem = store._unreadable(exc)
        return None, [f"cannot be compared with its design {design}, which {problem}"], None
    problem = store.checksum_problem(loaded)
    if problem == "has no checksum":  # a design written by an older clutchlab
        return loaded, [], store.checksum(loaded)
    if problem:
        return None, [f"cannot be compared with its design {design}, which {problem}"], None
    return loaded, [], str(loaded.attrs[store.CHECKSUM])


def require(expected: dict, *, action=_RECOMPUTE) -> None:
    """Raise :class:`ProvenanceError` unless every file passes :func:`file_problems`; its message
    has one line per failing file: the file, what differs, what to do.

    Parameters
    ----------
    expected : dict
        Path -> keyword arguments of :func:`file_problems` (``config``, ``source``, ``design``),
        and optionally ``action``: what to do with that file if it fails.
    action : str
        What the message tells the user to do with a failing file (unless its own is given).
    """
    lines = []
    for path, spec in expected.items():
        kwargs = dict(spec)
        todo = kwargs.pop("action", action)
        problems = file_problems(path, **kwargs)
        if problems:
            lines.append(f"{path} {'; '.join(problems)}; {todo}")
    if lines:
        raise ProvenanceError("\n".join(lines))


def _describe(path: Path) -> str:
    with store.open(path, indexes=False) as ds:
        a = ds.attrs
        parts = [f"study {_text(a['study'])}"] if "study" in a else []
        if "chunk_index" in a and "chunk_count" in a:
            parts.append(
                f"chunk {int(np.ravel(a['chunk_index'])[0]) + 1} of {_text(a['chunk_count'])}"
            )
        if "clutchlab_design_hash" in a:
            parts.append(f"design hash {_text(a['clutchlab_design_hash'])[:16]}")
        if "clutchlab_source" in a:
            parts.append(f"clutchlab source {_text(a['clutchlab_source'])}")
    return ", ".join(parts)


def _expected_from_config(config_file, study: str | None) -> dict:
    from . import config as cfg
    from . import source_hash

    resolved = cfg.load(config_file)
    if study not in resolved.get("studies", []):
        raise ProvenanceError(f"its study {study} is not one of {config_file}'s studies")
    return {"config": cfg.study_config_text(resolved[study]), "source": source_hash()}


def _check_one(path: Path, args) -> str:
    """One line about one file: ``PATH: ok (...)`` or ``PATH: FAILED: ...``."""
    kwargs = {"design": args.design}
    try:
        study = None
        if args.config is not None and path.exists():
            with store.open(path, indexes=False) as ds:
                study = _text(ds.attrs.get("study"))
        if study is not None:  # (a file without a study, e.g. sensitivity indices: checksum only)
            kwargs.update(_expected_from_config(args.config, study))
        problems = file_problems(path, **kwargs)
    except Exception as exc:  # a config that is refused, a design that cannot be read
        problems = [f"cannot be checked ({type(exc).__name__}: {str(exc).splitlines()[0]})"]
    if problems:
        return f"{path}: FAILED: {'; '.join(problems)}"
    described = _describe(path)
    return f"{path}: ok" + (f" ({described})" if described else "")


def main(argv=None) -> int:
    """``python -m clutchlab.verify [--config FILE] [--design FILE] PATH...``: one line per file,
    exit code 1 if any file fails its checksum or provenance."""
    parser = argparse.ArgumentParser(
        prog="clutchlab verify",
        description="Check clutchlab result and chunk files against their stored checksum "
        "(values and attributes) and provenance (config, design, source).",
    )
    parser.add_argument("paths", nargs="+", type=Path, metavar="PATH")
    parser.add_argument(
        "--config",
        help="a clutchlab config file: each file's study config must be this file's and its "
        "source the installed clutchlab's (command-line --config overrides are not known here)",
    )
    parser.add_argument(
        "--design",
        help="the design file the files must come from (default: work/<study>/design.h5 of the "
        "results folder, or design.h5 beside a chunk, if present)",
    )
    args = parser.parse_args(argv)
    failed = 0
    for path in args.paths:
        line = _check_one(path, args)
        failed += ": FAILED: " in line
        print(line, flush=True)
    return 1 if failed else 0


def cli(argv=None) -> int:
    """The ``clutchlab`` console script: ``clutchlab verify PATH...`` (the one command so far)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] != "verify":
        print("usage: clutchlab verify [--config FILE] [--design FILE] PATH...", file=sys.stderr)
        return 2
    return main(argv[1:])


if __name__ == "__main__":
    sys.exit(main())

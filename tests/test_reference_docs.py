"""The documentation: the generated parameter, output, config and API reference covers every study
parameter, output and public name; the config schema carries the reference's descriptions; the
README stays a short first page; user-facing text speaks of the product; every internal link of
the README and the docs pages resolves."""

import importlib
import pkgutil
import re
from pathlib import Path

import pytest
import yaml

import clutchlab
from clutchlab import reference_docs as rd
from clutchlab import studies

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SCHEMA = ROOT / "src" / "clutchlab" / "config.schema.yaml"


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """The generated reference and API pages, written as the docs build writes them."""
    out = tmp_path_factory.mktemp("docs")
    rd.write_pages(out / "reference", out / "api")
    return out


@pytest.mark.parametrize("name", rd.STUDIES)
def test_every_parameter_has_unit_meaning_and_source(name):
    study = studies.get(name)
    assert set(study.sources) == {p.name for p in study.parameters}
    for row in rd.parameter_rows(name):
        assert row["meaning"].strip(), row["name"]
        assert row["unit"].strip(), row["name"]
        assert row["source"].strip(), row["name"]
        # a source is a place in a paper or says that the value is assumed (and why)
        assert re.match(
            r"(the source paper \(00\d\)|assumed: |derived: |model choice: )", row["source"]
        ), row


@pytest.mark.parametrize("name", rd.STUDIES)
def test_every_output_has_a_meaning_and_valid_statuses(name):
    rows = rd.output_rows(name)
    assert {r["name"] for r in rows} >= set(studies.get(name).outputs)
    for row in rows:
        assert row["meaning"].strip(), row["name"]
        assert row["unit"].strip(), row["name"]
        assert row["valid"].strip(), row["name"]


@pytest.mark.parametrize("name", rd.STUDIES)
def test_study_page_lists_every_parameter_output_option_and_default_answer(name, pages):
    text = (pages / "reference" / f"{name}.md").read_text()
    study = studies.get(name)
    for p in study.parameters:
        assert f"| {p.name} |" in text, p.name
    for row in rd.output_rows(name):
        assert f"| {row['name']} |" in text, row["name"]
    for option in study.options:
        assert f"`{option}`" in text, option
    for objective in study.objectives:
        assert f"`{objective}`" in text, objective
    for output in study.constraints:
        assert f"- `{output}` " in text, output


def test_parameter_table_row_of_a_known_parameter():
    """One row checked by hand: the sprag's allowable contact stress (paper 002, Table 2)."""
    row = next(r for r in rd.parameter_rows("sprag") if r["name"] == "contact_allowable")
    assert row["unit"] == "Pa"
    assert row["default"] == "3.4e+09"
    assert row["range"] == "(0, ∞)"
    assert row["source"] == "the source paper (002), Table 2 (allowable)"


def _schema_parameters(schema, study):
    return schema["properties"][study]["allOf"][1]["properties"]["parameters"]["properties"]


@pytest.mark.parametrize("name", rd.STUDIES)
def test_schema_carries_the_reference_descriptions(name):
    schema = yaml.safe_load(SCHEMA.read_text())
    given = _schema_parameters(schema, name)
    assert set(given) == {p.name for p in studies.get(name).parameters}
    for key, spec in given.items():
        assert spec.get("description") == rd.schema_parameter_description(name, key), key


def _public_modules():
    """Every module of the package that declares ``__all__`` (private ones and the benchmarks
    excepted)."""
    found = {"clutchlab"}
    for info in pkgutil.walk_packages(clutchlab.__path__, "clutchlab."):
        if any(part.startswith("_") for part in info.name.split(".")) or ".bench" in info.name:
            continue
        if hasattr(importlib.import_module(info.name), "__all__"):
            found.add(info.name)
    return found


def test_api_reference_lists_every_public_name(pages):
    assert _public_modules() <= set(rd.PUBLIC_MODULES)
    index = (pages / "api" / "index.rst").read_text()
    for mod_name in rd.PUBLIC_MODULES:
        assert f"   {mod_name}\n" in index
        text = (pages / "api" / f"{mod_name}.rst").read_text()
        for name in importlib.import_module(mod_name).__all__:
            assert re.search(rf"^\.\. auto\w+:: {re.escape(mod_name)}\.{name}$", text, re.M), name


def test_config_reference_lists_every_top_level_and_study_key(pages):
    text = (pages / "reference" / "config.md").read_text()
    schema = yaml.safe_load(SCHEMA.read_text())
    for key in schema["properties"]:
        if key not in rd.STUDIES:
            assert f"`{key}`" in text, key
    for key in schema["$defs"]["study"]["properties"]:
        assert f"`{key}`" in text, key


def test_readme_is_a_short_first_page():
    lines = (ROOT / "README.md").read_text().splitlines()
    assert len(lines) <= 150
    text = "\n".join(lines)
    # the two set-up commands CI runs (.ci/run), exactly
    assert (
        "python3 -m venv .venv && .venv/bin/pip install -e . && .venv/bin/snakemake --cores 2"
        in text
    )
    assert (
        'python3 -m venv .venv && .venv/bin/pip install -e ".[test]" && .venv/bin/python -m pytest'
        in text
    )


def _user_texts(pages):
    files = [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "CONTRIBUTING.md"]
    files += sorted(p for p in DOCS.glob("*.md"))
    files += sorted((pages / "reference").glob("*.md"))
    return files


# the random-number seed (config key `seed`, `seed: 1`) and file and option names are allowed
_SEED_ALLOWED = re.compile(r"`seed`|\bseed: \d|\bseed\d{3}(_fit|\.yaml)?\b|random-number seed")
_HISTORY = re.compile(r"\bsessions?\b|\bissues? #?\d+|\bwork periods?\b|#\d+\b", re.I)


def test_no_build_history_or_paper_seed_words(pages):
    """User-facing text speaks of the product: no words about how it was built, no issue numbers,
    and "seed" only for the random-number seed (the papers are "the source papers")."""
    found = []
    for path in _user_texts(pages):
        for n, line in enumerate(path.read_text().splitlines(), 1):
            if _HISTORY.search(line):
                found.append(f"{path.name}:{n}: {line.strip()}")
            if re.search(r"\bseed", _SEED_ALLOWED.sub("", line), re.I):
                found.append(f"{path.name}:{n}: {line.strip()}")
    assert not found, "\n".join(found)


def test_the_word_check_catches_what_it_should():
    assert _HISTORY.search("as measured in an earlier session")
    assert _HISTORY.search("the heat outputs of issue 20")
    assert re.search(r"\bseed", _SEED_ALLOWED.sub("", "the seed design of seed 000"))
    assert not re.search(r"\bseed", _SEED_ALLOWED.sub("", "take a `seed`; `seed002_fit`"))


def _slug(heading: str) -> str:
    """The anchor of a Markdown heading (GitHub's and MyST's rule: lower case, punctuation
    dropped, spaces to hyphens)."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(path: Path) -> set[str]:
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
    return {_slug(m.group(1)) for m in re.finditer(r"^#{1,6} (.+)$", text, re.M)}


_LINK = re.compile(r"\]\(([^)\s]+)\)")


def _links(path: Path):
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
    for target in _LINK.findall(text):
        if not re.match(r"[a-z]+:", target):
            yield target


@pytest.mark.parametrize(
    "page", ["README.md", "CONTRIBUTING.md"] + [f"docs/{p.name}" for p in DOCS.glob("*.md")]
)
def test_every_internal_link_resolves(page, pages):
    """Every relative link of the README and the docs pages names a file that exists, and its
    anchor a heading of that file (the reference pages: as generated)."""
    src = ROOT / page
    bad = []
    for target in _links(src):
        file, _, anchor = target.partition("#")
        dest = (src.parent / file) if file else src
        if not dest.exists():
            rel = dest.resolve().relative_to(ROOT)
            if rel.parts[:2] in (("docs", "reference"), ("docs", "api")):
                dest = pages / Path(*rel.parts[1:])
        if not dest.exists():
            bad.append(target)
        elif anchor and dest.suffix == ".md" and anchor not in _anchors(dest):
            bad.append(target)
    assert not bad, bad


def test_link_check_catches_a_broken_anchor(tmp_path):
    page = tmp_path / "a.md"
    page.write_text("# Title\n\n## Units and kinds\n\n[x](#units-and-kinds) [y](#units)\n")
    anchors = _anchors(page)
    assert [t for t in _links(page) if t.lstrip("#") not in anchors] == ["#units"]


def test_the_version_has_a_changelog_entry():
    """The version is set once, in pyproject.toml (read at run time from the installed metadata);
    each version has its entry in CHANGELOG.md."""
    import tomllib

    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    changelog = (ROOT / "CHANGELOG.md").read_text()
    assert re.search(rf"^## {re.escape(version)} \(\d{{4}}-\d\d-\d\d\)$", changelog, re.M)
    assert not re.search(
        r"__version__\s*=\s*[\"']\d+\.\d+", (ROOT / "src/clutchlab/__init__.py").read_text()
    )


def test_every_config_key_has_a_meaning():
    """Every key of the config file reference (top level, report, a study section) carries a
    description in the schema, which editors show."""
    schema = yaml.safe_load(SCHEMA.read_text())
    rows = rd._schema_rows(schema["properties"]) + rd._schema_rows(
        schema["$defs"]["study"]["properties"]
    )
    assert [r["key"] for r in rows if not r["meaning"].strip()] == []

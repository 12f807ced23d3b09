"""`snakemake --lint` of the workflow (the Snakefile and workflows/rules/*.smk), failing on every
lint but one: ``python workflows/lint.py [snakemake options]`` (CI and the pre-commit hook run it).

The one lint let through asks each rule for a conda environment or a container. clutchlab's
software is the pip package in the venv that runs Snakemake (pyproject.toml), and every job runs
in that same environment; no conda channel or container image is part of the supported set-up, so
a declared one would be an untested promise.
"""

import re
import subprocess
import sys

ALLOWED = ("Specify a conda environment or container for each rule.",)
_ITEM = re.compile(r"^Lints for (.+):$")
_LINT = re.compile(r"^    \* (.+?):?$")


def lints(text: str) -> list[tuple[str, str]]:
    """(rule or snakefile, lint title) of each lint in ``snakemake --lint``'s text output."""
    found, item = [], None
    for line in text.splitlines():
        if m := _ITEM.match(line):
            item = m.group(1)
        elif item and (m := _LINT.match(line)):
            found.append((item, m.group(1).rstrip(":")))
    return found


def main(argv=None) -> int:
    args = sys.argv[1:] if argv is None else argv
    run = subprocess.run(
        [sys.executable, "-m", "snakemake", "--lint", *args],
        capture_output=True,
        text=True,
        check=False,
    )
    text = run.stdout + run.stderr
    found = lints(text)
    if run.returncode and not found:  # not a lint: the workflow did not parse
        print(text, file=sys.stderr)
        return run.returncode
    bad = [(item, title) for item, title in found if title not in ALLOWED]
    for item, title in bad:
        print(f"{item}: {title}", file=sys.stderr)
    allowed = len(found) - len(bad)
    print(f"snakemake --lint: {len(bad)} lints ({allowed} conda/container lints let through)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

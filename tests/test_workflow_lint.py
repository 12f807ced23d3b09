"""The workflow's lint check (workflows/lint.py) and the job scripts' log (clutchlab._joblog)."""

import importlib.util
import sys
from pathlib import Path

import pytest

from clutchlab._joblog import job_log

ROOT = Path(__file__).resolve().parents[1]


def _lint_module():
    spec = importlib.util.spec_from_file_location("workflow_lint", ROOT / "workflows" / "lint.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


SAMPLE = """Using workflow specific profile profiles/default for setting default command line arguments.
Lints for rule design (line 4, /x/workflows/rules/study.smk):
    * No log directive defined:
      Without a log directive, all output will be printed to the terminal.
    * Specify a conda environment or container for each rule.:
      This way, the used software for each specific step is documented.

Lints for rule numerics (line 108, /x/workflows/rules/report.smk):
    * Shell command directly uses variable RESULTS from outside of the rule:
      It is recommended to pass all files as input and output.
"""


def test_lint_output_is_read_rule_by_rule():
    found = _lint_module().lints(SAMPLE)
    assert found == [
        ("rule design (line 4, /x/workflows/rules/study.smk)", "No log directive defined"),
        (
            "rule design (line 4, /x/workflows/rules/study.smk)",
            "Specify a conda environment or container for each rule.",
        ),
        (
            "rule numerics (line 108, /x/workflows/rules/report.smk)",
            "Shell command directly uses variable RESULTS from outside of the rule",
        ),
    ]
    allowed = _lint_module().ALLOWED
    assert [t for _, t in found if t not in allowed] == [
        "No log directive defined",
        "Shell command directly uses variable RESULTS from outside of the rule",
    ]


def test_a_job_log_holds_what_the_job_printed_and_why_it_stopped(tmp_path, capsys):
    log = tmp_path / "job.log"
    with pytest.raises(SystemExit), job_log(log):
        print("scenarios done")
        print("progress", file=sys.stderr)
        raise SystemExit("clutchlab: a chunk failed")
    text = log.read_text()
    assert "scenarios done" in text and "progress" in text
    assert "clutchlab: a chunk failed" in text
    shown = capsys.readouterr()
    assert "scenarios done" in shown.out and "progress" in shown.err  # the terminal too
    assert sys.stdout is not None and "job.log" not in repr(sys.stdout)


def test_a_job_log_holds_the_traceback_of_an_error(tmp_path):
    log = tmp_path / "job.log"
    with pytest.raises(ZeroDivisionError), job_log(log):
        1 / 0  # noqa: B018
    assert "ZeroDivisionError" in log.read_text()

"""The suite's own set-up: the tests that share the session's small Snakemake run stay on one
pytest-xdist worker (tests/conftest.py; `--dist loadgroup` in pyproject.toml)."""

import pytest


def test_the_small_run_tests_are_one_group(request):
    """Each of them carries xdist's group suffix: else every worker makes the small run (minutes
    each) and tests that rerun Snakemake in its folder run at the same time. (With pytest 9.2 the
    suffix silently stopped taking, pytest-dev/pytest-xdist#1386; and a conftest hook that marks
    the tests after xdist's has read the marks is too late.)"""
    if not getattr(request.config.option, "loadgroup", False):
        pytest.skip("not on a pytest-xdist worker with --dist loadgroup")
    users = [i for i in request.session.items if "small_run" in getattr(i, "fixturenames", ())]
    if not users:
        pytest.skip("no test of this session uses the small run")
    assert all(i.nodeid.endswith("@small_run") for i in users), [
        i.nodeid for i in users if not i.nodeid.endswith("@small_run")
    ][:5]

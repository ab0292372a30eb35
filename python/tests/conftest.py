"""Shared fixtures: where the sources, the command line and the example robots are.

ctest sets KINCAL_SOURCE_DIR and KINCAL_CLI; run by hand from the source tree,
`PYTHONPATH=build/python /usr/bin/python3 -m pytest python/tests` finds them in ./build.
"""
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("KINCAL_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CLI = pathlib.Path(os.environ.get("KINCAL_CLI", SOURCE_DIR / "build" / "apps" / "kincal"))
ROBOTS = SOURCE_DIR / "examples" / "robots"


def skip_without_data(message):
    """A real-data test's skip: a failure instead under KINCAL_REQUIRE_DATA=1 (scripts/test sets it when
    ../shared/data exists), so that a moved data folder cannot pass as a skip."""
    if os.environ.get("KINCAL_REQUIRE_DATA") == "1":
        pytest.fail(f"KINCAL_REQUIRE_DATA=1, but {message}")
    pytest.skip(message)


@pytest.fixture
def robots():
    return ROBOTS


@pytest.fixture
def cli():
    if not CLI.exists():
        pytest.skip(f"no command line at {CLI} (build the kincal_cli target)")
    return CLI

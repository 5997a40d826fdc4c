# SPDX-License-Identifier: MIT
"""Fixtures of the pce Python tests: the repository's scenes and the C++ tools the results
are compared with (pce-probe, pce-sim), found through $PCE_PROBE / $PCE_SIM or in the
usual build directories. Where a tool is missing the tests that need it are skipped, except
when $PCE_PROBE / $PCE_SIM name it or under CI (CI set), where that is a failure: .ci/run
builds both and names them."""

import os
import pathlib
import shutil

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def _tool(env: str, relative: str):
    given = os.environ.get(env)
    if given:
        return pathlib.Path(given)
    for build in ("build-ci", "build"):
        candidate = REPO / build / relative
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return candidate
    found = shutil.which(pathlib.Path(relative).name)
    return pathlib.Path(found) if found else None


def _require(env: str, relative: str):
    path = _tool(env, relative)
    if os.environ.get(env) and not path.is_file():
        pytest.fail(f"${env} = {path} is not a file")
    if path is None or not path.is_file():
        message = f"{pathlib.Path(relative).name} not found (set ${env} or build it into build/)"
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)
    return path


@pytest.fixture(scope="session")
def probe():
    return _require("PCE_PROBE", "src/pce-probe")


@pytest.fixture(scope="session")
def pce_sim():
    return _require("PCE_SIM", "src/sim/pce-sim")


@pytest.fixture(scope="session")
def scenes():
    return REPO / "examples" / "scenes"


@pytest.fixture(scope="session")
def pce_bench():
    return _require("PCE_BENCH", "benchmarks/pce-bench")

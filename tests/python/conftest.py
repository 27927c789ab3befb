# Shared fixtures of the facet Python tests: where the CLI and the scenes are (CTest sets
# FACET_CLI and FACET_SCENES_DIR; run by hand they default to the Release build tree).
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def scenes_dir():
    return pathlib.Path(os.environ.get("FACET_SCENES_DIR", ROOT / "scenes"))


@pytest.fixture(scope="session")
def facet_cli():
    return pathlib.Path(os.environ.get("FACET_CLI", ROOT / "build" / "core" / "cli" / "facet"))

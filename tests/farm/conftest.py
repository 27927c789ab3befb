# Shared fixtures of the facet-farm tests: the CLI, facet-farm, small scene files derived from
# the shipped Cornell box, reference images from `facet render`, and loopback clusters.
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import facet
import facet.farm as farm

ROOT = pathlib.Path(__file__).resolve().parents[2]
CLI = pathlib.Path(os.environ.get("FACET_CLI", ROOT / "build" / "core" / "cli" / "facet"))
FARM = pathlib.Path(os.environ.get("FACET_FARM", ROOT / "build" / "core" / "python" / "facet-farm"))
SCENES = pathlib.Path(os.environ.get("FACET_SCENES_DIR", ROOT / "scenes"))


def write_scene(path, width, height, spp, seed=1, camera_dx=0.0, edit=None):
    """The Cornell box at width x height, spp, seed; camera moved by camera_dx (animations)."""
    d = json.loads((SCENES / "cornell_box.json").read_text())
    d["camera"]["width"], d["camera"]["height"] = width, height
    d["camera"]["position"][0] += camera_dx
    d["render"]["spp"], d["render"]["seed"] = spp, seed
    if edit:
        edit(d)
    pathlib.Path(path).write_text(json.dumps(d, indent=1))
    return pathlib.Path(path)


def cli_render(scene, out, *extra):
    """`facet render scene -o out` (the reference) and its image."""
    subprocess.run([str(CLI), "render", str(scene), "-o", str(out), *extra], check=True,
                   capture_output=True)
    return facet.read_image(str(out))


def farm_cmd(*args):
    return [sys.executable, str(FARM), *map(str, args)]


def session_processes(sid):
    """Pids of live processes in session `sid` (a command started with start_new_session)."""
    pids = []
    for stat in pathlib.Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        # fields: state ppid pgrp session ...; zombies are reaped by nobody we own: skip them.
        if int(fields[3]) == sid and fields[0] != "Z":
            pids.append(int(stat.parent.name))
    return pids


@pytest.fixture(scope="session", autouse=True)
def quiet():
    farm.quiet_logs()


def assert_same(a, b):
    assert a.shape == b.shape
    np.testing.assert_array_equal(a, b)

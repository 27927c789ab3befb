# The package installs: `cmake --install` puts facet/ (extension + pure-Python files) into
# <prefix>/lib/python3/dist-packages, and /usr/bin/python3 imports and renders from there.
import os
import pathlib
import subprocess
import sys

import pytest

import tiny_scenes as ts

BUILD = os.environ.get("FACET_BUILD_DIR")


@pytest.mark.skipif(not BUILD, reason="FACET_BUILD_DIR not set (CTest sets it)")
def test_installed_package_imports_and_renders(tmp_path):
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", BUILD, "--prefix", str(prefix)], check=True,
                   stdout=subprocess.DEVNULL)
    site = prefix / "lib" / "python3" / "dist-packages"
    assert (site / "facet" / "__init__.py").is_file()
    (tmp_path / "scene.json").write_text(ts.scene_json(2))
    code = ("import facet, sys; assert facet.__file__.startswith(sys.argv[1]), facet.__file__; "
            "img = facet.render(facet.load_scene('scene.json')); print(img.shape)")
    env = dict(os.environ, PYTHONPATH=str(site))
    out = subprocess.run(["/usr/bin/python3", "-c", code, str(site)], cwd=tmp_path, env=env,
                         check=True, capture_output=True, text=True).stdout
    assert out.strip() == f"({ts.HEIGHT}, {ts.WIDTH}, 3)"

"""shatterpy.scenes: a scene dict written as TOML, checked and run by `shatter`; and the package
installed by pip from python/pyproject.toml."""

import os
import shutil
import subprocess
import sys
import tomllib

import pytest

import shatterpy as sp
import shatterpy.scenes as ss
from conftest import ROOT, TINY, shatter_binary


def test_to_toml_reads_back_as_the_same_dict():
    scene = ss.load(TINY)
    scene["solver"]["contact_pair"] = [{"a": "target", "b": "projectile", "friction": 0.1}]
    scene["note"] = 'quotes " and \\ and unicode é'
    scene["output"]["columns"] = ["x", "y", "damage"]
    scene["impact"]["speed"] = 0.1 + 0.2  # a double that needs 17 digits
    assert tomllib.loads(ss.to_toml(scene)) == scene


def test_to_toml_refuses_what_toml_cannot_hold():
    with pytest.raises(ValueError, match="solver.end_time"):
        ss.to_toml({"solver": {"end_time": float("nan")}})
    with pytest.raises(TypeError):
        ss.to_toml({"a": object()})


def test_check_accepts_the_scene_and_names_a_bad_key(tmp_path):
    scene = ss.load(TINY)
    assert "run time" in ss.check(scene, binary=shatter_binary(), base_dir=tmp_path)
    scene["impact"]["speeed"] = 1.0
    with pytest.raises(ss.SceneError, match="speeed"):
        ss.check(scene, binary=shatter_binary(), base_dir=tmp_path)
    assert list(tmp_path.iterdir()) == []  # the temporary scene file is removed


def test_run_writes_the_scene_and_runs_it(tmp_path):
    scene = ss.load(TINY)
    scene["impact"]["speed"] = 2500.0
    out = ss.run(scene, tmp_path / "fast", binary=shatter_binary())
    assert os.path.exists(os.path.join(out, "timeseries.csv"))
    assert sp.scene(out)["impact"]["speed"] == 2500.0
    assert (tmp_path / "fast.toml").exists()
    with pytest.raises(ss.SceneError):  # the run directory holds a run: refused, message kept
        ss.run(scene, tmp_path / "fast", binary=shatter_binary())


def test_pip_installs_the_package_from_the_checkout(tmp_path):
    # Offline: Debian's setuptools and wheel (--no-build-isolation) in a venv that sees the system
    # site-packages (numpy, h5py). The installed copy, not the checkout, must be imported.
    # From a copy: setuptools builds in the source tree (build/, *.egg-info).
    src = tmp_path / "src"
    shutil.copytree(os.path.join(ROOT, "python"), src,
                    ignore=shutil.ignore_patterns("tests", "build", "*.egg-info", "__pycache__"))
    env_dir = tmp_path / "env"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(env_dir)],
                   check=True)
    pip = subprocess.run([str(env_dir / "bin" / "pip"), "install", "--no-build-isolation",
                          "--no-index", "--no-deps", "-q", str(src)],
                         capture_output=True, text=True, cwd=tmp_path)
    assert pip.returncode == 0, pip.stdout + pip.stderr
    r = subprocess.run([str(env_dir / "bin" / "python"), "-c",
                        "import shatterpy, shatterpy.scenes; print(shatterpy.__file__)"],
                       capture_output=True, text=True, cwd=tmp_path, check=True)
    assert str(env_dir) in r.stdout, r.stdout


def test_the_example_script_runs(tmp_path):
    env = dict(os.environ, SHATTER_BINARY=shatter_binary(),
               PYTHONPATH=os.path.join(ROOT, "python"))
    r = subprocess.run([sys.executable, os.path.join(ROOT, "python", "examples",
                                                     "sweep_speed.py"), str(tmp_path)],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.count("m/s: failure ratio") == 2, r.stdout

"""Fixtures: a tiny lab impact (tests/fuzz/tiny.toml, 4 400 points, about a second) run once per
session by the `shatter` binary named in $SHATTER_BINARY (ctest sets it; default
build/release/shatter), with its fragment catalogue."""

import os
import subprocess
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
sys.path.insert(0, os.path.join(ROOT, "python"))

TINY = os.path.join(ROOT, "tests", "fuzz", "tiny.toml")


def shatter_binary():
    path = os.environ.get("SHATTER_BINARY", os.path.join(ROOT, "build", "release", "shatter"))
    if not os.access(path, os.X_OK):
        pytest.fail(f"no shatter binary at {path}: build it or set SHATTER_BINARY")
    return path


def run_tiny(out, *sets):
    cmd = [shatter_binary(), "run", TINY, "--out", str(out), "--threads", "1", "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True)
    return out


@pytest.fixture(scope="session")
def run_dir(tmp_path_factory):
    """A finished tiny run (binary64 snapshots) with fragments.ss and fragments_particles.ss."""
    out = run_tiny(tmp_path_factory.mktemp("tiny") / "run")
    last = sorted((out / "snapshots").glob("snapshot_*.h5"))[-1]
    subprocess.run([shatter_binary(), "fragments", str(last), "--prefix", str(out / "again"),
                    "--ss-particles", "--quiet"], check=True)
    return out


@pytest.fixture(scope="session")
def single_run_dir(tmp_path_factory):
    """The same run with output.snapshot_precision = "single"."""
    return run_tiny(tmp_path_factory.mktemp("tiny32") / "run",
                    'output.snapshot_precision="single"')

"""Smoke tests of the user's tools (tools/): every tool answers --help, the shell scripts parse,
and the plot tools draw a tiny run (tests/fuzz/tiny.toml, 4 400 points, about a second, run by the
`shatter` binary named in $SHATTER_BINARY; ctest sets it). The studies (studies/) are not tested
here: they are records of one-off measurements."""

import os
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
TOOLS = os.path.join(ROOT, "tools")
PYTHON = "/usr/bin/python3"
TINY = os.path.join(ROOT, "tests", "fuzz", "tiny.toml")

PY_TOOLS = sorted(f for f in os.listdir(TOOLS) if f.endswith(".py"))
SH_TOOLS = sorted(f for f in os.listdir(TOOLS) if f.endswith(".sh"))


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120, **kw)


@pytest.mark.parametrize("tool", PY_TOOLS)
def test_python_tool_answers_help(tool):
    r = run([PYTHON, os.path.join(TOOLS, tool), "--help"])
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("usage:"), r.stdout[:200]


@pytest.mark.parametrize("tool", SH_TOOLS)
def test_shell_tool_parses_and_answers_help(tool):
    path = os.path.join(TOOLS, tool)
    assert run(["bash", "-n", path]).returncode == 0
    # --help prints the header comment and stops before doing anything (no install, no build).
    r = run(["bash", path, "--help"])
    assert r.returncode == 0, r.stderr
    with open(path) as f:
        second_line = f.read().splitlines()[1]
    assert r.stdout.splitlines()[0] == second_line.lstrip("# ")


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    binary = os.environ.get("SHATTER_BINARY", os.path.join(ROOT, "build", "release", "shatter"))
    if not os.access(binary, os.X_OK):
        pytest.fail(f"no shatter binary at {binary}: build it or set SHATTER_BINARY")
    out = tmp_path_factory.mktemp("tiny") / "run"
    subprocess.run([binary, "run", TINY, "--out", str(out), "--threads", "1", "--quiet"],
                   check=True, timeout=120)
    return out


@pytest.mark.parametrize("tool", ["plot_energy.py", "plot_failure_ratio.py",
                                  "plot_fragments.py", "plot_cross_section.py"])
def test_plot_tool_draws_a_tiny_run(tool, tiny_run, tmp_path):
    png = tmp_path / "figure.png"
    r = run([PYTHON, os.path.join(TOOLS, tool), str(tiny_run), "--out", str(png)])
    assert r.returncode == 0, r.stderr
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_ensemble_stats_summarises_a_table():
    table = "| run | a |\n|---|---|\n| 1 | 1.0 |\n| 2 | 3.0 |\n"
    r = run([PYTHON, os.path.join(TOOLS, "ensemble_stats.py")], input=table)
    assert r.returncode == 0, r.stderr
    # column a: mean 2, sample standard deviation sqrt(2) (two significant digits), range 1-3
    assert "a: n = 2: 2 ± 1.4 (1-3)" in r.stdout.splitlines(), r.stdout

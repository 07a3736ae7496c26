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


def png_height(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return int.from_bytes(head[20:24], "big")  # IHDR: width, then height


def test_cross_section_has_a_porosity_panel_for_a_porous_run(tiny_run, tmp_path):
    # The tiny scene with its target made porous (issue 29): the snapshots carry the distension,
    # and the figure gains one row of panels (the porosity) over the dense run's.
    binary = os.environ.get("SHATTER_BINARY", os.path.join(ROOT, "build", "release", "shatter"))
    out = tmp_path / "porous"
    subprocess.run([binary, "run", TINY, "--out", str(out), "--threads", "1", "--quiet", "--set",
                    'body.target.material="porous_basalt"'], check=True, timeout=120)
    dense_png, porous_png = tmp_path / "dense.png", tmp_path / "porous.png"
    tool = os.path.join(TOOLS, "plot_cross_section.py")
    for run_dir, png in ((tiny_run, dense_png), (out, porous_png)):
        r = run([PYTHON, tool, str(run_dir), "--out", str(png)])
        assert r.returncode == 0, r.stderr
    # rows of 3.1 inches at 120 dpi: one more row is 372 pixels more
    assert abs(png_height(porous_png) - png_height(dense_png) - 3.1 * 120) <= 1


def test_ensemble_stats_summarises_a_table():
    table = "| run | a |\n|---|---|\n| 1 | 1.0 |\n| 2 | 3.0 |\n"
    r = run([PYTHON, os.path.join(TOOLS, "ensemble_stats.py")], input=table)
    assert r.returncode == 0, r.stderr
    # column a: mean 2, sample standard deviation sqrt(2) (two significant digits), range 1-3
    assert "a: n = 2: 2 ± 1.4 (1-3)" in r.stdout.splitlines(), r.stdout


def non_background_pixels(png):
    """Pixels that differ from render.py's white background by more than 2/255 in any channel
    (antialiasing and PNG round-off stay under that on the background itself)."""
    import matplotlib.image
    import numpy as np
    rgb = matplotlib.image.imread(str(png))[:, :, :3]
    return int(np.count_nonzero(np.any(np.abs(rgb - 1.0) > 2.0 / 255.0, axis=2))), rgb.shape


def test_render_draws_the_particles_headless(tiny_run, tmp_path):
    # No display: the tool runs itself under xvfb-run (ParaView renders through X).
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = run([PYTHON, os.path.join(TOOLS, "render.py"), str(tiny_run), "--out", str(tmp_path),
             "--fields", "damage,speed,peak_pressure", "--size", "320x240", "--animate"],
            env=env)
    assert r.returncode == 0, r.stderr[-2000:]
    snapshots = len(list((tiny_run / "snapshots").glob("snapshot_*.h5")))
    for field in ("damage", "speed", "peak_pressure"):
        for view in ("3d", "slice"):
            n, shape = non_background_pixels(tmp_path / f"{field}_{view}.png")
            assert shape[:2] == (240, 320)
            # The particles at 3 px each plus the colour bar: measured 13 100-13 300 (3-D) and
            # 7 900-8 200 (slab) at this size; a blank view (no cells, as before vertex cells)
            # has only the colour bar and its labels, about 1 900. The floor of 5 000 tells
            # them apart.
            assert n > 5000, (field, view, n)
        frames = sorted(tmp_path.glob(f"{field}_3d_[0-9]*.png"))
        assert len(frames) == snapshots


def test_render_refuses_a_folder_without_a_run(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = run([PYTHON, os.path.join(TOOLS, "render.py"), str(tmp_path)], env=env)
    assert r.returncode != 0
    assert "particles.xmf" in r.stderr and "not found" in r.stderr


def rock_scene(tmp_path):
    """tests/fuzz/tiny.toml with its target renamed "rock": a scene the lab-impact figures do not
    fit (no body named "target"), as a user's own asteroid scene."""
    with open(TINY) as f:
        text = f.read()
    scene = tmp_path / "rock.toml"
    scene.write_text(text.replace("body.target", "body.rock").replace('target = "target"',
                                                                      'target = "rock"'))
    return scene


def test_study_sweeps_a_grid_over_seeds_and_resumes(tmp_path):
    import csv
    binary = os.environ.get("SHATTER_BINARY", os.path.join(ROOT, "build", "release", "shatter"))
    out = tmp_path / "study"
    cmd = [PYTHON, os.path.join(TOOLS, "study.py"), str(rock_scene(tmp_path)), "--out-dir",
           str(out), "--seeds", "2", "--grid", "impact.speed=2000,3200", "-j", "2",
           "--times", "5e-7", "--lab", "--shatter", binary]
    r = run(cmd)
    assert r.returncode == 0, r.stdout + r.stderr
    with open(out / "study.csv") as f:
        rows = list(csv.DictReader(f))
    assert sorted((row["point"], row["seed"]) for row in rows) == [
        ("impact.speed=2000", "1"), ("impact.speed=2000", "2"),
        ("impact.speed=3200", "1"), ("impact.speed=3200", "2")]
    for row in rows:
        assert 0.0 <= float(row["failure_end"]) <= 1.0
        assert 0.0 <= float(row["failure_at_5e-07s"]) <= float(row["failure_end"])
        assert 0.0 < float(row["largest_fraction"]) <= 1.0
    # Faster impact, more failure by the end (same seeds): the grid value reached the runs.
    fail = {(row["point"], row["seed"]): float(row["failure_end"]) for row in rows}
    for seed in ("1", "2"):
        assert fail[("impact.speed=3200", seed)] > fail[("impact.speed=2000", seed)]
    assert "lab-impact figures skipped" in r.stderr
    md = (out / "study.md").read_text()
    assert "| impact.speed=2000 | 2 |" in md and "| impact.speed=3200 | 2 |" in md
    # Restartable: a second call runs nothing again.
    r = run(cmd)
    assert r.returncode == 0, r.stderr
    assert r.stdout.count("finished before") == 4, r.stdout


def test_ensemble_summarises_a_scene_without_a_target(tmp_path):
    binary = os.environ.get("SHATTER_BINARY", os.path.join(ROOT, "build", "release", "shatter"))
    ens = tmp_path / "ens"
    r = run([PYTHON, os.path.join(TOOLS, "ensemble.py"), str(rock_scene(tmp_path)), "--out-dir",
             str(ens), "--seeds", "2", "--shatter", binary, "--nice", "0"])
    assert r.returncode == 0, r.stdout + r.stderr  # was KeyError: 'centre'
    assert "lab-impact figures (shells, core, offset) are NaN" in r.stderr
    assert (ens / "ensemble.md").stat().st_size > 0


def _qstar():
    import importlib.util
    spec = importlib.util.spec_from_file_location("qstar", os.path.join(TOOLS, "qstar.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_qstar_fit_minimum_and_search(tmp_path):
    """tools/qstar.py: BA99's 3 km/s fit has its minimum, 127 J/kg, at R = 117 m (to the 1%
    of a 1 m grid of radii); the bracket and bisection, on a stand-in trial with f = 1/2 at
    Q = 1000 J/kg, end with a bracket that holds 1000 and is narrower than 1 + tolerance."""
    q = _qstar()
    radii = [50.0 + k for k in range(200)]
    fits = [q.ba99_qstar(r, 3.0) for r in radii]
    k = fits.index(min(fits))
    assert abs(radii[k] - 117.0) <= 1.0 and abs(fits[k] - 127.2) < 0.5
    calls = []

    def stand_in(o, qq):
        calls.append(qq)
        return {"q": qq, "q_actual": qq, "fraction": 1.0 / (1.0 + (qq / 1000.0) ** 2), "cpu_s": 0.0}

    q.trial = stand_in
    import argparse
    o = argparse.Namespace(q_guess=300.0, step=4.0, max_bracket=8, tolerance=0.2, jobs=1,
                           radius=1.0, speed=3.0, work=str(tmp_path))
    cache = {}
    lo, hi = q.bisect(o, cache, *q.bracket(o, cache))
    assert lo <= 1000.0 <= hi and hi / lo < 1.2
    before = len(calls)
    assert q.bisect(o, cache, *q.bracket(o, cache)) == (lo, hi)  # a rerun reads its cache
    assert len(calls) == before

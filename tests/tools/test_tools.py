"""Smoke tests of the user's tools (tools/): every tool answers --help, the shell scripts parse,
and the plot tools draw a tiny run (tests/fuzz/tiny.toml, 4 400 points, about a second, run by the
`shatter` binary named in $SHATTER_BINARY; ctest sets it). The studies (studies/) are not tested
here: they are records of one-off measurements."""

import csv
import math
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


def write_beta_run(run, betas, launches, m_imp=2.0, speed=100.0):
    """A run folder as a [beta] scene leaves it: timeseries.csv with the beta columns and
    ejecta_launch.csv in the writer's format (src/fracture/ejecta_launch.cpp), fastest first."""
    run.mkdir()
    with open(run / "timeseries.csv", "w") as f:
        f.write("step,time_s,ejecta_mass_kg,ejecta_momentum_kg_m_per_s,"
                "impactor_momentum_kg_m_per_s,beta,beta_target,beta_launch,wall_s\n")
        for i, b in enumerate(betas):
            f.write(f"{i},{i * 1e-3},{i},{(b - 1) * m_imp * speed},{m_imp * speed},{b},{b},"
                    f"{b - 0.05},0\n")
    with open(run / "ejecta_launch.csv", "w") as f:
        f.write(f"# impactor_mass_kg={m_imp} impact_speed_m_per_s={speed}\n")
        f.write("id,launch_time_s,mass_kg,speed_m_per_s,normal_speed_m_per_s,back_speed_m_per_s,"
                "launch_radius_m,launch_height_m,cumulative_mass_kg\n")
        cumulative = 0.0
        for i, (v, m) in enumerate(sorted(launches, reverse=True)):
            cumulative += m
            f.write(f"{i},0.001,{m},{v},{v},{v},0.1,0.01,{cumulative}\n")


def test_beta_reports_the_drift_and_the_cumulative_ejecta_mass(tmp_path):
    run = tmp_path / "run"
    # beta = 1.0, 1.1, ..., 1.9: the last fifth (rows 8 and 9) moves by +0.1.
    write_beta_run(run, [1.0 + 0.1 * i for i in range(10)],
                   [(50.0, 1.0), (20.0, 1.0), (10.0, 2.0), (5.0, 4.0)])
    table = tmp_path / "mv.csv"
    r = run_tool_beta(run, "--csv", str(table))
    assert r.returncode == 0, r.stderr
    assert "beta: 1.9000 at the end; changed by +0.1000 over the last fifth" in r.stdout, r.stdout
    rows = [list(map(float, line.split(","))) for line in table.read_text().splitlines()[1:]]
    # From the fastest launch (50 m/s, M(>v) = 1 kg of m_imp = 2 kg) to the slowest (5 m/s, all
    # 8 kg), speeds as fractions of U = 100 m/s.
    assert rows[0][0] == pytest.approx(0.5) and rows[0][1] == pytest.approx(0.5)
    assert rows[-1][0] == pytest.approx(0.05) and rows[-1][1] == pytest.approx(4.0)
    # M(>v) never decreases towards slower speeds, and every mass is a partial sum of the launches.
    assert all(b[1] >= a[1] for a, b in zip(rows, rows[1:]))
    assert {row[1] for row in rows} <= {0.5, 1.0, 2.0, 4.0}
    # The Housen & Holsapple 2011 column, written out from the formula with the tool's defaults
    # (mu 0.41, nu 0.4, k 0.3, C1 0.55, rho 2400, delta 2703): the tool's to 6 digits.
    x = rows[0][0]
    hh = 3 * 0.3 / (4 * math.pi) * (2400 / 2703) ** (1 - 3 * 0.4) * (x / 0.55) ** (-3 * 0.41)
    assert rows[0][2] == pytest.approx(hh, rel=1e-5)


def test_beta_escape_speed_leaves_out_slow_launches(tmp_path):
    run = tmp_path / "run"
    write_beta_run(run, [1.0, 1.2], [(50.0, 1.0), (20.0, 1.0), (10.0, 2.0), (5.0, 4.0)])
    table = tmp_path / "mv.csv"
    r = run_tool_beta(run, "--csv", str(table), "--escape-speed", "15")
    assert r.returncode == 0, r.stderr
    rows = [list(map(float, line.split(","))) for line in table.read_text().splitlines()[1:]]
    assert rows[-1][0] == pytest.approx(0.2) and rows[-1][1] == pytest.approx(1.0)


def test_beta_fits_the_power_law_exponent_over_the_range_asked(tmp_path):
    run = tmp_path / "run"
    # M(>=v)/m = 0.1 (v/U)^(-1.2), i.e. mu = 0.4, at v = 80, 40, ..., 0.625 m/s (U = 100 m/s,
    # m_imp = 2 kg); one slow launch at 0.1 m/s (v/U = 0.001) far off the law (+50 kg).
    speeds = [80.0 * 0.5**i for i in range(8)]
    cumulative = [2.0 * 0.1 * (v / 100.0) ** -1.2 for v in speeds]
    masses = [cumulative[0]] + [b - a for a, b in zip(cumulative, cumulative[1:])]
    write_beta_run(run, [1.0, 1.2], list(zip(speeds, masses)) + [(0.1, 50.0)])
    r = run_tool_beta(run, "--fit", "0.005", "1")
    assert r.returncode == 0, r.stderr
    assert "(8 points): mu_fit 0.4000" in r.stdout, r.stdout
    assert "(M(>v)/m = 0.1 (v/U)^-1.2000)" in r.stdout, r.stdout
    # The range decides: with the off-law launch inside it the fit is not 0.4.
    r = run_tool_beta(run, "--fit", "0.0005", "1")
    assert "(9 points): mu_fit 0.4000" not in r.stdout, r.stdout


def test_beta_refuses_a_run_without_beta_columns(tiny_run):
    r = run_tool_beta(tiny_run)
    assert r.returncode != 0
    assert "has no beta columns" in r.stderr, r.stderr


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")  # IHDR


def test_plot_common_saves_at_its_dpi_and_beta_plots_with_it(tmp_path):
    # tools/plot_common.py's demo is 4 x 3 inches, beta.py's figure 10 x 4 inches: both saved at
    # plot_common.DPI (read from the module, so a changed DPI moves both and the test with them).
    import importlib.util
    spec = importlib.util.spec_from_file_location("plot_common",
                                                  os.path.join(TOOLS, "plot_common.py"))
    pc = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(pc)
    demo = tmp_path / "demo.png"
    r = run([PYTHON, os.path.join(TOOLS, "plot_common.py"), "--demo", str(demo)])
    assert r.returncode == 0, r.stderr
    assert png_size(demo) == (4 * pc.DPI, 3 * pc.DPI)
    beta_run, png = tmp_path / "run", tmp_path / "beta.png"
    write_beta_run(beta_run, [1.0, 1.1, 1.2], [(50.0, 1.0), (20.0, 1.0), (10.0, 2.0)])
    r = run_tool_beta(beta_run, "--plot", str(png))
    assert r.returncode == 0, r.stderr
    assert png_size(png) == (10 * pc.DPI, 4 * pc.DPI)


def run_tool_beta(run_dir, *args):
    return run([PYTHON, os.path.join(TOOLS, "beta.py"), str(run_dir), *args])


def test_qstar_bracket_from_either_side(tmp_path):
    """tools/qstar.py, one trial at a time: from a guess 3x above or below Q*_D (f = 1/2 at
    1000 J/kg), the bracket costs the guess plus one trial per factor of --step crossed (no trial
    on the far side of the guess), and the parallel path (--jobs 2) ends in a bracket holding
    1000 as well."""
    q = _qstar()
    import argparse
    for guess, jobs in ((3000.0, 1), (333.0, 1), (3000.0, 2)):
        calls = []

        def stand_in(o, qq):
            calls.append(qq)
            return {"q": qq, "q_actual": qq, "fraction": 1.0 / (1.0 + (qq / 1000.0) ** 2),
                    "cpu_s": 0.0}

        q.trial = stand_in
        o = argparse.Namespace(q_guess=guess, step=2.0, max_bracket=8, tolerance=0.25, jobs=jobs,
                               radius=1.0, speed=3.0, work=str(tmp_path / f"{guess}_{jobs}"))
        (tmp_path / f"{guess}_{jobs}").mkdir()
        cache = {}
        lo, hi = q.bracket(o, cache)
        assert lo <= 1000.0 <= hi and abs(hi / lo - 2.0) < 1e-12
        if jobs == 1:
            assert len(calls) == 3  # the guess and two halvings (or doublings)
        lo, hi = q.bisect(o, cache, lo, hi)
        assert lo <= 1000.0 <= hi and hi / lo < 1.25


def test_qstar_scene_and_csv_columns(tmp_path):
    """tools/qstar.py: the trial scene carries the flaw seed and the points per cell (the cell
    is that many point spacings, points_per_radius spacings to the target radius), and a CSV
    written before the seed, points_per_cell and options columns existed is upgraded once with
    the values its runs used (seed 1, 2 points per cell, no overrides, the engine's default
    flaws) before a row is added. --flaws benz_asphaug gives both bodies BA95's explicit flaws
    (explicit_flaws = 1, no total_flaws); --flaws resolution_independent the engine's own draw."""
    import argparse
    import csv as csvmod
    q = _qstar()
    o = argparse.Namespace(speed=3.0, radius=2.0, points_per_radius=8.0, points_per_cell=1,
                           crossings=5.0, sound_speed=4595.0, method="mpm", mesh=32, seed=7,
                           material="basalt_ba99", weibull_m=9.0, weibull_k=4e35, angle=45.0,
                           flaws="resolution_independent")
    text = q.scene_text(o, 1000.0, tmp_path / "out")
    assert "[fracture]\nseed = 7\n" in text and "points_per_cell = 1\n" in text
    assert "cell_size = 0.25\n" in text  # 1 point per cell, 8 spacings per 2 m radius
    assert text.count("total_flaws = 1e+10\n") == 2 and "explicit_flaws" not in text
    o.flaws = "benz_asphaug"
    text = q.scene_text(o, 1000.0, tmp_path / "out")
    assert text.count("weibull_k = 4e+35\nexplicit_flaws = 1\n") == 2
    assert "total_flaws" not in text
    old = tmp_path / "old.csv"
    legacy = q.COLUMNS[:q.COLUMNS.index("seed")]
    old.write_text(",".join(legacy) + "\n" + ",".join("1" for _ in legacy) + "\n")
    row = {c: "2" for c in q.COLUMNS}
    q.append_row(argparse.Namespace(csv=str(old)), row)
    rows = list(csvmod.DictReader(old.open()))
    assert list(rows[0].keys()) == q.COLUMNS and len(rows) == 2
    assert (rows[0]["seed"], rows[0]["points_per_cell"], rows[0]["options"],
            rows[0]["flaws"]) == ("1", "2", "", "resolution_independent")
    assert rows[1]["seed"] == "2"


def test_qstar_plot_draws_curves_and_variants(tmp_path):
    """tools/qstar.py --plot-only: a CSV with a curve (three sizes), a variant row (another
    flaw seed), a curve with BA95's flaws and a row in the older column set (no seed column)
    draws a non-empty PNG."""
    q = _qstar()
    legacy = q.COLUMNS[:q.COLUMNS.index("seed")]
    path = tmp_path / "q.csv"
    lines = [",".join(q.COLUMNS)]
    for radius, seed, flaws in ((1.0, 1, "resolution_independent"),
                                (100.0, 1, "resolution_independent"),
                                (1000.0, 1, "resolution_independent"),
                                (1000.0, 2, "resolution_independent"), (1.0, 1, "benz_asphaug"),
                                (100.0, 1, "benz_asphaug")):
        row = dict(radius_m=radius, speed_km_s=3.0, angle_deg=45.0, method="mpm",
                   material="basalt_ba99", qstar_J_per_kg=500.0, runs=5, points_per_target=7208,
                   points_per_radius=12.0, crossings=5.0, q_lo_J_per_kg=450.0,
                   q_hi_J_per_kg=550.0, f_lo=0.55, f_hi=0.45, tolerance=0.25, cpu_s=10,
                   ba99_fit_J_per_kg=555.0, seed=seed, points_per_cell=2, options="",
                   flaws=flaws)
        lines.append(",".join(str(row[c]) for c in q.COLUMNS))
    path.write_text("\n".join(lines) + "\n")
    q.plot(str(path), str(tmp_path / "q.png"))
    assert (tmp_path / "q.png").stat().st_size > 10000
    old = tmp_path / "old.csv"
    old.write_text("\n".join([",".join(legacy)] + [",".join(l.split(",")[:len(legacy)])
                                                   for l in lines[1:]]) + "\n")
    q.plot(str(old), str(tmp_path / "old.png"))
    assert (tmp_path / "old.png").stat().st_size > 10000


def write_crater_run(run, rz, centre_xy=(0.0, 0.0), h=0.1, depth=0.8, radius=1.0, boulders=False):
    """A run folder with a known crater: a lattice half-space (points spaced s = h/2, top at
    z = 0) struck along -z at centre_xy; snapshot 0 the intact target with the impactor above it,
    snapshot 1 the target with a paraboloid cavity z >= -depth (1 - r^2 / radius^2) removed and
    the impactor's points thrown 3 m up (ejecta in flight: not surface). r-z: x is r; 3-D: a
    half model (y >= 0) with the crater's axis at centre_xy. boulders: a third body, 40 points
    deep under the floor 1.5 m off the axis (a boulder field's body), which must not move the
    impact axis."""
    import h5py
    import numpy as np
    s = h / 2.0
    run.mkdir()
    geometry = 'geometry = "axisymmetric"\n' if rz else ""
    (run / "scene.toml").write_text(
        f'[solver]\n{geometry}cell_size = {h}\n'
        '[body.impactor]\nradius = 0.2\nvelocity = [0.0, 0.0, -1000.0]\npoints_per_cell = 2\n'
        '[body.target]\npoints_per_cell = 2\n'
        '[beta]\nimpactor = "impactor"\n')
    zs = -(np.arange(int(1.4 / s)) + 0.5) * s
    if rz:
        xs, ys = (np.arange(int(2.0 / s)) + 0.5) * s, np.zeros(1)
    else:
        xs = centre_xy[0] - 1.6 + (np.arange(int(3.2 / s)) + 0.5) * s
        ys = (np.arange(int(1.6 / s)) + 0.5) * s
    X, Y, Z = (g.ravel() for g in np.meshgrid(xs, ys, zs, indexing="ij"))
    target = np.stack([X, Y, Z], 1)
    r = np.hypot(X - centre_xy[0] * (not rz), Y - centre_xy[1] * (not rz))
    cavity = (r < radius) & (Z > -depth * (1.0 - (r / radius) ** 2))
    # On the axis (3-D: its centre off the symmetry plane y = 0, as a half model's points are).
    impactor = np.array([[centre_xy[0] * (not rz), 0.0 if rz else s / 2, 0.5 + k * s]
                         for k in range(4)])
    (run / "snapshots").mkdir()
    extra = np.zeros((0, 3))
    if boulders:
        extra = np.array([[centre_xy[0] * (not rz) - 1.5 + 0.01 * k, s / 2, -1.35]
                          for k in range(40)])
    names = [b"impactor", b"target"] + ([b"target_boulders"] if boulders else [])
    for i, (pts, imp_z) in enumerate([(target, 0.0), (target[~cavity], 3.0)]):
        imp = impactor + [0.0, 0.0, imp_z]
        with h5py.File(run / "snapshots" / f"snapshot_{i:06d}.h5", "w") as f:
            f.attrs["time"] = 1e-3 * i
            f.attrs["symmetry_axis"] = 1 if rz else 2  # r-z: the axis x = 0; 3-D: the plane y = 0
            f["particles/position"] = np.concatenate([imp, pts, extra])
            f["particles/body"] = np.array([0] * len(imp) + [1] * len(pts) + [2] * len(extra),
                                           dtype=np.int64)
            f["particles/mass"] = np.ones(len(imp) + len(pts) + len(extra))
            f["names/body"] = np.array(names)
            f["names/material"] = np.array([b"al", b"rock"])


@pytest.mark.parametrize("rz,boulders", [(True, False), (False, False), (False, True)])
def test_crater_measures_a_known_paraboloid(tmp_path, rz, boulders):
    """tools/crater.py on a hand-built crater (write_crater_run): depth 0.8 m, diameter 2 m,
    volume pi R^2 d / 2 = 1.2566 m^3 of a paraboloid. Tolerances from the measure's
    discretisation: the profile's top is exact to half a point spacing (s/2 = 0.025 m) in z, so
    the depth to s/2; the diameter to one ring width h = 0.1 m (ring centres against the wall's
    crossing, both sides); the volume to pi R^2 s/2 = 0.079 m^3 (6%; a shift of the whole floor by
    s/2). A wrong weight (2 pi r dr vs dr), unit or surface level misses these by far more."""
    import numpy as np
    run = tmp_path / "run"
    write_crater_run(run, rz, centre_xy=(0.3, 0.0), boulders=boulders)
    r = run_tool_crater(run, "--csv", str(tmp_path / "c.csv"))
    assert r.returncode == 0, r.stderr
    assert "pre-impact surface z = 0 m" in r.stderr, r.stderr
    rows = list(csv.DictReader(open(tmp_path / "c.csv")))
    assert len(rows) == 2
    first, last = ({k: float(v) for k, v in row.items() if k != "run"} for row in rows)
    # Intact surface: depth 0 to rounding, no crater (the impactor is 5 empty cells above).
    assert abs(first["depth_m"]) < 1e-12 and math.isnan(first["diameter_m"])
    assert abs(last["depth_m"] - 0.8) <= 0.025
    assert abs(last["diameter_m"] - 2.0) <= 0.1
    assert abs(last["volume_m3"] - np.pi * 0.4) <= np.pi * 0.025
    assert abs(last["t_aU"] - 1e-3 * 1000.0 / 0.2) < 1e-9
    assert last["depth_a"] == last["depth_m"] / 0.2
    # --surface -0.1: the paraboloid cut 0.1 m lower, depth 0.7, radius R' = sqrt(1 - 0.1 / 0.8),
    # volume pi R'^2 0.7 / 2 (same tolerances).
    only = run_tool_crater(run, "--last", "--surface", "-0.1")
    assert only.returncode == 0, only.stderr
    lowered = [{k: float(v) for k, v in row.items() if k != "run"}
               for row in csv.DictReader(only.stdout.splitlines())]
    r2 = 1.0 - 0.1 / 0.8
    assert len(lowered) == 1 and abs(lowered[0]["depth_m"] - 0.7) <= 0.025
    assert abs(lowered[0]["diameter_m"] - 2.0 * math.sqrt(r2)) <= 0.1
    assert abs(lowered[0]["volume_m3"] - np.pi * r2 * 0.35) <= np.pi * r2 * 0.025


def test_crater_refuses_an_oblique_impact(tmp_path):
    run = tmp_path / "run"
    write_crater_run(run, True)
    scene = (run / "scene.toml").read_text().replace("[0.0, 0.0, -1000.0]", "[500.0, 0.0, -866.0]")
    (run / "scene.toml").write_text(scene)
    r = run_tool_crater(run)
    assert r.returncode != 0 and "head-on craters only" in r.stderr, r.stderr


def run_tool_crater(run_dir, *args):
    return run([PYTHON, os.path.join(TOOLS, "crater.py"), str(run_dir), *args])


def test_study_summary_reports_beta_over_seeds(tmp_path):
    """A study of a [beta] scene: beta, beta_target and beta_launch at the end and at --times,
    mean +- sample standard deviation and range over the seeds (two hand-written runs)."""
    header = "step,time_s,failure_ratio,energy_error,beta,beta_target,beta_launch,wall_s\n"
    for seed, slope in ((1, 10.0), (2, 20.0)):
        run_dir = tmp_path / "base" / f"seed{seed}"
        run_dir.mkdir(parents=True)
        rows = [f"{i},{t},0,0,{1 + slope * t},{1 + slope * t},{1 + 0.5 * slope * t},{t * 100}"
                for i, t in enumerate((0.0, 0.01, 0.02))]
        (run_dir / "timeseries.csv").write_text(header + "\n".join(rows) + "\n")
        (run_dir / "study.done").write_text("hand-written\n")
    r = run([PYTHON, os.path.join(TOOLS, "study.py"), "--summarise", str(tmp_path),
             "--times", "0.01,0.05"])
    assert r.returncode == 0, r.stdout + r.stderr
    with open(tmp_path / "study.csv") as f:
        rows = {int(row["seed"]): row for row in csv.DictReader(f)}
    assert float(rows[1]["beta_end"]) == pytest.approx(1.2)
    assert float(rows[2]["beta_at_0.01s"]) == pytest.approx(1.2)
    assert float(rows[2]["beta_launch_end"]) == pytest.approx(1.2)
    assert math.isnan(float(rows[1]["beta_at_0.05s"]))  # past the end of the run
    md = (tmp_path / "study.md").read_text()
    # beta at the end: 1.2 and 1.4: mean 1.3, sample standard deviation 0.14, range 1.2-1.4
    assert "1.3 ± 0.14 (1.2-1.4)" in md, md

#!/usr/bin/env python3
"""Q*_D for one target size: bracket and bisect the impactor mass until the bound remnant is half
the target (issue 30; docs/validation-qstar.md).

Each trial writes a scene (target sphere in self-gravitating equilibrium, an impactor of the same
material through [impact], BA99's flaws), runs `shatter run`, then `shatter fragments` on the last
snapshot, and reads the bound remnant (PREFIX_bound.json: Benz & Asphaug 1999's iterative energy
criterion). Q = (1/2) m_imp v^2 / M_target (BA99's specific energy). The remnant fraction
f = M_bound / M_target falls with Q; the tool first brackets f = 1/2 (factors of --step from
--q-guess), then narrows the bracket in log Q, --jobs trials at a time (k-section: the trials of
one round run in parallel), until Q_hi / Q_lo < 1 + --tolerance; Q*_D is the geometric mean
(so the relative error is below tolerance / 2). Restartable: every trial's result is kept in
WORK/results.json and a finished trial is never run again.

Appends one row to the CSV (columns radius_m, speed_km_s, angle_deg, method, material,
qstar_J_per_kg, runs, points_per_target) and, with --plot, draws every row of it against BA99's
fitted curves (their Table III, basalt).

The flaws are drawn as Benz & Asphaug's code draws them (BA95 Sec. 4.3: N ln N flaws placed one by
one on random points), the method of BA99 whose curve the tool is compared with; --flaws
resolution_independent keeps the engine's own draw instead, whose weakest flaw per point lies ~3.5x
higher in tension at BA99's k and m and gives a Q*_D 4-7x higher in the strength regime
(docs/validation-qstar.md, session 16).

Example: tools/qstar.py --radius 100 --speed 3 --work /tmp/qstar-100m --csv docs/qstar.csv
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import re
import resource
import subprocess
import sys
import time
from pathlib import Path

COLUMNS = ["radius_m", "speed_km_s", "angle_deg", "method", "material", "qstar_J_per_kg", "runs",
           "points_per_target", "points_per_radius", "crossings", "q_lo_J_per_kg", "q_hi_J_per_kg",
           "f_lo", "f_hi", "tolerance", "cpu_s", "ba99_fit_J_per_kg", "seed", "points_per_cell",
           "options", "flaws"]
# Rows written before a column existed get its value for the scenes those runs used: the default
# flaw seed (fracture.seed = 1), 2 x 2 x 2 points per cell, no --set overrides, the engine's
# default (resolution-independent) flaws.
COLUMN_DEFAULTS = {"seed": "1", "points_per_cell": "2", "options": "",
                   "flaws": "resolution_independent"}
# BA99 Table III (basalt): Q*_D = Q0 (R / 1 cm)^a + B rho (R / 1 cm)^b, Q in erg/g, rho in g/cm^3.
# Not verified against the paper (its table could not be read; docs/validation-qstar.md, "The fit
# constants"): the 3 km/s row matches the one secondary transcription found, the 5 km/s row
# matches one and differs from another (Q0 = 7.0e7, a = -0.38).
BA99_FIT = {3.0: (3.5e7, -0.38, 0.3, 1.36), 5.0: (9.0e7, -0.36, 0.5, 1.36)}


# The other transcription of BA99's 5 km/s basalt row (docs/validation-qstar.md): drawn beside it.
BA99_FIT_5_ALT = (7.0e7, -0.38, 0.5, 1.36)


def ba99_qstar(radius_m, speed_km_s, rho=2.7, consts=None):
    """BA99's fitted Q*_D in J/kg (1 erg/g = 1e-4 J/kg) at radius_m, for their two speeds (or
    for the constants given)."""
    q0, a, b_coef, b = consts or BA99_FIT[speed_km_s]
    r_cm = radius_m * 100.0
    return 1e-4 * (q0 * r_cm ** a + b_coef * rho * r_cm ** b)


def damage_keys(o):
    """Grady-Kipp damage with the Weibull flaws k, m of --weibull-k/-m, drawn by one of the engine's
    two schemes (src/fracture/flaws.cpp): "resolution_independent" (the engine's default, the MPM
    paper's Sec. 3.3 draw: a point's weakest flaw uniform in index on [1, 10^m], so its threshold
    lies within a decade above the body's weakest, whatever the point count; total_flaws = 10^(m+1))
    or "benz_asphaug" (BA95 Sec. 4.3, Eq. 20: flaw j = 1, 2, ... with threshold (j / kV)^(1/m) to a
    random point until N ln N flaws are placed and every point holds one; the draw of Benz &
    Asphaug's SPH code, BA99's method)."""
    keys = f'model = "grady_kipp"\nweibull_m = {o.weibull_m}\nweibull_k = {o.weibull_k:.6g}\n'
    if o.flaws == "benz_asphaug":
        return keys + "explicit_flaws = 1"
    return keys + f"total_flaws = {10.0 ** (o.weibull_m + 1):.6g}"


def scene_text(o, q, run_dir):
    """The trial's scene: impactor radius from Q = (1/2) m v^2 / M_target (same density)."""
    v = o.speed * 1e3
    imp_radius = o.radius * (2.0 * q / (v * v)) ** (1.0 / 3.0)
    spacing = o.radius / o.points_per_radius  # points_per_radius points along a radius
    cell = o.points_per_cell * spacing
    half = 3.0 * o.radius
    end = o.crossings * 2.0 * o.radius / o.sound_speed
    # The impactor gets at least two points per radius, finer than the target's when it is small
    # (a sub-resolution impactor has no points); its mass is its own volume's either way.
    imp_spacing = min(spacing, 0.5 * imp_radius)
    return f"""# tools/qstar.py trial: Q = {q:.6g} J/kg
name = "qstar"
[solver]
method = "{o.method}"
cell_size = {cell:.9g}
end_time = {end:.9g}
[domain]
lo = [{-half:.9g}, {-half:.9g}, {-half:.9g}]
hi = [{half:.9g}, {half:.9g}, {half:.9g}]
boundary = "outflow"
[fracture]
seed = {o.seed}
[gravity]
self = true
equilibrium = true
mesh = {o.mesh}
[body.target]
shape = "sphere"
centre = [0.0, 0.0, 0.0]
radius = {o.radius:.9g}
material = "{o.material}"
points_per_cell = {o.points_per_cell}
[body.target.damage]
{damage_keys(o)}
[body.projectile]
shape = "sphere"
radius = {imp_radius:.9g}
spacing = {imp_spacing:.9g}
material = "{o.material}"
[body.projectile.damage]
{damage_keys(o)}
[impact]
projectile = "projectile"
target = "target"
speed = {v:.9g}
angle = {o.angle:.9g}
[output]
directory = "{run_dir}"
snapshot_every = 0.0
"""


def body_masses(shatter, snapshot, prefix):
    """Target and projectile masses (kg) at t = 0. The target's is the sum of the fragment
    table's target composition column (nothing is damaged at t = 0: the whole target is in
    fragments, which the check below enforces); the projectile's is the rest of the total (a
    sub-resolution impactor's few points are dust to the clustering)."""
    subprocess.run([shatter, "fragments", str(snapshot), "--prefix", str(prefix), "--quiet"],
                   check=True, stdout=subprocess.DEVNULL)
    lines = Path(str(prefix) + ".csv").read_text().splitlines()
    total = float(lines[0].split("total_mass_kg=")[1].split()[0])
    rows = list(csv.DictReader(lines[1:]))
    target = sum(float(r["mass_body_target_kg"]) for r in rows)
    in_fragments = sum(float(r["mass_kg"]) for r in rows)
    projectile = total - target
    if not (0.0 < projectile < 0.5 * target) or in_fragments < target:
        raise RuntimeError(f"{snapshot}: target {target} kg, projectile {projectile} kg: the "
                           "t = 0 fragment table does not separate the bodies")
    return target, projectile


def trial(o, q):
    """Runs one trial (or reads its finished result): the bound remnant's mass over the target's
    and Q from the lattice masses. q is the requested Q; the impactor's lattice holds a slightly
    different mass than its sphere, so the trial's actual Q = (1/2) m_imp v^2 / M_target is
    measured from the t = 0 snapshot and is what the result reports."""
    run_dir = Path(o.work) / f"q_{q:.6e}"
    result = run_dir / "result.json"
    if result.exists():
        return json.loads(result.read_text())
    run_dir.mkdir(parents=True, exist_ok=True)
    scene = run_dir / "scene.toml"
    scene.write_text(scene_text(o, q, run_dir / "out"))
    env = dict(os.environ, OMP_NUM_THREADS="1")
    threads = ["--threads", str(o.threads)] if o.threads else []
    for kv in o.set:
        threads += ["--set", kv]
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall0 = time.time()
    with open(run_dir / "run.log", "w") as log:
        subprocess.run([o.shatter, "run", str(scene), *threads], check=True, env=env, stdout=log,
                       stderr=subprocess.STDOUT)
    snaps = sorted((run_dir / "out" / "snapshots").glob("snapshot_*.h5"))
    if len(snaps) < 2:
        raise RuntimeError(f"{run_dir}: the run wrote fewer than two snapshots")
    subprocess.run([o.shatter, "fragments", str(snaps[-1]), "--quiet"], check=True,
                   stdout=subprocess.DEVNULL)
    bound = json.loads(next(snaps[-1].parent.glob(snaps[-1].stem + "*_bound.json")).read_text())
    m_target, m_imp = body_masses(o.shatter, snaps[0], run_dir / "out" / "initial")
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    points = re.search(r"body target: .*?, (\d+) points", (run_dir / "run.log").read_text())
    v = o.speed * 1e3
    out = {"q": q, "q_actual": 0.5 * m_imp * v * v / m_target,
           "fraction": bound["mass_kg"] / m_target, "target_points": int(points.group(1)),
           "dust_points_bound": bound.get("dust_points", 0), "wall_s": time.time() - wall0,
           # the children's CPU time: this trial's alone when --jobs 1
           "cpu_s": (cpu1.ru_utime + cpu1.ru_stime) - (cpu0.ru_utime + cpu0.ru_stime)}
    result.write_text(json.dumps(out))
    return out


def evaluate(o, qs, cache):
    todo = [q for q in qs if f"{q:.6e}" not in cache]
    with concurrent.futures.ThreadPoolExecutor(max_workers=o.jobs) as pool:
        for q, r in zip(todo, pool.map(lambda q: trial(o, q), todo)):
            cache[f"{q:.6e}"] = r
            print(f"Q = {r['q_actual']:.4g} J/kg (asked {q:.4g}): bound fraction "
                  f"{r['fraction']:.3f}, {r['cpu_s']:.0f} s CPU", flush=True)
    (Path(o.work) / "results.json").write_text(json.dumps(cache, indent=1))
    return [cache[f"{q:.6e}"]["fraction"] for q in qs]


def bracket(o, cache):
    """(Q_lo, Q_hi) with f(Q_lo) >= 1/2 > f(Q_hi)."""
    q = o.q_guess if o.q_guess else ba99_qstar(o.radius, o.speed if o.speed in BA99_FIT else 3.0)
    if o.jobs == 1:
        # one trial at a time: step from the guess towards f = 1/2, so a guess on the wrong side
        # costs no trial on the far side
        f_q = evaluate(o, [q], cache)[0]
        for _ in range(o.max_bracket):
            nxt = q * o.step if f_q >= 0.5 else q / o.step
            f_n = evaluate(o, [nxt], cache)[0]
            if (f_q >= 0.5) != (f_n >= 0.5):
                return (q, nxt) if f_q >= 0.5 else (nxt, q)
            q, f_q = nxt, f_n
    else:
        for _ in range(o.max_bracket):
            f_q, f_up = evaluate(o, [q, q * o.step], cache)
            if f_q >= 0.5 > f_up:
                return q, q * o.step
            q = q * o.step if f_up >= 0.5 else q / o.step
    sys.exit("qstar: no bracket found; widen --step or --max-bracket")


def bisect(o, cache, lo, hi):
    while hi / lo >= 1.0 + o.tolerance:
        k = o.jobs
        qs = [lo * (hi / lo) ** ((i + 1) / (k + 1)) for i in range(k)]
        for q, f in zip(qs, evaluate(o, qs, cache)):
            if f >= 0.5:
                lo = max(lo, q)
            else:
                hi = min(hi, q)
                break
    return lo, hi


def append_row(o, row):
    """Appends a row; a CSV written before a column existed is rewritten once with that column
    filled from COLUMN_DEFAULTS (what those runs used)."""
    path = Path(o.csv)
    rows = list(csv.DictReader(path.open())) if path.exists() else []
    if rows and list(rows[0].keys()) != COLUMNS:
        missing = [c for c in COLUMNS if c not in rows[0]]
        if any(c not in COLUMN_DEFAULTS for c in missing) or len(rows[0]) + len(missing) != len(COLUMNS):
            sys.exit(f"qstar: {path} has columns {list(rows[0])}; cannot upgrade to {COLUMNS}")
        with path.open("w", newline="") as f:
            w = csv.writer(f)
            w.writerow(COLUMNS)
            for r in rows:
                w.writerow([r.get(c, COLUMN_DEFAULTS.get(c)) for c in COLUMNS])
    new = not path.exists() or not rows
    with path.open("w" if new else "a", newline="") as f:
        w = csv.writer(f)
        if new:
            w.writerow(COLUMNS)
        w.writerow([row[c] for c in COLUMNS])


def flaw_label(flaws):
    return ", BA95 flaws" if flaws == "benz_asphaug" else ""


def plot(csv_path, png):
    """Every CSV row against BA99's fitted curves (constants unverified: docs/validation-qstar.md),
    with its bracket as an error bar. Left: the curves (rows with the default flaw seed, 2 points
    per cell and no overrides, grouped by method, material, speed, resolution and flaw draw).
    Right: the variants at single sizes (other flaw seeds, other settings), beside the curve rows
    at the same speed and resolution for reference."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = list(csv.DictReader(open(csv_path)))
    fig, axes = plt.subplots(1, 2, figsize=(13, 7.5), sharey=True)
    radii = [10 ** (e / 10) for e in range(-25, 51)]
    fits = [(3.0, BA99_FIT[3.0], "k--", "BA99 fit 3 km/s"),
            (5.0, BA99_FIT[5.0], "k:", "BA99 fit 5 km/s (Q0 9.0e7, a -0.36)"),
            (5.0, BA99_FIT_5_ALT, "k-.", "BA99 fit 5 km/s as also transcribed (Q0 7.0e7, a -0.38)")]
    for ax in axes:
        ax.set_prop_cycle(color=plt.cm.tab20.colors)  # more curves than the default 10 colours
        for _, consts, style, label in fits:
            ax.loglog(radii, [ba99_qstar(r, None, consts=consts) for r in radii], style,
                      lw=1, label=label + " (Table III, unverified)")

    def variant(r):
        # a catalogue of one's own only names where the material comes from: not a variant
        options = [o for o in (r.get("options") or "").split() if not o.startswith("catalogue=")]
        return (r.get("seed") or "1") != "1" or (r.get("points_per_cell") or "2") != "2" or \
            bool(options) or float(r.get("crossings") or 5) != 5.0 or \
            float(r.get("angle_deg") or 45) != 45.0

    def draw(ax, rs, fmt, label, lw=1.5):
        rs.sort(key=lambda r: float(r["radius_m"]))
        x = [float(r["radius_m"]) for r in rs]
        y = [float(r["qstar_J_per_kg"]) for r in rs]
        lo = [yy - float(r.get("q_lo_J_per_kg") or yy) for r, yy in zip(rs, y)]
        hi = [float(r.get("q_hi_J_per_kg") or yy) - yy for r, yy in zip(rs, y)]
        ax.errorbar(x, y, yerr=[lo, hi], fmt=fmt, ms=4, capsize=2, label=label, lw=lw)

    curves, variants = {}, {}
    for r in rows:
        key = (r["method"], r["material"], float(r["speed_km_s"]),
               float(r.get("points_per_radius") or 0),
               r.get("flaws") or COLUMN_DEFAULTS["flaws"])
        if variant(r):
            vkey = key + (r.get("seed") or "1", r.get("points_per_cell") or "2",
                          r.get("options") or "", float(r.get("crossings") or 5),
                          float(r.get("angle_deg") or 45))
            variants.setdefault(vkey, []).append(r)
        else:
            curves.setdefault(key, []).append(r)
    for (method, material, speed, ppr, flaws), rs in sorted(curves.items()):
        line = "o-" if speed == 3.0 else "s--"  # 5 km/s dashed
        if flaws == "benz_asphaug":
            line = "^-" if speed == 3.0 else "v--"
        draw(axes[0], rs, line if len(rs) > 2 else line[0],
             f"{method.upper()} {material} {speed:g} km/s, {ppr:g} pts/R{flaw_label(flaws)}",
             lw=2.5 if flaws == "benz_asphaug" else 1.0)
    for (method, material, speed, ppr, flaws, seed, ppc, options, cross, angle), rs in \
            sorted(variants.items()):
        what = [f"seed {seed}"] if seed != "1" else []
        what += [f"{angle:g} degrees"] if angle != 45.0 else []
        what += [f"{cross:g} crossings"] if cross != 5.0 else []
        what += [f"{ppc} pt/cell " + options.replace("solver.", "")] if ppc != "2" or options else []
        draw(axes[1], rs, "D", f"{method.upper()} {material} {speed:g} km/s, {ppr:g} pts/R"
             f"{flaw_label(flaws)}, " + ", ".join(what))
    for key, rs in sorted(curves.items()):
        # the curve's rows at the sizes where it has variants
        at = {r["radius_m"] for k, vs in variants.items() if k[:5] == key for r in vs}
        if at:
            method, material, speed, ppr, flaws = key
            draw(axes[1], [r for r in rs if r["radius_m"] in at], "o", f"{method.upper()} "
                 f"{material} {speed:g} km/s, {ppr:g} pts/R{flaw_label(flaws)}, seed 1, "
                 "5 crossings (left)")
    axes[0].set_title("Q*_D curves, 45 degrees, 5 crossings", fontsize=10)
    axes[1].set_title("Variants at single sizes (3 km/s)", fontsize=10)
    for ax in axes:
        ax.set_xlabel("target radius (m)")
        # below the axes: the curves span the whole plot
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1)
        ax.grid(True, which="major", alpha=0.3)
    axes[0].set_ylabel("Q*_D (J/kg)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--radius", type=float, help="target radius, m (required unless --plot-only)")
    p.add_argument("--speed", type=float, default=3.0, help="impact speed, km/s")
    p.add_argument("--angle", type=float, default=45.0, help="impact angle, degrees")
    p.add_argument("--material", default="basalt_ba99")
    p.add_argument("--method", default="mpm", choices=["mpm", "sph"])
    p.add_argument("--weibull-k", type=float, default=4e35, help="m^-3 (BA99 basalt)")
    p.add_argument("--weibull-m", type=float, default=9.0)
    p.add_argument("--flaws", default="benz_asphaug",
                   choices=["resolution_independent", "benz_asphaug"],
                   help="flaw draw: BA95's explicit flaws (BA99's method, the default), or the engine's "
                   "resolution-independent draw (docs/validation-qstar.md, session 16)")
    p.add_argument("--points-per-radius", type=float, default=10.0)
    p.add_argument("--points-per-cell", type=int, default=2,
                   help="points per cell per axis (the cell is this many point spacings)")
    p.add_argument("--seed", type=int, default=1, help="flaw seed (fracture.seed)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="scene override passed to `shatter run --set` (repeatable), e.g. "
                   "solver.transfer=\"xpic\"")
    p.add_argument("--mesh", type=int, default=64, help="gravity mesh nodes per side")
    p.add_argument("--crossings", type=float, default=10.0,
                   help="end time in target sound crossings (2 R / c)")
    p.add_argument("--sound-speed", type=float, default=4595.0, help="m/s (BA99 basalt c_p)")
    p.add_argument("--q-guess", type=float, default=0.0, help="J/kg; 0 = BA99's fit")
    p.add_argument("--step", type=float, default=4.0, help="bracketing factor")
    p.add_argument("--max-bracket", type=int, default=8)
    p.add_argument("--tolerance", type=float, default=0.2, help="stop when Q_hi/Q_lo < 1 + this")
    p.add_argument("--jobs", type=int, default=1, help="trials run at once")
    p.add_argument("--threads", type=int, default=0, help="threads per trial (0 = shatter's default)")
    p.add_argument("--shatter", default="build/release/shatter")
    p.add_argument("--work", help="trial directory (restartable; required unless --plot-only)")
    p.add_argument("--csv", default="docs/qstar.csv")
    p.add_argument("--plot", help="PNG of every CSV row against BA99's fits")
    p.add_argument("--plot-only", action="store_true", help="redraw --plot from --csv and stop")
    o = p.parse_args()
    if o.plot_only:
        plot(o.csv, o.plot)
        return
    if o.radius is None or o.work is None:
        p.error("--radius and --work are required (unless --plot-only)")
    Path(o.work).mkdir(parents=True, exist_ok=True)
    cache_file = Path(o.work) / "results.json"
    cache = json.loads(cache_file.read_text()) if cache_file.exists() else {}
    lo, hi = bisect(o, cache, *bracket(o, cache))
    r_lo, r_hi = cache[f"{lo:.6e}"], cache[f"{hi:.6e}"]
    # Q*_D: the geometric mean of the bracket's actual (lattice) Qs
    qstar = math.sqrt(r_lo["q_actual"] * r_hi["q_actual"])
    fit = ba99_qstar(o.radius, o.speed) if o.speed in BA99_FIT else float("nan")
    print(f"Q*_D = {qstar:.4g} J/kg (bracket {r_lo['q_actual']:.4g} .. {r_hi['q_actual']:.4g}, "
          f"{len(cache)} runs; BA99 fit {fit:.4g})")
    append_row(o, {"radius_m": o.radius, "speed_km_s": o.speed, "angle_deg": o.angle,
                   "method": o.method, "material": o.material, "qstar_J_per_kg": f"{qstar:.6g}",
                   "runs": len(cache), "points_per_target": r_lo["target_points"],
                   "points_per_radius": o.points_per_radius, "crossings": o.crossings,
                   "q_lo_J_per_kg": f"{r_lo['q_actual']:.6g}",
                   "q_hi_J_per_kg": f"{r_hi['q_actual']:.6g}", "f_lo": f"{r_lo['fraction']:.4f}",
                   "f_hi": f"{r_hi['fraction']:.4f}", "tolerance": o.tolerance,
                   "cpu_s": f"{sum(r['cpu_s'] for r in cache.values()):.0f}",
                   "ba99_fit_J_per_kg": f"{fit:.6g}", "seed": o.seed,
                   "points_per_cell": o.points_per_cell, "options": " ".join(o.set),
                   "flaws": o.flaws})
    if o.plot:
        plot(o.csv, o.plot)


if __name__ == "__main__":
    main()

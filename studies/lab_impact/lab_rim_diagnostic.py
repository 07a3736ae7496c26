#!/usr/bin/python3
"""Why the laboratory impact's core grows under refinement: the rim diagnostic
(docs/validation-lab-impact.md, "Resolution study", issue 16 item 4).

Usage: lab_rim_diagnostic.py RUN_DIR [RUN_DIR ...] [--labels ...] [--csv-prefix P] [--out FIG]
                             [--end-us T]

Each RUN_DIR is a `shatter run` of scenes/lab-impact.toml (half model). Every point is followed
by id from the first snapshot (its initial position; points that left the domain count as
failed). For every run the script measures:

1. *Failure by shell and sector*: the failed fraction (D >= the scene's threshold) of the target
   per shell of initial distance from the target centre (1.5 mm shells) and per sector of the
   angle theta between the point's initial direction from the centre and the impact point's:
   far (cos theta < -0.5), side (|cos theta| <= 0.5), near (cos theta > 0.5), at every snapshot.
   The *front* of a sector is the initial radius, from 12 mm outwards, where the shell's intact
   fraction first falls below one half (linear between shell centres).
2. *Failed bands*: along the lattice lines of the initial point lattice, inside each 3 mm
   shell at the last snapshot (up to --end-us): the failed runs (consecutive failed points) per
   mm of line and their mean length in points and in mm. A damage band one lattice spacing wide
   at every resolution is a mesh-size effect of local damage.
3. *The pulse on the antipodal axis* (runs with snapshots at least every 1 us): the radial stress
   sigma_rr = u.sigma.u (u the unit vector from the impact point's side through the centre) of
   the points within 2.5 mm of the axis through the impact point and the centre, in 0.5 mm
   bins of initial distance from the centre, at 8, 10 and 12 us: the direct pulse's compressive
   peak, the width of the connected range above half of it (FWHM, mm) and the integral of the
   connected compression (MPa mm; at 8 us it still joins the crater's compression). Per 2 mm bin
   of distance on the antipodal side: the first snapshot at which half the bin's points have
   failed, and the median over its points of the largest principal stress each carried while
   intact up to --tension-until-us (16 us: the direct pulse's first reflection).
   In a run without failure (`body.target.damage.weibull_k=1e20`) that is the tension the
   undamaged target would carry; with damage on, a point fails within a step of reaching
   eps_max E and the snapshots miss its peak.
4. *Flaws* (runs with a checkpoint.h5 holding eps_max and weibull_m): the strain at which a
   point's damage cap (n_act / n_f)^(1/3) = (eps / eps_max)^(m_p/3) (Eqs. 17 and 22) reaches
   the failure threshold, as a fraction of eps_max (5th, 50th, 95th percentile): whether the
   failure strain depends on the point's volume through n_f and m_p.

Writes CSV files (--csv-prefix: _shells.csv, _front.csv, _bands.csv, _pulse.csv,
_axis_failure.csv) and a figure (--out: the pulse along the axis at 12 us, the failed fraction
per shell in the far and side sectors, the failed layer's depth against the pulse's width, when
the antipodal axis fails), and prints the tables as markdown.
"""

import argparse
import csv
import glob
import os
import tomllib

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

SECTORS = {"far": (-1.01, -0.5), "side": (-0.5, 0.5), "near": (0.5, 1.01)}
R_EDGES_MM = np.arange(0.0, 30.01, 1.5)
BAND_EDGES_MM = np.arange(12.0, 27.01, 3.0)
PULSE_TIMES_US = (8.0, 10.0, 12.0)
PULSE_FROM_MM = {8.0: -5.0, 10.0: 0.0, 12.0: 5.0}  # where to look for the direct pulse's peak
AXIS_RADIUS = 2.5e-3
AXIS_BIN = 0.5e-3


def read(path, keys):
    with h5py.File(path, "r") as f:
        p = f["particles"]
        out = {k: p[k][()] for k in keys}
        out["t"] = float(f.attrs["time"])
    return out


class Run:
    """A run's scene, its target's initial lattice, and snapshot reader by id."""

    def __init__(self, run_dir, end_us):
        self.dir = run_dir
        with open(os.path.join(run_dir, "scene.toml"), "rb") as f:
            self.scene = tomllib.load(f)
        self.threshold = self.scene.get("fracture", {}).get("threshold", 0.9)
        tb = self.scene["body"]["target"]
        self.centre = np.array(tb["centre"])
        self.radius = tb["radius"]
        self.cell = self.scene["solver"]["cell_size"]
        self.spacing = self.cell / tb.get("points_per_cell", 2)
        files = sorted(glob.glob(os.path.join(run_dir, "snapshots", "snapshot_*.h5")))
        self.files = [p for p in files if read_time(p) <= end_us * 1e-6 * (1 + 1e-9)]
        first = read(self.files[0], ["id", "position", "body", "mass"])
        body = first["body"].astype(int)
        self.tb = int(np.argmax(np.bincount(body, weights=first["mass"])))
        target = body == self.tb
        proj = first["position"][~target].mean(axis=0)
        proj[2] = self.centre[2]  # the half model (symmetry plane z = 0) holds half the projectile
        self.u_impact = (proj - self.centre) / np.linalg.norm(proj - self.centre)
        ids = first["id"][target].astype(np.int64)
        order = np.argsort(ids)
        self.ids = ids[order]
        self.pos0 = first["position"][target][order] - self.centre
        self.r0 = np.linalg.norm(self.pos0, axis=1)
        self.cos = self.pos0 @ self.u_impact / np.maximum(self.r0, 1e-30)

    def at(self, path, keys):
        """Columns of a snapshot in the order of self.ids; missing points: damage 1, others 0."""
        s = read(path, ["id", "body"] + keys)
        ids = s["id"].astype(np.int64)
        idx = np.searchsorted(self.ids, ids)
        ok = (idx < len(self.ids)) & (self.ids[np.minimum(idx, len(self.ids) - 1)] == ids)
        out = {"t": s["t"]}
        for k in keys:
            shape = (len(self.ids),) + s[k].shape[1:]
            a = np.ones(shape) if k == "damage" else np.zeros(shape)
            a[idx[ok]] = s[k][ok]
            out[k] = a
        return out


def read_time(path):
    with h5py.File(path, "r") as f:
        return float(f.attrs["time"])


def shells(run):
    """Failed fraction per (time, sector, shell) and the front per sector and time."""
    rows, fronts = [], []
    mids = 0.5 * (R_EDGES_MM[1:] + R_EDGES_MM[:-1])
    for path in run.files[1:]:
        s = run.at(path, ["damage"])
        failed = s["damage"] >= run.threshold
        for name, (lo, hi) in SECTORS.items():
            m = (run.cos >= lo) & (run.cos < hi)
            frac = []
            for a, b in zip(R_EDGES_MM[:-1], R_EDGES_MM[1:]):
                sel = m & (run.r0 >= a * 1e-3) & (run.r0 < b * 1e-3)
                f = float(failed[sel].mean()) if sel.any() else float("nan")
                frac.append(f)
                rows.append({"t_us": 1e6 * s["t"], "sector": name, "r_lo_mm": a, "r_hi_mm": b,
                             "failed": f, "points": int(sel.sum())})
            intact = 1.0 - np.array(frac)
            front = float("nan")
            for k in range(len(mids) - 1):
                if mids[k] >= 12.0 and intact[k] >= 0.5 > intact[k + 1]:
                    front = mids[k] + (intact[k] - 0.5) / (intact[k] - intact[k + 1]) * (
                        mids[k + 1] - mids[k])
                    break
            fronts.append({"t_us": 1e6 * s["t"], "sector": name, "front_mm": front})
    return rows, fronts


def bands(run):
    """Failed runs along the initial lattice's lines, per 3 mm shell, at the last snapshot."""
    s = run.at(run.files[-1], ["damage"])
    failed = s["damage"] >= run.threshold
    lo = run.pos0.min(axis=0)
    ijk = np.round((run.pos0 - lo) / run.spacing).astype(int)
    if np.abs(run.pos0 - lo - ijk * run.spacing).max() > 1e-3 * run.spacing:
        raise SystemExit(f"{run.dir}: the target's points are not on a lattice of spacing "
                         f"{run.spacing} m (a turned lattice?): no band analysis")
    n = ijk.max(axis=0) + 1
    state = np.full(n, -1, np.int8)
    state[tuple(ijk.T)] = failed
    radius = np.full(n, np.nan)
    radius[tuple(ijk.T)] = run.r0
    rows = []
    for a, b in zip(BAND_EDGES_MM[:-1], BAND_EDGES_MM[1:]):
        runs_total, length, nfail, npts, lengths = 0, 0.0, 0, 0, []
        for ax in range(3):
            g = np.moveaxis(state, ax, -1).reshape(-1, n[ax])
            r = np.moveaxis(radius, ax, -1).reshape(-1, n[ax])
            inside = (r >= a * 1e-3) & (r < b * 1e-3)
            f = ((g == 1) & inside).astype(np.int8)
            edges = np.diff(np.pad(f, ((0, 0), (1, 1))), axis=1)
            starts = np.argwhere(edges == 1)
            ends = np.argwhere(edges == -1)
            lengths.append(ends[:, 1] - starts[:, 1])
            runs_total += len(starts)
            length += inside.sum() * run.spacing
            nfail += int(f.sum())
            npts += int(inside.sum())
        lengths = np.concatenate(lengths)
        rows.append({"r_lo_mm": a, "r_hi_mm": b, "failed": nfail / max(npts, 1),
                     "runs_per_mm": runs_total / (1e3 * length),
                     "mean_run_points": float(lengths.mean()) if len(lengths) else 0.0,
                     "mean_run_mm": 1e3 * run.spacing * float(lengths.mean()) if len(lengths)
                     else 0.0,
                     "single_point_runs": float((lengths == 1).mean()) if len(lengths) else 0.0})
    return rows


def principal_stress_rr(stress, u):
    """u.sigma.u with the snapshot's Tensor6 order xx, xy, xz, yy, yz, zz."""
    xx, xy, xz, yy, yz, zz = stress.T
    return (u[0] * u[0] * xx + u[1] * u[1] * yy + u[2] * u[2] * zz
            + 2 * (u[0] * u[1] * xy + u[0] * u[2] * xz + u[1] * u[2] * yz))


def principal_max(stress):
    """Largest principal value of each stress (Tensor6 order xx, xy, xz, yy, yz, zz)."""
    xx, xy, xz, yy, yz, zz = stress.T
    m = np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1),
                  np.stack([xz, yz, zz], -1)], -2)
    return np.linalg.eigvalsh(m)[:, -1]


def dense(run):
    return len(run.files) >= 3 and np.diff(
        [read_time(p) for p in run.files[:30]]).max() <= 1e-6 * (1 + 1e-6)


def pulse(run, until_us):
    """The compressive pulse on the axis through the impact point and the centre, the largest
    tension its points carry while intact until `until_us`, and when they fail; None without
    dense snapshots."""
    if not dense(run):
        return None
    times = np.array([read_time(p) for p in run.files]) * 1e6
    u = -run.u_impact
    x = run.pos0 @ u
    sel = np.linalg.norm(run.pos0 - np.outer(x, u), axis=1) < AXIS_RADIUS
    xs = x[sel]
    edges = np.arange(-run.radius, run.radius + 1e-9, AXIS_BIN)
    mids = 0.5 * (edges[1:] + edges[:-1])
    which = np.digitize(xs, edges) - 1
    profiles, peaks = {}, []
    dmg = []
    tmax = np.full(sel.sum(), -np.inf)
    for path, t in zip(run.files, times):
        s = run.at(path, ["stress", "damage"])
        failed = s["damage"][sel] >= run.threshold
        dmg.append(failed)
        if t <= until_us + 1e-6:
            s1 = principal_max(s["stress"][sel]) / 1e6
            tmax = np.where(failed, tmax, np.maximum(tmax, s1))
        near = [t0 for t0 in PULSE_TIMES_US if abs(t - t0) < 0.05]
        if near:
            srr = principal_stress_rr(s["stress"][sel], u) / 1e6
            prof = np.array([srr[which == i].mean() if (which == i).any() else np.nan
                             for i in range(len(mids))])
            ok = np.isfinite(prof)
            prof = np.interp(mids, mids[ok], prof[ok])
            profiles[near[0]] = prof
            # the direct pulse's peak, ahead of the compression behind it near the crater
            k = int(np.argmin(np.where(mids >= PULSE_FROM_MM[near[0]] * 1e-3, prof, np.inf)))
            p = -prof[k]
            # the compressive pulse: the connected range around the peak above half of it
            lo = k
            while lo > 0 and -prof[lo - 1] >= 0.5 * p:
                lo -= 1
            hi = k
            while hi < len(prof) - 1 and -prof[hi + 1] >= 0.5 * p:
                hi += 1
            zero_lo = k
            while zero_lo > 0 and prof[zero_lo - 1] < 0:
                zero_lo -= 1
            zero_hi = k
            while zero_hi < len(prof) - 1 and prof[zero_hi + 1] < 0:
                zero_hi += 1
            peaks.append({"t_us": near[0], "peak_MPa": p, "at_mm": 1e3 * mids[k],
                          "fwhm_mm": 1e3 * (hi - lo + 1) * AXIS_BIN,
                          "integral_MPa_mm": -prof[zero_lo:zero_hi + 1].sum() * AXIS_BIN * 1e3})
    dmg = np.array(dmg)
    fail_rows = []
    for a in np.arange(8.0, 30.0, 2.0):
        m = (xs >= a * 1e-3) & (xs < (a + 2) * 1e-3)
        frac = dmg[:, m].mean(axis=1)
        k = np.where(frac >= 0.5)[0]
        fail_rows.append({"x_lo_mm": a, "x_hi_mm": a + 2,
                          "t_half_failed_us": float(times[k[0]]) if len(k) else float("nan"),
                          "failed_end": float(frac[-1]),
                          "max_tension_intact_MPa": float(np.median(tmax[m]))})
    return {"mids_mm": 1e3 * mids, "profiles": profiles, "peaks": peaks, "fail": fail_rows}


def flaws(run):
    path = os.path.join(run.dir, "checkpoint.h5")
    if not os.path.exists(path):
        return None
    with h5py.File(path, "r") as f:
        p = f["particles"]
        if "eps_max" not in p or "weibull_m" not in p:
            return None
        target = p["body"][()] == run.tb
        m = p["weibull_m"][()][target]
        nf = p["n_flaws"][()][target]
    ratio = run.threshold ** (3.0 / np.maximum(m, 1e-12))  # (eps/eps_max)^(m_p/3) = threshold
    return {"n_flaws_median": float(np.median(nf)),
            "m_p": np.percentile(m, [5, 50, 95]).tolist(),
            "fail_strain_over_eps_max": np.percentile(ratio, [5, 50, 95]).tolist()}


CSV_TIMES_US = (8.0, 10.0, 12.0, 14.0, 16.0, 20.0, 30.0, 40.0, 60.0, 100.0)


def kept_time(t_us):
    """The times the time-resolved CSVs keep (CSV_TIMES_US)."""
    return any(abs(t_us - t) < 0.05 for t in CSV_TIMES_US)


def write_csv(path, rows, extra):
    rows = [[r for r in g if "t_us" not in r or kept_time(r["t_us"])] for g in rows]
    if not any(rows):
        return
    keys = list(extra[0].keys()) + list(next(g for g in rows if g)[0].keys())
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for group, ex in zip(rows, extra):
            for r in group:
                w.writerow({**ex, **{k: (f"{v:.6g}" if isinstance(v, float) else v)
                                     for k, v in r.items()}})


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dirs", nargs="+")
    ap.add_argument("--labels", nargs="*", help="one per RUN_DIR (default: the point spacing)")
    ap.add_argument("--csv-prefix", default="out/lab-rim")
    ap.add_argument("--out", default="out/lab-rim.png")
    ap.add_argument("--end-us", type=float, default=100.0,
                    help="ignore snapshots after this time (us)")
    ap.add_argument("--tension-until-us", type=float, default=16.0,
                    help="largest tension while intact: up to this time (us)")
    a = ap.parse_args()
    runs = [Run(d, a.end_us) for d in a.run_dirs]
    labels = a.labels or [f"{1e3 * r.spacing:.1f} mm" for r in runs]
    if len(labels) != len(runs):
        raise SystemExit(f"--labels: {len(labels)} labels for {len(runs)} run directories")
    for d in (os.path.dirname(a.out), os.path.dirname(a.csv_prefix)):
        if d:
            os.makedirs(d, exist_ok=True)
    results = []
    for run, name in zip(runs, labels):
        sh, fr = shells(run)
        results.append({"name": name, "run": run, "shells": sh, "fronts": fr,
                        "bands": bands(run), "pulse": pulse(run, a.tension_until_us),
                        "flaws": flaws(run)})
    extra = [{"label": r["name"],
              "spacing_mm": f"{1e3 * r['run'].spacing:.3g}"} for r in results]
    write_csv(a.csv_prefix + "_shells.csv", [r["shells"] for r in results], extra)
    write_csv(a.csv_prefix + "_front.csv", [r["fronts"] for r in results], extra)
    write_csv(a.csv_prefix + "_bands.csv", [r["bands"] for r in results], extra)
    pr = [(r["pulse"]["peaks"], e) for r, e in zip(results, extra) if r["pulse"]]
    write_csv(a.csv_prefix + "_pulse.csv", [p for p, _ in pr], [e for _, e in pr])
    fa = [(r["pulse"]["fail"], e) for r, e in zip(results, extra) if r["pulse"]]
    write_csv(a.csv_prefix + "_axis_failure.csv", [p for p, _ in fa], [e for _, e in fa])

    print("## Front (initial radius where the intact fraction falls below 1/2), last snapshot\n")
    print("| run | t (us) | far (mm) | side (mm) | near (mm) |\n|---|---|---|---|---|")
    for r in results:
        last = max(f["t_us"] for f in r["fronts"])
        f = {x["sector"]: x["front_mm"] for x in r["fronts"] if x["t_us"] == last}
        print(f"| {r['name']} | {last:.0f} | {f['far']:.1f} | {f['side']:.1f} | {f['near']:.1f} |")
    print("\n## The front against time (far / side sector, mm; nan: no crossing yet)\n")
    when = (14.0, 16.0, 20.0, 25.0, 30.0, 40.0, 100.0)
    print("| run | " + " | ".join(f"{t:.0f} us" for t in when) + " |")
    print("|---" * (len(when) + 1) + "|")
    for r in results:
        cells = []
        for t in when:
            f = {x["sector"]: x["front_mm"] for x in r["fronts"] if abs(x["t_us"] - t) < 0.05}
            cells.append(f"{f['far']:.1f} / {f['side']:.1f}" if f else "")
        print(f"| {r['name']} | " + " | ".join(cells) + " |")
    print("\n## Failed bands along lattice lines, last snapshot\n")
    print("| run | shell (mm) | failed | failed runs per mm | mean run (points) | mean run (mm) |"
          "\n|---|---|---|---|---|---|")
    for r in results:
        for b in r["bands"]:
            print(f"| {r['name']} | {b['r_lo_mm']:.0f}-{b['r_hi_mm']:.0f} | {b['failed']:.3f} | "
                  f"{b['runs_per_mm']:.3f} | {b['mean_run_points']:.2f} | {b['mean_run_mm']:.2f} |")
    print("\n## Pulse on the antipodal axis (sigma_rr, compression)\n")
    print("| run | t (us) | peak (MPa) | at (mm from centre) | FWHM (mm) | integral (MPa mm) |"
          "\n|---|---|---|---|---|---|")
    for r in results:
        for p in (r["pulse"] or {"peaks": []})["peaks"]:
            print(f"| {r['name']} | {p['t_us']:.0f} | {p['peak_MPa']:.1f} | {p['at_mm']:.1f} | "
                  f"{p['fwhm_mm']:.1f} | {p['integral_MPa_mm']:.0f} |")
    print("\n## When the antipodal axis fails (first snapshot with half the bin failed, us)\n")
    dense = [r for r in results if r["pulse"]]
    if dense:
        print("| x from centre (mm) | " + " | ".join(r["name"] for r in dense) + " |")
        print("|---" * (len(dense) + 1) + "|")
        for k, f in enumerate(dense[0]["pulse"]["fail"]):
            cells = [r["pulse"]["fail"][k] for r in dense]
            print(f"| {f['x_lo_mm']:.0f}-{f['x_hi_mm']:.0f} | " + " | ".join(
                f"{c['t_half_failed_us']:.1f} ({c['failed_end']:.2f}; "
                f"{c['max_tension_intact_MPa']:.0f})" for c in cells) + " |")
    print("\n(first time half the bin failed, us; the bin's failed fraction at the end; the median"
          f" of its points' largest tension while intact up to {a.tension_until_us:g} us, MPa)")
    print("\n## Flaws: failure strain over eps_max (5th, 50th, 95th percentile)\n")
    for r in results:
        if r["flaws"]:
            fl = r["flaws"]
            print(f"- {r['name']}: n_f median {fl['n_flaws_median']:.0f}, m_p "
                  f"{', '.join(f'{v:.1f}' for v in fl['m_p'])}, eps_fail/eps_max "
                  f"{', '.join(f'{v:.4f}' for v in fl['fail_strain_over_eps_max'])}")

    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
    for k, r in enumerate(results):
        style = dict(color=f"C{k % 10}", label=r["name"])
        if r["pulse"] and 12.0 in r["pulse"]["profiles"]:
            axes[0, 0].plot(r["pulse"]["mids_mm"], r["pulse"]["profiles"][12.0], **style)
        last = max(x["t_us"] for x in r["shells"])
        for name, ls in (("far", "-"), ("side", "--")):
            rows = [x for x in r["shells"] if x["t_us"] == last and x["sector"] == name]
            mids = [0.5 * (x["r_lo_mm"] + x["r_hi_mm"]) for x in rows]
            axes[0, 1].plot(mids, [100 * x["failed"] for x in rows], ls=ls, marker="o", ms=3,
                            **(style if name == "far" else {"color": style["color"]}))
        if r["pulse"]:
            f = r["pulse"]["fail"]
            axes[1, 1].plot([0.5 * (x["x_lo_mm"] + x["x_hi_mm"]) for x in f],
                            [x["t_half_failed_us"] for x in f], marker="o", ms=3, **style)
        if r["pulse"] and any(p["t_us"] == 12.0 for p in r["pulse"]["peaks"]):
            width = [p["fwhm_mm"] for p in r["pulse"]["peaks"] if p["t_us"] == 12.0][0]
            for name, marker, fill in (("far", "o", None), ("side", "s", "none")):
                front = [x["front_mm"] for x in r["fronts"] if x["t_us"] == last
                         and x["sector"] == name][0]
                axes[1, 0].plot([width], [1e3 * r["run"].radius - front], marker=marker,
                                ls="", mfc=fill, **(style if name == "far" else
                                                    {"color": style["color"]}))
    axes[0, 0].set_xlabel("initial distance from the centre along the antipodal axis (mm)")
    axes[0, 0].set_ylabel("sigma_rr at 12 us (MPa, tension > 0)")
    axes[0, 0].set_xlim(0.0, 30.0)  # the antipodal half; the crater's compression lies at x < 0
    axes[0, 1].set_xlabel("initial distance from the target centre (mm)")
    axes[0, 1].set_ylabel("failed at the last snapshot (%): far sector -, side --")
    axes[1, 0].set_xlabel("FWHM of the direct pulse on the antipodal axis at 12 us (mm)")
    axes[1, 0].set_ylabel("failed layer: radius - front (mm); far o, side square")
    axes[1, 1].set_xlabel("initial distance from the centre along the antipodal axis (mm)")
    axes[1, 1].set_ylabel("half the bin failed at (us)")
    for ax in axes.flat:
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.suptitle("modified Lundborg Y0 = 60 MPa: the pulse reaching the far side and the rim "
                 "it fails (half model, seed 1)")
    fig.tight_layout()
    fig.savefig(a.out, dpi=100)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Why SPH and MPM part on the laboratory impact after the free-surface reflection
(docs/validation-sph.md, "Why the methods part"; issues 10 and 11).

Input: four runs of scenes/lab-impact.toml at the same resolution with dense snapshots
(--set output.snapshot_every=0.5e-6, to 40 us): SPH and MPM, damage on and damage off
(--set body.target.damage.weibull_k=1e20). Both methods build the same point lattice, so the
points are matched by id.

  sph_lab_parting.py --sph-on A --mpm-on B --sph-off C --mpm-off D [--out-prefix P]

Prints and plots:
  1. gauges (points by starting position): on the axis (within 20 degrees of the line from the
     impact point through the target centre) at 10, 20, 30, 40, 50 mm from the impact point,
     and off the axis (40-50 degrees from it) at 20 and 30 mm: mean radial stress s_rr (radial
     from the impact point), mean largest principal stress s_1, and for damage on the failed
     share (D >= 0.9) and s_1 of the still intact points, to 40 us (P_gauges.png);
  2. the parting set: target points failed in MPM at 20 us but intact in SPH at 20 us, against
     the points failed in both: where they lie, when MPM fails them, the tension they carried
     in each run (damage on: while intact; damage off: the undamaged wave) (P_parting.png);
  3. opening: rho / rho0 and the relative normal velocity across neighbours of failed points
     (mechanism (a): whether failed material separates) at 20 and 40 us.
Per-run arrays are cached next to each run (RUN/parting_cache.npz).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "tools"))
import shatter_plot as sp  # noqa: E402

FAILED = 0.9


def load(run):
    cache = os.path.join(run, "parting_cache.npz")
    if os.path.exists(cache):
        z = np.load(cache)
        return {k: z[k] for k in z.files}
    files = sp.snapshots(run)
    _, first, axis = sp.read_snapshot(files[0])
    target, centre, radius, inward, imp = sp.impact_geometry(first, axis, sp.scene(run))
    ids = np.sort(first["id"][first["body"].astype(int) == target].astype(np.int64))
    n, nt = len(ids), len(files)
    out = {k: np.full((nt, n) + s, np.nan, np.float32)
           for k, s in [("x", (3,)), ("v", (3,)), ("s", (6,)), ("d", ()), ("rho", ())]}
    out["t"] = np.zeros(nt)
    for i, f in enumerate(files):
        t, c, _ = sp.read_snapshot(f)
        out["t"][i] = t
        cid = c["id"].astype(np.int64)
        o = np.argsort(cid)
        k = np.searchsorted(cid[o], ids)
        k = np.minimum(k, len(o) - 1)
        present = cid[o][k] == ids
        src = o[k[present]]
        out["x"][i, present] = np.stack([c["x"], c["y"], c["z"]], 1)[src]
        out["v"][i, present] = np.stack([c["vx"], c["vy"], c["vz"]], 1)[src]
        out["s"][i, present] = np.stack([c[name] for _, name in sp.STRESS_COLUMNS], 1)[src]
        out["d"][i, present] = c["damage"][src] if "damage" in c else 0.0
        out["rho"][i, present] = c["rho"][src]
    out["ids"] = ids
    out["geom"] = np.concatenate([centre, [radius], inward, imp])
    np.savez(cache, **out)
    return out


def tensors(s6):
    s = np.zeros(s6.shape[:-1] + (3, 3), np.float64)
    for ((i, j), _), k in zip(sp.STRESS_COLUMNS, range(6)):
        s[..., i, j] = s6[..., k]
        s[..., j, i] = s6[..., k]
    return s


def principal_max(s6):
    s = tensors(s6)
    ok = np.isfinite(s).all(axis=(-1, -2))
    out = np.full(s.shape[:-2], np.nan)
    out[ok] = np.linalg.eigvalsh(s[ok])[..., -1]
    return out


def radial_stress(s6, x, imp):
    r = x - imp
    nn = r / np.linalg.norm(r, axis=-1)[..., None]
    return np.einsum("...i,...ij,...j->...", nn, tensors(s6), nn)


def nanmean(a, axis):
    with np.errstate(all="ignore"):
        return np.nanmean(a, axis=axis)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    for k in ("sph-on", "mpm-on", "sph-off", "mpm-off"):
        ap.add_argument("--" + k, required=True)
    ap.add_argument("--out-prefix", default="parting")
    ap.add_argument("--split", type=float, default=20e-6, help="time at which to compare (s)")
    a = ap.parse_args()
    runs = {"SPH on": a.sph_on, "MPM on": a.mpm_on, "SPH off": a.sph_off, "MPM off": a.mpm_off}
    data = {k: load(v) for k, v in runs.items()}
    ref = data["MPM on"]
    for k, d in data.items():
        if not np.array_equal(d["ids"], ref["ids"]):
            raise SystemExit(f"{k}: target points differ from MPM on's (ids); same lattice needed")
    g = ref["geom"]
    centre, radius, inward, imp = g[:3], g[3], g[4:7], g[7:10]
    x0 = ref["x"][0].astype(np.float64)
    rel = x0 - imp
    dist = np.linalg.norm(rel, axis=1)
    ang = np.degrees(np.arccos(np.clip(rel @ inward / np.maximum(dist, 1e-12), -1, 1)))
    rc = np.linalg.norm(x0 - centre, axis=1)

    # Derived per run: s_1 and s_rr (T, N).
    for k, d in data.items():
        d["s1"] = principal_max(d["s"].astype(np.float64))
        d["srr"] = radial_stress(d["s"].astype(np.float64), d["x"].astype(np.float64), imp)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # 1. Gauges.
    gauges = [(f"axis {r} mm", (np.abs(dist - r * 1e-3) < 1.5e-3) & (ang < 20))
              for r in (10, 20, 30, 40, 50)]
    gauges += [(f"45° {r} mm", (np.abs(dist - r * 1e-3) < 1.5e-3) & (ang > 40) & (ang < 50))
               for r in (20, 30)]
    windows = [(0, 12e-6), (12e-6, 20e-6), (20e-6, 41e-6)]
    print("## Gauges: max over each window of the gauge-mean s_1 (MPa); damage on: also the "
          "failed share at the window's end and the largest mean s_1 of its intact points")
    print("| gauge | points | run | s_1 max 0-12 us | 12-20 us | 20-40 us | min s_rr | "
          "failed at 12 / 20 / 40 us | intact s_1 max 12-20 / 20-40 us |")
    print("|---|---|---|---|---|---|---|---|---|")
    fig, ax = plt.subplots(3, len(gauges), figsize=(2.6 * len(gauges), 7.2), sharex=True)
    colours = {"SPH on": "C0", "MPM on": "C3", "SPH off": "C0", "MPM off": "C3"}
    styles = {"SPH on": "-", "MPM on": "-", "SPH off": ":", "MPM off": ":"}
    for j, (name, sel) in enumerate(gauges):
        for k, d in data.items():
            t = d["t"] * 1e6
            s1 = nanmean(d["s1"][:, sel], 1) / 1e6
            srr = nanmean(d["srr"][:, sel], 1) / 1e6
            fail = np.mean(d["d"][:, sel] >= FAILED, axis=1)
            intact = np.where(d["d"][:, sel] < FAILED, d["s1"][:, sel], np.nan)
            s1i = nanmean(intact, 1) / 1e6
            w = [np.nanmax(s1[(d["t"] >= lo) & (d["t"] < hi)]) for lo, hi in windows]
            iw = [np.nanmax(s1i[(d["t"] >= lo) & (d["t"] < hi)]) if k.endswith("on") else np.nan
                  for lo, hi in windows[1:]]
            fi = [fail[np.argmin(np.abs(d["t"] - tt))] for tt in (12e-6, 20e-6, 40e-6)]
            on = k.endswith("on")
            print(f"| {name} | {sel.sum()} | {k} | {w[0]:.0f} | {w[1]:.0f} | {w[2]:.0f} | "
                  f"{np.nanmin(srr):.0f} | "
                  + (" / ".join(f"{100 * f:.0f}%" for f in fi) if on else "-") + " | "
                  + (" / ".join(f"{v:.0f}" for v in iw) if on else "-") + " |")
            ax[0, j].plot(t, srr, styles[k], color=colours[k], lw=1, label=k)
            ax[1, j].plot(t, s1, styles[k], color=colours[k], lw=1, label=k)
            if on:
                ax[2, j].plot(t, 100 * fail, color=colours[k], lw=1, label=k)
        ax[0, j].set_title(f"{name} ({sel.sum()} pts)", fontsize=9)
        ax[0, j].set_ylim(-300, 300)
        ax[1, j].set_ylim(-100, 300)
        ax[1, j].axhline(40, color="k", lw=0.5, ls="--")
        ax[2, j].set_xlabel("t (us)")
        for i in range(3):
            ax[i, j].axvspan(12, 20, color="0.9", zorder=0)
            ax[i, j].tick_params(labelsize=8)
    ax[0, 0].set_ylabel("mean s_rr (MPa)")
    ax[1, 0].set_ylabel("mean s_1 (MPa)")
    ax[2, 0].set_ylabel("failed (%)")
    ax[1, 0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.out_prefix + "_gauges.png", dpi=80)

    # 2. The parting set.
    it = int(np.argmin(np.abs(ref["t"] - a.split)))
    dm, ds = data["MPM on"]["d"], data["SPH on"]["d"]
    ok = np.isfinite(dm[it]) & np.isfinite(ds[it])
    F = ok & (dm[it] >= FAILED) & (ds[it] < FAILED)
    B = ok & (dm[it] >= FAILED) & (ds[it] >= FAILED)
    S = ok & (dm[it] < FAILED) & (ds[it] >= FAILED)
    Ii = ok & (dm[it] < FAILED) & (ds[it] < FAILED)
    n = ok.sum()
    print(f"\n## Parting set at {1e6 * ref['t'][it]:.1f} us ({n} target points)")
    print(f"failed in both {B.sum() / n:.3f}, MPM only {F.sum() / n:.3f}, SPH only "
          f"{S.sum() / n:.3f}, intact in both {Ii.sum() / n:.3f}")
    for name, sel in (("MPM only", F), ("both", B), ("intact both", Ii)):
        print(f"{name}: distance from the target centre {1e3 * np.median(rc[sel]):.1f} mm median "
              f"({1e3 * np.percentile(rc[sel], 10):.1f}-{1e3 * np.percentile(rc[sel], 90):.1f}), "
              f"from the impact point {1e3 * np.median(dist[sel]):.1f} mm")

    def fail_time(d):
        f = d >= FAILED
        first = np.argmax(f, axis=0).astype(float)
        first[~f.any(axis=0)] = np.nan
        return first

    tf_m = fail_time(dm)
    tf_s = fail_time(ds)
    tt = ref["t"] * 1e6
    for name, sel, tf in (("MPM only, MPM", F, tf_m), ("both, MPM", B, tf_m),
                          ("both, SPH", B, tf_s)):
        v = tt[tf[sel].astype(int)]
        print(f"failure time {name}: median {np.median(v):.1f} us (10-90%: "
              f"{np.percentile(v, 10):.1f}-{np.percentile(v, 90):.1f})")
    # Tension carried by the parting set: per run, the largest s_1 each point had while intact
    # (damage on) or at all (damage off), before 12 us and in 12-20 us.
    print("\nlargest s_1 a point carried (median over the set, MPa; damage on: while intact)")
    print("| set | run | 0-12 us | 12-20 us | 20-40 us |")
    print("|---|---|---|---|---|")
    peaks = {}
    for name, sel in (("MPM only", F), ("both", B), ("intact both", Ii)):
        for k, d in data.items():
            s1 = d["s1"][:, sel]
            if k.endswith("on"):
                s1 = np.where(d["d"][:, sel] < FAILED, s1, np.nan)
            row = []
            for lo, hi in windows:
                w = (d["t"] >= lo) & (d["t"] < hi)
                with np.errstate(all="ignore"):
                    m = np.nanmax(s1[w], axis=0)
                row.append(np.nanmedian(m) / 1e6)
                peaks[(name, k, lo)] = m
            print(f"| {name} | {k} | " + " | ".join(f"{r:.0f}" for r in row) + " |")

    # Was the MPM-only failure next to material that had already failed? For each point of F,
    # at the snapshot where MPM fails it, the distance to the nearest point failed a snapshot
    # earlier (starting positions, in spacings).
    from scipy.spatial import cKDTree
    spacing = np.median(cKDTree(x0).query(x0, k=2)[0][:, 1])
    near = []
    for i in np.where(F)[0][:: max(1, F.sum() // 2000)]:
        k = int(tf_m[i])
        prev = dm[k - 1] >= FAILED
        if prev.sum() == 0:
            continue
        dd, _ = cKDTree(x0[prev]).query(x0[i])
        near.append(dd / spacing)
    near = np.array(near)
    print(f"\nMPM-only failures: distance to the nearest point failed one snapshot earlier "
          f"(spacings): median {np.median(near):.2f}, within 1.5 spacings "
          f"{np.mean(near < 1.5):.2f}, within 3 {np.mean(near < 3):.2f}")

    # 3. Opening of failed material: rho / rho0 of failed points, and the normal velocity
    # jump between neighbouring points (within 1.5 spacings) where at least one is failed:
    # (v_j - v_i) . (x_j - x_i) / |x_j - x_i|, positive = opening.
    print("\n## Opening of failed material")
    print("| run | t (us) | failed: median rho/rho0 | share with rho/rho0 < 0.98 | "
          "pairs with a failed point: median opening rate (m/s) | share opening faster than "
          "1 m/s | intact pairs: median |")
    print("|---|---|---|---|---|---|---|")
    tree = cKDTree(x0)
    pairs = np.array(sorted(tree.query_pairs(1.5 * spacing)))
    for k in ("SPH on", "MPM on"):
        d = data[k]
        rho0 = d["rho"][0]
        for tsel in (12e-6, 20e-6, 40e-6):
            i = int(np.argmin(np.abs(d["t"] - tsel)))
            f = d["d"][i] >= FAILED
            ratio = d["rho"][i] / rho0
            x, v = d["x"][i].astype(np.float64), d["v"][i].astype(np.float64)
            dx = x[pairs[:, 1]] - x[pairs[:, 0]]
            dv = v[pairs[:, 1]] - v[pairs[:, 0]]
            rate = np.einsum("ij,ij->i", dv, dx) / np.linalg.norm(dx, axis=1)
            pf = f[pairs[:, 0]] | f[pairs[:, 1]]
            good = np.isfinite(rate)
            print(f"| {k} | {1e6 * d['t'][i]:.0f} | {np.nanmedian(ratio[f]):.4f} | "
                  f"{np.nanmean(ratio[f] < 0.98):.3f} | {np.median(rate[pf & good]):.2f} | "
                  f"{np.mean(rate[pf & good] > 1.0):.3f} | {np.median(rate[~pf & good]):.3f} |")

    # Figure: the parting set's largest intact s_1 (damage on) and undamaged s_1 (off) in
    # 12-20 us, each method; and where the set lies on the symmetry plane.
    fig, ax = plt.subplots(1, 3, figsize=(13, 4))
    bins = np.linspace(-50, 400, 46)
    for k in data:
        m = peaks[("MPM only", k, 12e-6)] / 1e6
        ax[0].hist(np.clip(m[np.isfinite(m)], -50, 400), bins=bins, histtype="step",
                   color=colours[k], ls=styles[k], label=k)
    ax[0].axvline(40, color="k", lw=0.5, ls="--")
    ax[0].set_xlabel("largest s_1 in 12-20 us (MPa; damage on: while intact)")
    ax[0].set_ylabel("points (MPM-only failures)")
    ax[0].legend(fontsize=8)
    v = tt[tf_m[F].astype(int)]
    ax[1].hist(v, bins=np.arange(0, 41, 1), color="C3", alpha=0.7, label="MPM-only: MPM fails")
    vb = tt[tf_m[B].astype(int)]
    ax[1].hist(vb, bins=np.arange(0, 41, 1), histtype="step", color="k", label="both: MPM fails")
    vs = tt[tf_s[B].astype(int)]
    ax[1].hist(vs, bins=np.arange(0, 41, 1), histtype="step", color="C0", label="both: SPH fails")
    ax[1].set_xlabel("failure time (us)")
    ax[1].legend(fontsize=8)
    plane = x0[:, 2] < 1.3e-3
    for sel, c, lab in ((Ii, "0.8", "intact in both"), (B, "k", "failed in both"),
                        (F, "C3", "MPM only"), (S, "C0", "SPH only")):
        q = sel & plane
        ax[2].scatter(1e3 * x0[q, 0], 1e3 * x0[q, 1], s=3, c=c, label=lab)
    ax[2].plot(1e3 * imp[0], 1e3 * imp[1], "k*", ms=10)
    ax[2].set_aspect("equal")
    ax[2].set_title(f"failed at {1e6 * ref['t'][it]:.0f} us, plane z ~ 0 (start positions)",
                    fontsize=9)
    ax[2].legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(a.out_prefix + "_parting.png", dpi=80)


if __name__ == "__main__":
    main()

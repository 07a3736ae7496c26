#!/usr/bin/python3
"""Shares of a shatter run's `perf record` profile per step stage (docs/performance.md).

The Release build has no frame pointers, so the profile is flat (`perf record -e cpu-clock`, no
call graph) and each sampled symbol is put in the stage whose code it is by the first pattern
below that matches its demangled name (a kernel inlined into a stage's loop carries the kernel's
name). Patterns follow the source at main a5b4437 (src/mpm/stages/, src/sph/); a symbol that
matches none is counted as "other" and the largest of them are listed, so a renamed kernel shows
up instead of vanishing. cpu-clock samples are CPU time, so the shares do not depend on the load.

    perf record -e cpu-clock -F 1000 -o RUN.data -- shatter run SCENE --threads 1 ...
    /usr/bin/python3 tools/peers/perf_stages.py RUN.data --method sph --points 32930 --steps 340

With --points and --steps, each stage's CPU ns per point and step is printed too (samples x the
sampling period over points x steps); "set-up, output" (scene generation, snapshots, HDF5, zlib)
and "kernel" (the OS) are outside the step.
"""
import argparse
import re
import subprocess
from collections import defaultdict

OUTSIDE = [
    ("set-up, output", r"scene::|io::|libz|libhdf5|H5[A-Z]|toml|fill_lattice|spdlog|fmt::"),
]
MPM = [
    ("constitutive", r"velocity_gradient|step7|constitutive::|ComposedModel|damage::|eos::|"
                     r"strength::|porosity::|xsimd::kernel::cbrt"),
    ("remap", r"p2g_block<[^<>,]*, false|p2g_point<false|p2g_flush<false|remap_momentum|"
              r"stages::remap|mpm::remap"),
    ("p2g", r"p2g_block<[^<>,]*, true|p2g_point<true|p2g_flush<true|mpm::p2g|colour_loop"),
    ("g2p", r"g2p_block|g2p<|G2PWindow|g2p_gather"),
    ("remap_velocity", r"remap_velocity"),
    ("grid_update", r"Boundaries::|sum_over_nodes|node_unresolved|grid_update|update_nodes"),
    ("sort", r"copy_columns|save_columns|Checked|check_finite|sort_particles|compute_keys|"
             r"ParticleStore::permute|SparseGrid::|__introsort_loop<unsigned int"),
    ("advance_positions, outflow", r"advance_positions|outflow|remove_if"),
    ("energy", r"exact_sum|mpm::energy|momentum_sums|failure_ratio"),
    ("time_step", r"time_step|stable_dt|fastest"),
]
SPH = [
    ("forces", r"forces_particle|partition_within_support|Impl::forces|forces_chunk|compact_lists"),
    ("rates", r"rates_particle|Impl::rates|heat_from_kick|midpoint_smoothing"),
    ("material", r"constitutive::|eos::|strength::|damage::|porosity::|materials::|"
                 r"Impl::material|evolve_switch"),
    ("search (check, lists, mirrors, re-order)",
     r"NeighbourSearch|append_within_reach|cell_keys|check_state|lists_still_cover|build_search|"
     r"smoothing_lengths|permute|reorder|place_ghosts|mirror_|refresh_ghost|particle_skins|"
     r"KeyIndex|__cbrt|scalbn|frexp|xsimd::kernel::cbrt|__introsort_loop<unsigned int|"
     r"merge_sort|wide_"),
    ("kick", r"Impl::kick|constrain_velocities"),
    ("drift", r"Impl::drift|reflect_after_drift|outflow_after_drift|remove_if"),
    ("energy, next dt", r"Impl::energy|stable_dt|next_dt|deterministic_sum|momentum_sums"),
]


def profile(data):
    out = subprocess.run(
        ["perf", "report", "-i", data, "--no-children", "-n", "--sort", "dso,symbol", "--stdio",
         "--field-separator", "\t"], capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        if not line or line.startswith("#"):
            continue
        parts = line.split("\t")
        if len(parts) < 4:
            continue
        rows.append((int(parts[1]), parts[2].strip(), parts[3].strip()))
    # cpu-clock's event count is CPU nanoseconds: the mean period of a sample.
    m = re.search(r"Event count \(approx\.\): (\d+)", out)
    total = sum(r[0] for r in rows)
    period = float(m.group(1)) * 1e-9 / total if m and total else None
    return rows, period


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("data")
    ap.add_argument("--method", choices=["mpm", "sph"], required=True)
    ap.add_argument("--points", type=float)
    ap.add_argument("--steps", type=float)
    ap.add_argument("--other", type=int, default=8, help="unmatched symbols to list")
    args = ap.parse_args()
    rows, period = profile(args.data)
    table = (MPM if args.method == "mpm" else SPH) + OUTSIDE
    stages = defaultdict(int)
    other = []
    total = sum(r[0] for r in rows)
    for samples, dso, sym in rows:
        name = f"{dso} {sym}"
        if "[k]" in sym or "kernel" in dso:
            stages["kernel"] += samples
            continue
        for stage, pattern in table:
            if re.search(pattern, name):
                stages[stage] += samples
                break
        else:
            stages["other"] += samples
            other.append((samples, name))
    step = sum(v for k, v in stages.items() if k not in ("set-up, output", "kernel"))
    per = args.points and args.steps and period
    print(f"{total} samples ({period * total if period else float('nan'):.2f} CPU-s); "
          f"in the step (without set-up, output, kernel): {step}")
    print("| stage | samples | share of the step | CPU ns per point-step |")
    print("|---|---:|---:|---:|")
    for stage, n in sorted(stages.items(), key=lambda kv: -kv[1]):
        ns = f"{n * period / (args.points * args.steps) * 1e9:.1f}" if per else "-"
        share = f"{100.0 * n / step:.1f} %" if stage not in ("set-up, output", "kernel") else "-"
        print(f"| {stage} | {n} | {share} | {ns} |")
    if per:
        print(f"| step | {step} | 100 % | {step * period / (args.points * args.steps) * 1e9:.1f} |")
    for samples, name in sorted(other, reverse=True)[: args.other]:
        print(f"  other: {samples} {name[:150]}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Per-round rates and ratios of a tools/peers/rounds.sh directory (docs/performance.md, "Peers").

Rates are particle-steps per second of process CPU (user + sys of /usr/bin/time -v):
  shatter loop  = points x steps / (CPU of the run - CPU of its 1 ns run)
  shatter whole = points x steps / CPU of the run
  peer loop     = points x steps / the peer's own step-loop CPU time (OpenSPH driver: "loop ... s
                  CPU"; MPM3D-F90: "Total CPU Time"), peer whole = points x steps / process CPU.
Peer points and steps: the OpenSPH driver prints them; MPM3D-F90 prints "Number of particles" and
writes one EnergyPlot.dat line per step. Ratios (shatter / peer) are taken within a round; the
last lines give the median and range over the rounds, the peak resident set of each code and
the load (1-minute average from the uptime lines around each process).

    /usr/bin/python3 tools/peers/rounds_table.py OUTDIR
"""
import glob
import os
import re
import statistics
import sys


def timev(path):
    s = open(path).read()
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", s).group(1))
    system = float(re.search(r"System time \(seconds\): ([\d.]+)", s).group(1))
    parts = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", s).group(1)
    wall = sum(float(x) * 60**i for i, x in enumerate(reversed(parts.split(":"))))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", s).group(1))
    return user + system, wall, rss / 1024.0


def loads(path):
    return [float(line.split("load average:")[1].split(",")[0]) for line in open(path)]


def peer_counts(directory, log):
    text = open(log).read()
    m = re.search(r"done: (\d+) steps, (\d+) particles; loop ([\d.]+) s CPU", text)
    if m:  # the OpenSPH driver (tools/peers/opensph_labimpact.cpp)
        return int(m.group(1)), int(m.group(2)), float(m.group(3))
    points = int(re.search(r"Number of particles =\s+(\d+)", text).group(1))
    loop = float(re.search(r"Total CPU Time is\s+([\d.]+)", text).group(1))
    with open(os.path.join(directory, "EnergyPlot.dat")) as f:
        steps = sum(1 for line in f if line.strip())
    return steps, points, loop


def main(out):
    ratios = {}
    rss = {}
    load_all = []
    for d in sorted(glob.glob(os.path.join(out, "r*")), key=lambda p: int(p.rsplit("r", 1)[1])):
        if not os.path.exists(os.path.join(d, "done")):
            continue
        c_init, _, _ = timev(os.path.join(d, "sh_init.time"))
        c_run, w_run, r_run = timev(os.path.join(d, "sh_run.time"))
        log = open(os.path.join(d, "sh_run.log")).read()
        steps = int(re.search(r"finished: t = [^,]*, (\d+) steps", log).group(1))
        points = int(re.search(r"(\d+) points in", log).group(1))
        sh_loop = points * steps / (c_run - c_init)
        sh_whole = points * steps / c_run
        ld = loads(os.path.join(d, "sh_run.uptime"))
        rss.setdefault("shatter", []).append(r_run)
        line = (f"{os.path.basename(d)}: shatter {points} points {steps} steps, loop "
                f"{sh_loop / 1e6:.3f} (whole {sh_whole / 1e6:.3f}) M/CPU-s, {c_run:.2f} CPU-s "
                f"{w_run:.1f} wall-s {r_run:.1f} MiB")
        for tfile in sorted(glob.glob(os.path.join(d, "peer_*.time"))):
            name = os.path.basename(tfile)[5:-5]
            c, w, r = timev(tfile)
            p_steps, p_points, p_loop = peer_counts(
                os.path.join(d, "peer_" + name), os.path.join(d, f"peer_{name}.log"))
            p_loop_rate = p_points * p_steps / p_loop
            p_whole = p_points * p_steps / c
            ld += loads(os.path.join(d, f"peer_{name}.uptime"))
            rss.setdefault(name, []).append(r)
            ratios.setdefault(name + " loop", []).append(sh_loop / p_loop_rate)
            ratios.setdefault(name + " whole", []).append(sh_whole / p_whole)
            line += (f"; {name} {p_points} points {p_steps} steps, loop {p_loop_rate / 1e6:.3f} "
                     f"(whole {p_whole / 1e6:.3f}) M/CPU-s, {c:.2f} CPU-s {w:.1f} wall-s "
                     f"{r:.1f} MiB; shatter / {name} {sh_loop / p_loop_rate:.2f} "
                     f"({sh_whole / p_whole:.2f})")
        load_all += ld
        print(line + f"; load {min(ld):.2f}-{max(ld):.2f}")
    for key, v in ratios.items():
        print(f"shatter / {key}: median {statistics.median(v):.2f}, range "
              f"{min(v):.2f}-{max(v):.2f} ({len(v)} rounds)")
    for key, v in rss.items():
        print(f"peak RSS {key}: {min(v):.1f}-{max(v):.1f} MiB")
    if load_all:
        print(f"load {min(load_all):.2f}-{max(load_all):.2f}")


if __name__ == "__main__":
    main(sys.argv[1])

"""Fault injection of issue 33 for tests/fuzz/fuzz.py: a full disk (a tmpfs of random size as the
run directory, then more space and a resume), a stop by SIGTERM at a random moment with a cadence
of rows that is no divisor of the stop step, rows of timeseries.csv lost before a resume, and two
resumes of one checkpoint at once. Each trial ends with the run's outputs compared byte for byte
with an uninterrupted run's (the wall-clock column aside), or with the refusal it must give."""

import os
import random
import shutil
import signal
import subprocess
import time
import types

KINDS = ("disk", "stop", "rows", "concurrent")
CADENCE = ["--set", "output.timeseries_every=7"]  # the stop trials' rows


def _tmpfs(path, size):
    """Mounts (or remounts) a tmpfs of `size` at path; False where this process cannot."""
    os.makedirs(path, exist_ok=True)
    opts = ["-o", f"remount,size={size}"] if os.path.ismount(path) else ["-o", f"size={size}"]
    r = subprocess.run(["mount", "-t", "tmpfs"] + opts + ["tmpfs", path], capture_output=True)
    return r.returncode == 0


def _leftovers(out):
    bad = []
    for d, _, names in os.walk(out):
        bad += [os.path.join(d, n) for n in names if n.endswith(".tmp") or n == "shatter.lock"]
    return bad


def _finish(h, out, limit=20):
    """Resumes until the run exits 0; the failure text, or '' when it finished."""
    for _ in range(limit):
        r = h.shatter(["resume", os.path.join(out, "checkpoint.h5"), "--threads", "1", "--quiet"])
        if r.code == 0:
            return ""
        if r.code != 1:
            return f"resume exit {r.code}: {r.err[-300:]}"
    return "did not finish"


def disk_trial(h, rng):
    disk = os.path.join(h.work, "disk")
    size = f"{rng.randrange(800, 1500)}k"
    if not _tmpfs(disk, size):
        return "skipped (no tmpfs)"
    out = os.path.join(disk, "run")
    shutil.rmtree(out, ignore_errors=True)
    try:
        r = h.shatter(["run", h.tiny, "--out", out, "--threads", "1", "--quiet"])
        if r.code not in (0, 1) or (r.code == 1 and "cannot" not in r.err):
            return f"{size}: exit {r.code}: {r.err[-300:]}"
        if _leftovers(out):
            return f"{size}: left {_leftovers(out)}"
        _tmpfs(disk, "32m")
        if r.code == 1:
            if not os.path.exists(os.path.join(out, "checkpoint.h5")):
                return "before the first checkpoint"  # `run --overwrite` starts again: not a trial
            failed = _finish(h, out)
            if failed:
                return f"{size}: {failed}"
        diffs = h.compare(h.ref, h.outputs(out))
        return f"{size}: outputs differ: {diffs}" if diffs else f"{size}: identical"
    finally:
        subprocess.run(["umount", disk], capture_output=True)


def stop_trial(h, rng):
    out = os.path.join(h.work, "stopped")
    shutil.rmtree(out, ignore_errors=True)
    p = subprocess.Popen([h.binary, "run", h.tiny, "--out", out, "--threads", "1", "--quiet"]
                         + CADENCE, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    time.sleep(rng.uniform(0.05, 0.9) * h.ref_seconds)
    p.send_signal(signal.SIGTERM)
    err = p.communicate()[1].decode(errors="replace")
    if p.returncode == 0:
        return "finished before the signal"
    if p.returncode == -signal.SIGTERM and not os.path.exists(os.path.join(out, "checkpoint.h5")):
        return "stopped before the run loop (the default action: nothing to resume)"
    if p.returncode != 128 + signal.SIGTERM:
        return f"exit {p.returncode}: {err[-300:]}"
    if not os.path.exists(os.path.join(out, "checkpoint.h5")):
        return "stopped before a checkpoint could be written"
    failed = _finish(h, out)
    if failed:
        return failed
    diffs = h.compare(h.ref_cadence, h.outputs(out))
    return f"outputs differ: {diffs}" if diffs else "identical"


def rows_trial(h, rng):
    out = os.path.join(h.work, "rows")
    shutil.rmtree(out, ignore_errors=True)
    r = h.shatter(["run", h.tiny, "--out", out, "--threads", "1", "--quiet", "--set",
                   "solver.end_time=0.5e-6"])
    if r.code != 0:
        return f"run exit {r.code}"
    ts = os.path.join(out, "timeseries.csv")
    how = rng.choice(["deleted", "emptied", "truncated"])
    if how == "deleted":
        os.remove(ts)
    else:
        with open(ts, "r+b") as f:
            f.truncate(0 if how == "emptied" else rng.randrange(1, os.path.getsize(ts) // 2))
    before = open(ts, "rb").read() if os.path.exists(ts) else None
    r = h.shatter(["resume", os.path.join(out, "checkpoint.h5"), "--threads", "1", "--quiet",
                   "--set", "solver.end_time=1.0e-6"])
    after = open(ts, "rb").read() if os.path.exists(ts) else None
    if r.code != 2 or "timeseries.csv" not in r.err or before != after:
        return f"{how}: exit {r.code}, file {'kept' if before == after else 'changed'}: {r.err[-300:]}"
    return f"{how}: refused"


def concurrent_trial(h, rng):
    out = os.path.join(h.work, "twice")
    shutil.rmtree(out, ignore_errors=True)
    r = h.shatter(["run", h.tiny, "--out", out, "--threads", "1", "--quiet", "--set",
                   "solver.end_time=0.5e-6"])
    if r.code != 0:
        return f"run exit {r.code}"
    args = [h.binary, "resume", os.path.join(out, "checkpoint.h5"), "--threads", "1", "--quiet",
            "--set", "solver.end_time=1.0e-6"]
    first = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    time.sleep(rng.uniform(0.0, 0.3) * h.ref_seconds)
    second = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    codes = sorted([first.wait(), second.wait()])
    if codes not in ([0, 0], [0, 2]):
        return f"exit codes {codes}"
    # scene.toml's header records the first run's --set of the end time
    diffs = [d for d in h.compare(h.ref, h.outputs(out)) if d != "scene.toml"]
    return f"{codes}: outputs differ: {diffs}" if diffs else f"{codes}: identical"


GOOD = ("identical", "refused", "skipped", "finished before", "stopped before",
        "before the first")


def fault_trials(h, trials, seed, verbose=False):
    """Runs `trials` random trials; returns (outcome counts, failures)."""
    rng = random.Random(seed)
    counts, failures = {}, []
    run = {"disk": disk_trial, "stop": stop_trial, "rows": rows_trial,
           "concurrent": concurrent_trial}
    for k in range(trials):
        kind = KINDS[k % len(KINDS)]
        outcome = run[kind](h, rng)
        good = any(g in outcome for g in GOOD) and "differ" not in outcome
        key = f"{kind}: {'ok' if good else 'FAILED'}"
        counts[key] = counts.get(key, 0) + 1
        if not good:
            failures.append(f"fault {k} ({kind}): {outcome}")
        elif verbose:
            print(f"  fault {k} ({kind}): {outcome}")
    return counts, failures


def part(binary, work, tiny, ref, ref_seconds, shatter, outputs, compare, trials, seed):
    """fuzz.py's fault part: a reference run with the stop trials' cadence, then the trials."""
    ref_cadence = os.path.join(work, "reference_cadence")
    shatter(binary, ["run", tiny, "--out", ref_cadence, "--threads", "1", "--quiet"] + CADENCE,
            cwd=work)
    h = types.SimpleNamespace(
        binary=binary, work=work, tiny=tiny, ref=ref, ref_seconds=ref_seconds,
        ref_cadence=outputs(ref_cadence), outputs=outputs, compare=compare,
        shatter=lambda args: shatter(binary, args, cwd=work))
    return fault_trials(h, trials, seed, verbose=True)

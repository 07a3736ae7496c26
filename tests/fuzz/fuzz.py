#!/usr/bin/env python3
"""Fuzzing and fault injection for `shatter` (issue 14; docs/reliability.md).

Runs the built program as a hostile user would and checks, for every case, that it
  - does not crash (no signal, no exit status other than 0, 2 or 3),
  - does not hang (each case under a timeout; a run still advancing in simulated time when the
    timeout strikes is a long run, not a hang),
  - does not fail silently (exit 2 and 3 print an error; exit 3 leaves a post-mortem snapshot),
  - writes no corrupt output (what an accepted run wrote reads back with its checksums), and
  - names the key at fault (a refused scene mutation names the mutated key, or at least its
    table, together with the file and line or the command line).

Parts:
  scenes   every key of every shipped scene mutated (nan, inf, huge, tiny, negative, zero, wrong
           type, deleted, misspelt; table headers misspelt): `run --check` for the shipped scenes,
           a full run for tests/fuzz/tiny.toml
  junk     whole files of junk given as the scene (random bytes, NULs, deep nesting, a
           directory, a FIFO, an HDF5 file, ...)
  cli      extreme command-line values (--threads, --set, --out, resume, fragments, material)
  kills    SIGKILL at random moments of a run and of its resumes, until it finishes; every output
           byte-compared with an uninterrupted run (the wall-clock column of timeseries.csv aside)
  corrupt  random bytes of a checkpoint flipped: the resume refuses it naming the dataset, or
           (flip in unused bytes) finishes byte-identical
  faults   (tests/fuzz/faults.py, issue 33) a full disk, SIGTERM then resume, lost time-series
           rows, two resumes at once

Bounded (CI): `fuzz.py --shatter BIN --cases 150 --kills 4` (a seeded sample of the scene
cases). Long (before a release): `fuzz.py --shatter BIN --long` (every case, 100 kill loops,
20 corruptions), see docs/reliability.md.
"""

import argparse
import concurrent.futures
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import faults  # noqa: E402  (tests/fuzz/faults.py)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
TIMEOUT = 20.0  # s per case: the tiny run takes ~0.5 s in Release, ~10 s under ASan

# ---------------------------------------------------------------------------------------------
# Running shatter


class Result:
    def __init__(self, code, out, err, seconds, timed_out):
        self.code, self.out, self.err, self.seconds, self.timed_out = code, out, err, seconds, timed_out


def shatter(binary, args, cwd, timeout=TIMEOUT, env=None):
    t0 = time.monotonic()
    p = subprocess.Popen([binary] + args, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=env, start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        timed_out = True
    return Result(p.returncode, out.decode(errors="replace"), err.decode(errors="replace"),
                  time.monotonic() - t0, timed_out)


def advancing(out_dir):
    """True when the run's time series has at least two rows with increasing time."""
    try:
        with open(os.path.join(out_dir, "timeseries.csv")) as f:
            rows = [l.split(",") for l in f.read().splitlines()[1:]]
        times = [float(r[1]) for r in rows if len(r) > 2]
        return len(times) >= 2 and times[-1] > times[0]
    except (OSError, ValueError):
        return False


# ---------------------------------------------------------------------------------------------
# Output verification: what an accepted run wrote must read back.

try:
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import shatter_plot  # noqa: E402  (h5py and numpy; the snapshot checksum check)
except ImportError:
    shatter_plot = None


def verify_outputs(binary, out_dir, tmp):
    """Empty string when the run directory reads back, else what is wrong."""
    ts = os.path.join(out_dir, "timeseries.csv")
    if not os.path.exists(ts):
        return "no timeseries.csv"
    with open(ts) as f:
        lines = f.read().split("\n")
    if lines[-1] != "":
        return "timeseries.csv does not end with a newline"
    header = lines[0].split(",")
    for l in lines[1:-1]:
        if len(l.split(",")) != len(header):
            return f"torn timeseries row: {l[:60]}"
    snaps = sorted(os.listdir(os.path.join(out_dir, "snapshots")))
    if not snaps:
        return "no snapshot"
    last = os.path.join(out_dir, "snapshots", snaps[-1])
    if shatter_plot is not None:
        for s in snaps:
            try:
                shatter_plot.read_snapshot(os.path.join(out_dir, "snapshots", s))
            except Exception as e:  # noqa: BLE001
                return f"snapshot {s} does not read back: {e}"
    # The C++ reader (checksums verified) through a command that reads a snapshot.
    r = shatter(binary, ["fragments", last, "--prefix", os.path.join(tmp, "verify"), "--quiet"],
                cwd=tmp)
    if r.code != 0:
        return f"`shatter fragments` refuses {last}: {r.err.strip()[-300:]}"
    return ""


# ---------------------------------------------------------------------------------------------
# Scene mutations

KEY_LINE = re.compile(r"^(\s*)([A-Za-z0-9_]+)(\s*=\s*)(.*)$")
HEADER_LINE = re.compile(r"^\s*\[([A-Za-z0-9_.]+)\]\s*(#.*)?$")


def split_comment(value):
    """(value, comment) with a trailing # comment outside quotes split off."""
    quote = None
    for i, c in enumerate(value):
        if quote:
            if c == quote:
                quote = None
        elif c in "\"'":
            quote = c
        elif c == "#":
            return value[:i].rstrip(), value[i:]
    return value.rstrip(), ""


def kind_of(value):
    if value.startswith("{"):
        return "table"
    if value.startswith("["):
        return "array" if value.endswith("]") else None  # multi-line arrays are left alone
    if value.startswith('"') or value.startswith("'"):
        return "string"
    if value in ("true", "false"):
        return "bool"
    return "number"


def misspell(key):
    if len(key) >= 4:
        return key[:1] + key[2] + key[1] + key[3:]
    return key + "x"


MUTATIONS = {
    "number": [("nan", "nan"), ("inf", "inf"), ("-inf", "-inf"), ("huge", "1.0e300"),
               ("-huge", "-1.0e300"), ("tiny", "1.0e-300"), ("negative", "-1.0"), ("zero", "0"),
               ("wrong type", '"x"')],
    "string": [("wrong type", "1.0"), ("empty", '""'), ("unknown", '"zzz_unknown"')],
    "bool": [("wrong type", "1")],
    "array": [("nan", "[nan, 0.0, 0.0]"), ("inf", "[inf, 0.0, 0.0]"),
              ("huge", "[1.0e300, 1.0e300, 1.0e300]"), ("tiny", "[1.0e-300, 0.0, 0.0]"),
              ("wrong length", "[1.0, 2.0]"), ("wrong type", '"x"'), ("empty", "[]")],
    "table": [("wrong type", "1.0")],
}


def scene_cases(path):
    """(label, key path, mutated text) for every key line and table header of the scene."""
    with open(path) as f:
        lines = f.read().split("\n")
    table = ""
    cases = []
    for i, line in enumerate(lines):
        h = HEADER_LINE.match(line)
        if h:
            table = h.group(1)
            parts = table.split(".")
            bad = ".".join(parts[:-1] + [misspell(parts[-1])])
            mutated = lines[:i] + [line.replace("[" + table + "]", "[" + bad + "]")] + lines[i + 1:]
            cases.append((f"[{table}] misspelt", table, "\n".join(mutated)))
            continue
        m = KEY_LINE.match(line)
        if not m or line.lstrip().startswith("#"):
            continue
        indent, key, eq, rest = m.groups()
        value, comment = split_comment(rest)
        kind = kind_of(value)
        if kind is None:
            continue
        dotted = f"{table}.{key}" if table else key
        variants = [(name, indent + key + eq + v + (" " + comment if comment else ""))
                    for name, v in MUTATIONS[kind]]
        variants.append(("deleted", None))
        variants.append(("misspelt", indent + misspell(key) + eq + rest))
        for name, new in variants:
            mutated = lines[:i] + ([] if new is None else [new]) + lines[i + 1:]
            cases.append((f"{dotted} {name}", dotted, "\n".join(mutated)))
    return cases


def shipped_scenes():
    out = []
    for d, _, files in os.walk(os.path.join(ROOT, "scenes")):
        for f in sorted(files):
            if f.endswith(".toml") and f != "materials.toml":
                out.append(os.path.relpath(os.path.join(d, f), ROOT))
    return sorted(out)


SCENE_ERROR = re.compile(r"(\.toml:\d+|command line \(--set [^)]*\)|\.toml): ([A-Za-z0-9_.\[\]]+): ")


def names_key(err, dotted):
    """'key' when the message names the key (dotted path or leaf), 'table' when only its table,
    'other' when it names another key in the scene-error format (file:line: key: ...), a
    consequence of the mutation (a deleted symmetry plane puts a body outside the domain); ''
    when it names no key or no place."""
    if not re.search(r"(\.toml:\d+|command line|\.toml: )", err):
        return ""
    leaf = dotted.split(".")[-1]
    if dotted in err or re.search(r"\b" + re.escape(leaf) + r"\b", err):
        return "key"
    table = ".".join(dotted.split(".")[:-1])
    if table and table in err:
        return "table"
    if SCENE_ERROR.search(err):
        return "other"
    return ""


class Tally:
    def __init__(self):
        self.counts = {}
        self.failures = []
        self.table_only = []

    def add(self, outcome):
        self.counts[outcome] = self.counts.get(outcome, 0) + 1

    def fail(self, label, why):
        self.failures.append(f"{label}: {why}")


def run_scene_case(binary, tree, scene_rel, label, dotted, text, full_run, tally):
    scene_dir = os.path.join(tree, os.path.dirname(scene_rel))
    fd, path = tempfile.mkstemp(suffix=".toml", prefix="fuzz_", dir=scene_dir)
    os.close(fd)
    with open(path, "w") as f:
        f.write(text)
    case_dir = tempfile.mkdtemp(prefix="case_", dir=tree)
    out = os.path.join(case_dir, "out")
    try:
        args = ["run", path, "--out", out, "--threads", "1"]
        if not full_run:
            args.append("--check")
        r = shatter(binary, args, cwd=case_dir)
        where = f"{scene_rel} {label}"
        if r.timed_out:
            if full_run and advancing(out):
                tally.add("long run (advancing at the timeout)")
            else:
                tally.fail(where, f"hang: no progress within {TIMEOUT:.0f} s")
            return
        if r.code == 0:
            tally.add("accepted")
            if full_run:
                bad = verify_outputs(binary, out, case_dir)
                if bad:
                    tally.fail(where, "accepted, but " + bad)
        elif r.code == 2:
            named = names_key(r.err, dotted)
            if named == "key":
                tally.add("refused, names the key")
            elif named in ("table", "other"):
                tally.add("refused, names the key's table" if named == "table" else
                          "refused, names the key it conflicts with")
                tally.table_only.append(f"{where}: {r.err.strip().splitlines()[-1][:200]}")
            else:
                tally.fail(where, "refused without naming the key: " + r.err.strip()[-300:])
        elif r.code == 3:
            tally.add("stopped by the guard (exit 3)")
            if "numerical failure" not in r.err or not any(
                    n.startswith("failed_step") for n in os.listdir(out)):
                tally.fail(where, "exit 3 without message or post-mortem file: " + r.err[-300:])
        else:
            tally.fail(where, f"exit status {r.code}: " + r.err.strip()[-400:])
    finally:
        os.remove(path)
        shutil.rmtree(case_dir, ignore_errors=True)


# ---------------------------------------------------------------------------------------------
# Junk files and command-line extremes


def junk_cases(tree, rng):
    d = os.path.join(tree, "junk")
    os.makedirs(d, exist_ok=True)

    def put(name, data):
        p = os.path.join(d, name)
        with open(p, "wb") as f:
            f.write(data)
        return p

    cases = [
        ("empty file", put("empty.toml", b"")),
        ("random bytes", put("random.toml", bytes(rng.randrange(256) for _ in range(4096)))),
        ("NUL bytes", put("nul.toml", b"\0" * 1000)),
        ("one long line", put("long.toml", b"a" * 1_000_000)),
        ("deep nesting", put("deep.toml", b"a = " + b"[" * 100000 + b"]" * 100000)),
        ("unterminated string", put("unterminated.toml", b'name = "abc\n[solver]\n')),
        ("huge integer", put("int.toml", b"[solver]\ncell_size = 99999999999999999999999999\n")),
        ("duplicate key", put("dup.toml", b"[solver]\ncell_size = 1.0\ncell_size = 2.0\n")),
        ("invalid UTF-8", put("utf8.toml", b'name = "\xff\xfe"\n')),
        ("valid TOML, not a scene", put("other.toml", b'[package]\nname = "x"\n')),
        ("a directory", d),
        ("no such file", os.path.join(d, "missing.toml")),
    ]
    fifo = os.path.join(d, "fifo.toml")
    os.mkfifo(fifo)
    cases.append(("a FIFO", fifo))
    return cases


def cli_cases(tiny, out, checkpoint, snapshot, junk_file):
    r = ["run", tiny, "--out", out, "--overwrite"]
    return [
        (r + ["--threads", "999999999"], (0, 2)),
        (r + ["--threads", "-1"], (2,)),
        (r + ["--threads", "abc"], (2,)),
        (r + ["--set", "noequals"], (2,)),
        (r + ["--set", "solver..cell_size=1"], (2,)),
        (r + ["--set", "=1"], (2,)),
        (r + ["--set", "solver.end_time=1e400"], (2,)),
        (r + ["--set", "solver.end_time.x=1"], (2,)),
        (r + ["--set", "body.target.material.young=-1"], (2,)),
        (r + ["--set", "output.snapshot_every=1e-300"], (2,)),
        (["run", tiny, "--out", junk_file], (1, 2)),
        (["resume", os.path.join(out, "nothing.h5")], (2,)),
        (["resume", tiny], (2,)),
        (["resume", junk_file], (2,)),
        (["resume", checkpoint, "--set", "solver.cfl=0.5"], (2,)),
        (["resume", checkpoint, "--set", "solver.end_time=-1"], (2,)),
        (["fragments", junk_file], (1, 2)),
        (["fragments", snapshot, "--threshold", "nan", "--prefix", out + "/f"], (1, 2)),
        (["fragments", snapshot, "--method", "nonsense", "--prefix", out + "/f"], (1, 2)),
        (["material", "basalt", "--rho", "nan"], (2,)),
        (["material", "basalt", "--rho", "1e308", "--energy", "1e308"], (0, 2)),
        (["material", "basalt", "--hugoniot", "1e300", "--points", "2000000000"], (0, 2)),
        (["material", "nonsense"], (2,)),
        (["material", "basalt", "--catalogue", junk_file], (2,)),
        (["--threads"], (2,)),
        ([], (2,)),
    ]


# ---------------------------------------------------------------------------------------------
# Kill and resume


def outputs(out_dir):
    files = {}
    for d, _, names in os.walk(out_dir):
        for n in names:
            p = os.path.join(d, n)
            rel = os.path.relpath(p, out_dir)
            with open(p, "rb") as f:
                data = f.read()
            if rel == "timeseries.csv":  # the wall-clock column aside
                data = b"\n".join(l.rsplit(b",", 1)[0] for l in data.split(b"\n"))
            files[rel] = data
    return files


def compare(ref, got):
    diffs = [k for k in sorted(set(ref) | set(got)) if ref.get(k) != got.get(k)]
    return diffs


# Kill loops alternate between the tiny scene as it is and a variant whose target moves at 8 km/s
# towards an outflow face 2 mm away, so particles leave before most checkpoints (the internal
# energy then has to come from the checkpoint to continue bit for bit).
OUTFLOW = ["--set", "domain.hi=[0.012,0.05,0.05]", "--set", "body.target.velocity=[8000.0,0.0,0.0]"]


def kill_loop(binary, tiny, work, ref, ref_seconds, rng, label, extra=()):
    """Kills the run at random moments, resumes until it completes; returns (kills, resumes,
    differing files)."""
    out = os.path.join(work, label)
    kills = resumes = 0
    started = False
    for attempt in range(60):
        cp = os.path.join(out, "checkpoint.h5")
        if started and os.path.exists(cp):
            args = ["resume", cp, "--threads", "1", "--quiet"]
            resumes += 1
        else:
            args = ["run", tiny, "--out", out, "--overwrite", "--threads", "1", "--quiet"]
            args += list(extra)
        started = True
        # Kill while the run is alive in 3 of 4 attempts, let it finish in the 4th.
        delay = rng.uniform(0.0, 1.2 * ref_seconds) if attempt % 4 != 3 else None
        p = subprocess.Popen([binary] + args, cwd=work, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, start_new_session=True)
        if delay is not None:
            try:
                p.wait(timeout=delay)
            except subprocess.TimeoutExpired:
                p.send_signal(signal.SIGKILL)
                p.wait()
                kills += 1
                continue
        try:
            _, err = p.communicate(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            return kills, resumes, ["hang"]
        if p.returncode == 0 and os.path.exists(os.path.join(out, "fragments.csv")):
            # A resume at the end time completes the last outputs and exits 0: the run is done
            # when it exits 0 from a run or a resume.
            return kills, resumes, compare(ref, outputs(out))
        if p.returncode not in (0,):
            return kills, resumes, [f"exit {p.returncode}: {err.decode()[-300:]}"]
    return kills, resumes, ["did not finish in 60 attempts"]


def corrupt_trial(binary, tiny, work, rng, label, ref_mid):
    """Runs to a checkpoint, flips bytes in it, resumes: refused naming what is corrupt, or
    (bytes HDF5 does not read) a byte-identical finish."""
    out = os.path.join(work, label)
    r = shatter(binary, ["run", tiny, "--out", out, "--overwrite", "--threads", "1", "--quiet",
                         "--set", "solver.end_time=0.5e-6"], cwd=work)
    if r.code != 0:
        return f"setup run failed: {r.err[-300:]}"
    cp = os.path.join(out, "checkpoint.h5")
    data = bytearray(open(cp, "rb").read())
    n = rng.choice([1, 8, 64])
    start = rng.randrange(len(data) - n)
    for i in range(start, start + n):
        data[i] ^= 0xFF
    open(cp, "wb").write(bytes(data))
    r = shatter(binary, ["resume", cp, "--threads", "1", "--quiet", "--set",
                         "solver.end_time=1.0e-6"], cwd=work)
    if r.timed_out:
        return "hang on a corrupt checkpoint"
    if r.code == 2:
        if "checkpoint.h5" not in r.err:
            return "refused without naming the file: " + r.err[-300:]
        return "refused"
    if r.code == 0:
        # Accepted: the flipped bytes were unused by the reader; the state must then be intact.
        got = outputs(out)
        diffs = [k for k in ref_mid if k.startswith("snapshots/") and got.get(k) != ref_mid[k]]
        return "accepted, identical" if not diffs else f"accepted a corrupt checkpoint: {diffs}"
    return f"exit {r.code}: {r.err[-300:]}"


# ---------------------------------------------------------------------------------------------


def main():
    global TIMEOUT
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--shatter", required=True, help="the built shatter program")
    ap.add_argument("--cases", type=int, default=int(os.environ.get("SHATTER_FUZZ_CASES", "150")),
                    help="scene mutations to run, a seeded sample (0 = all); env SHATTER_FUZZ_CASES")
    ap.add_argument("--kills", type=int, default=4, help="kill-and-resume loops")
    ap.add_argument("--corruptions", type=int, default=3, help="corrupt-checkpoint trials")
    ap.add_argument("--faults", type=int, default=4, help="fault-injection trials (faults.py)")
    ap.add_argument("--long", action="store_true",
                    help="every case, 100 kill loops, 20 corruptions, 40 faults (before a release)")
    ap.add_argument("--seed", type=int, default=14)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=20.0, help="s per case")
    ap.add_argument("--keep", action="store_true", help="keep the work directory")
    a = ap.parse_args()
    TIMEOUT = a.timeout
    if a.long:
        a.cases, a.kills, a.corruptions = 0, max(a.kills, 100), max(a.corruptions, 20)
        a.faults = max(a.faults, 40)
    binary = os.path.abspath(a.shatter)
    rng = random.Random(a.seed)
    t_start = time.monotonic()

    work = tempfile.mkdtemp(prefix="shatter_fuzz_")
    tree = os.path.join(work, "tree")
    shutil.copytree(os.path.join(ROOT, "scenes"), os.path.join(tree, "scenes"))
    shutil.copytree(os.path.join(ROOT, "data"), os.path.join(tree, "data"))
    os.makedirs(os.path.join(tree, "tests", "fuzz"))
    tiny_rel = os.path.join("tests", "fuzz", "tiny.toml")
    shutil.copy(os.path.join(ROOT, tiny_rel), os.path.join(tree, tiny_rel))
    tiny = os.path.join(tree, tiny_rel)
    tally = Tally()

    # --- scenes
    all_cases = []
    for s in [tiny_rel] + shipped_scenes():
        for label, dotted, text in scene_cases(os.path.join(tree, s)):
            all_cases.append((s, label, dotted, text, s == tiny_rel))
    total = len(all_cases)
    if a.cases and a.cases < total:
        # Every tiny-scene key keeps at least its nan and deleted cases; the rest is sampled.
        rng_cases = random.Random(a.seed)
        must = [c for c in all_cases if c[4] and (c[1].endswith(" nan") or c[1].endswith(" deleted"))]
        rest = [c for c in all_cases if c not in must]
        chosen = must[:a.cases] + rng_cases.sample(rest, max(0, a.cases - len(must)))
    else:
        chosen = all_cases
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as ex:
        list(ex.map(lambda c: run_scene_case(binary, tree, c[0], c[1], c[2], c[3], c[4], tally),
                    chosen))
    print(f"scene mutations: {len(chosen)} of {total} cases ({len(shipped_scenes())} shipped "
          f"scenes + tiny.toml), {time.monotonic() - t_start:.1f} s")
    for k, v in sorted(tally.counts.items()):
        print(f"  {v:5d}  {k}")
    n_scene_fail = len(tally.failures)

    # --- junk files
    t0 = time.monotonic()
    junk = junk_cases(work, rng)
    for label, path in junk:
        r = shatter(binary, ["run", path, "--out", os.path.join(work, "junk_out")], cwd=work,
                    timeout=10.0)
        if r.timed_out:
            tally.fail(f"junk: {label}", "hang")
        elif r.code != 2:
            tally.fail(f"junk: {label}", f"exit {r.code}: {r.err[-300:]}")
        elif os.path.basename(path) not in r.err and path not in r.err:
            tally.fail(f"junk: {label}", "message does not name the file: " + r.err[-300:])
    print(f"junk files: {len(junk)} cases, {time.monotonic() - t0:.1f} s")

    # --- reference run (kill loops, CLI cases and corruption compare against it)
    ref_dir = os.path.join(work, "reference")
    r = shatter(binary, ["run", tiny, "--out", ref_dir, "--threads", "1", "--quiet"], cwd=work)
    if r.code != 0:
        print("reference run failed:", r.err)
        return 1
    ref = outputs(ref_dir)
    ref_seconds = r.seconds
    ref_outflow_dir = os.path.join(work, "reference_outflow")
    r = shatter(binary, ["run", tiny, "--out", ref_outflow_dir, "--threads", "1", "--quiet"]
                + OUTFLOW, cwd=work)
    if r.code != 0:
        print("reference run (outflow) failed:", r.err)
        return 1
    ref_outflow = outputs(ref_outflow_dir)
    bad = verify_outputs(binary, ref_dir, work)
    if bad:
        tally.fail("reference run", bad)

    # --- command line
    t0 = time.monotonic()
    cli_out = os.path.join(work, "cli_out")
    snapshot = os.path.join(ref_dir, "snapshots", sorted(os.listdir(
        os.path.join(ref_dir, "snapshots")))[-1])
    cases = cli_cases(tiny, cli_out, os.path.join(ref_dir, "checkpoint.h5"), snapshot,
                      os.path.join(work, "junk", "random.toml"))
    for args, allowed in cases:
        r = shatter(binary, args, cwd=work)
        label = "cli: shatter " + " ".join(os.path.basename(x) if os.sep in x else x for x in args)
        if r.timed_out:
            tally.fail(label, "hang")
        elif r.code not in allowed:
            tally.fail(label, f"exit {r.code} (expected {allowed}): {r.err[-300:]}")
        elif r.code != 0 and not r.err.strip() and not r.out.strip():
            tally.fail(label, "refused silently")
    print(f"command line: {len(cases)} cases, {time.monotonic() - t0:.1f} s")

    # --- kill and resume
    t0 = time.monotonic()
    kills = resumes = identical = 0
    for k in range(a.kills):
        if k % 2 == 0:
            nk, nr, diffs = kill_loop(binary, tiny, work, ref, ref_seconds, rng, f"kill{k}")
        else:
            nk, nr, diffs = kill_loop(binary, tiny, work, ref_outflow, ref_seconds, rng,
                                      f"kill{k}", OUTFLOW)
        kills += nk
        resumes += nr
        if diffs:
            tally.fail(f"kill loop {k} ({nk} kills, {nr} resumes)", f"outputs differ: {diffs}")
        else:
            identical += 1
        shutil.rmtree(os.path.join(work, f"kill{k}"), ignore_errors=True)
    print(f"kill and resume: {a.kills} loops, {kills} SIGKILLs, {resumes} resumes, "
          f"{identical} of {a.kills} finished byte-identical to the uninterrupted run, "
          f"{time.monotonic() - t0:.1f} s")

    # --- corrupt checkpoints
    t0 = time.monotonic()
    if a.corruptions:
        mid = os.path.join(work, "mid")
        shatter(binary, ["run", tiny, "--out", mid, "--threads", "1", "--quiet"], cwd=work)
        ref_mid = outputs(mid)
        outcomes = {}
        for k in range(a.corruptions):
            o = corrupt_trial(binary, tiny, work, rng, f"corrupt{k}", ref_mid)
            outcomes[o.split(":")[0]] = outcomes.get(o.split(":")[0], 0) + 1
            if not (o == "refused" or o == "accepted, identical"):
                tally.fail(f"corrupt checkpoint {k}", o)
        print(f"corrupt checkpoints: {a.corruptions} trials: {outcomes}, "
              f"{time.monotonic() - t0:.1f} s")
        # Snapshots: the C++ reader (through `shatter fragments`) and tools/shatter_plot.py.
        snap = os.path.join(work, "corrupt_snapshot.h5")
        shutil.copy(snapshot, snap)
        data = bytearray(open(snap, "rb").read())
        at = rng.randrange(len(data) // 2, len(data) - 64)  # the data arrays lie after the header
        for i in range(at, at + 64):
            data[i] ^= 0xFF
        open(snap, "wb").write(bytes(data))
        r = shatter(binary, ["fragments", snap, "--prefix", os.path.join(work, "cs"), "--quiet"],
                    cwd=work)
        cxx = "refused" if r.code != 0 and "corrupt_snapshot.h5" in r.err else f"exit {r.code}"
        py = "no h5py"
        if shatter_plot is not None:
            try:
                shatter_plot.read_snapshot(snap)
                py = "read"
            except Exception:  # noqa: BLE001  (CorruptSnapshot, or HDF5's own error)
                py = "refused"
        print(f"corrupt snapshot (64 bytes at {at} of {len(data)}): C++ reader {cxx}, "
              f"shatter_plot.py {py}")
        # Bytes the readers never touch (padding, free space) may be flipped without effect;
        # then both must read it, otherwise both must refuse it.
        if cxx not in ("refused", "exit 0") or (py != "no h5py" and (py == "read") != (cxx == "exit 0")):
            tally.fail("corrupt snapshot", f"C++ reader {cxx}, shatter_plot.py {py}: {r.err[-300:]}")

    # --- fault injection (issue 33)
    if a.faults:
        t0 = time.monotonic()
        counts, failures = faults.part(binary, work, tiny, ref, ref_seconds, shatter, outputs,
                                       compare, a.faults, a.seed)
        for f in failures:
            tally.fail(f.split(":")[0], f.split(":", 1)[1])
        print(f"faults: {a.faults} trials: {counts}, {time.monotonic() - t0:.1f} s")

    if tally.table_only:
        print(f"refusals naming the key's table or another key ({len(tally.table_only)}), e.g.:")
        for t in tally.table_only[:5]:
            print("   ", t)
    print(f"total {time.monotonic() - t_start:.1f} s")
    if not a.keep:
        shutil.rmtree(work, ignore_errors=True)
    else:
        print("work directory:", work)
    if tally.failures:
        print(f"\n{len(tally.failures)} FAILURES ({n_scene_fail} in scene mutations):")
        for f in tally.failures:
            print("  ", f)
        return 1
    print("no failures")
    return 0


if __name__ == "__main__":
    sys.exit(main())

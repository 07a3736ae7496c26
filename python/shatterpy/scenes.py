"""Write a scene from a dict, check it with `shatter check`, and run it.

    import shatterpy.scenes as ss
    scene = ss.load("scenes/lab-impact.toml")          # or build the dict yourself
    scene["impact"]["speed"] = 4000.0
    ss.check(scene)                                     # raises SceneError with shatter's message
    run_dir = ss.run(scene, "out/fast", threads=2)      # returns the run directory

The TOML is written here (Python's standard library reads TOML but does not write it): tables,
arrays of tables, arrays, strings, booleans, integers and floats, which is everything a scene
holds. The `shatter` program is the one given, else $SHATTER_BINARY, else `shatter` on the PATH.
"""

import json
import math
import os
import shutil
import subprocess
import tempfile
import tomllib

__all__ = ["SceneError", "to_toml", "write", "load", "check", "run", "shatter_binary"]


class SceneError(ValueError):
    """`shatter check` or `shatter run` refused a scene; the message is shatter's."""


def shatter_binary(binary=None):
    path = binary or os.environ.get("SHATTER_BINARY") or shutil.which("shatter")
    if not path or not os.access(path, os.X_OK):
        raise FileNotFoundError("no shatter program: pass binary=, set $SHATTER_BINARY or put "
                                "shatter on the PATH")
    return path


def _key(k):
    if not isinstance(k, str):
        raise TypeError(f"scene keys are strings, not {k!r}")
    bare = k and all(c.isalnum() or c in "_-" for c in k)
    return k if bare else json.dumps(k)


def _value(v, where):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise ValueError(f"{where}: {v} is not a finite number (TOML scenes need one)")
        return repr(v)  # shortest text that reads back as the same double
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)  # a TOML basic string: same escapes
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x, where) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x, where)}" for k, x in v.items()) + "}"
    raise TypeError(f"{where}: cannot write {type(v).__name__} {v!r} to TOML")


def _is_table_array(v):
    return isinstance(v, (list, tuple)) and v and all(isinstance(x, dict) for x in v)


def _table(lines, table, path):
    # Plain keys first, then sub-tables and arrays of tables (TOML's order rule).
    for k, v in table.items():
        if not isinstance(v, dict) and not _is_table_array(v):
            lines.append(f"{_key(k)} = {_value(v, '.'.join(path + [k]))}")
    for k, v in table.items():
        sub = path + [k]
        name = ".".join(_key(p) for p in sub)
        if isinstance(v, dict):
            lines.append("")
            lines.append(f"[{name}]")
            _table(lines, v, sub)
        elif _is_table_array(v):
            for item in v:
                lines.append("")
                lines.append(f"[[{name}]]")
                _table(lines, item, sub)


def to_toml(scene):
    """The scene dict as TOML text (tomllib.loads gives the dict back)."""
    lines = []
    _table(lines, scene, [])
    return "\n".join(lines).lstrip("\n") + "\n"


def write(scene, path):
    with open(path, "w") as f:
        f.write(to_toml(scene))
    return path


def load(path):
    with open(path, "rb") as f:
        return tomllib.load(f)


def _scene_file(scene, where):
    """(path, temporary?) of a scene given as a dict or a file name."""
    if isinstance(scene, dict):
        fd, path = tempfile.mkstemp(suffix=".toml", prefix="scene_", dir=where)
        with os.fdopen(fd, "w") as f:
            f.write(to_toml(scene))
        return path, True
    return os.fspath(scene), False


def check(scene, binary=None, base_dir=None):
    """Runs `shatter check` on the scene (a dict, or a file). A dict is written into base_dir
    (default: the working directory), where its relative file names (meshes, catalogue) are
    found. Returns shatter's report; raises SceneError with its message when refused."""
    path, temporary = _scene_file(scene, base_dir or os.getcwd())
    try:
        r = subprocess.run([shatter_binary(binary), "check", path], capture_output=True,
                           text=True)
    finally:
        if temporary:
            os.remove(path)
    if r.returncode != 0:
        raise SceneError((r.stderr or r.stdout).strip())
    return r.stdout


def run(scene, out, binary=None, threads=1, sets=(), overwrite=False, quiet=True):
    """Runs the scene (a dict, or a file) into the directory `out` and returns its path. A dict
    is first written to OUT.toml beside the run directory (kept: the run's own record is
    OUT/scene.toml). Raises SceneError with shatter's message when the run fails."""
    out = os.fspath(out)
    if isinstance(scene, dict):
        os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
        path = write(scene, out.rstrip("/") + ".toml")
    else:
        path = os.fspath(scene)
    cmd = [shatter_binary(binary), "run", path, "--out", out, "--threads", str(threads)]
    for s in sets:
        cmd += ["--set", s]
    if overwrite:
        cmd.append("--overwrite")
    if quiet:
        cmd.append("--quiet")
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SceneError((r.stderr or r.stdout).strip())
    return out

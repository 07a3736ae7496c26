#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then the installed program run from there, away from
# the source and build trees (issue 13 item 8): it must find the installed catalogue
# (PREFIX/share/shatter/materials.toml, not the source tree's), check and run an installed example
# scene; the Python package, when the tree has one, must be importable from the prefix.
# Usage: install_test.sh CMAKE BUILD_DIR SOURCE_DIR
set -euo pipefail
cmake=$1 build=$2 source=$3
prefix=$(mktemp -d "${TMPDIR:-/tmp}/shatter_install.XXXXXX")
trap 'rm -rf "$prefix"' EXIT
"$cmake" --install "$build" --prefix "$prefix" >/dev/null

fail() { echo "install test: $*" >&2; exit 1; }
bin=$prefix/bin/shatter
[ -x "$bin" ] || fail "no $bin"
[ -f "$prefix/share/shatter/materials.toml" ] || fail "no share/shatter/materials.toml"
cd "$prefix"

# The catalogue the program loads is the installed one.
log=$("$bin" material --list 2>&1 >/dev/null)
grep -qF "catalogue $prefix/share/shatter/materials.toml" <<<"$log" ||
  fail "material --list did not load the installed catalogue: $log"

# A scene from the installed examples, coarsened to ~4 000 points and 3 steps.
scene=share/shatter/scenes/examples/iron-on-basalt-1km.toml
coarse=(--set solver.cell_size=80.0 --set solver.end_time=0.004)
"$bin" check "$scene" "${coarse[@]}" --threads 1 >check.txt || fail "check refused $scene"
grep -q "^points: " check.txt || fail "check printed no points: $(cat check.txt)"
"$bin" run "$scene" "${coarse[@]}" --out run --threads 1 --quiet || fail "run failed"
[ -f run/checkpoint.h5 ] && [ -f run/particles.xmf ] || fail "run wrote no checkpoint/snapshots"

# An explicit SHATTER_DATA_DIR that holds no catalogue is an error naming it.
if SHATTER_DATA_DIR=/nonexistent "$bin" material --list >/dev/null 2>err.txt; then
  fail "SHATTER_DATA_DIR=/nonexistent was accepted"
fi
grep -q "SHATTER_DATA_DIR=/nonexistent" err.txt || fail "unclear error: $(cat err.txt)"

if [ -d "$source/python/shatterpy" ]; then
  site=$(ls -d "$prefix"/lib*/python*/site-packages 2>/dev/null | head -1)
  [ -f "$site/shatterpy/__init__.py" ] || fail "shatterpy not installed under lib*/python*/site-packages"
  where=$(PYTHONPATH=$site /usr/bin/python3 -c 'import shatterpy; print(shatterpy.__file__)') ||
    fail "import shatterpy failed from $site"
  [[ $where == "$site"/* ]] || fail "shatterpy imported from $where, not the prefix"
fi
# The user's tools: every tools/*.py installed (side by side: they import each other), each
# answering --help from the prefix with the installed shatterpy on PYTHONPATH (the plot tools
# import it); the shell scripts and the studies stay in the source tree.
tools=$prefix/share/shatter/tools
site=$(ls -d "$prefix"/lib*/python*/site-packages 2>/dev/null | head -1)
for tool in "$source"/tools/*.py; do
  name=$(basename "$tool")
  [ -x "$tools/$name" ] || fail "tool $name not installed (executable) in $tools"
  out=$(PYTHONPATH=$site MPLBACKEND=Agg /usr/bin/python3 "$tools/$name" --help 2>&1) || fail "$name --help: $out"
  [[ $out == usage:* ]] || fail "$name --help printed no usage: ${out:0:200}"
done
[ -z "$(ls "$tools"/*.sh 2>/dev/null)" ] || fail "developer scripts installed: $(ls "$tools"/*.sh)"
[ ! -e "$prefix/share/shatter/studies" ] || fail "studies/ installed"

echo "install test: ok ($prefix)"

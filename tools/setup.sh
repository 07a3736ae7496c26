#!/usr/bin/env bash
# Installs the Debian 12 packages shatter needs (DESIGN.md, "Dependencies"). Idempotent: does
# nothing when everything is already installed. Needs root (or sudo) only when it installs.
# `setup.sh --tests` also installs what only the tests need (tools/test.sh passes it), so the
# main command (tools/run-main.sh) does not download ParaView.
set -euo pipefail
if [ "${1:-}" = "--help" ] || [ "${1:-}" = "-h" ]; then
  sed -n '2,/^set -euo/p' "$0" | sed -n 's/^# \{0,1\}//p'
  exit 0
fi

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libxsimd-dev libtbb-dev libhdf5-dev
  libbenchmark-dev libgtest-dev libgmock-dev
  libtomlplusplus-dev libcli11-dev libspdlog-dev libfmt-dev
  # self-gravity's FFT (src/gravity)
  libfftw3-dev
  python3 python3-numpy python3-matplotlib python3-h5py
  # MPI domain decomposition (docs/mpi.md): `mpirun -np N shatter run SCENE`
  libopenmpi-dev openmpi-bin
)
test_packages=(
  # tests of the Python package (python/tests): pytest, and ParaView 5.11's own Xdmf3 reader for
  # particles.xmf (about 140 MB to download; Debian's VTK 9.1 has no Xdmf3 reader, and its
  # python3-xdmf bindings do not import)
  python3-pytest python3-paraview
  # meshio's XDMF time-series reader on particles.xmf (python/tests/test_xdmf_paraview.py)
  python3-meshio
  # headless pictures: tools/render.py runs ParaView under xvfb-run (tests/tools)
  xvfb xauth
)
if [ "${1:-}" = "--tests" ]; then
  packages+=("${test_packages[@]}")
elif [ $# -gt 0 ]; then
  echo "setup.sh: unknown option '$1' (the only option is --tests)" >&2
  exit 2
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"

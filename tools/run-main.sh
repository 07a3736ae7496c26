#!/usr/bin/env bash
# The README's quick start: set up, build (Release, as tools/test.sh does), run the coarse
# laboratory impact (scenes/lab-impact-coarse.toml) into out/lab-impact, then draw its figures
# into out/lab-impact/plots (cross-section, failure ratio, fragments, energy error).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh

jobs=$(nproc)
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHATTER_BUILD_BENCH=ON
cmake --build build/release -j "$jobs" --target shatter

build/release/shatter run scenes/lab-impact-coarse.toml --out out/lab-impact --overwrite \
  --threads "$jobs" --log out/lab-impact.log

/usr/bin/python3 tools/plot_cross_section.py out/lab-impact --times 10e-6 20e-6 40e-6 100e-6
/usr/bin/python3 tools/plot_failure_ratio.py out/lab-impact
/usr/bin/python3 tools/plot_fragments.py out/lab-impact
/usr/bin/python3 tools/plot_energy.py out/lab-impact
echo "results: out/lab-impact (open particles.xmf in ParaView; figures in out/lab-impact/plots)"

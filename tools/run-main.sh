#!/usr/bin/env bash
# The README's quick start: set up, build (Release, as tools/test.sh does), then run the coarse
# laboratory impact twice, as the MPM paper's nominal case (scenes/lab-impact-coarse.toml, into
# out/lab-impact) and with its modified Lundborg strength variant, which forms the experiment's
# core (scenes/lab-impact-lundborg.toml at the same 1.2 mm spacing, into out/lab-impact-lundborg),
# and draw each run's figures into RUN/plots (cross-section, failure ratio, fragments, energy).
set -euo pipefail
if [ "${1:-}" = "--help" ] || [ "${1:-}" = "-h" ]; then
  sed -n '2,/^set -euo/p' "$0" | sed -n 's/^# \{0,1\}//p'
  exit 0
fi
cd "$(dirname "$0")/.."
bash tools/setup.sh

jobs=$(nproc)
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHATTER_BUILD_BENCH=ON
cmake --build build/release -j "$jobs" --target shatter

build/release/shatter run scenes/lab-impact-coarse.toml --out out/lab-impact --overwrite \
  --threads "$jobs" --log out/lab-impact.log
build/release/shatter run scenes/lab-impact-lundborg.toml --set solver.cell_size=2.4e-3 \
  --set output.snapshot_every=5e-6 --out out/lab-impact-lundborg --overwrite --threads "$jobs" \
  --log out/lab-impact-lundborg.log

for run in out/lab-impact out/lab-impact-lundborg; do
  /usr/bin/python3 tools/plot_cross_section.py "$run" --times 10e-6 20e-6 40e-6 100e-6
  /usr/bin/python3 tools/plot_failure_ratio.py "$run"
  /usr/bin/python3 tools/plot_fragments.py "$run"
  /usr/bin/python3 tools/plot_energy.py "$run"
done
echo "results: out/lab-impact and out/lab-impact-lundborg (open particles.xmf in ParaView;" \
  "fragments.csv; figures in plots/)"

#!/usr/bin/env bash
# The cost of `tactus run --vtk` (docs/outputs.md): a lockstep run's wall time and CPU time
# (user + system, less sensitive to other work on a shared machine) with and without the
# series, median of 3 each, and the series' bytes per frame.
#   bench/outputs/vtk_cost.sh [SCENE] [DURATION] [RATE]     (SCENE empty: the default scene)
set -euo pipefail
tactus=${TACTUS:-build/release/bin/tactus}
scene=${1:-}
duration=${2:-2}
rate=${3:-30}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export OPENBLAS_NUM_THREADS=1

median() { sort -g | sed -n 2p; }
measure() {  # "wall cpu" seconds of one run
  local start end cpu
  start=$(date +%s.%N)
  cpu=$( { TIMEFORMAT='%U %S'; time "$tactus" run $scene --lockstep --duration "$duration" "$@" > /dev/null 2>&1; } 2>&1 )
  end=$(date +%s.%N)
  echo "$(echo "$end - $start" | bc -l) $(echo "$cpu" | awk '{print $1 + $2}')"
}
runs_plain=$(for i in 1 2 3; do measure; done)
runs_with=$(for i in 1 2 3; do rm -rf "$out/vtk"; measure --vtk "$out/vtk" --vtk-rate "$rate"; done)
plain=$(echo "$runs_plain" | cut -d' ' -f1 | median)
with=$(echo "$runs_with" | cut -d' ' -f1 | median)
plain_cpu=$(echo "$runs_plain" | cut -d' ' -f2 | median)
with_cpu=$(echo "$runs_with" | cut -d' ' -f2 | median)
frames=$(grep -o 'timestep="[^"]*"' "$out"/vtk/*.pvd | sort -u | wc -l)
bytes=$(du -cb "$out"/vtk/*.vtu | tail -1 | cut -f1)
printf 'scene %s, %s s lockstep, --vtk-rate %s\n' "${scene:-default}" "$duration" "$rate"
printf '  wall: without --vtk %.3f s, with %.3f s (%+.1f ms per frame)\n' "$plain" "$with" \
  "$(echo "($with - $plain) * 1000 / $frames" | bc -l)"
printf '  cpu:  without --vtk %.3f s, with %.3f s (%+.1f ms per frame)\n' "$plain_cpu" "$with_cpu" \
  "$(echo "($with_cpu - $plain_cpu) * 1000 / $frames" | bc -l)"
printf '  %d frames, %d bytes of .vtu, %d bytes per frame\n' "$frames" "$bytes" "$((bytes / frames))"

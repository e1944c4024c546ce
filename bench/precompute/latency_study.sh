#!/bin/bash
# Seed 001 ran its solver ranks on two clusters 300 km apart. This emulates that on one
# machine: under mpirun, the even solver ranks hold every task and result for a one-way
# latency (TACTUS_PRECOMPUTE_LATENCY="MS:JITTER_MS", src/precompute/distributed.cpp), and the
# build's wall time is compared with none. docs/precompute.md, "Latency".
#
#   bench/precompute/latency_study.sh [SCENE] [RANKS] [REPEATS] [IN_FLIGHT]
# SCENE defaults to bench/precompute/organ501.toml, RANKS (solver ranks + the scheduler) to 3,
# REPEATS to 3, IN_FLIGHT (transitions a rank may owe at once, `--in-flight`) to 1. Prints
# one line per latency: the median wall time of the build and its ratio to the run without
# latency.
set -euo pipefail
cd "$(dirname "$0")/../.."
scene=${1:-bench/precompute/organ501.toml}
ranks=${2:-3}
repeats=${3:-3}
in_flight=${4:-1}
tactus=build/release/bin/tactus
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
root=()
[ "$(id -u)" = 0 ] && root=(--allow-run-as-root)

median_wall() {  # the build's wall time [s] for latency $1 (MS:JITTER_MS), median of the repeats
  local times=()
  for _ in $(seq "$repeats"); do
    rm -f "$out/space.h5" "$out/space.h5.journal"
    local line
    line=$(TACTUS_PRECOMPUTE_LATENCY="$1" OPENBLAS_NUM_THREADS=1 mpirun -np "$ranks" --oversubscribe "${root[@]}" \
      -x TACTUS_PRECOMPUTE_LATENCY -x OPENBLAS_NUM_THREADS "$tactus" -q precompute "$scene" -o "$out/space.h5" --in-flight "$in_flight" |
      grep -o 'solves in [0-9.]* s wall')
    times+=("$(echo "$line" | awk '{print $3}')")
  done
  printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'
}

base=$(median_wall 0:0)
echo "latency 0 ms: median wall ${base} s"
for latency in 5:2.5 10:5 20:10; do
  wall=$(median_wall "$latency")
  echo "latency ${latency%%:*} ms (jitter ±${latency##*:} ms) on the even solver ranks: median wall ${wall} s," \
    "$(awk -v a="$wall" -v b="$base" 'BEGIN {printf "%.3f", a / b}') of none"
done

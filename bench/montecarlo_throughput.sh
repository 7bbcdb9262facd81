#!/usr/bin/env bash
# Monte Carlo throughput (simulations per second) on 1 and 2 MPI ranks, and the
# speed-up. Usage: bash bench/montecarlo_throughput.sh [samples] [ranks...]
# Needs the build (scripts/setup.sh). Prints one line per rank count.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
samples="${1:-32}"
shift || true
ranks=("${@:-1 2}")
read -r -a ranks <<< "${ranks[*]}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
base=""
printf "%-6s %-8s %-10s %-12s %s\n" ranks samples wall_s sims_per_s speedup
for n in "${ranks[@]}"; do
  start=$(date +%s.%N)
  mpirun --oversubscribe -np "$n" "$here/build/drivers/rover" montecarlo \
    --study "$here/configs/studies/preload_mc.json" --samples "$samples" --no-plot \
    --progress-interval 0 --out "$out/mc_$n.h5" 2> "$out/log_$n"
  end=$(date +%s.%N)
  wall=$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')
  rate=$(awk -v n="$samples" -v w="$wall" 'BEGIN { print n / w }')
  [[ -z "$base" ]] && base=$rate
  printf "%-6s %-8s %-10.2f %-12.3f %.2f\n" "$n" "$samples" "$wall" "$rate" \
    "$(awk -v r="$rate" -v b="$base" 'BEGIN { print r / b }')"
done

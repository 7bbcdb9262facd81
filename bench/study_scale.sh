#!/usr/bin/env bash
# Study throughput and memory at scale: runs/s and peak resident memory of
# rank 0 for the drop Monte Carlo (configs/studies/preload_mc.json, stiff
# integrator) and for the 1 m/s obstacle run, on 1 and 2 ranks, for
# N = 10^3 and 10^4 samples (10^5 with ROVER_SCALE_BIG=1). Whole studies:
# runs, QoIs, bands, HDF5, no plots.
#   bash bench/study_scale.sh [drop|obstacle|all|ceiling]
# ROVER_BIN=path/to/rover measures another build (default build/drivers/rover).
# `ceiling` measures what the machine itself gives two processes: the
# 1-rank drop study of 1000 samples alone, then two copies of it at once
# (independent processes, no MPI between them). Their combined rate over the
# single rate bounds the speed-up any farm can reach on these two cores.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rover="${ROVER_BIN:-$here/build/drivers/rover}"
[[ -x "$rover" ]] || { echo "study_scale: no rover program at '$rover' (ROVER_BIN, or build first: bash scripts/setup.sh)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
which="${1:-all}"
case "$which" in
  drop|obstacle|all|ceiling) ;;
  *) echo "study_scale: unknown mode '$which' (drop, obstacle, all or ceiling)" >&2; exit 1 ;;
esac
sizes=(1000 10000)
[[ "${ROVER_SCALE_BIG:-0}" == 1 ]] && sizes+=(100000)

# The obstacle study: the preload Monte Carlo on obstacle_v1.
cat > "$out/obstacle_mc.json" <<JSON
{"type": "montecarlo", "name": "obstacle_mc", "scenario": "$here/configs/scenarios/obstacle_v1.json",
 "integrator": {"method": "rosenbrock"},
 "parameters": {"M0": {"distribution": "normal", "from_config": true}},
 "design": {"type": "monte_carlo", "samples": 100, "seed": 1},
 "qoi": ["B_r_rise", "G_rise", "max_abs_roll", "lateral_drift"], "channels": ["B_r_z"]}
JSON

run() {  # study ranks samples
  local study="$1" ranks="$2" n="$3" log="$out/log"
  /usr/bin/time -f "%e %M" -o "$out/time" mpirun --oversubscribe -np "$ranks" "$rover" montecarlo \
    --study "$study" --samples "$n" --no-plot --progress-interval 3600 --out "$out/r.h5" > "$log" 2>&1
  read -r wall rss < "$out/time"
  printf "%-9s %5d %8d %9.1f %10.1f %12.0f\n" "$4" "$ranks" "$n" "$wall" "$(echo "$n / $wall" | bc -l)" "$((rss / 1024))"
}

if [[ "$which" == ceiling ]]; then
  one() { /usr/bin/time -f "%e" -o "$out/time$1" "$rover" montecarlo --study "$here/configs/studies/preload_mc.json" \
            --samples 1000 --no-plot --progress-interval 3600 --out "$out/c$1.h5" > "$out/log$1" 2>&1; }
  one a
  alone=$(cat "$out/timea")
  one b & one c & wait
  both=$(awk '{print ($1 > m) ? $1 : m; m = ($1 > m) ? $1 : m}' "$out/timeb" "$out/timec" | tail -1)
  printf "one process: 1000 runs in %.1f s (%.1f runs/s); two at once: 2000 runs in %.1f s (%.1f runs/s); ratio %.2f\n" \
    "$alone" "$(echo "1000 / $alone" | bc -l)" "$both" "$(echo "2000 / $both" | bc -l)" "$(echo "2 * $alone / $both" | bc -l)"
  exit 0
fi

printf "%-9s %5s %8s %9s %10s %12s\n" study ranks samples "wall[s]" "runs/s" "peak_RSS[MB]"
for n in "${sizes[@]}"; do
  for ranks in 1 2; do
    [[ "$which" == all || "$which" == drop ]] && run "$here/configs/studies/preload_mc.json" "$ranks" "$n" drop
    if [[ "$which" == all || "$which" == obstacle ]] && (( n <= 1000 )); then
      run "$out/obstacle_mc.json" "$ranks" "$n" obstacle
    fi
  done
done

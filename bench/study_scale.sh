#!/usr/bin/env bash
# Study throughput and memory at scale: runs/s and peak resident memory of
# rank 0 for the drop Monte Carlo (configs/studies/preload_mc.json, stiff
# integrator) and for the 1 m/s obstacle run, on 1 and 2 ranks, for
# N = 10^3 and 10^4 samples (10^5 with ROVER_SCALE_BIG=1). Whole studies:
# runs, QoIs, bands, HDF5, no plots.
#   bash bench/study_scale.sh [drop|obstacle|all|ceiling|speedup]
# ROVER_BIN=path/to/rover measures another build (default build/drivers/rover).
# `ceiling` measures what the machine itself gives two processes: the
# 1-rank drop study of 1000 samples alone, then two copies of it at once
# (independent processes, no MPI between them). Their combined rate over the
# single rate bounds the speed-up any farm can reach on these two cores.
# `speedup` measures the 1 -> 2 rank speed-up in rounds, so that a shared
# machine's drifting speed cancels: 1,000 drops on 1 rank, 2,000 on 2 ranks,
# then two independent 1-rank runs of 1,000 at once, ROVER_SCALE_PAIRS rounds
# (default 5). Each round gives the speed-up 2 x (1 rank) / (2 ranks), the
# machine's own ceiling 2 x (1 rank) / (2 processes), and the farm against
# independent processes, (2 processes) / (2 ranks): 1 when the farm costs
# nothing beyond what the machine gives. The medians are the figures to quote.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rover="${ROVER_BIN:-$here/build/drivers/rover}"
[[ -x "$rover" ]] || { echo "study_scale: no rover program at '$rover' (ROVER_BIN, or build first: bash scripts/setup.sh)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
which="${1:-all}"
case "$which" in
  drop|obstacle|all|ceiling|speedup) ;;
  *) echo "study_scale: unknown mode '$which' (drop, obstacle, all, ceiling or speedup)" >&2; exit 1 ;;
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

# Runs a command under /usr/bin/time (format, file); its output goes to log.
# A run that fails or is interrupted stops the benchmark with the command and the end of its output.
timed() {  # format time_file log command...
  local format="$1" time_file="$2" log="$3"
  shift 3
  if ! /usr/bin/time -f "$format" -o "$time_file" "$@" > "$log" 2>&1; then
    { echo "study_scale: this run did not finish: $*"; echo "its last lines:"; tail -n 20 "$log"; } >&2
    exit 1
  fi
}

declare -A walls  # "study samples ranks" -> wall seconds
run() {  # study ranks samples label
  local study="$1" ranks="$2" n="$3"
  timed "%e %M" "$out/time" "$out/log" mpirun --oversubscribe -np "$ranks" "$rover" montecarlo \
    --study "$study" --samples "$n" --no-plot --progress-interval 3600 --out "$out/r.h5"
  read -r wall rss < "$out/time"
  walls["$4 $n $ranks"]="$wall"
  printf "%-9s %5d %8d %9.1f %10.1f %12.0f\n" "$4" "$ranks" "$n" "$wall" "$(echo "$n / $wall" | bc -l)" "$((rss / 1024))"
}

drop="$here/configs/studies/preload_mc.json"
# 1,000 drops in a process of its own, without mpirun (whose default binding
# would put two such runs on one core); its wall time goes to $out/time<tag>.
alone() {  # tag
  timed "%e" "$out/time$1" "$out/log$1" "$rover" montecarlo --study "$drop" --samples 1000 --no-plot \
    --progress-interval 3600 --out "$out/s$1.h5"
}
# Two such processes at once; prints the wall time of the slower.
two_at_once() {
  local first second status=0
  alone c & first=$!
  alone d & second=$!
  wait "$first" || status=1
  wait "$second" || status=1
  (( status == 0 )) || exit 1
  sort -g "$out/timec" "$out/timed" | tail -1
}

if [[ "$which" == ceiling ]]; then
  alone a
  one=$(cat "$out/timea")
  both=$(two_at_once)
  printf "one process: 1000 runs in %.1f s (%.1f runs/s); two at once: 2000 runs in %.1f s (%.1f runs/s); ratio %.2f\n" \
    "$one" "$(echo "1000 / $one" | bc -l)" "$both" "$(echo "2000 / $both" | bc -l)" "$(echo "2 * $one / $both" | bc -l)"
  exit 0
fi

if [[ "$which" == speedup ]]; then
  pairs="${ROVER_SCALE_PAIRS:-5}"
  [[ "$pairs" =~ ^[1-9][0-9]*$ ]] || { echo "study_scale: ROVER_SCALE_PAIRS must be a positive integer, got '$pairs'" >&2; exit 1; }
  wall_of() {  # ranks samples tag: the study's wall time in seconds
    timed "%e" "$out/time$3" "$out/log$3" mpirun --oversubscribe -np "$1" "$rover" montecarlo --study "$drop" \
      --samples "$2" --no-plot --progress-interval 3600 --out "$out/s$3.h5"
    cat "$out/time$3"
  }
  wall_of 1 200 w > /dev/null  # warm-up: caches, the page cache of the binary
  printf "%5s %10s %10s %12s %9s %8s %10s\n" round "1 rank" "2 ranks" "2 processes" speed-up ceiling "farm/ceil"
  for ((p = 1; p <= pairs; ++p)); do
    one=$(wall_of 1 1000 a)
    two=$(wall_of 2 2000 b)
    both=$(two_at_once)
    echo "$one $two $both" >> "$out/rounds"
    printf "%5d %9.1fs %9.1fs %11.1fs %9.2f %8.2f %10.3f\n" "$p" "$one" "$two" "$both" \
      "$(echo "2 * $one / $two" | bc -l)" "$(echo "2 * $one / $both" | bc -l)" "$(echo "$both / $two" | bc -l)"
  done
  awk 'function median(a, n,   i, j, t) {
         for (i = 2; i <= n; ++i) for (j = i; j > 1 && a[j - 1] > a[j]; --j) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
         return (n % 2) ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2 }
       { s[NR] = 2 * $1 / $2; c[NR] = 2 * $1 / $3; f[NR] = $3 / $2 }
       END { printf "medians over %d rounds: speed-up 1 -> 2 ranks %.2f; two independent processes %.2f; farm / independent %.3f\n",
                    NR, median(s, NR), median(c, NR), median(f, NR) }' "$out/rounds"
  exit 0
fi

printf "%-9s %5s %8s %9s %10s %12s\n" study ranks samples "wall[s]" "runs/s" "peak_RSS[MB]"
for n in "${sizes[@]}"; do
  for ranks in 1 2; do
    [[ "$which" == all || "$which" == drop ]] && run "$drop" "$ranks" "$n" drop
    if [[ "$which" == all || "$which" == obstacle ]] && (( n <= 1000 )); then
      run "$out/obstacle_mc.json" "$ranks" "$n" obstacle
    fi
  done
done
for key in "${!walls[@]}"; do
  read -r study n ranks <<< "$key"
  [[ "$ranks" == 1 && -n "${walls["$study $n 2"]:-}" ]] || continue
  printf "speed-up 1 -> 2 ranks, %s, %d samples: %.2f\n" "$study" "$n" "$(echo "${walls[$key]} / ${walls["$study $n 2"]}" | bc -l)"
done | sort
echo "(single whole studies; on a shared machine whose speed drifts, 'speedup' pairs the runs)"

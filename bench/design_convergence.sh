#!/usr/bin/env bash
# How many runs for the same answer: plain Monte Carlo against the
# Owen-scrambled Sobol' design on the preload Monte Carlo of the horizontal
# drop (configs/studies/preload_mc.json and its Sobol' twin
# configs/studies/drop_convergence.json: the 8 preloads of Table 1, the stiff
# integrator). Runs R replicates of each design with independent seeds, N_MAX
# runs each, and one independent Sobol' reference of N_REF runs with
# `mpirun rover montecarlo`, then bench/design_convergence (the analysis:
# errors of the B_l z band and of the peak compression B_l_z_min's mean and sd
# at every power-of-two prefix N, log-log fits, the runs for 1 % error on the
# sd). Results: <out>/design_convergence.csv, _band.png, _qoi.png, summary.txt
# (docs/design_convergence.md reports one measurement).
#
# Run count: 2 R N_MAX + N_REF (the defaults: 2 * 8 * 1024 + 8192 = 24,576
# drops, about 30 ms each on one core). Not a unit test: minutes of runs.
# Finished replicate files are kept; running the same command again reuses
# them (and resumes an interrupted run from its checkpoint).
#
# Usage: bench/design_convergence.sh [--replicates R] [--n-max N] [--n-ref N]
#            [--ranks P] [--duration S] [--fit-min N] [--out DIR] [--rover BIN] [--analysis BIN]
#   --replicates  independent seeds per design (default 8)
#   --n-max       runs per replicate, a power of two (default 1024)
#   --n-ref       runs of the Sobol' reference (default 8192)
#   --ranks       MPI ranks of each rover run (default 2)
#   --duration    drop duration [s] instead of the scenario's 1 s, e.g. 0.3 for a
#                 quick check (the peak compression is at 0.18 s; the band then
#                 covers the shorter curve)
#   --fit-min     smallest N of the power-law fits (default 16; at least 2 sizes up to --n-max)
#   --out         directory of the result files (default results/design_convergence)
#   --rover       the rover program (default build/drivers/rover)
#   --analysis    the analysis program (default build/bench/design_convergence)
# Quick check: bench/design_convergence.sh --replicates 4 --n-max 64 --n-ref 256 --duration 0.3 --out results/dc_quick
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
replicates=8 n_max=1024 n_ref=8192 ranks=2 duration="" fit_min=16 out=results/design_convergence
rover=$here/build/drivers/rover analysis=$here/build/bench/design_convergence
while [ $# -gt 0 ]; do
  case "$1" in
    --replicates) replicates=$2 ;;
    --n-max) n_max=$2 ;;
    --n-ref) n_ref=$2 ;;
    --ranks) ranks=$2 ;;
    --duration) duration=$2 ;;
    --fit-min) fit_min=$2 ;;
    --out) out=$2 ;;
    --rover) rover=$2 ;;
    --analysis) analysis=$2 ;;
    *) echo "design_convergence.sh: unknown option $1 (see the top of $0)" >&2; exit 2 ;;
  esac
  shift 2
done
for v in "$replicates" "$n_max" "$n_ref" "$ranks" "$fit_min"; do
  [[ "$v" =~ ^[1-9][0-9]*$ ]] || { echo "design_convergence.sh: not a positive integer: $v" >&2; exit 2; }
done
(( replicates >= 2 )) || { echo "design_convergence.sh: --replicates must be at least 2" >&2; exit 2; }
(( (n_max & (n_max - 1)) == 0 )) || { echo "design_convergence.sh: --n-max must be a power of two, got $n_max" >&2; exit 2; }
for bin in "$rover" "$analysis"; do
  [ -x "$bin" ] || { echo "design_convergence.sh: $bin not built (cmake --build build --target rover design_convergence)" >&2; exit 2; }
done
mkdir -p "$out/logs"

mc_study=$here/configs/studies/preload_mc.json
sobol_study=$here/configs/studies/drop_convergence.json
if [ -n "$duration" ]; then
  # A copy of the scenario with another duration (its name says which, so the
  # analysis refuses to mix files of different durations), and of both studies.
  scenario=$out/configs/drop_horizontal_duration_$duration.json
  mkdir -p "$out/configs"
  sed -e "s|\"duration\": 1.0|\"duration\": $duration|" -e "s|\"\.\./rover.json\"|\"$here/configs/rover.json\"|" \
      -e "s|\"\.\./terrains/flat.json\"|\"$here/configs/terrains/flat.json\"|" \
      "$here/configs/scenarios/drop_horizontal.json" > "$scenario"
  if ! grep -q "\"duration\": $duration," "$scenario" || ! grep -q "\"$here/configs/rover.json\"" "$scenario" ||
     ! grep -q "\"$here/configs/terrains/flat.json\"" "$scenario"; then
    echo "design_convergence.sh: could not rewrite $here/configs/scenarios/drop_horizontal.json" >&2; exit 1
  fi
  for study in mc_study sobol_study; do
    copy=$out/configs/$(basename "${!study}" .json)_duration_$duration.json
    sed "s|\"\.\./scenarios/drop_horizontal.json\"|\"$scenario\"|" "${!study}" > "$copy"
    grep -q "\"$scenario\"" "$copy" || { echo "design_convergence.sh: could not rewrite ${!study}" >&2; exit 1; }
    printf -v "$study" '%s' "$copy"
  done
fi

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
runs=$((2 * replicates * n_max + n_ref))
echo "design_convergence.sh: $replicates replicates x $n_max runs per design + a Sobol' reference of $n_ref:" \
     "$runs runs on $ranks ranks${duration:+, duration $duration s}"
start=$(date +%s)
done_runs=0
# montecarlo STUDY SAMPLES SEED FILE: one rover run set, skipped if FILE exists.
montecarlo() {
  local study=$1 samples=$2 seed=$3 file=$4 resume=() kept=" (kept from an earlier call)"
  if [ ! -f "$file" ]; then
    kept=""
    [ -f "$file.checkpoint" ] && resume=(--resume)
    nice mpirun --oversubscribe -np "$ranks" "$rover" montecarlo --study "$study" --samples "$samples" \
      --seed "$seed" --out "$file" --no-plot --progress-interval 60 "${resume[@]}" \
      > "$out/logs/$(basename "$file" .h5).log" 2>&1 ||
      { echo "design_convergence.sh: rover montecarlo failed, see $out/logs/$(basename "$file" .h5).log" >&2; exit 1; }
  fi
  done_runs=$((done_runs + samples))
  echo "  $(basename "$file")$kept: $done_runs / $runs runs, $(( $(date +%s) - start )) s"
}

# Seeds: Monte Carlo 1001.., Sobol' 2001.., the reference 9001 (independent of all).
mc_files=() sobol_files=()
reference=$out/reference_sobol_n${n_ref}_seed9001.h5
montecarlo "$sobol_study" "$n_ref" 9001 "$reference"
for r in $(seq 1 "$replicates"); do
  mc_files+=("$out/mc_n${n_max}_seed$((1000 + r)).h5")
  montecarlo "$mc_study" "$n_max" $((1000 + r)) "${mc_files[-1]}"
  sobol_files+=("$out/sobol_n${n_max}_seed$((2000 + r)).h5")
  montecarlo "$sobol_study" "$n_max" $((2000 + r)) "${sobol_files[-1]}"
done

"$analysis" --reference "$reference" --mc "${mc_files[@]}" --sobol "${sobol_files[@]}" \
  --qoi B_l_z_min --channel B_l_z --fit-min "$fit_min" --out "$out/design_convergence" | tee "$out/summary.txt"

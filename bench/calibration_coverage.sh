#!/usr/bin/env bash
# Coverage of the calibration's 95 % intervals (Gauss-Newton, and optionally
# the posterior's central 95 % interval) over independent noise seeds: for
# each seed a SYNTHETIC horizontal drop is made with `rover synthesize` at
# c_q = 0.25 (0.1 mm noise, 0.05 s offset) and calibrated; the fraction of
# intervals holding 0.25 should be near 0.95 (binomial sd over 40 seeds:
# 0.034). Data and fit use the same (stiff) integrator, so the integrator's
# error is not mistaken for noise. Not a unit test: minutes of runs.
#
# Usage: bench/calibration_coverage.sh [ROVER] [SEEDS] [POSTERIOR] [FIRST]
#   ROVER      the rover binary (default build/drivers/rover)
#   SEEDS      the last noise seed (default 40)
#   POSTERIOR  1: also sample the posterior (16 walkers x 150 steps per seed,
#              the first 75 discarded; slow). The walkers start in a ball
#              around the Gauss-Newton fit, 2 % of the prior's width: with
#              the prior on the bounds [0.02, 1] and the start at c_q = 0.1
#              the 0.02-wide ball did not contract to the posterior (sd
#              0.0005) in 150 steps, and its "95 % interval" was ten times the
#              Gauss-Newton one. The prior is uniform on [0.2, 0.3]: +-100
#              posterior sd around the truth, flat where the likelihood is not
#              negligible, and a 0.002-wide starting ball.
#   FIRST      the first noise seed (default 1), to split the seeds over processes
set -euo pipefail
rover=${1:-build/drivers/rover}
seeds=${2:-40}
first=${4:-1}
posterior=${3:-0}
source_dir=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cat > "$work/drop.json" <<JSON
{"name": "drop_rosenbrock", "rover": "$source_dir/configs/rover.json",
 "terrain": "$source_dir/configs/terrains/flat.json", "duration": 1.0,
 "initial_q": {"z": 0.281, "chi": 0.039, "psi": 0.0042}, "output_rate": 1000,
 "integrator": {"method": "rosenbrock"}}
JSON

gn_hits=0 post_hits=0 runs=0
printf "seed  c_q_fit  gn_lower  gn_upper  post_q025  post_q975\n"
for seed in $(seq "$first" "$seeds"); do
  "$rover" synthesize --scenario "$work/drop.json" --cq 0.25 --noise 1e-4 --offset 0.05 --rate 500 \
      --seed "$seed" --out "$work/data.csv" > /dev/null 2>&1
  cat > "$work/fit.json" <<JSON
{"type": "calibration", "name": "coverage", "scenario": "$work/drop.json", "data": "$work/data.csv",
 "fit": ["c_q"], "bounds": {"c_q": [0.02, 1.0], "time_offset": [-0.2, 0.2]}, "initial": {"c_q": 0.1},
 "max_evaluations": 40, "xtol_rel": 1e-5,
 "priors": {"c_q": {"distribution": "uniform", "min": 0.2, "max": 0.3}},
 "mcmc": {"walkers": 16, "steps": 150, "discard": 75, "seed": $seed, "predictive_draws": 0}}
JSON
  line=$("$rover" calibrate --study "$work/fit.json" --no-plot --out "$work/fit.h5" 2>&1 | grep '^  c_q = ')
  # "  c_q = 0.250292 +- 0.00102 (95 %), se 0.00052"
  read -r fit half < <(echo "$line" | awk '{print $3, $5}')
  lower=$(awk -v a="$fit" -v b="$half" 'BEGIN{printf "%.6g", a - b}')
  upper=$(awk -v a="$fit" -v b="$half" 'BEGIN{printf "%.6g", a + b}')
  gn_hits=$((gn_hits + $(awk -v l="$lower" -v u="$upper" 'BEGIN{print (l <= 0.25 && 0.25 <= u) ? 1 : 0}')))
  q025=- q975=-
  if [ "$posterior" = 1 ]; then
    sed -i "s/\"initial\": {\"c_q\": 0.1}/\"initial\": {\"c_q\": $fit}/" "$work/fit.json"
    line=$("$rover" calibrate --study "$work/fit.json" --method mcmc --no-plot --out "$work/post.h5" 2>&1 |
           grep '^  c_q = ')
    # "  c_q = m +- sd (sd); 95 % [q025, q975]; ..."
    q025=$(echo "$line" | sed -E 's/.*\[([^,]+), ([^]]+)\].*/\1/')
    q975=$(echo "$line" | sed -E 's/.*\[([^,]+), ([^]]+)\].*/\2/')
    post_hits=$((post_hits + $(awk -v l="$q025" -v u="$q975" 'BEGIN{print (l <= 0.25 && 0.25 <= u) ? 1 : 0}')))
  fi
  runs=$((runs + 1))
  printf "%4d  %.6f  %.6f  %.6f  %s  %s\n" "$seed" "$fit" "$lower" "$upper" "$q025" "$q975"
done
awk -v n="$runs" 'BEGIN{printf "binomial: %.1f of %d expected at 95 %% coverage, sd %.2f (2 sd: %.1f .. %d)\n",
                      0.95 * n, n, sqrt(n * 0.95 * 0.05), 0.95 * n - 2 * sqrt(n * 0.95 * 0.05), n}'
echo "Gauss-Newton 95 % intervals holding c_q = 0.25: $gn_hits / $runs"
[ "$posterior" = 1 ] && echo "posterior 95 % intervals holding c_q = 0.25: $post_hits / $runs"
exit 0

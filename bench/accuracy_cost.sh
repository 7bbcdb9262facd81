#!/usr/bin/env bash
# The accuracy-cost frontier of the integrators (docs/model.md §9): the five
# paper scenarios (both drops, the obstacle at 0.34, 1 and 2 m/s) run with
# each integrator over a range of tolerances (and, for the stiff ones, slip
# tolerances: slip_tol in the scenario files); per setting and scenario,
# bench/paper_scenarios_bench prints the RMS and largest difference of B_l z
# and B_r z from Dormand-Prince at rtol 1e-10 (cached: the references take
# minutes once), accepted and rejected steps, right-hand sides and the wall
# time (one run each; pin it to a quiet core for times worth comparing).
#   bench/accuracy_cost.sh [BUILD_DIR]      (default: build)
# Environment: ROVER_CACHE (reference cache directory), ROVER_ONLY (one
# scenario), ROVER_METHODS (space-separated subset of: rosenbrock rodas4
# dopri5), ROVER_REFERENCE_RTOL (the reference's rtol, default 1e-10).
set -euo pipefail

build_dir=${1:-build}
bench="$build_dir/bench/paper_scenarios_bench"
if [[ ! -x "$bench" ]]; then
  echo "no $bench: build the target paper_scenarios_bench first" >&2
  exit 2
fi
methods=${ROVER_METHODS:-"rosenbrock rodas4 dopri5"}
extra=()
[[ -n "${ROVER_CACHE:-}" ]] && extra+=(--cache "$ROVER_CACHE")
[[ -n "${ROVER_ONLY:-}" ]] && extra+=(--only "$ROVER_ONLY")
[[ -n "${ROVER_REFERENCE_RTOL:-}" ]] && extra+=(--reference-rtol "$ROVER_REFERENCE_RTOL")

# method rtol atol [slip_tol], cheapest first within each method.
settings=(
  "rosenbrock 1e-4 2e-3" "rosenbrock 1e-5 2e-4" "rosenbrock 1e-5 1e-5" "rosenbrock 1e-5 1e-6"
  "rosenbrock 1e-5 1e-7" "rosenbrock 1e-5 1e-8" "rosenbrock 1e-6 1e-8"
  "rosenbrock 1e-5 1e-5 0.01" "rosenbrock 1e-5 1e-5 0.005" "rosenbrock 1e-5 3e-6 0.01"
  "rosenbrock 1e-5 1e-6 0.01" "rosenbrock 1e-5 1e-6 0.002" "rosenbrock 1e-5 3e-7 0.01"
  "rosenbrock 1e-5 1e-7 0.002"
  "rodas4 1e-4 2e-3" "rodas4 1e-5 2e-4" "rodas4 1e-5 1e-5" "rodas4 1e-5 1e-6" "rodas4 1e-6 1e-7"
  "rodas4 1e-7 1e-8"
  "dopri5 1e-6 1e-9" "dopri5 1e-7 1e-10" "dopri5 1e-8 1e-11" "dopri5 1e-9 1e-12"
)

lscpu | grep 'Model name' || true
for setting in "${settings[@]}"; do
  read -r method rtol atol slip <<<"$setting"
  [[ " $methods " == *" $method "* ]] || continue
  slip_args=()
  [[ -n "$slip" ]] && slip_args=(--slip "$slip")
  echo
  "$bench" --method "$method" --rtol "$rtol" --atol "$atol" "${slip_args[@]}" --repeats 1 "${extra[@]}"
done

#!/usr/bin/env bash
# The main job: installs what is needed, builds, and runs a default end-to-end
# reproduction on the default configs (a few minutes on 2 cores):
#   both drop tests and the 1 m/s obstacle run, a Monte Carlo band over the
#   preloads, a coarse (f, c_q) response surface, a calibration of c_q on the
#   shipped SYNTHETIC drop curve, Sobol' indices of the Ishigami verification
#   model and of the drop, Morris screening of the drop, and a batch
#   evaluation of a small design. Results (HDF5 + PNG) go to results/.
# Environment: ROVER_RANKS (MPI ranks, default: number of cores),
#              ROVER_MC_SAMPLES (Monte Carlo samples, default 2000),
#              ROVER_SOBOL_SAMPLES (Sobol' base samples of the drop, default 128),
#              ROVER_SKIP_SETUP=1 (re-run with the existing build, no apt-get/cmake).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# The main job needs only the `rover` program; the test command builds the rest.
if [[ "${ROVER_SKIP_SETUP:-0}" != 1 ]]; then ROVER_BUILD_TARGET=rover bash "$here/scripts/setup.sh"; fi
cd "$here"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ranks="${ROVER_RANKS:-$(nproc)}"
samples="${ROVER_MC_SAMPLES:-2000}"
sobol_samples="${ROVER_SOBOL_SAMPLES:-128}"
rover=("$here/build/drivers/rover")
mpi=(mpirun --oversubscribe -np "$ranks")
mkdir -p results
start=$(date +%s)
step() { echo; echo "== $* ($(( $(date +%s) - start )) s)"; }

step "drop tests (paper Fig. 11a-b)"
"${rover[@]}" simulate --scenario configs/scenarios/drop_horizontal.json --out results/drop_horizontal.h5
"${rover[@]}" simulate --scenario configs/scenarios/drop_skewed.json --out results/drop_skewed.h5
step "obstacle negotiation at 1 m/s (Fig. 11c-h)"
"${rover[@]}" simulate --scenario configs/scenarios/obstacle_v1.json --out results/obstacle_v1.h5
step "Monte Carlo over the preloads, $samples samples on $ranks ranks (Fig. 13d)"
"${mpi[@]}" "${rover[@]}" montecarlo --study configs/studies/preload_mc.json --samples "$samples" --out results/preload_mc.h5
step "coarse (f, c_q) response surface on $ranks ranks (Fig. 13a-c)"
"${mpi[@]}" "${rover[@]}" surface --study configs/studies/f_cq_surface_coarse.json --out results/f_cq_surface_coarse.h5
step "calibration of c_q on the synthetic drop curve"
"${mpi[@]}" "${rover[@]}" calibrate --study configs/studies/calibration.json --out results/calibration.h5
"${rover[@]}" compare results/drop_horizontal.h5 configs/data/drop_horizontal_synthetic.csv --time-offset 0.05 --rest-time 0.9 > results/compare_drop_vs_synthetic.json
step "Sobol' indices of the Ishigami function (verification against the exact indices)"
"${rover[@]}" sensitivity --study configs/studies/sobol_ishigami.json --out results/sobol_ishigami.h5
step "Sobol' indices of the drop, N = $sobol_samples base samples on $ranks ranks"
"${mpi[@]}" "${rover[@]}" sensitivity --study configs/studies/sobol_drop.json --samples "$sobol_samples" --out results/sobol_drop.h5
step "Morris screening of 16 parameters on the drop"
"${mpi[@]}" "${rover[@]}" sensitivity --study configs/studies/morris_drop.json --out results/morris_drop.h5
step "batch evaluation of a design CSV (the interface for Dakota, OpenTURNS, SALib)"
printf 'c_q,f,scenario.initial_q.z\n0.10,1e4,0.281\n0.14,1e4,0.281\n0.25,1e4,0.281\n0.14,1e3,0.290\n' > results/evaluate_design.csv
"${mpi[@]}" "${rover[@]}" evaluate --scenario configs/scenarios/drop_horizontal.json --design results/evaluate_design.csv \
  --qoi B_l_z_min,t_min,deflection,at_rest --integrator rosenbrock --out results/evaluate.csv
cat results/evaluate.csv
step "done: results in $here/results"
ls -1 results

#!/usr/bin/env bash
# Runs the shipped studies (at reduced sizes) with two builds of `rover` and
# checks that every HDF5 dataset they write is bit-identical: the check that a
# restructuring changed no number. Attributes (provenance, timings, paths) are
# not compared, nor the wall times the studies measure (a surface's t_c and
# its regression on f, a Monte Carlo run's wall_time_s); every other
# dataset's name, shape, type and bytes are.
#   bash bench/same_results.sh OLD_ROVER NEW_ROVER [WORK_DIR]
# Exit status 0 when every dataset matches, 1 otherwise (each difference listed).
# Needs h5py (Debian: python3-h5py, installed by scripts/setup.sh).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if (($# < 2)); then sed -n 2,8p "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 2; fi
old="$(realpath "$1")"; new="$(realpath "$2")"
work="${3:-$(mktemp -d)}"
mkdir -p "$work/old" "$work/new"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
studies="$here/configs/studies"
scenario="$here/configs/scenarios/drop_horizontal.json"
printf 'c_q,f,scenario.initial_q.z\n0.10,1e4,0.281\n0.25,1e3,0.290\n' > "$work/design.csv"

run_all() {  # $1: the rover binary, $2: output directory
  local rover="$1" out="$2"
  "$rover" montecarlo --study "$studies/preload_mc.json" --samples 40 --out "$out/preload_mc.h5"
  "$rover" surface --study "$studies/f_cq_surface_coarse.json" --out "$out/surface.h5"
  "$rover" calibrate --study "$studies/calibration.json" --out "$out/calibration.h5"
  "$rover" calibrate --study "$studies/calibration.json" --algorithm LN_BOBYQA --max-evaluations 8 --profile \
    --out "$out/calibration_search.h5"
  "$rover" calibrate --study "$studies/calibration_mcmc.json" --steps 20 --discard 5 --walkers 8 \
    --out "$out/calibration_mcmc.h5" || true  # too short to mix: status 2 is expected
  "$rover" sensitivity --study "$studies/sobol_ishigami.json" --out "$out/sobol_ishigami.h5"
  "$rover" sensitivity --study "$studies/sobol_drop.json" --samples 16 --out "$out/sobol_drop.h5"
  "$rover" sensitivity --study "$studies/morris_drop.json" --out "$out/morris_drop.h5"
  "$rover" evaluate --scenario "$scenario" --design "$work/design.csv" --qoi B_l_z_min,t_min,deflection \
    --integrator rosenbrock --out "$out/evaluate.h5"
}
echo "same_results: old $old"; run_all "$old" "$work/old" > "$work/old.log" 2>&1
echo "same_results: new $new"; run_all "$new" "$work/new" > "$work/new.log" 2>&1
/usr/bin/python3 - "$work/old" "$work/new" <<'PY'
import sys, pathlib, h5py, numpy as np
old_dir, new_dir = map(pathlib.Path, sys.argv[1:3])
bad = 0
WALL_TIMES = {"surface.h5": {"t_c", "sweep/t_c", "sweep/regression"},
              "preload_mc.h5": {"samples/wall_time_s"}}
for old_path in sorted(old_dir.glob("*.h5")):
    new_path = new_dir / old_path.name
    if not new_path.exists():
        print(f"MISSING {new_path}"); bad += 1; continue
    with h5py.File(old_path) as a, h5py.File(new_path) as b:
        names_a, names_b = [], []
        a.visititems(lambda n, o: names_a.append(n) if isinstance(o, h5py.Dataset) else None)
        b.visititems(lambda n, o: names_b.append(n) if isinstance(o, h5py.Dataset) else None)
        for n in sorted(set(names_a) | set(names_b)):
            if n in WALL_TIMES.get(old_path.name, ()): continue
            if n not in a or n not in b:
                print(f"{old_path.name}:/{n} only in {'old' if n in a else 'new'}"); bad += 1; continue
            x, y = np.asarray(a[n][()]), np.asarray(b[n][()])
            if x.dtype == object or y.dtype == object:  # variable-length strings
                same = x.shape == y.shape and x.tolist() == y.tolist()
            else:
                same = x.shape == y.shape and x.dtype == y.dtype and x.tobytes() == y.tobytes()
            if not same:
                print(f"{old_path.name}:/{n} differs"); bad += 1
        print(f"{old_path.name}: {len(names_a)} datasets compared")
print("same_results: all datasets bit-identical" if bad == 0 else f"same_results: {bad} differences")
sys.exit(1 if bad else 0)
PY

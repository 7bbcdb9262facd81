#!/usr/bin/env bash
# How much faster is a drop study now than at an earlier revision, on THIS
# machine? Builds the program of revision REV beside the current build and
# times both on the same drop Monte Carlo, in turns (current, REV, current,
# REV, ...), one process at a time on one core, so that a drifting machine
# speed cancels pair by pair. Prints each pair's CPU times and their ratio,
# and the median ratio: the per-run speed-up of the current build over REV.
#   bash bench/against_revision.sh REV
# Settings (environment):
#   ROVER_BIN=path       the current program (default build/drivers/rover)
#   ROVER_REV_NATIVE=ON  build REV with -march=native (default OFF: a portable
#                        build, as scripts/setup.sh built before it turned
#                        native; ON compares the code alone)
#   ROVER_PAIRS=N        pairs of runs (default 5)
#   ROVER_SAMPLES=N      drops per run (default 200)
# Each side runs its own revision's configs/studies/preload_mc.json, with the
# stiff integrator named if that file does not name one (before the stiff
# integrator became the studies' default, it ran Dormand-Prince). Whole
# processes are timed (start-up and the result file included), by /usr/bin/time.
# Why: a throughput goal set on one machine says little on another, whose
# cores may be slower; the same comparison on both says whether the code
# improved by the same factor.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
usage="usage: bash bench/against_revision.sh REV   (a commit, tag or branch of this repository)"
[[ $# -eq 1 ]] || { echo "against_revision: $usage" >&2; exit 1; }
rev="$1"
rover="${ROVER_BIN:-$here/build/drivers/rover}"
[[ -x "$rover" ]] || { echo "against_revision: no rover program at '$rover' (ROVER_BIN, or build first: bash scripts/setup.sh)" >&2; exit 1; }
commit="$(git -C "$here" rev-parse --verify --quiet "$rev^{commit}")" ||
  { echo "against_revision: '$rev' is not a commit of $here" >&2; exit 1; }
native="${ROVER_REV_NATIVE:-OFF}"
case "$native" in
  ON|on|1) native=ON ;;
  OFF|off|0) native=OFF ;;
  *) echo "against_revision: ROVER_REV_NATIVE must be ON or OFF, got '$native'" >&2; exit 1 ;;
esac
pairs="${ROVER_PAIRS:-5}"
samples="${ROVER_SAMPLES:-200}"
# Checked before the build, which takes minutes: 1 .. 100 pairs, and the
# sample range the rover program itself accepts.
in_range() {  # name value largest
  [[ "$2" =~ ^[1-9][0-9]{0,9}$ ]] && (( $2 <= $3 )) ||
    { echo "against_revision: $1 must be an integer from 1 to $3, got '$2'" >&2; exit 1; }
}
in_range ROVER_PAIRS "$pairs" 100
in_range ROVER_SAMPLES "$samples" 100000000
[[ -x /usr/bin/time ]] || { echo "against_revision: needs /usr/bin/time (apt-get install time)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

work="$(mktemp -d)"
cleanup() {
  git -C "$here" worktree remove --force "$work/src" > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
git -C "$here" worktree add --detach "$work/src" "$commit" > /dev/null 2>&1 ||
  { echo "against_revision: could not check out $commit" >&2; exit 1; }

echo "against_revision: building $rev (${commit:0:10}, ROVER_NATIVE=$native) in $work/build; a few minutes ..."
if ! { cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DROVER_NATIVE="$native" \
         -DROVER_BUILD_TESTS=OFF -DROVER_BUILD_BENCH=OFF &&
       cmake --build "$work/build" --parallel "$(nproc)" --target rover; } > "$work/build.log" 2>&1; then
  echo "against_revision: the build of $rev failed; its last lines:" >&2
  tail -n 20 "$work/build.log" >&2
  exit 1
fi
old_rover="$work/build/drivers/rover"

# REV's study: its own preload_mc.json, or, if that names no integrator, a
# copy beside it (so that its relative scenario path still holds) naming
# the stiff one.
study_for() {  # source_root
  local original="$1/configs/studies/preload_mc.json" study="$1/configs/studies/preload_mc_against.json"
  [[ -f "$original" ]] || { echo "against_revision: $original is missing" >&2; exit 1; }
  if grep -q '"integrator"' "$original"; then
    echo "$original"
  else
    sed '0,/{/s//{\n  "integrator": {"method": "rosenbrock"},/' "$original" > "$study"
    echo "$study"
  fi
}
# The current side reads the file in place (its scenario path is relative to it).
new_study="$here/configs/studies/preload_mc.json"
grep -q '"rosenbrock"' "$new_study" ||
  { echo "against_revision: $new_study does not run the stiff integrator" >&2; exit 1; }
old_study="$(study_for "$work/src")"

pin=()
command -v taskset > /dev/null && pin=(taskset -c 0)
cpu_seconds() {  # program study tag: user + system seconds of one whole run
  if ! /usr/bin/time -f "%U %S" -o "$work/time$3" "${pin[@]}" "$1" montecarlo --study "$2" --samples "$samples" \
         --no-plot --progress-interval 3600 --out "$work/run$3.h5" > "$work/log$3" 2>&1; then
    { echo "against_revision: this run did not finish: $1 montecarlo --study $2"; tail -n 20 "$work/log$3"; } >&2
    exit 1
  fi
  awk '{ printf "%.3f", $1 + $2 }' "$work/time$3"
}

cpu_seconds "$rover" "$new_study" w > /dev/null  # warm-up of both binaries' pages
cpu_seconds "$old_rover" "$old_study" w > /dev/null
printf "%5s %12s %12s %8s\n" pair "current [s]" "$rev [s]" ratio
for ((p = 1; p <= pairs; ++p)); do
  now=$(cpu_seconds "$rover" "$new_study" a)
  then_=$(cpu_seconds "$old_rover" "$old_study" b)
  echo "$now $then_" >> "$work/pairs"
  awk -v p="$p" -v a="$now" -v b="$then_" 'BEGIN { printf "%5d %12.2f %12.2f %8.3f\n", p, a, b, a / b }'
done
awk -v rev="$rev" -v n="$samples" 'function median(a, k,   i, j, t) {
       for (i = 2; i <= k; ++i) for (j = i; j > 1 && a[j - 1] > a[j]; --j) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
       return (k % 2) ? a[(k + 1) / 2] : (a[k / 2] + a[k / 2 + 1]) / 2 }
     { r[NR] = $1 / $2; lo = (NR == 1 || r[NR] < lo) ? r[NR] : lo; hi = (NR == 1 || r[NR] > hi) ? r[NR] : hi }
     END { m = median(r, NR)
           printf "median CPU-time ratio current / %s over %d pairs of %d drops: %.3f (%.3f-%.3f), a speed-up of %.2fx\n",
                  rev, NR, n, m, lo, hi, 1 / m }' "$work/pairs"

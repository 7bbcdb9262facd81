#!/usr/bin/python3
"""Coverage of the calibration's 95 % intervals on many new synthetic drops.

Each experiment draws a truth across the bounds (c_q uniform in [0.05, 0.5]
N m s/rad, f log-uniform in [1e3, 3e4] 1/rad), a drop (horizontal or skewed),
a channel (B_l_z or B_r_z), a sample rate (200-1000 Hz), a noise sd
(0.03-0.3 mm, log-uniform) and a release time on the data clock (0-0.1 s);
makes the curve with `rover synthesize` on Dormand-Prince at rtol 1e-8, atol
1e-11 (not the integrator the fit uses); drops a random 20 % of its rows
(uneven sampling); and fits (c_q, f) with the shipped defaults (no
"integrator", no "algorithm": Levenberg-Marquardt on the stiff integrator
with the integration check). It reports, per parameter, how often the 95 %
Gauss-Newton interval holds the truth, with its binomial standard error, the
share of fits that converged, the fits flagged as not valid, and the wall
time; every unflagged interval that misses its truth by more than 3 standard
errors is listed. Not a unit test: about 10-20 s an experiment on 2 cores.

  /usr/bin/python3 bench/calibration_coverage.py [--rover build/drivers/rover]
      [--experiments 100] [--ranks 2] [--seed 1] [--out results/calibration_coverage.csv]
"""
import argparse
import csv
import json
import math
import os
import pathlib
import random
import subprocess
import sys
import tempfile
import time

import h5py

SOURCE = pathlib.Path(__file__).resolve().parent.parent
BOUNDS = {"c_q": (0.02, 1.0), "f": (1e2, 1e5)}
REFERENCE = {"method": "dopri5", "rtol": 1e-8, "atol": 1e-11}


def draw_experiment(rng, index):
    scenario = rng.choice(["drop_horizontal", "drop_skewed"])
    return {
        "index": index,
        "scenario": scenario,
        "channel": rng.choice(["B_l_z", "B_r_z"]),
        "truth_c_q": rng.uniform(0.05, 0.5),
        "truth_f": math.exp(rng.uniform(math.log(1e3), math.log(3e4))),
        "rate_hz": rng.choice([200, 250, 400, 500, 800, 1000]),
        "noise_m": math.exp(rng.uniform(math.log(3e-5), math.log(3e-4))),
        "offset_s": rng.uniform(0.0, 0.1),
        "seed": rng.randrange(1, 2**31),
    }


def reference_scenario(work, name):
    """The shipped scenario on the reference integrator, as its own file."""
    text = json.loads((SOURCE / "configs/scenarios" / f"{name}.json").read_text())
    for key in ("rover", "terrain"):
        if key in text:
            text[key] = str((SOURCE / "configs/scenarios" / text[key]).resolve())
    text["integrator"] = REFERENCE
    path = work / f"{name}_reference.json"
    path.write_text(json.dumps(text))
    return path


def make_data(args, work, e, rng):
    raw = work / f"raw_{e['index']}.csv"
    subprocess.run([args.rover, "synthesize", "--scenario", str(reference_scenario(work, e["scenario"])),
                    "--channel", e["channel"], "--cq", repr(e["truth_c_q"]), "--f", repr(e["truth_f"]),
                    "--noise", repr(e["noise_m"]), "--offset", repr(e["offset_s"]),
                    "--rate", str(e["rate_hz"]), "--seed", str(e["seed"]), "--out", str(raw)],
                   check=True, capture_output=True)
    rows = [line for line in raw.read_text().splitlines() if line and not line.startswith("#")]
    header, data = rows[0], rows[1:]
    kept = sorted(rng.sample(range(len(data)), k=int(0.8 * len(data))))
    path = work / f"data_{e['index']}.csv"
    path.write_text("\n".join([header] + [data[i] for i in kept]) + "\n")
    return path


def fit(args, work, e, data):
    study = {"type": "calibration", "name": f"coverage_{e['index']}",
             "scenario": str(SOURCE / "configs/scenarios" / f"{e['scenario']}.json"),
             "data": [{"file": str(data), "channel": e["channel"]}],
             "fit": ["c_q", "f"], "bounds": {"c_q": list(BOUNDS["c_q"]), "f": list(BOUNDS["f"]),
                                             "time_offset": [-0.05, 0.2]},
             "initial": {"c_q": 0.2, "f": 1e4}}
    path = work / f"study_{e['index']}.json"
    path.write_text(json.dumps(study))
    out = work / f"fit_{e['index']}.h5"
    command = ["mpirun", "--oversubscribe", "-np", str(args.ranks), args.rover] if args.ranks > 1 else [args.rover]
    start = time.monotonic()
    run = subprocess.run(command + ["calibrate", "--study", str(path), "--no-plot", "--out", str(out)],
                         capture_output=True, text=True)
    wall = time.monotonic() - start
    if not out.exists():
        return {"status": run.returncode, "wall_s": wall, "log": run.stderr[-2000:]}
    with h5py.File(out) as h5:
        best = h5["best"]
        names = [n.decode() if isinstance(n, bytes) else n for n in best["names"][()]]
        result = {"status": run.returncode, "wall_s": wall,
                  "converged": int(best.attrs["converged"]), "valid": int(best.attrs["intervals_valid"])}
        for k, name in enumerate(names):
            result[name] = best["values"][k]
            if "stderr" in best:
                result[name + "_se"] = best["stderr"][k]
                result[name + "_lower"] = best["lower"][k]
                result[name + "_upper"] = best["upper"][k]
    return result


def binomial(hits, n):
    p = hits / n if n else float("nan")
    return p, math.sqrt(p * (1 - p) / n) if n else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rover", default=str(SOURCE / "build/drivers/rover"))
    parser.add_argument("--experiments", type=int, default=100)
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", default=str(SOURCE / "results/calibration_coverage.csv"))
    parser.add_argument("--only", default="", help="comma-separated experiment indices to run (the others are drawn, not run)")
    parser.add_argument("--keep", default="", help="a folder that keeps each experiment's data, study and result")
    args = parser.parse_args()
    pathlib.Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    if not 1 <= args.experiments <= 100000:
        sys.exit(f"--experiments must be in 1..100000, got {args.experiments}")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    rng = random.Random(args.seed)
    rows = []
    progress = open(args.out + ".rows.jsonl", "w")  # every experiment as it ends, kept if the run stops
    only = {int(i) for i in args.only.split(",") if i}
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(args.keep or tmp)
        work.mkdir(parents=True, exist_ok=True)
        for i in range(args.experiments):
            e = draw_experiment(rng, i)
            if only and i not in only:
                make_data(args, work, e, rng)  # its random draws, so that later experiments get theirs
                continue
            try:
                r = fit(args, work, e, make_data(args, work, e, rng))
            except (OSError, subprocess.CalledProcessError) as error:
                r = {"status": -1, "wall_s": 0.0, "log": str(error)}
            row = {**e, **r}
            rows.append(row)
            progress.write(json.dumps({k: float(v) if hasattr(v, "dtype") else v for k, v in row.items()}) + "\n")
            progress.flush()
            print(f"{i + 1}/{args.experiments}: {e['scenario']} {e['channel']} {e['rate_hz']} Hz "
                  f"{e['noise_m'] * 1e3:.3f} mm truth c_q {e['truth_c_q']:.4f} f {e['truth_f']:.0f}: "
                  f"fit c_q {r.get('c_q', float('nan')):.4f} f {r.get('f', float('nan')):.0f} "
                  f"converged {r.get('converged', 0)} valid {r.get('valid', 0)} status {r['status']} "
                  f"{r['wall_s']:.1f} s", flush=True)
    progress.close()
    keys = sorted({k for row in rows for k in row if k != "log"})
    with open(args.out + ".part", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys)
        writer.writeheader()
        writer.writerows({k: v for k, v in row.items() if k != "log"} for row in rows)
    os.replace(args.out + ".part", args.out)
    report(rows)


def report(rows):
    n = len(rows)
    converged = sum(r.get("converged", 0) for r in rows)
    valid = [r for r in rows if r.get("valid", 0) == 1]
    print(f"\n{n} experiments; converged {converged} ({100 * converged / n:.1f} %); "
          f"intervals valid {len(valid)}; median wall {sorted(r['wall_s'] for r in rows)[n // 2]:.1f} s")
    print("| parameter | coverage of the valid 95 % intervals | binomial se | unflagged misses > 3 se |")
    print("|---|---|---|---|")
    for name in ("c_q", "f"):
        inside = [r for r in valid if f"{name}_lower" in r]
        hits = sum(1 for r in inside if r[f"{name}_lower"] <= truth(r, name) <= r[f"{name}_upper"])
        far = [r["index"] for r in inside if abs(r[name] - truth(r, name)) > 3 * r[f"{name}_se"]]
        p, se = binomial(hits, len(inside))
        print(f"| {name} | {100 * p:.1f} % ({hits}/{len(inside)}) | {100 * se:.1f} % | {far} |")


def truth(row, name):
    return row["truth_" + name]


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Sobol' indices of the drop's peak compression with OpenTURNS driving `rover evaluate`.

OpenTURNS draws a pick-freeze design over (c_q, f), `rover evaluate` runs one
drop per row, and OpenTURNS' Martinez estimator turns the QoIs into first-order
and total indices. After a build, from any folder (X.csv and Y.csv are
written there):

    /usr/bin/python3 docs/examples/evaluate_openturns.py [ROVER_BINARY]
"""
import csv
import math
import pathlib
import subprocess
import sys

import openturns as ot

root = pathlib.Path(__file__).resolve().parents[2]  # the repository
rover = sys.argv[1] if len(sys.argv) > 1 else str(root / "build/drivers/rover")
ot.RandomGenerator.SetSeed(1)
inputs = ot.ComposedDistribution([ot.Uniform(0.05, 0.4),                      # c_q [N m s/rad]
                                  ot.LogUniform(math.log(1e3), math.log(1e5))])  # f [1/rad]
size = 128
design = ot.SobolIndicesExperiment(inputs, size).generate()  # (2 + d) size rows, pick-freeze order

with open("X.csv", "w", newline="") as f:
    writer = csv.writer(f)
    writer.writerow(["c_q", "f"])
    writer.writerows([list(row) for row in design])
subprocess.run([rover, "evaluate", "--scenario", str(root / "configs/scenarios/drop_horizontal.json"), "--design", "X.csv",
                "--qoi", "B_l_z_min", "--integrator", "rosenbrock", "--out", "Y.csv"], check=True)

with open("Y.csv", newline="") as f:
    rows = list(csv.DictReader(f))
assert all(row["status"] == "0" for row in rows), "a run failed: see the message column of Y.csv"
outputs = ot.Sample([[float(row["B_l_z_min"])] for row in rows])
indices = ot.MartinezSensitivityAlgorithm(design, outputs, size)
for name, first, total in zip(["c_q", "f"], indices.getFirstOrderIndices(), indices.getTotalOrderIndices()):
    print(f"B_l_z_min: {name:4s} S1 {first:6.3f}  ST {total:6.3f}")

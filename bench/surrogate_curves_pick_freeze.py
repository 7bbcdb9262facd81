#!/usr/bin/env python3
"""Compares the indices along time of a PCE result (`rover surrogate` or
`rover sensitivity` method pce, with "channels") with a pick-freeze result
(`rover sensitivity`, e.g. sobol_drop.json at --samples 1024).

Usage: bench/surrogate_curves_pick_freeze.py results/surrogate_drop.h5 results/sobol_drop.h5 [--tolerance 0.03]

Per channel both files hold: /indices_t/<channel>/{S1, ST, variance} (inputs
x time samples) and /aggregated/<channel>/{S1, ST}. Printed: the
variance-weighted aggregated indices of both, and the largest difference of
S1(t) and ST(t) over the samples whose variance exceeds 1 % of the largest
(where the variance is tiny both estimators are noise). Inputs are matched
by /inputs/names. Exit status 1 when an aggregated index differs by more
than the tolerance.
"""
import argparse
import sys

import h5py
import numpy as np

VARIANCE_SHARE = 0.01


def names(h5):
    return [n.decode() if isinstance(n, bytes) else str(n) for n in h5["inputs/names"][:]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pce")
    parser.add_argument("pick_freeze")
    parser.add_argument("--tolerance", type=float, default=0.03)
    args = parser.parse_args()
    pce, pf = h5py.File(args.pce, "r"), h5py.File(args.pick_freeze, "r")
    order = [names(pce).index(n) for n in names(pf)]
    labels = names(pf)
    worst = 0.0
    for channel in pf["indices_t"]:
        if channel not in pce.get("indices_t", {}):
            continue
        print(f"{channel}: aggregated S1 / ST, PCE against pick-freeze")
        for kind in ("S1", "ST"):
            a = pce[f"aggregated/{channel}/{kind}"][:][order]
            b = pf[f"aggregated/{channel}/{kind}"][:]
            for label, x, y in zip(labels, a, b):
                if max(x, y) >= 0.01:
                    print(f"  {kind} {label:28s} {x:6.3f} {y:6.3f}")
            worst = max(worst, float(np.abs(a - b).max()))
        variance = pf[f"indices_t/{channel}/variance"][:]
        mask = variance > VARIANCE_SHARE * variance.max()
        for kind in ("S1", "ST"):
            a = pce[f"indices_t/{channel}/{kind}"][:][order][:, mask]
            b = pf[f"indices_t/{channel}/{kind}"][:][:, mask]
            print(f"  {kind}(t): largest difference {np.abs(a - b).max():.3f} over {mask.sum()} of "
                  f"{mask.size} samples (variance > {VARIANCE_SHARE:.0%} of its largest)")
    print(f"largest aggregated difference {worst:.4f} (tolerance {args.tolerance})")
    return 1 if worst > args.tolerance else 0


if __name__ == "__main__":
    sys.exit(main())

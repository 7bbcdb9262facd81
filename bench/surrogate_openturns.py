#!/usr/bin/env python3
"""Compares the Sobol' indices of a `rover surrogate` PCE with OpenTURNS'.

Usage: bench/surrogate_openturns.py results/surrogate_drop.h5 [--tolerance 0.02]

OpenTURNS (python3-openturns) fits a sparse PCE on the same successful
training runs, with the same input distributions, hyperbolic truncation
(degree and q-norm of the saved model) and basis selection (LARS with the
corrected leave-one-out error), and the first-order and total indices of both
are printed side by side. Exit status 1 when an index differs by more than
the tolerance; 0, with a message, where OpenTURNS is not installed.
"""
import argparse
import sys

import h5py
import numpy as np


def ot_marginal(ot, kind, a, b, lower, upper):
    """The OpenTURNS distribution of one /surrogate/inputs row; a log-uniform
    input is expanded in log x, as rover expands it."""
    if kind == "uniform":
        return ot.Uniform(a, b)
    if kind == "log_uniform":
        return ot.Uniform(np.log(a), np.log(b))
    base = ot.Normal(a, b) if kind == "normal" else ot.LogNormal(a, b)
    if np.isfinite(lower) or np.isfinite(upper):
        lo = lower if np.isfinite(lower) else base.getRange().getLowerBound()[0]
        hi = upper if np.isfinite(upper) else base.getRange().getUpperBound()[0]
        return ot.TruncatedDistribution(base, max(lo, 0.0) if kind == "lognormal" else lo, hi)
    return base


def openturns_indices(ot, x, y, marginals, degree, q_norm):
    d = len(marginals)
    distribution = ot.ComposedDistribution(marginals)
    enumerate_function = ot.HyperbolicAnisotropicEnumerateFunction(d, q_norm)
    factories = [ot.StandardDistributionPolynomialFactory(m) for m in marginals]
    basis = ot.OrthogonalProductPolynomialFactory(factories, enumerate_function)
    terms = enumerate_function.getStrataCumulatedCardinal(degree)
    selection = ot.LeastSquaresMetaModelSelectionFactory(ot.LARS(), ot.CorrectedLeaveOneOut())
    algorithm = ot.FunctionalChaosAlgorithm(ot.Sample(x), ot.Sample(y.reshape(-1, 1)), distribution,
                                            ot.FixedStrategy(basis, terms), ot.LeastSquaresStrategy(selection))
    algorithm.run()
    sobol = ot.FunctionalChaosSobolIndices(algorithm.getResult())
    return (np.array([sobol.getSobolIndex(i) for i in range(d)]),
            np.array([sobol.getSobolTotalIndex(i) for i in range(d)]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("result", help="HDF5 file of `rover surrogate --study` with a PCE")
    parser.add_argument("--tolerance", type=float, default=0.02)
    args = parser.parse_args()
    try:
        import openturns as ot
    except ImportError:
        print("surrogate_openturns: skipped: OpenTURNS is not installed (apt-get install python3-openturns)")
        return 0
    with h5py.File(args.result, "r") as h5:
        if h5["/surrogate"].attrs["kind"] != "pce":
            sys.exit(f"{args.result}: the surrogate is not a PCE")
        labels = [s.decode() if isinstance(s, bytes) else s for s in h5["/surrogate/inputs/labels"][()]]
        kinds = [s.decode() if isinstance(s, bytes) else s for s in h5["/surrogate/inputs/distribution"][()]]
        parameters = h5["/surrogate/inputs/parameters"][()]
        ok = h5["/samples/status"][()] == 0
        x = h5["/inputs/values"][()][ok]
        for j, kind in enumerate(kinds):
            if kind == "log_uniform":
                x[:, j] = np.log(x[:, j])
        marginals = [ot_marginal(ot, k, *p) for k, p in zip(kinds, parameters)]
        worst = 0.0
        for name in h5["/surrogate/outputs"][()]:
            name = name.decode() if isinstance(name, bytes) else name
            if not h5[f"/indices/{name}"].attrs["defined"]:
                continue
            model = h5[f"/surrogate/models/{name}"]
            s1, st = openturns_indices(ot, x, h5[f"/qoi/{name}"][()][ok], marginals,
                                       int(model.attrs["degree"]), float(model.attrs["q_norm"]))
            ours_s1, ours_st = h5[f"/indices/{name}/S1"][()], h5[f"/indices/{name}/ST"][()]
            print(f"{name}: {'input':24s} {'S1 rover':>9s} {'S1 OT':>9s} {'ST rover':>9s} {'ST OT':>9s}")
            for i, label in enumerate(labels):
                print(f"  {label:24s} {ours_s1[i]:9.4f} {s1[i]:9.4f} {ours_st[i]:9.4f} {st[i]:9.4f}")
            worst = max(worst, np.abs(ours_s1 - s1).max(), np.abs(ours_st - st).max())
    print(f"largest difference {worst:.4f} (tolerance {args.tolerance})")
    return 0 if worst <= args.tolerance else 1


if __name__ == "__main__":
    sys.exit(main())

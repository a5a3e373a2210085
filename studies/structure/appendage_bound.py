#!/usr/bin/env python3
"""How much an appendage of the structure study can be seen at all: an upper bound on what any
diagnosis can gain from it.

For each `A_appendage_*` case of a set made by generate.py (and, for contrast, each `B_mass_*`
null), the case's record is fitted twice by least squares, with numpy/scipy only (no memid code):

  reference  the shear building with k1, k2, k3, alpha, beta and the masses m1, m2 free (as
             memid's reference frees the masses the data determine);
  truth form the same plus the generator's own appendage (a mass on a spring and damper at the
             case's true floor, released relaxed) with its mass, frequency and damping free,
             started from a grid of frequencies and from the truth.

The in-sample gain of the truth form is the profiled Gaussian log-likelihood ratio
(m/2) ln(SS_ref / SS_truth) with white noise, m the number of residuals: the most an unmodeled
mode of any form can gain on that record. A candidate with k = 3 parameters needs
ΔBIC = -2 gain + k ln m < -10 before it is even scored out of sample, i.e. a gain above
(10 + 3 ln m) / 2 = 17.4 nats at m = 4002.

usage:  python3 studies/structure/appendage_bound.py DIR      (DIR from generate.py, ~1 min a case)
"""
import json
import sys

import numpy as np
from scipy.linalg import expm
from scipy.optimize import least_squares

H, N = 0.005, 2001
Q0 = np.array([0.01, 0.02, 0.03])
NOMINAL = np.array([2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3, 1000.0, 1000.0])


def response(p, appendage=None, j=0):
    """q1, q3 of the building at p = (k1, k2, k3, alpha, beta, m1, m2), with an appendage
    (mass, frequency, damping ratio) at floor j released relaxed; exact discretisation."""
    k1, k2, k3, alpha, beta, m1, m2 = p
    M = np.diag([m1, m2, 1000.0])
    K = np.array([[k1 + k2, -k2, 0], [-k2, k2 + k3, -k3], [0, -k3, k3]])
    D = alpha * M + beta * K
    Mi = np.linalg.inv(M)
    ns = 6 + (2 if appendage is not None else 0)
    A = np.zeros((ns, ns))
    A[:3, 3:6] = np.eye(3)
    A[3:6, :3] = -Mi @ K
    A[3:6, 3:6] = -Mi @ D
    x = np.zeros(ns)
    x[:3] = Q0
    if appendage is not None:
        # r = appendage displacement relative to floor j: m_a (q_j'' + r'') = -k_a r - c_a r'.
        ma, f, zeta = appendage
        w = 2 * np.pi * f
        A[3:6, 6] += Mi[:, j] * ma * w * w
        A[3:6, 7] += Mi[:, j] * ma * 2 * zeta * w
        A[6, 7] = 1.0
        A[7, :] = -A[3 + j, :]
        A[7, 6] += -w * w
        A[7, 7] += -2 * zeta * w
    step = expm(A * H)
    out = np.empty((N, 2))
    for k in range(N):
        out[k] = x[[0, 2]]
        x = step @ x
    return out


def gain(y, j, truth):
    scale = y.std(axis=0)
    ref = least_squares(lambda s: ((response(s * NOMINAL) - y) / scale).ravel(), np.ones(7), x_scale="jac")
    starts = [(f, 1.0) for f in (5, 8, 12, 16, 20, 25, 30)]
    if truth:
        starts.append((truth["f"], truth["mass"] / 10.0))
    best = None
    for f0, m0 in starts:
        def residual(s):
            return ((response(s[:7] * NOMINAL, (10.0 * s[7], s[8], s[9]), j) - y) / scale).ravel()
        try:
            fit = least_squares(residual, np.r_[ref.x, m0, f0, 0.02],
                                bounds=(np.r_[np.full(7, 0.2), 0, 1, 0], np.r_[np.full(7, 5), 30, 60, 0.3]),
                                x_scale="jac")
        except (ValueError, np.linalg.LinAlgError):
            continue
        if best is None or fit.cost < best.cost:
            best = fit
    if best is None:
        return float("nan"), (float("nan"),) * 3
    m = y.size
    return m / 2 * np.log(ref.cost / best.cost), best.x[7:] * [10, 1, 1]


def main():
    root = sys.argv[1]
    cases = json.load(open(f"{root}/truth.json"))["cases"]
    bar = (10 + 3 * np.log(2 * N)) / 2
    print(f"gain a 3-parameter mode needs for dBIC < -10: {bar:.1f} nats")
    for case in cases:
        if not (case["name"].startswith("A_appendage") or case["name"].startswith("B_mass")):
            continue
        y = np.loadtxt(f"{root}/{case['data']}", delimiter=",", skiprows=1)[:, 1:]
        truth = (case["truth"].get("effects") or [{}])[0]
        floors = [int(truth["coordinate"][1]) - 1] if "coordinate" in truth else [0, 1, 2]
        with np.errstate(all="ignore"):
            for j in floors:
                g, (ma, f, zeta) = gain(y, j, truth if "f" in truth else None)
                said = f"truth {truth['mass']:.0f} kg {truth['f']:.1f} Hz" if "f" in truth else "null"
                print(f"{case['name']:24s} floor {j + 1}  {said:22s} gain {g:6.1f} nats"
                      f"  (fitted {ma:.1f} kg, {f:.1f} Hz, zeta {zeta:.3f})", flush=True)


if __name__ == "__main__":
    main()

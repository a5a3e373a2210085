#!/usr/bin/env python3
"""What a sensor's drift on a forced record with noise on its recorded force gains under the
noise's true covariance, and under per-output linear predictors of 20 and more lags of it: the
independent check behind the predictor's order (docs/diagnose.md, "The force's noise predicted to
its modes' length"; crates/discrepancy/src/diagnose/force_noise.rs, `predictor_of`).

The building of studies/structure (masses 1000 kg, k1..k3, Rayleigh alpha, beta free) is fitted by
scipy's least squares to the record, without and with a drift on SENSOR (the drift's rate free),
both RMS-weighted as the diagnosis' refits are. The noise's covariance is the generator's own:
white noise of the truth's input-noise share of the applied force's RMS through the fitted
building (its exact sampled impulse response, Toeplitz), beside each column's white sensor noise
at the truth's level (truth.json). The gain is the Gaussian log-likelihood of the drift's residual
less the reference's: under the joint covariance (both outputs), per output (cross-covariance
dropped), and per output by the profiled likelihood of a linear predictor of q lags of that
covariance (Levinson-Durbin, as the diagnosis scores). Shares no code with the diagnosis.

    python3 studies/structure/drift_gain.py DRAW CASE SENSOR      # e.g. /tmp/g41 A_drift_medium_s1 q1
"""
import argparse
import json
import os
import sys

import numpy as np
from scipy.linalg import cho_factor, cho_solve, solve_toeplitz, toeplitz
from scipy.optimize import least_squares

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import generate as G  # noqa: E402  (the study's own building and exact zero-order-hold stepping)

COLUMNS = {"q1": 0, "q3": 1}


def simulate(theta, u, drift_on=None):
    k1, k2, k3, a, b = theta[:5]
    M = np.diag([1000.0, 1000.0, 1000.0])
    K = np.array([[k1 + k2, -k2, 0.0], [-k2, k2 + k3, -k3], [0.0, -k3, k3]])
    y = G.linear_zoh(*G.state_space(M, K, a * M + b * K), u)[:, [0, 2]].copy()
    if drift_on is not None:
        y[:, drift_on] += theta[5] * 1e-6 * np.arange(len(u)) * G.H
    return y


def fit(u, y, drift_on):
    start = [2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3] + ([0.0] if drift_on is not None else [])
    scale = np.array([1e6, 1e6, 1e6, 0.1, 1e-3, 1.0][: len(start)])
    w = 1.0 / np.std(y, axis=0)
    r = least_squares(lambda p: ((simulate(p * scale, u, drift_on) - y) * w).ravel(),
                      np.array(start) / scale, xtol=1e-12, ftol=1e-12)
    theta = r.x * scale
    return y - simulate(theta, u, drift_on), theta


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("draw")
    ap.add_argument("case")
    ap.add_argument("sensor", choices=sorted(COLUMNS))
    opt = ap.parse_args()
    truth = {c["name"]: c for c in json.load(open(os.path.join(opt.draw, "truth.json")))["cases"]}[opt.case]["truth"]
    data = np.loadtxt(os.path.join(opt.draw, "data", opt.case + ".csv"), delimiter=",", skiprows=1)
    u, y = data[:, 1], data[:, 2:]
    n = len(u)
    reference, theta = fit(u, y, None)
    drifted, theta_d = fit(u, y, COLUMNS[opt.sensor])
    impulse = np.zeros(n)
    impulse[0] = 1.0
    g = simulate(theta, impulse)
    t1, t3 = toeplitz(g[:, 0], np.zeros(n)), toeplitz(g[:, 1], np.zeros(n))
    se2 = (truth["input"]["noise"] * truth["input"]["rms"]) ** 2
    clean = y - reference  # the fitted response stands for the clean one in the sensors' levels
    sv = (truth["level"] * np.sqrt(np.mean((clean - clean.mean(axis=0)) ** 2, axis=0))) ** 2
    joint = np.block([[se2 * t1 @ t1.T + sv[0] * np.eye(n), se2 * t1 @ t3.T],
                      [se2 * t3 @ t1.T, se2 * t3 @ t3.T + sv[1] * np.eye(n)]])
    apart = joint.copy()
    apart[:n, n:] = 0.0
    apart[n:, :n] = 0.0

    def loglik(r, cov):
        v = r.T.ravel()
        return -0.5 * v @ cho_solve(cho_factor(cov), v)

    def predictor_gain(q):
        total = 0.0
        for o, t in enumerate((t1, t3)):
            gamma = np.array([se2 * t[l:, 0] @ t[: n - l, 0] for l in range(q + 1)])
            gamma[0] += sv[o]
            a = solve_toeplitz(gamma[:q], gamma[1:])

            def profiled(e):
                innovations = e[q:] - np.array([a @ e[k - 1::-1][:q] for k in range(q, n)])
                m = len(innovations)
                return -0.5 * m * np.log(innovations @ innovations / m)
            total += profiled(drifted[:, o]) - profiled(reference[:, o])
        return total

    print(f"{opt.case}: drift on {opt.sensor} fitted {theta_d[5] * 1e-6:.3e} m/s; truth {truth['effects']}")
    print(f"gain under the joint covariance {loglik(drifted, joint) - loglik(reference, joint):.1f} nats, "
          f"per output {loglik(drifted, apart) - loglik(reference, apart):.1f}")
    for q in (1, 20, 40, 60, 80, 100):
        print(f"per-output predictor of {q} lags: {predictor_gain(q):.1f} nats")


if __name__ == "__main__":
    main()

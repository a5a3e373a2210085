#!/usr/bin/env python3
"""Where the noise on a recorded force shows: in the force's own quiet band, and in what a fitted
model's residual holds at its modes (thirty-sixth session; docs/diagnose.md, "The force's noise
read from its own quiet band").

Independent of the Rust code: the fitted building (the stiffnesses and Rayleigh damping that
`memid diagnose --json` reports for the baseline, the masses of the model file) is sampled
exactly (zero-order hold, scipy's expm), driven by the recorded force, and its residual's Welch
spectrum (Hann, a quarter of the record) is set beside what white noise of a given share of the
force's RMS puts there through the model, |G(e^{iwh})|^2 sigma_e^2 (the one-sided density), plus
the sensors' floor (the residual's own mean level at 60-100 Hz, where the model's response to
the force's noise is nil). The force's quiet band is read as the Rust code reads it
(crates/discrepancy/src/frf/input_noise.rs, `quiet_level`): the bins under 1e-3 of its largest,
those above three times their median left out, their mean level as a variance.

usage: python3 studies/structure/quiet_read.py DRAW_DIR KEEP_DIR CASE [CASE ...] [--share 0.01]
  DRAW_DIR  a draw of studies/structure/generate.py --forced (truth.json, data/)
  KEEP_DIR  the diagnoses' JSON of that draw (studies/diagnose/score.py --keep)
"""
import argparse
import json

import numpy as np
from scipy.linalg import expm
from scipy.signal import welch

BANDS = [(0, 2), (2, 6), (6, 12), (12, 20), (20, 40), (40, 100)]


def fitted_building(keep):
    """A, B, C of the fitted three-storey building (force on floor 3; q1, q3 measured)."""
    p = {x["name"]: x["final"] for x in keep["baseline"]["parameters"]}
    k = [p["k1"], p["k2"], p["k3"]]
    m = np.array([1000.0, 1000.0, 1000.0])
    K = np.array([[k[0] + k[1], -k[1], 0], [-k[1], k[1] + k[2], -k[2]], [0, -k[2], k[2]]])
    M = np.diag(m)
    D = p["alpha"] * M + p["beta"] * K
    A = np.zeros((6, 6))
    A[:3, 3:] = np.eye(3)
    A[3:, :3] = -np.linalg.solve(M, K)
    A[3:, 3:] = -np.linalg.solve(M, D)
    B = np.zeros((6, 1))
    B[3:, 0] = np.linalg.solve(M, [0, 0, 1.0])
    C = np.zeros((2, 6))
    C[0, 0], C[1, 2] = 1.0, 1.0
    return A, B, C


def quiet_level(u, length):
    """The force's noise variance from its quiet band, or None (the Rust rule's flatness test aside)."""
    f, P = welch(u, fs=1.0, window="hann", nperseg=length, detrend="constant")
    P = P[1:length // 2]
    quiet = P[P < 1e-3 * P.max()]
    if len(quiet) < max(4, len(P) / 8):
        return None
    quiet = quiet[quiet <= 3 * np.median(quiet)]
    return float(quiet.mean() / 2.0)  # one-sided density at fs = 1 -> variance of white noise


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("draw")
    ap.add_argument("keep")
    ap.add_argument("cases", nargs="+")
    ap.add_argument("--share", type=float, default=0.01)
    opt = ap.parse_args()
    truth = {x["name"]: x for x in json.load(open(f"{opt.draw}/truth.json"))["cases"]}
    for name in opt.cases:
        case = truth[name]
        data = np.loadtxt(f"{opt.draw}/{case['data']}", delimiter=",", skiprows=1)
        t, u, y = data[:, 0], data[:, 1], data[:, 2:4]
        h = t[1] - t[0]
        keep = json.load(open(f"{opt.keep}/{name}.json"))
        A, B, C = fitted_building(keep)
        E = expm(np.block([[A, B], [np.zeros((1, 7))]]) * h)
        Phi, G = E[:6, :6], E[:6, 6]
        x, sim = np.zeros(6), np.zeros((len(u), 2))
        for i in range(len(u)):
            sim[i] = C @ x
            x = Phi @ x + G * u[i]
        r = y - sim
        length = len(u) // 4
        f, Pr = welch(r, fs=1 / h, window="hann", nperseg=length, axis=0, detrend="constant")
        z = np.exp(2j * np.pi * f * h)
        Gf = np.array([C @ np.linalg.solve(zz * np.eye(6) - Phi, G) for zz in z])
        rms_u = float(np.sqrt(np.mean(u ** 2)))
        sigma = opt.share * rms_u
        floor = Pr[(f >= 60) & (f < 100)].mean(axis=0)
        quiet = quiet_level(u, length)
        read = "none" if quiet is None else f"{100 * np.sqrt(quiet) / rms_u:.2f} %"
        kind = case["truth"].get("input", {}).get("kind")
        print(f"{name} ({kind}): the force's quiet band reads its noise at {read} of its RMS "
              f"(truth {100 * case['truth'].get('input', {}).get('noise', float('nan')):.2f} %)")
        for lo, hi in BANDS:
            s = (f >= lo) & (f < hi)
            for o, col in enumerate(["q1", "q3"]):
                expected = (sigma ** 2 * 2 * h * np.abs(Gf[s, o]) ** 2).mean() + floor[o]
                print(f"  {lo:>3}-{hi:<3} Hz {col}: residual {Pr[s, o].mean():.3e}, "
                      f"{100 * opt.share:g} % noise and floor {expected:.3e} (ratio {Pr[s, o].mean() / expected:.2f})")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Check the independent truth plant against `memid simulate` (run from the project root).

  python3 studies/diagnose/check_plant.py [--memid target/release/memid]

1. Linear plant: the fixture and three perturbed parameter sets (C_v, K_p, modal damping, theta(0),
   hub and motor inertia, EI/rho, rho, L), 128 Hz, 30 s: max |difference| / peak per output.
2. The catalog's textbook nonlinear forms (where the binary knows them) against this RK4
   (h = 1/1280 s): current clamp, smooth current limiter, voltage clamp, Coulomb, quadratic drag,
   cubic stiffness, an inertia-coupled mode; and the exact delay against memid's Padé(1,1).
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.dont_write_bytecode = True          # keep the repository free of __pycache__
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from truthplant import NOMINAL, Plant, Sim  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURE = os.path.join(HERE, "..", "..", "fixtures", "slewing.ron")
T = np.arange(3841) / 128


def simulate(memid, ron_text, sets, work):
    m = os.path.join(work, "m.ron")
    o = os.path.join(work, "s.csv")
    open(m, "w").write(ron_text)
    cmd = [memid, "simulate", "--model", m, "--rate", "128", "--duration", "30", "-o", o]
    for k, v in sets:
        cmd += ["--set", f"{k}={v!r}"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode:
        return None, r.stderr.strip().splitlines()[-1]
    return np.loadtxt(o, delimiter=",", skiprows=1)[:, 1:], ""


def rel(Y, d):
    return [float(np.max(np.abs(Y[:, k] - d[:, k])) / np.max(np.abs(d[:, k]))) for k in range(3)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--memid", default="target/release/memid")
    a = ap.parse_args()
    src = open(FIXTURE).read()
    worst = 0.0
    with tempfile.TemporaryDirectory() as work:
        print("linear plant vs memid simulate (max |diff| / peak: theta, theta_dot, strain)")
        cases = [dict(),
                 dict(cv=0.3, kp=6.1, modal_damping=[0.8, 0.7, 1.4], theta0=0.73),
                 dict(cv=0.07, kp=10.2, hub_inertia=3.49e-3 * 1.2, motor_inertia=6.02e-2 * 0.85,
                      ei_over_rho=0.857 * 1.1, theta0=0.31),
                 dict(cv=0.15, kp=7.0, rho=0.5792 * 1.05, length=1.19 * 0.98, theta0=0.6)]
        for c in cases:
            p = dict(NOMINAL)
            p.update(c)
            txt = src.replace("hub_angle: 0.5,", f"hub_angle: {p['theta0']!r},")
            sets = [(k, p[k]) for k in ("cv", "kp", "hub_inertia", "motor_inertia", "ei_over_rho", "rho", "length")]
            sets += [(f"modal_damping_{i + 1}", v) for i, v in enumerate(p["modal_damping"])]
            d, err = simulate(a.memid, txt, sets, work)
            if d is None:
                print("  memid failed:", err)
                continue
            e = rel(Plant(p).linear_response(T), d)
            worst = max(worst, max(e))
            print(f"  {str(c) or 'fixture':<100} {e[0]:.1e} {e[1]:.1e} {e[2]:.1e}")
        print(f"  worst {worst:.2e}")

        print("nonlinear textbook forms vs memid simulate (RK4 h = 1/1280 s here)")
        pl = Plant(NOMINAL)

        def eff(text):
            return src.replace('    free: ["cv"],', f'    effects: [{text}],\n    free: ["cv"],')

        def sim(config, **kw):
            s = Sim(pl, 1)
            config(s)
            return s.run(**kw)[0]

        w = 2 * np.pi * 0.6
        eM = np.zeros((5, 5))
        eM[0, 4] = eM[4, 0] = 0.25
        eK = np.zeros((5, 5))
        eK[4, 4] = w * w
        eD = np.zeros((5, 5))
        eD[4, 4] = 2 * 0.03 * w
        M, K, D, _, _, sr = pl.augmented(eM, eK, eD, 1)
        checks = [
            ("AmplifierSaturation(current_limit: 1.3, sharp: true)",
             lambda: sim(lambda s: setattr(s, "isat", lambda i: np.clip(i, -1.3, 1.3)))),
            ("AmplifierSaturation(current_limit: 1.3)",
             lambda: sim(lambda s: setattr(s, "isat", lambda i: i / (1 + (i / 1.3) ** 8) ** 0.125))),
            ("VoltageSaturation(voltage_limit: 3.0, sharp: true)",
             lambda: sim(lambda s: setattr(s, "vsat", lambda u: np.clip(u, -3.0, 3.0)))),
            ("CoulombFriction(torque: 0.01, smoothing_velocity: 0.005)",
             lambda: sim(lambda s: s.tau_hubs.append(lambda t, q, qd, z: -0.01 * np.tanh(qd[:, 0] / 0.005)))),
            ("QuadraticDrag(hub: 0.06)",
             lambda: sim(lambda s: s.tau_hubs.append(lambda t, q, qd, z: -0.06 * np.abs(qd[:, 0]) * qd[:, 0]))),
            ("CubicStiffness(coefficient: 0.5)",
             lambda: sim(lambda s: s.tau_hubs.append(lambda t, q, qd, z: -0.5 * q[:, 0] ** 3))),
            ("UnmodeledMode(frequency_hz: 0.6, damping_ratio: 0.03, coupling: 0.25)",
             lambda: pl.linear_response(T, M, K, D, sr)),
            ("TimeDelay(delay: 0.1)  [memid: Pade(1,1); here: exact]",
             lambda: sim(lambda s: None, delay=np.array([0.1]))),
        ]
        Y0 = pl.linear_response(T)
        for text, f in checks:
            d, err = simulate(a.memid, eff(text.split("  [")[0]), [], work)
            if d is None:
                print(f"  {text:<75} memid: {err[:80]}")
                continue
            Y = f()
            e = rel(Y, d)
            size = rel(Y0, d)
            print(f"  {text:<75} {e[0]:.1e} {e[1]:.1e} {e[2]:.1e}   (effect {max(size):.2f} of peak)")


if __name__ == "__main__":
    main()

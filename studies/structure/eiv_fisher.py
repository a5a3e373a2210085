#!/usr/bin/env python3
"""How well a forced record with noise on its recorded force determines a sensor's effect, by
Fisher information: the independent check behind docs/diagnose.md, "The force's noise predicted to
its modes' length". Shares no code with the diagnosis.

The nominal building of studies/structure (its `generate.py`: masses 1000 kg, k = 2.5, 2.25,
1.875 MN/m, Rayleigh alpha 0.375, beta 1.25e-3), driven on floor 3 by each of the study's inputs
(band-limited random, chirp; unit RMS), read at q1 and q3. The noise: white noise of 1 % of the
force's RMS on the recorded force, through the building's exact sampled impulse response
(Toeplitz; it reaches both outputs through one response), beside white sensor noise of 0.5, 1 and
2 % of each output's RMS. For a drift, an offset and a scale on q1 and a drift on q3, with the five
free parameters profiled out, it prints the standard error of the per-output model (the
cross-covariance dropped; the sandwich, since the noise is correlated across outputs) and of the
exact-force record (sensor noise alone), each over the joint model's.

    python3 studies/structure/eiv_fisher.py        # about 1.5 min
"""
import os
import sys

import numpy as np
from scipy.linalg import cho_factor, cho_solve, toeplitz

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import generate as G  # noqa: E402

N = G.N


def simulate(theta, u):
    k1, k2, k3, a, b = theta
    M = np.diag([1000.0, 1000.0, 1000.0])
    K = np.array([[k1 + k2, -k2, 0.0], [-k2, k2 + k3, -k3], [0.0, -k3, k3]])
    return G.linear_zoh(*G.state_space(M, K, a * M + b * K), u)[:, [0, 2]]


def main():
    theta = np.array([2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3])
    impulse = np.zeros(N)
    impulse[0] = 1.0
    g = simulate(theta, impulse)
    t1, t3 = toeplitz(g[:, 0], np.zeros(N)), toeplitz(g[:, 1], np.zeros(N))
    rng = np.random.default_rng(3)
    t = np.arange(N) * G.H
    zero = np.zeros(N)
    print("ratios of standard errors to the joint model's: per output | exact force")
    for kind in ("random", "chirp"):
        u = G.input_shape(rng, kind)
        u /= np.std(u)
        y = simulate(theta, u)
        jac = np.array([((simulate(theta * (1 + 1e-6 * (np.arange(5) == i)), u) - y) / (theta[i] * 1e-6)).T.ravel()
                        for i in range(5)]).T
        force = 0.01 ** 2
        for level in (0.005, 0.01, 0.02):
            sensor = (level * y.std(axis=0)) ** 2
            joint = np.block([[force * t1 @ t1.T + sensor[0] * np.eye(N), force * t1 @ t3.T],
                              [force * t3 @ t1.T, force * t3 @ t3.T + sensor[1] * np.eye(N)]])
            apart = joint.copy()
            apart[:N, N:] = 0.0
            apart[N:, :N] = 0.0
            exact = np.concatenate([np.full(N, sensor[0]), np.full(N, sensor[1])])
            effects = {"drift q1": np.concatenate([t, zero]), "offset q1": np.concatenate([np.ones(N), zero]),
                       "scale q1": np.concatenate([y[:, 0], zero]), "drift q3": np.concatenate([zero, t])}
            row = []
            for name, effect in effects.items():
                a = np.column_stack([effect, jac])
                var_joint = np.linalg.inv(a.T @ cho_solve(cho_factor(joint), a))[0, 0]
                wa = cho_solve(cho_factor(apart), a)
                bread = np.linalg.inv(a.T @ wa)
                var_apart = (bread @ (wa.T @ joint @ wa) @ bread)[0, 0]
                var_exact = np.linalg.inv(a.T @ (a / exact[:, None]))[0, 0]
                row.append(f"{name} {np.sqrt(var_apart / var_joint):.2f} | {np.sqrt(var_exact / var_joint):.2f}")
            print(f"{kind:6s} sensor {level:.3f}: " + "; ".join(row))


if __name__ == "__main__":
    main()

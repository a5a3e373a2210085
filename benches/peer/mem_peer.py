#!/usr/bin/env python3
"""The same MEM iteration the way an engineer would write it in Python, for benches/peer/compare.py.

Two versions, both exact (Fréchet derivatives of the exponential at a constant interval h):
  straightforward  scipy.linalg.expm_frechet once per parameter, a Python loop over samples
                   propagating x and each sensitivity separately, numpy lstsq for the step;
  vectorised       one expm_frechet per parameter, then a Python loop over samples that
                   advances [x, S] as one matrix product and the stacked Ψ as another, SVD step.
The model family matches memid's benches in shape (n lightly coupled damped modes, parameters
scaling stiffness and damping of interleaved mode groups, displacement outputs, h = 1/12.8 s).
Prints JSON: seconds per iteration for each size and a whole paper-size fit.
"""
import json
import sys
import time

import numpy as np
import scipy.linalg

SIZES = [("paper", 4, 2, 3, 400), ("medium", 20, 5, 4, 2000), ("large", 100, 20, 10, 10000)]
H = 1.0 / 12.8


def family(n_modes, n_params, n_outputs, seed=2026):
    rng = np.random.default_rng(seed)
    t = np.eye(n_modes) + 0.05 * rng.standard_normal((n_modes, n_modes)) / np.sqrt(n_modes)
    omega = 2 * np.pi * 0.1 * 50.0 ** (np.arange(n_modes) / max(n_modes - 1, 1))
    zeta = 0.01 + 0.09 * rng.random(n_modes)
    n_stiff = (n_params + 1) // 2
    n_damp = max(n_params - n_stiff, 1)
    def term(values, group, groups):
        d = np.diag([values[i] if i % groups == group else 0.0 for i in range(n_modes)])
        return t.T @ d @ t
    ks = [term(omega ** 2, g, n_stiff) for g in range(n_stiff)]
    ds = [term(2 * zeta * omega, g, n_damp) for g in range(n_damp)]
    n = 2 * n_modes
    def a_of(p):
        a = np.zeros((n, n))
        a[:n_modes, n_modes:] = np.eye(n_modes)
        for i, k in enumerate(ks):
            a[n_modes:, :n_modes] -= p[i] * k
        for g, d in enumerate(ds):
            scale = p[n_stiff + g] if n_stiff + g < n_params else 1.0
            a[n_modes:, n_modes:] -= scale * d
        return a
    def da(i):
        d = np.zeros((n, n))
        if i < n_stiff:
            d[n_modes:, :n_modes] = -ks[i]
        else:
            d[n_modes:, n_modes:] = -ds[i - n_stiff]
        return d
    c = np.zeros((n_outputs, n))
    for o in range(n_outputs):
        c[o, o * n_modes // n_outputs] = 1.0
    x0 = np.concatenate([rng.standard_normal(n_modes), np.zeros(n_modes)])
    return a_of, da, c, x0


def straightforward(a, das, c, x0, k):
    phi = None
    psis = []
    for d in das:
        phi, psi = scipy.linalg.expm_frechet(a * H, d * H)
        psis.append(psi)
    return march(c, x0, len(das), k, lambda step, x, s: (phi @ x, [phi @ s[i] + psis[i] @ x for i in range(len(das))]))


def march(c, x0, j, k, advance):
    """Outputs and sensitivities of k samples: y = Cx, ∂y/∂P_i = Cs_i, then (x, s) ← advance."""
    x = x0.copy()
    s = [np.zeros_like(x0) for _ in range(j)]
    y = np.empty((k, c.shape[0]))
    sens = np.empty((k, c.shape[0], j))
    for step in range(k):
        y[step] = c @ x
        for i in range(j):
            sens[step, :, i] = c @ s[i]
        x, s = advance(step, x, s)
    return y, sens.reshape(k * c.shape[0], j)


def vectorised(a, das, c, x0, k):
    psis = []
    for d in das:
        phi, psi = scipy.linalg.expm_frechet(a * H, d * H)
        psis.append(psi)
    n, j, p = a.shape[0], len(das), c.shape[0]
    psi_stack = np.vstack(psis)
    block = np.zeros((n, j + 1))
    block[:, 0] = x0
    y = np.empty((k, p, j + 1))
    for step in range(k):
        y[step] = c @ block
        w = psi_stack @ block[:, 0]
        block = phi @ block
        block[:, 1:] += w.reshape(j, n).T
    return y[:, :, 0], y[:, :, 1:].reshape(k * p, j)


def forced_straightforward(a, das, b, c, x0, u, k):
    """A forced (zero-order hold) MEM response as a SciPy user writes it: Φ and Γ from the
    exponential of [[A, B], [0, 0]]h, and their derivatives from its Fréchet derivative in the
    direction [[∂A/∂P_i, 0], [0, 0]]h; then x ← Φx + Γu, s_i ← Φs_i + ∂Φ_i x + ∂Γ_i u."""
    n, m = b.shape
    big = np.zeros((n + m, n + m))
    big[:n, :n] = a
    big[:n, n:] = b
    grads = []
    for d in das:
        e = np.zeros_like(big)
        e[:n, :n] = d
        full, dfull = scipy.linalg.expm_frechet(big * H, e * H)
        grads.append((dfull[:n, :n], dfull[:n, n:]))
    phi, gamma = full[:n, :n], full[:n, n:]
    j = len(das)
    return march(c, x0, j, k, lambda step, x, s: (
        phi @ x + gamma @ u[step],
        [phi @ s[i] + grads[i][0] @ x + grads[i][1] @ u[step] for i in range(j)]))


def iteration(version, a_of, da, c, x0, p, data, k):
    a = a_of(p)
    das = [da(i) for i in range(len(p))]
    y, s = version(a, das, c, x0, k)
    r = (data - y).ravel()
    u, sv, vt = np.linalg.svd(s, full_matrices=False)
    return vt.T @ ((u.T @ r) / sv)


def timed(f, reps):
    f()
    times = []
    for _ in range(reps):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    times.sort()
    return times[len(times) // 2]


def main():
    out = {"sizes": {}}
    for name, modes, j, p, k in SIZES:
        a_of, da, c, x0 = family(modes, j, p)
        truth = np.ones(j) * 1.05
        data, _ = vectorised(a_of(truth), [da(i) for i in range(j)], c, x0, k)
        p0 = np.ones(j)
        reps = {"paper": 201, "medium": 11, "large": 1}[name]
        entry = {}
        for label, version in (("straightforward", straightforward), ("vectorised", vectorised)):
            entry[label] = timed(lambda: iteration(version, a_of, da, c, x0, p0, data, k), reps)
        out["sizes"][name] = entry
        print(f"{name}: {entry}", file=sys.stderr)
    # A forced paper-size iteration: the same family driven by a random force on its first
    # coordinate (B = e_{n+1}), zero-order hold.
    name, modes, j, p, k = SIZES[0]
    a_of, da, c, x0 = family(modes, j, p)
    b = np.zeros((2 * modes, 1))
    b[modes, 0] = 1.0
    u = np.random.default_rng(1).standard_normal((k, 1))
    data, _ = forced_straightforward(a_of(np.ones(j) * 1.03), [da(i) for i in range(j)], b, c, x0, u, k)

    def forced_iteration():
        q = np.ones(j)
        y, s = forced_straightforward(a_of(q), [da(i) for i in range(j)], b, c, x0, u, k)
        r = (data - y).ravel()
        uu, sv, vt = np.linalg.svd(s, full_matrices=False)
        return vt.T @ ((uu.T @ r) / sv)
    out["forced_paper_iteration"] = {"straightforward": timed(forced_iteration, 201)}
    print(f"forced paper: {out['forced_paper_iteration']}", file=sys.stderr)
    # A whole paper-size fit from a 30 % perturbed start (Gauss–Newton until |ΔP| ≤ 1e-8 |P|).
    name, modes, j, p, k = SIZES[0]
    a_of, da, c, x0 = family(modes, j, p)
    data, _ = vectorised(a_of(np.ones(j)), [da(i) for i in range(j)], c, x0, k)
    for label, version in (("straightforward", straightforward), ("vectorised", vectorised)):
        def fit():
            q = np.ones(j) * 1.3
            for _ in range(50):
                step = iteration(version, a_of, da, c, x0, q, data, k)
                q = q + step
                if np.all(np.abs(step) <= 1e-8 * np.abs(q)):
                    break
            return q
        out.setdefault("paper_fit", {})[label] = timed(fit, 21)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Independent high-precision references for the `expm` crate's accuracy tests.

For every case this script stores, as JSON:
  a, e          the matrix A and a direction E (float64, exactly as the Rust test reads them)
  exp_a         e^A, computed at 60 significant digits and rounded to float64
  frechet       L(A, E), the top-right block of exp([[A, E], [0, A]]) at 60 digits
  kappa_exp     scipy.linalg.expm_cond(A): the relative condition number of e^A (Frobenius)
  kappa_frechet expm_cond of the block matrix times ||exp(block)||_F / ||L||_F: a bound on how
                much relative error in L a backward-stable evaluation can cause
  scipy_exp_err, scipy_frechet_err
                the relative Frobenius error of scipy.linalg.expm / expm_frechet on the case,
                so that the Rust tests can check "no worse than SciPy".

The 60-digit exponential is computed by scaling and squaring with a Taylor series whose
truncation error is below 1e-70 (mpmath numbers in numpy object arrays); it shares no code
with the Rust implementation (Padé approximants with double-precision backward-error bounds).

Run:  python3 make_reference.py > cases.json     (needs numpy, scipy, mpmath)
"""
import json
import sys

import mpmath
import numpy as np
import scipy.linalg

mpmath.mp.dps = 60


def to_mp(a):
    return np.vectorize(mpmath.mpf, otypes=[object])(np.asarray(a, dtype=float))


def mp_norm1(a):
    return max(sum(abs(a[i, j]) for i in range(a.shape[0])) for j in range(a.shape[1]))


def mp_expm(a):
    n = a.shape[0]
    norm = mp_norm1(a)
    s = 0
    while norm / (2 ** s) > mpmath.mpf("0.25"):
        s += 1
    x = a / (2 ** s)
    ident = np.array([[mpmath.mpf(1) if i == j else mpmath.mpf(0) for j in range(n)] for i in range(n)], dtype=object)
    result = ident.copy()
    term = ident.copy()
    k = 0
    while True:
        k += 1
        term = (term @ x) / k
        result = result + term
        if mp_norm1(term) < mpmath.mpf("1e-75") * max(mp_norm1(result), mpmath.mpf(1)):
            break
    for _ in range(s):
        result = result @ result
    return result


def to_f64(a):
    return np.array([[float(v) for v in row] for row in a])


def rel_err(x, ref):
    d = np.linalg.norm(ref)
    return float(np.linalg.norm(x - ref) / d) if d > 0 else float(np.linalg.norm(x))


def case(name, a, e):
    a = np.asarray(a, dtype=float)
    e = np.asarray(e, dtype=float)
    n = a.shape[0]
    block = np.zeros((2 * n, 2 * n))
    block[:n, :n] = a
    block[:n, n:] = e
    block[n:, n:] = a
    big = mp_expm(to_mp(block))
    exp_a = to_f64(big[:n, :n])
    frechet = to_f64(big[:n, n:])
    kappa_exp = float(scipy.linalg.expm_cond(a))
    # scale E to the size of A so that the block's conditioning reflects A, not E's size
    scale = np.linalg.norm(a) / max(np.linalg.norm(e), 1e-300)
    block_scaled = block.copy()
    block_scaled[:n, n:] *= scale
    exp_block = to_f64(mp_expm(to_mp(block_scaled)))
    kappa_block = float(scipy.linalg.expm_cond(block_scaled))
    kappa_frechet = kappa_block * np.linalg.norm(exp_block) / max(np.linalg.norm(frechet) * scale, 1e-300)
    s_exp, s_l = scipy.linalg.expm_frechet(a, e)
    print(f"{name}: n={n} kappa_exp={kappa_exp:.3g} kappa_L={kappa_frechet:.3g} "
          f"scipy errs {rel_err(scipy.linalg.expm(a), exp_a):.2e} {rel_err(s_l, frechet):.2e}", file=sys.stderr)
    return {
        "name": name,
        "n": n,
        "a": a.tolist(),
        "e": e.tolist(),
        "exp_a": exp_a.tolist(),
        "frechet": frechet.tolist(),
        "kappa_exp": kappa_exp,
        "kappa_frechet": float(kappa_frechet),
        "scipy_exp_err": rel_err(scipy.linalg.expm(a), exp_a),
        "scipy_frechet_err": rel_err(s_l, frechet),
    }


def structural(freqs_hz, zetas, h, rng):
    """Closed-loop second-order system with lightly coupled modes, first-order form times h."""
    n = len(freqs_hz)
    w = 2 * np.pi * np.asarray(freqs_hz)
    q, _ = np.linalg.qr(np.eye(n) + 0.2 * rng.standard_normal((n, n)))
    k = q @ np.diag(w ** 2) @ q.T
    d = q @ np.diag(2 * np.asarray(zetas) * w) @ q.T
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-k, -d]])
    return a * h


def main():
    rng = np.random.default_rng(20261121)
    cases = []
    def direction(n):
        return rng.standard_normal((n, n))
    cases.append(case("rotation_generator", [[0.0, 1.0], [-1.0, 0.0]], direction(2)))
    cases.append(case("rotation_generator_large", [[0.0, 30.0], [-30.0, 0.0]], direction(2)))
    cases.append(case("repeated_eigenvalue", [[-0.5, 1.0], [0.0, -0.5]], direction(2)))
    jordan = np.diag(np.ones(5), 1)[:6, :6]
    cases.append(case("nilpotent_jordan_6", jordan, direction(6)))
    cases.append(case("diagonal_spread", np.diag(-np.logspace(-3, 3, 10)), direction(10)))
    cases.append(case("diagonal_spread_signed", np.diag(np.concatenate([np.logspace(-3, 2.5, 5), -np.logspace(-3, 3, 5)])), direction(10)))
    skew = rng.standard_normal((6, 6))
    skew = skew - skew.T
    skew *= 300.0 / np.linalg.norm(skew, 1)
    cases.append(case("skew_norm_300", skew, direction(6)))
    damped = -50.0 * np.eye(6) + skew * (1000.0 / 300.0)
    cases.append(case("damped_skew_norm_1000", damped, direction(6)))
    tri = np.triu(np.full((6, 6), 100.0), 1) + np.diag(-np.arange(1.0, 7.0))
    cases.append(case("nonnormal_triangular", tri, direction(6)))
    cases.append(case("nonnormal_2x2", [[-1.0, 1e4], [0.0, -1.01]], direction(2)))
    cases.append(case("moler_van_loan", [[-49.0, 24.0], [-64.0, 31.0]], direction(2)))
    freqs = [0.15, 1.72, 10.0, 30.0]
    zetas = [0.30, 0.02, 0.05, 0.01]
    cases.append(case("structural_h_12_8", structural(freqs, zetas, 1 / 12.8, rng), direction(8)))
    cases.append(case("structural_h_128", structural(freqs, zetas, 1 / 128, rng), direction(8)))
    for n in (16, 40):
        r = rng.standard_normal((n, n)) / np.sqrt(n)
        shift = np.max(np.linalg.eigvals(r).real) + 0.5
        cases.append(case(f"random_stable_{n}", r - shift * np.eye(n), direction(n)))
    # Moler's 3×3 over-scaling example (Al-Mohy & Higham 2009a, §1; SciPy's test suite): ‖A‖₁ ≈ 2e10
    # asks for ~35 squarings, but the powers decay and few are needed.
    moler = [[0.0, 1e-8, 0.0], [-(2e10 + 4e8 / 6.0), -3.0, 2e10], [200.0 / 3.0, 0.0, -200.0 / 3.0]]
    cases.append(case("moler_3x3_overscaling", moler, direction(3)))
    json.dump({"generator": "make_reference.py", "digits": 60, "cases": cases}, sys.stdout)


if __name__ == "__main__":
    main()

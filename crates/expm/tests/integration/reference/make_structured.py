#!/usr/bin/env python3
"""Exact references for the `expm` crate on nilpotent, strictly triangular and Jordan matrices.

Why: for nilpotent A the Padé degree/scaling choice, which looks only at norms of powers of A
(and those vanish: A^n = 0), says "tiny problem", while the Fréchet derivative's series
L(A, E) = sum_k 1/k! sum_{i+j=k-1} A^i E A^j still carries the non-vanishing terms A^i E A^j.
These cases check e^A and L(A, E) on exactly that structure.

Families (every A and E has float64 entries; the references are for those float64 values):
  nilpotent_super    first superdiagonal = s, zero elsewhere; n in {2,3,4,5,6,8,10,12,16},
                     s in {1,2,5,10,20,50,100}
  strict_triangular  strictly upper triangular, integer entries uniform in [-s, s];
                     n in {3,4,6,8,12,16}, s in {1,10,100}
  jordan             lambda*I + N, N the superdiagonal-s nilpotent matrix;
                     lambda in {-1, 0.5, -20}, n in {2,4,8,16}, s in {1,10,100}
  issue              the reported case: 4x4 superdiagonal s, s in {1, 20}
Two directions E per A: "int" (integers uniform in [-3, 3]) and "normal" (standard normal
rounded to 3 decimals, then taken as the float64 it is stored as).  Every random draw comes
from numpy.random.default_rng seeded by (family, n, s, lambda index), so each case is
reproducible on its own.

References (no Padé, no scaling and squaring, no floating point before the final rounding):
  For nilpotent N (A^n = 0) the series terminate:
      e^N     = sum_{k<n} N^k / k!
      L(N, E) = sum_{k=1}^{2n-1} S_k / k!,   S_1 = E,  S_{k+1} = N S_k + E N^k
                (S_k = sum_{i+j=k-1} N^i E N^j),
  evaluated in exact rational arithmetic (fractions.Fraction; Fraction(float) is exact) and
  rounded once to float64 (int/int true division in CPython is correctly rounded).
  For Jordan blocks lambda*I commutes with everything:
      e^{lambda I + N} = e^lambda e^N,   L(lambda I + N, E) = e^lambda L(N, E),
  with e^lambda at 60 digits (mpmath) times the exact rationals, then rounded to float64.
  A handful of cases are cross-checked against make_reference.py's independent 60-digit method
  (scaling and squaring of a Taylor series on the block [[A, E], [0, A]]).

Stored per case, besides name/family/n/s/lambda/direction/a/e/exp_a/frechet:
  kappa_exp, kappa_frechet   exactly as make_reference.py: scipy.linalg.expm_cond(A), and
                             expm_cond of the block [[A, cE], [0, A]] (c = ||A||_F/||E||_F) times
                             ||exp(block)||_F / (c ||L||_F).  exp(block) = [[e^A, cL], [0, e^A]]
                             exactly, so its norm is taken from the exact references.
                             null if not finite.
  kappa_exp_series, kappa_frechet_series
                             the same two quantities with the Kronecker form of the derivative
                             built from the terminating series (K = e^lambda sum_{i,j}
                             (N^j)^T (x) N^i / (i+j+1)!, float64) instead of SciPy's expm_frechet:
                             an independent check on SciPy's condition numbers.
  scipy_exp_err, scipy_frechet_err
                             relative Frobenius errors of scipy.linalg.expm / expm_frechet.

Run:  python3 make_structured.py      (writes structured.json and make_structured.log here;
                                        needs numpy, scipy, mpmath; a few minutes)
"""
import json
import math
import os
import sys
import time
from fractions import Fraction

import mpmath
import numpy as np
import scipy.linalg

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_reference as mr  # noqa: E402  (mp_expm, to_mp, rel_err; sets mpmath to 60 digits)

mpmath.mp.dps = 60

FAMILY_ID = {"nilpotent_super": 1, "strict_triangular": 2, "jordan": 3, "issue": 4}
LAMBDAS = (-1.0, 0.5, -20.0)
MAX_BYTES = 2_000_000

LOG = []


def log(line=""):
    print(line, flush=True)
    LOG.append(line)


# ---------------------------------------------------------------- matrices


def superdiag(n, s):
    return np.diag(np.full(n - 1, float(s)), 1)


def rng_for(family, n, s, lam_index=0):
    return np.random.default_rng([FAMILY_ID[family], n, int(s), lam_index, 20261121])


def strict_triangular(n, s, rng):
    a = rng.integers(-s, s, size=(n, n), endpoint=True).astype(float)
    return np.triu(a, 1)


def directions(n, rng):
    e_int = rng.integers(-3, 3, size=(n, n), endpoint=True).astype(float)
    e_normal = np.round(rng.standard_normal((n, n)), 3)
    return [("int", e_int), ("normal", e_normal)]


# ---------------------------------------------------------------- exact series


def to_frac(a):
    return np.array([[Fraction(float(v)) for v in row] for row in a], dtype=object)


def is_zero(m):
    return all(v == 0 for v in m.flat)


def exact_nilpotent(n_mat, e):
    """e^N and L(N, E) as exact Fraction arrays for nilpotent N (float64 entries)."""
    n = n_mat.shape[0]
    nf = to_frac(n_mat)
    ef = to_frac(e)
    ident = np.array([[Fraction(int(i == j)) for j in range(n)] for i in range(n)], dtype=object)
    powers = [ident]
    while not is_zero(powers[-1]):
        assert len(powers) <= n, "matrix is not nilpotent"
        powers.append(powers[-1] @ nf)
    powers.pop()  # drop the zero power
    exp = sum((p / math.factorial(k) for k, p in enumerate(powers)),
              np.zeros((n, n), dtype=object) + Fraction(0))
    q = len(powers)  # N^q = 0, so S_k = 0 for k > 2q - 1
    s_k = ef.copy()
    frechet = s_k / 1
    for k in range(1, 2 * q - 1):
        # S_{k+1} = N S_k + E N^k
        s_k = nf @ s_k
        if k < q:
            s_k = s_k + ef @ powers[k]
        frechet = frechet + s_k / math.factorial(k + 1)
    assert is_zero(nf @ s_k), "series did not terminate"  # S_{2q} = N S_{2q-1} + E N^{2q-1} = N S_{2q-1}
    return exp, frechet


def frac_to_f64(m):
    return np.array([[float(v) for v in row] for row in m])


def frac_to_mp(m):
    return np.array([[mpmath.mpf(v.numerator) / v.denominator for v in row] for row in m],
                    dtype=object)


def mp_to_f64(m):
    return np.array([[float(v) for v in row] for row in m])


# ---------------------------------------------------------------- condition numbers


def kron_series_norm(nil, lam):
    """||K||_2 for K the Kronecker form of L(lam I + nil, .), from the terminating series."""
    m = nil.shape[0]
    powers = [np.eye(m)]
    while np.any(powers[-1] != 0) and len(powers) <= m:
        powers.append(powers[-1] @ nil)
    if not np.any(powers[-1] != 0):
        powers.pop()
    q = len(powers)
    k = np.zeros((m * m, m * m))
    for j in range(q):
        mj = sum(powers[i] / math.factorial(i + j + 1) for i in range(q))
        k += np.kron(powers[j].T, mj)
    return math.exp(lam) * np.linalg.norm(k, 2)


def finite_or_none(x):
    x = float(x)
    return x if math.isfinite(x) else None


def kappas(a, e, exp_ref, l_ref, lam):
    """make_reference.py's kappa_exp and kappa_frechet, plus the series-based versions."""
    n = a.shape[0]
    block = np.zeros((2 * n, 2 * n))
    block[:n, :n] = a
    block[:n, n:] = e
    block[n:, n:] = a
    scale = np.linalg.norm(a) / max(np.linalg.norm(e), 1e-300)
    block_scaled = block.copy()
    block_scaled[:n, n:] *= scale
    # exp(block_scaled) = [[e^A, scale L], [0, e^A]] exactly (L is linear in E)
    exp_block_norm = math.sqrt(2 * np.linalg.norm(exp_ref) ** 2 + (scale * np.linalg.norm(l_ref)) ** 2)
    l_norm = max(np.linalg.norm(l_ref) * scale, 1e-300)
    with np.errstate(all="ignore"):
        kappa_exp = float(scipy.linalg.expm_cond(a))
        kappa_block = float(scipy.linalg.expm_cond(block_scaled))
    kappa_frechet = kappa_block * exp_block_norm / l_norm
    # independent: Kronecker form from the exact series structure
    nil_a = a - lam * np.eye(n)
    nil_block = block_scaled - lam * np.eye(2 * n)
    kappa_exp_s = kron_series_norm(nil_a, lam) * np.linalg.norm(a) / np.linalg.norm(exp_ref)
    kappa_block_s = kron_series_norm(nil_block, lam) * np.linalg.norm(block_scaled) / exp_block_norm
    kappa_frechet_s = kappa_block_s * exp_block_norm / l_norm
    return (finite_or_none(kappa_exp), finite_or_none(kappa_frechet),
            finite_or_none(kappa_exp_s), finite_or_none(kappa_frechet_s))


# ---------------------------------------------------------------- cases


CROSS_CHECK = {
    "issue_n4_s1_int",
    "issue_n4_s20_normal",
    "nilpotent_super_n8_s10_normal",
    "nilpotent_super_n16_s100_int",
    "strict_triangular_n8_s10_normal",
    "strict_triangular_n16_s100_int",
    "jordan_lm1_n4_s1_normal",
    "jordan_lm20_n8_s10_int",
    "jordan_l0.5_n16_s100_normal",
}
CROSS = []  # (family, name, exp agreement, L agreement, float64 entries differing)


def lam_tag(lam):
    return f"l{lam:g}".replace("-", "m")


def make_case(family, name, a, e, params, lam=0.0):
    n = a.shape[0]
    t0 = time.time()
    nil = a - lam * np.eye(n)
    exp_q, l_q = exact_nilpotent(nil, e)
    if lam == 0.0:
        exp_ref = frac_to_f64(exp_q)
        l_ref = frac_to_f64(l_q)
        exp_mp = frac_to_mp(exp_q)
        l_mp = frac_to_mp(l_q)
    else:
        el = mpmath.exp(mpmath.mpf(lam))
        exp_mp = frac_to_mp(exp_q) * el
        l_mp = frac_to_mp(l_q) * el
        exp_ref = mp_to_f64(exp_mp)
        l_ref = mp_to_f64(l_mp)
    assert np.all(np.isfinite(exp_ref)) and np.all(np.isfinite(l_ref))

    k_exp, k_l, k_exp_s, k_l_s = kappas(a, e, exp_ref, l_ref, lam)
    with np.errstate(all="ignore"):
        s_exp = scipy.linalg.expm(a)
        _, s_l = scipy.linalg.expm_frechet(a, e)
    scipy_exp_err = mr.rel_err(s_exp, exp_ref)
    scipy_l_err = mr.rel_err(s_l, l_ref)

    if name in CROSS_CHECK:
        block = np.zeros((2 * n, 2 * n))
        block[:n, :n] = a
        block[:n, n:] = e
        block[n:, n:] = a
        big = mr.mp_expm(mr.to_mp(block))

        def agree(x, ref):
            ref_norm = mpmath.sqrt(sum(v * v for v in ref.flat))
            return float(max(abs(x[i, j] - ref[i, j]) for i in range(n) for j in range(n)) / ref_norm)

        ag_exp = agree(big[:n, :n], exp_mp)
        ag_l = agree(big[:n, n:], l_mp)
        differ = int(np.sum(mp_to_f64(big[:n, :n]) != exp_ref) + np.sum(mp_to_f64(big[:n, n:]) != l_ref))
        CROSS.append((family, name, ag_exp, ag_l, differ))
        log(f"  cross-check {name}: max |block60 - exact| / ||exact||_F  e^A {ag_exp:.1e}  "
            f"L {ag_l:.1e};  float64 entries differing after rounding: {differ} of {2 * n * n}")

    fmt = lambda x: "null" if x is None else f"{x:.3g}"  # noqa: E731
    log(f"{name:36} n={n:2} kappa_exp={fmt(k_exp):>9} (series {fmt(k_exp_s):>9}) "
        f"kappa_L={fmt(k_l):>9} (series {fmt(k_l_s):>9}) "
        f"scipy errs {scipy_exp_err:.2e} {scipy_l_err:.2e}  [{time.time() - t0:.1f}s]")
    return {
        "name": name,
        "family": family,
        "n": n,
        **params,
        "a": a.tolist(),
        "e": e.tolist(),
        "exp_a": exp_ref.tolist(),
        "frechet": l_ref.tolist(),
        "kappa_exp": k_exp,
        "kappa_frechet": k_l,
        "kappa_exp_series": k_exp_s,
        "kappa_frechet_series": k_l_s,
        "scipy_exp_err": scipy_exp_err,
        "scipy_frechet_err": scipy_l_err,
    }


def family_cases():
    """(family, name, a, e, params, lambda) for every case, in file order."""
    out = []
    for s in (1, 20):
        n = 4
        for tag, e in directions(n, rng_for("issue", n, s)):
            out.append(("issue", f"issue_n{n}_s{s}_{tag}", superdiag(n, s), e,
                        {"s": float(s), "direction": tag}, 0.0))
    for n in (2, 3, 4, 5, 6, 8, 10, 12, 16):
        for s in (1, 2, 5, 10, 20, 50, 100):
            for tag, e in directions(n, rng_for("nilpotent_super", n, s)):
                out.append(("nilpotent_super", f"nilpotent_super_n{n}_s{s}_{tag}", superdiag(n, s), e,
                            {"s": float(s), "direction": tag}, 0.0))
    for n in (3, 4, 6, 8, 12, 16):
        for s in (1, 10, 100):
            rng = rng_for("strict_triangular", n, s)
            a = strict_triangular(n, s, rng)
            for tag, e in directions(n, rng):
                out.append(("strict_triangular", f"strict_triangular_n{n}_s{s}_{tag}", a, e,
                            {"s": float(s), "direction": tag}, 0.0))
    for li, lam in enumerate(LAMBDAS):
        for n in (2, 4, 8, 16):
            for s in (1, 10, 100):
                a = lam * np.eye(n) + superdiag(n, s)
                for tag, e in directions(n, rng_for("jordan", n, s, li + 1)):
                    out.append(("jordan", f"jordan_{lam_tag(lam)}_n{n}_s{s}_{tag}", a, e,
                                {"s": float(s), "lambda": lam, "direction": tag}, lam))
    return out


def main():
    t0 = time.time()
    cases = [make_case(f, name, a, e, p, lam) for f, name, a, e, p, lam in family_cases()]
    doc = {
        "generator": "make_structured.py",
        "method": "exact rational terminating series (Jordan: times 60-digit e^lambda), rounded to float64",
        "cases": cases,
    }
    text = json.dumps(doc, separators=(",", ":"))
    dropped = []
    if len(text.encode()) > MAX_BYTES:
        # drop the largest (n = 16, s = 100) cases of the "normal" direction, keeping n = 16
        # present in every family
        for c in sorted(cases, key=lambda c: (-c["n"], -c.get("s", 0))):
            if c["n"] == 16 and c.get("s") == 100 and c["direction"] == "normal":
                dropped.append(c["name"])
        cases = [c for c in cases if c["name"] not in dropped]
        doc["cases"] = cases
        text = json.dumps(doc, separators=(",", ":"))
    with open(os.path.join(HERE, "structured.json"), "w") as f:
        f.write(text)
        f.write("\n")

    log()
    log("summary")
    log(f"  file: structured.json, {len(text.encode())} bytes, {len(cases)} cases"
        + (f"; dropped {dropped}" if dropped else ""))
    for fam in FAMILY_ID:
        cs = [c for c in cases if c["family"] == fam]
        worst_e = max(cs, key=lambda c: c["scipy_exp_err"])
        worst_l = max(cs, key=lambda c: c["scipy_frechet_err"])
        n16 = sum(c["n"] == 16 for c in cs)
        nulls = [c["name"] for c in cs if c["kappa_exp"] is None or c["kappa_frechet"] is None]
        ratio = [max(c["kappa_exp"] / c["kappa_exp_series"], c["kappa_exp_series"] / c["kappa_exp"],
                     c["kappa_frechet"] / c["kappa_frechet_series"], c["kappa_frechet_series"] / c["kappa_frechet"])
                 for c in cs if None not in (c["kappa_exp"], c["kappa_frechet"],
                                             c["kappa_exp_series"], c["kappa_frechet_series"])]
        log(f"  {fam}: {len(cs)} cases ({n16} with n = 16)")
        log(f"    scipy max rel err  e^A {worst_e['scipy_exp_err']:.2e} ({worst_e['name']})"
            f"   L {worst_l['scipy_frechet_err']:.2e} ({worst_l['name']})")
        log(f"    kappa: SciPy expm_cond vs series Kronecker form, worst ratio {max(ratio):.6f}"
            + (f"; kappa null (not finite) for {nulls}" if nulls else "; all kappa finite"))
        for _, name, ag_e, ag_l, differ in [x for x in CROSS if x[0] == fam]:
            log(f"    cross-check vs 60-digit block exponential {name}: e^A {ag_e:.1e}, L {ag_l:.1e}, "
                f"float64 entries differing {differ}")
    log(f"  total time {time.time() - t0:.0f} s")
    with open(os.path.join(HERE, "make_structured.log"), "w") as f:
        f.write("\n".join(LOG) + "\n")


if __name__ == "__main__":
    main()

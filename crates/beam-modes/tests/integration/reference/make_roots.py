#!/usr/bin/env python3
"""High-precision roots of the spring-hinged/free beam's characteristic equation.

    Delta(lam, kappa) = lam*(sin(lam)*cosh(lam) - cos(lam)*sinh(lam)) - kappa*(1 + cos(lam)*cosh(lam))

For each kappa the i-th root lies between the (i-1)-th pinned-free root (0 for i = 1) and the
i-th clamped-free root; each is found at 40
digits by bisection (150 halvings: the bracket shrinks below 1e-44) on a sign change of
Delta/cosh. Also stores the two limits.
Independent of the Rust code (different formulation: no series, no tanh/sech rewrite).

Run:  python3 make_roots.py > roots.json
"""
import json
import mpmath as mp

mp.mp.dps = 40
N = 8


def delta(lam, kappa):
    return lam * (mp.sin(lam) * mp.cosh(lam) - mp.cos(lam) * mp.sinh(lam)) - kappa * (1 + mp.cos(lam) * mp.cosh(lam))


def bisect(f, lo, hi):
    flo = f(lo)
    assert flo * f(hi) < 0, (lo, hi)
    for _ in range(150):
        mid = (lo + hi) / 2
        fm = f(mid)
        if fm == 0:
            return mid
        if (fm < 0) == (flo < 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return (lo + hi) / 2


def pinned(j):
    if j == 0:
        return mp.mpf(0)
    return bisect(lambda l: mp.sin(l) - mp.cos(l) * mp.tanh(l), j * mp.pi, j * mp.pi + mp.pi / 2)


def clamped(j):
    return bisect(lambda l: 1 / mp.cosh(l) + mp.cos(l), (j - 1) * mp.pi, j * mp.pi)


def root(i, kappa):
    lo, hi = pinned(i - 1), clamped(i)
    if lo == 0:
        lo = mp.mpf("1e-30")
    r = bisect(lambda l: delta(l, kappa) / mp.cosh(l), lo, hi)
    assert lo <= r <= hi, (i, kappa, r)
    return r


out = {
    "pinned_free": [mp.nstr(pinned(j), 30) for j in range(1, N + 1)],
    "clamped_free": [mp.nstr(clamped(j), 30) for j in range(1, N + 1)],
    "roots": [],
}
for kappa in ["1e-6", "0.01", "0.1", "0.644", "1", "10", "100", "1000", "1e6"]:
    k = mp.mpf(kappa)
    out["roots"].append({"kappa": float(k), "lambda": [mp.nstr(root(i, k), 30) for i in range(1, N + 1)]})
print(json.dumps(out, indent=1))

#!/usr/bin/env python3
"""Truth generator for `memid diagnose` on a structure model file (the 3-storey shear building).

Shares no code with memid (numpy + scipy only). Every case is a 10 s free decay at 200 Hz of a
shear building M q'' + D q' + K q = f(q, q') from q(0) = [0.01, 0.02, 0.03] m at rest, measured
as q1 and q3 (the columns of fixtures/shear_building.ron, which is the model every case is
diagnosed with, k1, k2, k3, alpha, beta free). The truth's parameters are drawn around the
independent fixture's truth (k_i x U(0.85, 1.15), alpha and beta x U(0.7, 1.3)); noise is 0.5-2 %
of each column's RMS, white or AR(1).

Families (as studies/diagnose, so that its score.py scores them):
  A  catalog physics in forms other than the candidates', strengths weak / medium / strong:
     cubic (k3 q^3 + k5 q^5 at a floor), friction (F tanh(v / v_s) at a floor), drag
     (c |v|^e sign v, e in 1.5-2.5, at a floor), offset / scale / drift of q1 or q3,
     quantization of q1 or q3 (noise before or after the quantizer), and a mode the model lacks
     (an appendage on a spring and damper at a floor, 15-25 Hz, a fourth degree of freedom)
  B  nulls: white or AR(1) noise (rho up to 0.9), and mismatches the free parameters cannot absorb
     (modal instead of Rayleigh damping, floor 2's mass 15 % off)
  C  physics outside the catalog: a storey stiffness degrading during the record, and pounding of
     the roof against a stop (a one-sided spring); with --more-c also a one-sided Hertzian contact
     (f = k d^1.5) and a one-sided linear stop at a random floor and side, the stop's force at the
     penetration the linear decay would reach 0.1 / 0.3 / 1 x k_jj q_peak (weak / medium / strong);
     with --more-degrading also a storey (any of the three; its spring acts on the storey's drift)
     that loses 2 / 5 / 10 % of its stiffness by the record's end, by an exponential law in time
     (tau 1-4 s) or in a sudden smooth step (tanh, at 1-4 s, width 0.3 s)

With --ringing-appendages six family-A cases are appended (free decay only): the appendage form
again (1 / 2.5 / 5 % mass, 15-25 Hz, a floor at random), released displaced from its floor so that
it rings, by as much as makes its ringing as visible as the offsets' ladder, 0.5 N b^2 nats for
b = 0.15 / 0.4 / 1 sigma (weak / medium / strong; ring_nats: the part of what the release adds to
q1 and q3 in the span of the coupled mode, in noise sigma). Released relaxed (the appendage form
above), an appendage moves with its floor and shows in a free decay as an added mass, at the noise
(studies/structure/appendage_bound.py); these show it as a mode. The truth records the release [m],
ring_nats and the coupled mode's frequency and damping (coupled_f, coupled_zeta). Appended after
every other case, so that a seed's other cases are those without it.

With --accelerations the records are the floor accelerations a1, a3 (q'' from the equations of
motion, the effects' forces included) instead of the displacements, diagnosed with
fixtures/shear_building_acc2.ron; the truth's draws are the same as without it, so a seed gives
the same buildings, effects and noise sequences read by other sensors. Sensor effects act on
a1 or a3, at the same strengths relative to the column's noise.

With --forced every case starts at rest (the appendage too) and is shaken by a measured force u [N]
on floor 3 (F = [0, 0, 1]), held constant over each sample interval (zero-order hold: u[k] acts on
[t_k, t_k+1)); the records are t,u,q1,q3, diagnosed with fixtures/shear_building_forced_q.ron. The
input is, 50/50 per case, white Gaussian noise through a 4th-order Butterworth low-pass at 40 Hz or
a linear chirp 1 -> 40 Hz over the record (random phase, 0.2 s cosine tapers at both ends), scaled
so that the case's own linear building (its M, K, D, no effect) peaks at |q3| = 0.03 m. It is drawn
from a generator of its own, seeded [the set's seed, case index], so the cases' draws from the set's
generator are those without --forced (the same buildings, effects and noise sequences); the
strengths' peaks (and the pounding's gap) are those of the linear forced response to the case's
own input. --input-noise L adds white noise of L x RMS(u) to the recorded u only (the building
feels the clean u). The truth records the input ("input": kind, rms of the applied u, noise).
The truth of a forced appendage case also records `resonance_nats`, how far the appendage can be
seen as a mode of its own (see resonance_nats). --check first compares the interval-by-interval integration with the exact discrete-time solution
of the linear building (the matrix exponential), and stops unless --out is given too.

usage:  python3 studies/structure/generate.py --out DIR --set dev|held [--seed N] [--more-c] [--more-degrading]
                                              [--ringing-appendages]
                                              [--accelerations | --forced [--input-noise L]] [--check]
"""
import argparse
import json
import os
import shutil

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm
from scipy.signal import butter, chirp, lfilter

H, N = 0.005, 2001
Q0 = np.array([0.01, 0.02, 0.03])
TRUTH = dict(k=(2.62e6, 2.16e6, 1.96e6), alpha=0.42, beta=1.18e-3)
FREE = "k1,k2,k3,alpha,beta"
# What the records measure: the displacements q1, q3 (columns 0, 2 of simulate's q, v, q''), or
# with --accelerations the accelerations of floors 1 and 3 (columns 6, 8); set in main().
MEASURED, COLUMNS, MODEL = [0, 2], ["q1", "q3"], "shear_building.ron"
# --forced: the input's force on the floors (a shaker on the roof), and its scale (the peak |q3|
# of the case's linear building driven by it) [m].
F_IN, PEAK_Q3 = np.array([0.0, 0.0, 1.0]), 0.03


def matrices(rng, mass2=1000.0, modal=None):
    k = np.array(TRUTH["k"]) * rng.uniform(0.85, 1.15, 3)
    alpha = TRUTH["alpha"] * rng.uniform(0.7, 1.3)
    beta = TRUTH["beta"] * rng.uniform(0.7, 1.3)
    m = np.array([1000.0, mass2, 1000.0])
    K = np.array([[k[0] + k[1], -k[1], 0.0], [-k[1], k[1] + k[2], -k[2]], [0.0, -k[2], k[2]]])
    M = np.diag(m)
    if modal is None:
        D = alpha * M + beta * K
    else:
        w2, phi = np.linalg.eigh(np.linalg.inv(np.sqrt(M)) @ K @ np.linalg.inv(np.sqrt(M)))
        phi = np.linalg.inv(np.sqrt(M)) @ phi  # mass-normalised
        D = M @ phi @ np.diag(2 * np.array(modal) * np.sqrt(w2)) @ phi.T @ M
    return M, K, D


def simulate(M, K, D, force=None, extra=None, u=None, release=0.0):
    """force(q, v, t) -> generalised force on the floors; extra: an appendage (j, m, f, zeta);
    u: None for the free decay from Q0, or (--forced) the force F_IN u[k] held over [t_k, t_k+1)
    from rest; release: in free decay, the appendage's displacement from its floor at the release
    [m] (0: released relaxed, moving with its floor)."""
    Minv = np.linalg.inv(M)

    def rhs(t, x, uk=None):  # uk: the held input (--forced)
        q, v = x[:3], x[3:6]
        f = -K @ q - D @ v
        if uk is not None:
            f = f + F_IN * uk
        if force is not None:
            f = f + force(q, v, t)
        out = np.zeros_like(x)
        out[:3] = v
        if extra is not None:
            j, ma, fa, za = extra
            ka, ca = ma * (2 * np.pi * fa) ** 2, 2 * za * ma * 2 * np.pi * fa
            c = ka * (x[6] - q[j]) + ca * (x[7] - v[j])
            f[j] += c
            out[6], out[7] = x[7], -c / ma
        out[3:6] = Minv @ f
        return out

    x0 = np.zeros(8 if extra is not None else 6)
    t = np.arange(N) * H
    if u is not None:  # at rest, then one integration per sample interval: u is constant inside each
        x = np.empty((N, len(x0)))
        x[0] = x0
        for k in range(N - 1):
            sol = solve_ivp(rhs, (t[k], t[k + 1]), x[k], method="DOP853", args=(u[k],), rtol=1e-9, atol=1e-12)
            if not sol.success:
                raise RuntimeError(sol.message)
            x[k + 1] = sol.y[:, -1]
        acc = np.array([rhs(tk, x[k], u[k])[3:6] for k, tk in enumerate(t)])  # u[k] acts from t_k on
        return np.hstack([x[:, :6], acc])  # (N, 9): q, v, q''
    x0[:3] = Q0
    if extra is not None:
        x0[6] = Q0[extra[0]] + release
    sol = solve_ivp(rhs, (0.0, t[-1]), x0, method="DOP853", t_eval=t, rtol=1e-9, atol=1e-12, max_step=H)
    if not sol.success:
        raise RuntimeError(sol.message)
    acc = np.array([rhs(tk, sol.y[:, k])[3:6] for k, tk in enumerate(t)])
    return np.hstack([sol.y[:6].T, acc])  # (N, 9): q, v, q''


def state_space(M, K, D, extra=None):
    """The linear building (with an appendage (j, m, f, zeta) as in simulate) as x' = A x + B u,
    x = [q, v] (+ [qa, va]), u the force on floor 3 (F_IN)."""
    n = 3 if extra is None else 4
    Mi = np.zeros((n, n))
    Mi[:3, :3] = np.linalg.inv(M)
    Kx, Dx = np.zeros((n, n)), np.zeros((n, n))
    Kx[:3, :3], Dx[:3, :3] = K, D
    if extra is not None:  # the appendage's spring and damper between floor j and coordinate 3
        j, ma, fa, za = extra
        Mi[3, 3] = 1.0 / ma
        for C, c in ((Kx, ma * (2 * np.pi * fa) ** 2), (Dx, 2 * za * ma * 2 * np.pi * fa)):
            C[j, j] += c
            C[3, 3] += c
            C[j, 3] -= c
            C[3, j] -= c
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ Kx, -Mi @ Dx]])
    B = np.concatenate([np.zeros(n), Mi[:, :3] @ F_IN])
    order = [0, 1, 2, n, n + 1, n + 2] + ([3, 7] if extra is not None else [])  # simulate's order
    return A[np.ix_(order, order)], B[order]


def linear_zoh(A, B, u):
    """The exact sampled response of x' = A x + B u from rest with u[k] held over [t_k, t_k+1): the
    matrix exponential of [[A, B], [0, 0]] H steps the state (no integrator). (N, len(A))."""
    n = len(A)
    E = expm(np.block([[A, B[:, None]], [np.zeros((1, n + 1))]]) * H)
    Ad, Bd = E[:n, :n], E[:n, n]
    x = np.zeros((N, n))
    for k in range(N - 1):
        x[k + 1] = Ad @ x[k] + Bd * u[k]
    return x


def resonance_nats(M, K, D, extra, u, sigma):
    """--forced: how far an appendage (j, m, f, zeta) can be seen as a mode of its own, in nats:
    half the squared norm, in units of each column's noise sigma, of the part of its effect on the
    measured columns (the exact zero-order-hold response of the linear building with it, less the
    one without) that lies in the span of a trial mode at its frequency and damping driven by u
    (eta and eta'/omega of eta'' + 2 zeta omega eta' + omega^2 eta = omega^2 u, from rest). The
    rest of its effect the building's own masses and stiffness, refitted, take up: below its
    frequency an appendage moves with its floor, an added mass. A bound to set beside the
    diagnosis's held-out threshold (10 nats); measurement noise and the refit only lower it."""
    j, ma, fa, za = extra
    x0 = linear_zoh(*state_space(M, K, D), u)[:, MEASURED]
    x1 = linear_zoh(*state_space(M, K, D, extra), u)[:, MEASURED]
    d = (x1 - x0) / sigma
    w = 2 * np.pi * fa
    E = expm(np.array([[0.0, w, 0.0], [-w, -2 * za * w, w], [0.0, 0.0, 0.0]]) * H)
    eta, z = np.zeros((N, 2)), np.zeros(2)
    for k in range(N):
        eta[k] = z
        z = E[:2, :2] @ z + E[:2, 2] * u[k]
    q, _ = np.linalg.qr(eta)
    return float(0.5 * np.sum((q.T @ d) ** 2))


def coupled_mode(M, K, D, extra):
    """The eigenvalue (upper half-plane) of the building with the appendage nearest the
    appendage's own frequency: its mode as the record shows it."""
    lam = np.linalg.eigvals(state_space(M, K, D, extra)[0])
    return lam[np.argmin(np.abs(lam - 2j * np.pi * extra[2]))]


def ring_nats(M, K, D, extra, release, sigma):
    """Free decay: how far an appendage (j, m, f, zeta) released `release` [m] from its floor can
    be seen ringing as a mode of its own, in nats: half the squared norm, in units of each
    column's noise sigma, of the part of what the release adds to the measured columns (the
    linear building with the appendage from Q0 with and without the release) that lies in the
    span of the coupled mode nearest the appendage's frequency (e^(-zeta w t) cos and sin at the
    eigenvalue of the building with it). The free decay of an appendage released relaxed is
    the measure's zero."""
    A, _ = state_space(M, K, D, extra)
    lam = coupled_mode(M, K, D, extra)
    t = np.arange(N) * H
    basis = np.column_stack([np.exp(lam.real * t) * np.cos(lam.imag * t), np.exp(lam.real * t) * np.sin(lam.imag * t)])
    x0 = np.zeros(8)  # simulate's order: q, v, then the appendage's qa, va
    x0[6] = release
    E = expm(A * H)
    x = np.empty((N, 8))
    x[0] = x0
    for k in range(N - 1):
        x[k + 1] = E @ x[k]
    # The measured columns (simulate's q, v, q'' order): displacements, or with --accelerations
    # the floors' accelerations q'' = (A x)[v].
    d = (x[:, MEASURED] if max(MEASURED) < 3 else (x @ A.T)[:, [m - 3 for m in MEASURED]]) / sigma
    q, _ = np.linalg.qr(basis)
    return float(0.5 * np.sum((q.T @ d) ** 2))


def ringing_release(M, K, D, extra, sigma, nats):
    """The appendage's release from its floor [m] at which ring_nats is `nats` (it is quadratic in
    the release)."""
    return float(np.sqrt(nats / ring_nats(M, K, D, extra, 1.0, sigma)))


def input_shape(g, kind):
    """An input of the kind, unscaled, drawn from the generator g."""
    t = np.arange(N) * H
    if kind == "random":  # band-limited random: white noise through a Butterworth low-pass at 40 Hz
        b, a = butter(4, 40.0, fs=1.0 / H)
        return lfilter(b, a, g.standard_normal(N))
    # a linear sweep 1 -> 40 Hz over the record, at a random phase, tapered over 0.2 s at both ends
    w = chirp(t, f0=1.0, t1=t[-1], f1=40.0, method="linear", phi=g.uniform(0.0, 360.0))
    taper = 0.5 * (1.0 - np.cos(np.pi * np.clip(np.minimum(t, t[-1] - t) / 0.2, 0.0, 1.0)))
    return w * taper + 0.0  # (+ 0.0: the tapered ends are 0.0, not -0.0, in the records)


def excitation(seed, index):
    """--forced: case `index`'s input kind and shape (unscaled), and a white sequence for
    --input-noise, from a generator of their own (the set's generator is not touched)."""
    g = np.random.default_rng([seed, index])
    kind = ["random", "chirp"][int(g.integers(0, 2))]
    return kind, input_shape(g, kind), g.standard_normal(N)


def drive(M, K, D, w):
    """--forced: the input shape w scaled so that the linear building M, K, D (no effect) driven by
    it peaks at |q3| = PEAK_Q3; None (free decay) without --forced."""
    if w is None:
        return None
    x = linear_zoh(*state_space(M, K, D), w)
    return w * (PEAK_Q3 / np.max(np.abs(x[:, 2])))


def peaks(M, K, D, u=None):
    """The peaks of |q| and |q'| of the linear building: its free decay, or its response to u."""
    x = simulate(M, K, D) if u is None else linear_zoh(*state_space(M, K, D), u)
    return np.max(np.abs(x[:, :3]), axis=0), np.max(np.abs(x[:, 3:6]), axis=0)


def noise(rng, clean, level, rho):
    e = rng.standard_normal(clean.shape)
    if rho:
        for k in range(1, len(e)):
            e[k] = rho * e[k - 1] + np.sqrt(1 - rho * rho) * e[k]
    rms = np.sqrt(np.mean((clean - clean.mean(axis=0)) ** 2, axis=0))
    return level * rms * e, level * rms


def record(y, u):
    """A case's columns: with --forced the applied input first (t,u,q1,q3)."""
    return y if u is None else np.column_stack([u, y])


LEVELS = {"weak": 0, "medium": 1, "strong": 2}


def case_a(rng, kind, strength, w=None):  # w: --forced's input shape (see drive), else None
    s = LEVELS[strength]
    M, K, D = matrices(rng)
    u = drive(M, K, D, w)
    qpk, vpk = peaks(M, K, D, u)
    j = int(rng.integers(0, 3))
    o = int(rng.integers(0, 2))  # which output a sensor effect is on
    out_name = COLUMNS[o]
    level, rho = rng.uniform(0.005, 0.02), [0.0, 0.0, 0.5][int(rng.integers(0, 3))]
    force, extra, post, truth, release = None, None, None, {}, 0.0
    if kind == "cubic":
        r = [0.02, 0.05, 0.15][s] * float(rng.choice([-1, 1]))  # nonlinear / linear storey force at the peak
        k = K[j, j] * r / qpk[j] ** 2
        k3, k5 = 0.7 * k, 0.3 * k / qpk[j] ** 2
        force = lambda q, v, t: -np.eye(3)[j] * (k3 * q[j] ** 3 + k5 * q[j] ** 5)
        name, truth = "cubic_stiffness", dict(coordinate=f"q{j + 1}", k3=k3, k5=k5)
    elif kind == "friction":
        F = [0.005, 0.015, 0.04][s] * K[j, j] * qpk[j]
        vs = 0.005 * vpk[j]
        force = lambda q, v, t: -np.eye(3)[j] * F * np.tanh(v[j] / vs)
        name, truth = "coulomb_friction", dict(coordinate=f"q{j + 1}", force=F, v_s=vs)
    elif kind == "drag":
        e = rng.uniform(1.5, 2.5)
        c = [0.1, 0.3, 1.0][s] * D[j, j] * vpk[j] / vpk[j] ** e
        force = lambda q, v, t: -np.eye(3)[j] * c * np.abs(v[j]) ** e * np.sign(v[j])
        name, truth = "quadratic_drag", dict(coordinate=f"q{j + 1}", c=c, exponent=e)
    elif kind in ("appendage", "ringing_appendage"):
        ratio = [0.01, 0.025, 0.05][s]
        extra = (j, ratio * 1000.0, rng.uniform(15, 25), rng.uniform(0.005, 0.02))
        name, truth = "unmodeled_mode", dict(coordinate=f"q{j + 1}", mass=extra[1], f=extra[2], zeta=extra[3])
        if kind == "ringing_appendage":  # --ringing-appendages: released from its floor so that it rings
            # as visibly as the offsets' ladder (0.15 / 0.4 / 1 sigma on one column: 0.5 N b^2 nats);
            # sigma depends on the record it is the noise of, so the release is solved twice.
            nats = 0.5 * N * [0.15, 0.4, 1.0][s] ** 2
            for _ in range(2):
                sigma = noise(np.random.default_rng(0), simulate(M, K, D, extra=extra, release=release)[:, MEASURED],
                              level, rho)[1]
                release = ringing_release(M, K, D, extra, sigma, nats)
            truth.update(release=release, ring_target_nats=nats)
    else:
        name = {"offset": "output_offset", "scale": "sensor_scale", "drift": "sensor_drift",
                "quantization": "sensor_quantization"}[kind]
        truth = dict(sensor=out_name)
    try:
        x = simulate(M, K, D, force, extra, u, release)
    except RuntimeError:
        if kind != "cubic" or u is None:
            raise
        # A softening spring driven past its fold escapes (k3 q^3 + k5 q^5 has no bound): drawn again
        # at half the strength until the forced response stays bounded; draws that never escaped are
        # unchanged, and no random number is used here.
        while True:
            k3, k5 = 0.5 * k3, 0.5 * k5
            truth.update(k3=k3, k5=k5, halved=truth.get("halved", 0) + 1)
            try:
                x = simulate(M, K, D, force, extra, u)
                break
            except RuntimeError:
                if truth["halved"] >= 6:
                    raise
    clean = x[:, MEASURED].copy()
    e, sigma = noise(rng, clean, level, rho)
    if kind == "appendage" and u is not None:
        truth["resonance_nats"] = resonance_nats(M, K, D, extra, u, sigma)
    if kind == "ringing_appendage":
        truth["ring_nats"] = ring_nats(M, K, D, extra, release, sigma)
        lam = coupled_mode(M, K, D, extra)
        truth.update(coupled_f=abs(lam) / (2 * np.pi), coupled_zeta=-lam.real / abs(lam))
    y = clean + e
    t = np.arange(N) * H
    if kind == "offset":
        b = [0.15, 0.4, 1.0][s] * sigma[o] * rng.choice([-1, 1])
        y[:, o] += b
        truth["offset"] = b
    elif kind == "scale":
        sc = [0.005, 0.01, 0.03][s] * rng.choice([-1, 1])
        y[:, o] = (1 + sc) * clean[:, o] + e[:, o]
        truth["scale"] = sc
    elif kind == "drift":
        d = [0.3, 1.0, 3.0][s] * sigma[o] / t[-1] * rng.choice([-1, 1])
        y[:, o] += d * t
        truth["rate"] = d
    elif kind == "quantization":
        step = [1.0, 2.0, 4.0][s] * sigma[o]
        before = bool(rng.integers(0, 2))
        y[:, o] = step * np.round((clean[:, o] + e[:, o]) / step) if before else step * np.round(clean[:, o] / step) + e[:, o]
        truth.update(step=step, noise_before_quantizer=before)
    truth.update(effect=name)
    return record(y, u), name, dict(level=level, rho=rho, effects=[truth])


def case_b(rng, kind, w=None):
    rho = 0.0
    if kind == "white":
        M, K, D = matrices(rng)
    elif kind == "coloured":
        M, K, D = matrices(rng)
        rho = float(rng.choice([0.5, 0.8, 0.9]))
    elif kind == "modal_damping":
        M, K, D = matrices(rng, modal=list(rng.uniform(0.015, 0.05, 3)))
    else:  # mass
        M, K, D = matrices(rng, mass2=1000.0 * float(rng.choice([0.85, 1.15])))
    u = drive(M, K, D, w)  # scaled on the case's own (mismatched) building
    x = simulate(M, K, D, u=u)
    clean = x[:, MEASURED].copy()
    level = rng.uniform(0.005, 0.02)
    e, _ = noise(rng, clean, level, rho)
    return record(clean + e, u), dict(level=level, rho=rho, null_kind=kind, effects=[])


def case_c(rng, kind, strength, w=None):
    s = LEVELS[strength]
    M, K, D = matrices(rng)
    u = drive(M, K, D, w)
    qpk, vpk = peaks(M, K, D, u)
    if kind in ("contact", "stop"):  # one-sided, at any floor, on either side (--more-c only)
        j, side = int(rng.integers(0, 3)), float(rng.choice([-1.0, 1.0]))
        gap = rng.uniform(0.5, 0.8) * qpk[j]
        reach = qpk[j] - gap  # the penetration the linear decay (or forced response) would reach
        peak_force = [0.1, 0.3, 1.0][s] * K[j, j] * qpk[j]  # the stop's force at that penetration
        law = 1.5 if kind == "contact" else 1.0  # Hertzian or linear
        kc = peak_force / reach ** law
        force = lambda q, v, t: -np.eye(3)[j] * side * kc * max(side * q[j] - gap, 0.0) ** law
        truth = dict(kind=f"one_sided_{kind}", coordinate=f"q{j + 1}", side=side, gap=gap, k=kc, law=law)
    elif kind in ("loss_exp", "loss_step"):  # a storey that degrades by another law (--more-degrading)
        j = int(rng.integers(0, 3))  # the storey: its spring joins floor j to floor j-1 (the ground for j = 0)
        loss = [0.02, 0.05, 0.1][s]  # the share of that storey's stiffness lost by the end of the record
        ks = [K[0, 0] + K[0, 1], -K[0, 1], -K[1, 2]][j]  # k1, k2, k3
        T = (N - 1) * H
        if kind == "loss_exp":  # k_s(t) = k_s (1 - loss (1 - e^(-t/tau)) / (1 - e^(-T/tau)))
            tau = rng.uniform(1.0, 4.0)
            share = lambda t: (1.0 - np.exp(-t / tau)) / (1.0 - np.exp(-T / tau))
            law = dict(tau=tau)
        else:  # a sudden loss, a smooth step at t_d of width w
            td, w = rng.uniform(1.0, 4.0), 0.3
            share = lambda t: 0.5 * (1.0 + np.tanh((t - td) / w))
            law = dict(t_d=td, width=w)

        def force(q, v, t):
            drift = q[j] - (q[j - 1] if j > 0 else 0.0)
            f = np.zeros(3)
            f[j] += loss * share(t) * ks * drift
            if j > 0:
                f[j - 1] -= loss * share(t) * ks * drift
            return f

        truth = dict(kind=f"stiffness_{kind}", storey=j + 1, loss=loss, **law)
    elif kind == "degrading":
        loss = [0.02, 0.05, 0.1][s]  # storey 1 loses this share of its stiffness over the record
        k1 = K[0, 0] + K[0, 1]  # the storey-1 spring (K[0,1] = -k2)
        force = lambda q, v, t: np.array([loss * k1 * t / 10.0 * q[0], 0.0, 0.0])
        truth = dict(kind="stiffness_degradation", loss=loss)
    else:  # pounding: the roof hits a stop at 60-80 % of its peak
        gap = [0.8, 0.7, 0.6][s] * qpk[2]
        kstop = 5.0 * K[2, 2]
        force = lambda q, v, t: np.array([0.0, 0.0, -kstop * max(q[2] - gap, 0.0)])
        truth = dict(kind="pounding", gap=gap, k_stop=kstop)
    x = simulate(M, K, D, force, u=u)
    clean = x[:, MEASURED].copy()
    level = rng.uniform(0.005, 0.02)
    e, _ = noise(rng, clean, level, 0.0)
    truth.update(level=level, effects=[])
    return record(clean + e, u), truth


def self_check():
    """--check: the interval-by-interval integration of simulate (u given) against the exact
    discrete-time solution of the same linear building (linear_zoh, the matrix exponential), for
    both kinds of input, on drawn buildings with Rayleigh or modal damping, two with an appendage
    (at rest too). The error is the largest over the samples relative to the peak, of the floors'
    q and of their q'; it must be below 1e-8. For scale, the same distance for u[k] acting one
    sample late (what a misaligned hold would cost)."""
    g = np.random.default_rng(7)  # a generator of its own: the sets' draws are not touched
    print("self-check: ZOH integration (DOP853 per interval) vs expm of [[A, B], [0, 0]] H")
    worst = 0.0
    for kind, modal, extra in [("random", None, None), ("chirp", None, None), ("random", [0.02, 0.03, 0.04], None),
                               ("chirp", None, (2, 25.0, 20.0, 0.01)), ("random", None, (0, 50.0, 15.0, 0.02))]:
        M, K, D = matrices(g, modal=modal)
        u = drive(M, K, D, input_shape(g, kind))
        exact = linear_zoh(*state_space(M, K, D, extra), u)
        x = simulate(M, K, D, extra=extra, u=u)
        errs = [np.max(np.abs(x[:, c] - exact[:, c])) / np.max(np.abs(exact[:, c])) for c in (slice(0, 3), slice(3, 6))]
        late = linear_zoh(*state_space(M, K, D, extra), np.concatenate([[0.0], u[:-1]]))
        shift = np.max(np.abs(late[:, :3] - exact[:, :3])) / np.max(np.abs(exact[:, :3]))
        worst = max(worst, *errs)
        print(f"  {kind:6s} {'modal' if modal else 'Rayleigh':8s} appendage={extra is not None!s:5s} "
              f"rms(u)={np.sqrt(np.mean(u ** 2)):9.1f} N  peak|q3| linear {np.max(np.abs(exact[:, 2])):.6f} "
              f"integrated {np.max(np.abs(x[:, 2])):.6f} m  err q {errs[0]:.1e}  q' {errs[1]:.1e}  "
              f"(u one sample late: {shift:.1e})")
    print(f"  worst relative error {worst:.2e} (must be < 1e-8)")
    assert worst < 1e-8, worst


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", help="the set's directory (required unless --check alone)")
    ap.add_argument("--set", choices=["dev", "held"], default="dev")
    ap.add_argument("--seed", type=int, default=None, help="a fresh draw (default: the set's own seed)")
    ap.add_argument("--more-c", action="store_true",
                    help="append family-C forms absent from dev and held: a one-sided Hertzian contact and "
                         "a one-sided linear stop at a random floor and side (12 cases)")
    ap.add_argument("--more-degrading", action="store_true",
                    help="append family-C degradations absent from dev and held: a storey (any of the three) that "
                         "loses stiffness by an exponential law in time or in a sudden smooth step (12 cases)")
    ap.add_argument("--ringing-appendages", action="store_true",
                    help="append family-A appendages released from their floor so that they ring, at the offsets' "
                         "ladder of visibility (6 cases; free decay only)")
    ap.add_argument("--accelerations", action="store_true",
                    help="record the accelerations a1, a3 (fixtures/shear_building_acc2.ron) instead of q1, q3")
    ap.add_argument("--forced", action="store_true",
                    help="start at rest and shake floor 3 with a measured, zero-order-held force u (random or "
                         "chirp); records t,u,q1,q3 (fixtures/shear_building_forced_q.ron)")
    ap.add_argument("--input-noise", type=float, default=0.0, metavar="LEVEL",
                    help="with --forced: white noise of LEVEL x RMS(u) on the recorded u only (default 0)")
    ap.add_argument("--check", action="store_true",
                    help="first check the forced integration against the exact discrete-time linear solution")
    opt = ap.parse_args()
    if opt.forced and opt.accelerations:
        ap.error("--forced records displacements (t,u,q1,q3); it cannot be combined with --accelerations")
    if opt.ringing_appendages and opt.forced:
        ap.error("--ringing-appendages releases an appendage in free decay; a forced record starts at rest")
    if opt.input_noise and not opt.forced:
        ap.error("--input-noise needs --forced")
    if opt.input_noise < 0:
        ap.error("--input-noise must be >= 0")
    if opt.out is None and not opt.check:
        ap.error("the following arguments are required: --out")
    if opt.check:
        self_check()
        if opt.out is None:
            return
    global MEASURED, COLUMNS, MODEL
    if opt.accelerations:
        MEASURED, COLUMNS, MODEL = [6, 8], ["a1", "a3"], "shear_building_acc2.ron"
    if opt.forced:
        MODEL = "shear_building_forced_q.ron"
    set_seed = opt.seed if opt.seed is not None else (20261123 if opt.set == "dev" else 20261124)
    rng = np.random.default_rng(set_seed)
    os.makedirs(os.path.join(opt.out, "data"), exist_ok=True)
    here = os.path.dirname(os.path.abspath(__file__))
    shutil.copy(os.path.join(here, "..", "..", "fixtures", MODEL), os.path.join(opt.out, MODEL))
    cases = []

    def run(case, *a):
        """A case function's result; with --forced the case gets its input (drawn from a generator of its
        own, seeded [set_seed, case index]), the recorded u its noise, and the truth the input."""
        if not opt.forced:
            return case(rng, *a)
        kind, w, e = excitation(set_seed, len(cases))
        *res, truth = case(rng, *a, w=w)
        u = res[0][:, 0]  # the applied input, recorded as column u
        rms = float(np.sqrt(np.mean(u ** 2)))
        if opt.input_noise:
            u += opt.input_noise * rms * e
        truth["input"] = dict(kind=kind, rms=rms, noise=opt.input_noise)
        return (*res, truth)

    def write(name, y, family, effect, accept, strength, truth):
        path = os.path.join("data", name + ".csv")
        with open(os.path.join(opt.out, path), "w") as f:
            f.write(",".join(["t"] + (["u"] if opt.forced else []) + COLUMNS) + "\n")
            for k in range(N):
                f.write(",".join([f"{k * H!r}"] + [f"{float(v)!r}" for v in y[k]]) + "\n")
        cases.append(dict(name=name, model=MODEL, data=path, free=FREE, args=[], family=family,
                          effect=effect, accept=accept, strength=strength, truth=truth))

    for kind in ["cubic", "friction", "drag", "offset", "scale", "drift", "quantization", "appendage"]:
        for strength in LEVELS:
            for seed in range(2):
                y, name, truth = run(case_a, kind, strength)
                write(f"A_{kind}_{strength}_s{seed}", y, "A", name, [name], strength, truth)
    for kind in ["white"] * 8 + ["coloured"] * 10 + ["modal_damping"] * 6 + ["mass"] * 6:
        y, truth = run(case_b, kind)
        write(f"B_{kind}_{len(cases)}", y, "B", "none", ["none"], "-", truth)
    for kind in ["degrading", "pounding"]:
        for strength in LEVELS:
            for seed in range(2):
                y, truth = run(case_c, kind, strength)
                write(f"C_{kind}_{strength}_s{seed}", y, "C", "none", ["none"], strength, truth)
    for kind in (["contact", "stop"] if opt.more_c else []) + (["loss_exp", "loss_step"] if opt.more_degrading else []):
        for strength in LEVELS:
            for seed in range(2):
                y, truth = run(case_c, kind, strength)
                write(f"C_{kind}_{strength}_s{seed}", y, "C", "none", ["none"], strength, truth)
    for strength in LEVELS if opt.ringing_appendages else []:
        for seed in range(2):
            y, name, truth = run(case_a, "ringing_appendage", strength)
            write(f"A_ringing_appendage_{strength}_s{seed}", y, "A", name, [name], strength, truth)
    json.dump(dict(cases=cases), open(os.path.join(opt.out, "truth.json"), "w"), indent=1)
    print(len(cases), "cases in", opt.out)


if __name__ == "__main__":
    main()

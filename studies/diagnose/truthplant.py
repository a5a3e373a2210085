"""Independent truth plant for the diagnosis study: the closed-loop slewing beam of
Garcia & Inman (Eqs. 17-21), written from the paper and the project's documentation only.

Nothing here is shared with the Rust crates.  Conventions (from the paper, docs/model-file.md,
docs/paper-reproduction.md and the crate-level math statements):

* beam: uniform Euler-Bernoulli, length L, EI = (EI/rho)*rho, mass per length rho, root at radius
  a from the slewing axis, spring-hinged at the root with the servo stiffness
  k_s = G*K_p*K_t/R_a as root spring, free tip.  Root 1 of that beam is the quasi-rigid rotation
  (described by theta), so the flexible coordinates q_1..q_n use roots 2..n+1.  Modes are
  mass-normalised (int rho phi_i phi_j = delta_ij).
* Eq. 17: M~ = [[int rho (a+x)^2 dx + I_H, I_i], [I_i, 1]], K~ = diag(0, w_i^2),
  I_i = int rho (a+x) phi_i dx.
* Eqs. 18-21 with the amplifier gain G: e_a = G K_p (theta_ref - theta),
  M = M~ + diag(I_m, 0), D = diag(C_v + K_b K_t/R_a, 2 zeta_i w_i),
  K = [[k_s, 0], [k_s Gamma_i, diag(w_i^2)]], Gamma_i = phi_i'(0).
* outputs: theta [rad], theta_dot [rad/s], root strain (h/2) sum q_i phi_i''(0) in microstrain.

The mode shapes are computed here by root finding on the characteristic equation and Gauss-Legendre
quadrature of the (numerically normalised) shapes, not by any closed form.
"""
import math

import numpy as np
from scipy.linalg import expm
from scipy.optimize import brentq

# ----------------------------------------------------------------------------------------------
# nominal constants: the values of fixtures/slewing.ron (read by hand, not parsed from the crate)
NOMINAL = dict(
    length=1.19, ei_over_rho=0.857, rho=0.5792, hub_radius=0.06, thickness=0.00079375,
    hub_inertia=3.49e-3, motor_inertia=6.02e-2, kt=5.508e-2, kb=5.539e-2, ra=2.0,
    amplifier_gain=1.8204, kp=8.0, cv=0.0528, modal_damping=[0.5, 1.0, 1.0], theta0=0.5,
)


# ----------------------------------------------------------------------------------------------
# beam modes of a spring-hinged / free Euler-Bernoulli beam

def _char(lam, kappa):
    """Characteristic function divided by cosh(lam): lam (sin - cos tanh) - kappa (sech + cos)."""
    return lam * (math.sin(lam) - math.cos(lam) * math.tanh(lam)) - kappa * (1.0 / math.cosh(lam) + math.cos(lam))


def _pinned_free_roots(n):
    """Non-zero roots of tan x = tanh x (kappa = 0)."""
    out = []
    for j in range(1, n + 1):
        lo, hi = j * math.pi + 1e-9, j * math.pi + math.pi / 2 - 1e-9
        out.append(brentq(lambda x: math.sin(x) - math.cos(x) * math.tanh(x), lo, hi, xtol=1e-15))
    return out


def _clamped_free_roots(n):
    """Roots of cos x cosh x = -1 (kappa -> infinity)."""
    out = []
    for j in range(n):
        lo, hi = j * math.pi + 1e-9, (j + 1) * math.pi - 1e-9
        out.append(brentq(lambda x: math.cos(x) + 1.0 / math.cosh(x), lo, hi, xtol=1e-15))
    return out


_GL_X, _GL_W = np.polynomial.legendre.leggauss(400)


def beam_modes(L, EI, rho, a, k_root, n):
    """First n flexible modes (roots 2..n+1).  Returns dict of arrays: omega, I (participation
    integrals int rho (a+x) phi), gamma (phi'(0)), curv0 (phi''(0)), lam, and the shape function."""
    kappa = k_root * L / EI
    cf = _clamped_free_roots(n + 1)
    pf = _pinned_free_roots(n + 1)
    lams = []
    for i in range(1, n + 1):            # root i+1 in (pf[i-1], cf[i])
        lo, hi = pf[i - 1] + 1e-12, cf[i] - 1e-12
        lams.append(brentq(lambda x: _char(x, kappa), lo, hi, xtol=1e-15, rtol=1e-15, maxiter=500))
    x = 0.5 * L * (_GL_X + 1.0)
    w = 0.5 * L * _GL_W
    out = dict(omega=[], I=[], gamma=[], curv0=[], lam=[], tip=[])
    for lam in lams:
        beta = lam / L
        ch, sh, c, s = math.cosh(lam), math.sinh(lam), math.cos(lam), math.sin(lam)
        # rows: root moment balance, zero moment at tip, zero shear at tip; unknowns A, B, D
        mat = np.array([[2.0 * lam, -kappa, -kappa],
                        [ch + c, sh, -s],
                        [sh - s, ch, -c]])
        _, sv, vt = np.linalg.svd(mat)
        A, B, D = vt[-1]
        bx = beta * x
        phi = A * (np.cosh(bx) - np.cos(bx)) + B * np.sinh(bx) + D * np.sin(bx)
        norm = math.sqrt(rho * np.sum(w * phi * phi))
        A, B, D = A / norm, B / norm, D / norm
        phi = phi / norm
        if B + D < 0:                     # sign convention: positive root slope
            A, B, D, phi = -A, -B, -D, -phi
        out["lam"].append(lam)
        out["omega"].append(beta * beta * math.sqrt(EI / rho))
        out["I"].append(rho * np.sum(w * (a + x) * phi))
        out["gamma"].append(beta * (B + D))
        out["curv0"].append(2.0 * beta * beta * A)
        out["tip"].append(A * (ch - c) + B * sh + D * s)
    return {k: np.array(v) for k, v in out.items()}


# ----------------------------------------------------------------------------------------------
# the closed loop

class Plant:
    """Closed-loop plant with parameters p (dict like NOMINAL).  Degrees of freedom
    [theta, q_1..q_n]; optional extra DOFs are appended by the generator (unmodeled mode)."""

    def __init__(self, p):
        self.p = dict(p)
        L, rho, a = p["length"], p["rho"], p["hub_radius"]
        EI = p["ei_over_rho"] * rho
        self.ks = p["amplifier_gain"] * p["kp"] * p["kt"] / p["ra"]        # servo stiffness
        self.cb = p["kb"] * p["kt"] / p["ra"]                              # back-EMF damping
        n = len(p["modal_damping"])
        m = beam_modes(L, EI, rho, a, self.ks, n)
        self.modes = m
        self.n = n
        J = rho * ((a + L) ** 3 - a ** 3) / 3.0 + p["hub_inertia"] + p["motor_inertia"]
        ndof = n + 1
        M = np.eye(ndof)
        M[0, 0] = J
        M[0, 1:] = m["I"]
        M[1:, 0] = m["I"]
        K = np.zeros((ndof, ndof))
        K[0, 0] = self.ks
        K[1:, 0] = self.ks * m["gamma"]
        K[1:, 1:] = np.diag(m["omega"] ** 2)
        D = np.zeros((ndof, ndof))
        D[0, 0] = p["cv"] + self.cb
        D[1:, 1:] = np.diag(p["modal_damping"])
        self.M, self.K, self.D = M, K, D
        # generalised-force directions: servo (root moment) path and plain hub torque
        self.b_servo = np.concatenate([[1.0], m["gamma"]])
        self.e_hub = np.zeros(ndof)
        self.e_hub[0] = 1.0
        self.strain_row = np.concatenate([[0.0], 0.5 * p["thickness"] * m["curv0"] * 1e6])
        self.theta0 = p["theta0"]
        self.theta_dot0 = p.get("theta_dot0", 0.0)

    # -- augmentation (extra mechanical DOFs) ---------------------------------------------------
    def augmented(self, extra_M=None, extra_K=None, extra_D=None, n_extra=0):
        """Return (M, K, D, b_servo, e_hub, strain_row) with n_extra DOFs appended; extra_* are
        full-size additive matrices."""
        N = self.n + 1 + n_extra
        def pad(X):
            Y = np.zeros((N, N))
            Y[:X.shape[0], :X.shape[1]] = X
            return Y
        M, K, D = pad(self.M), pad(self.K), pad(self.D)
        for i in range(self.n + 1, N):
            M[i, i] = 1.0
        if extra_M is not None:
            M = M + extra_M
        if extra_K is not None:
            K = K + extra_K
        if extra_D is not None:
            D = D + extra_D
        z = np.zeros(n_extra)
        return M, K, D, np.concatenate([self.b_servo, z]), np.concatenate([self.e_hub, z]), \
            np.concatenate([self.strain_row, z])

    def first_order(self, M=None, K=None, D=None):
        M = self.M if M is None else M
        K = self.K if K is None else K
        D = self.D if D is None else D
        N = M.shape[0]
        Mi = np.linalg.inv(M)
        A = np.zeros((2 * N, 2 * N))
        A[:N, N:] = np.eye(N)
        A[N:, :N] = -Mi @ K
        A[N:, N:] = -Mi @ D
        return A

    def x0(self, N=None):
        N = self.n + 1 if N is None else N
        x = np.zeros(2 * N)
        x[0] = self.theta0
        x[N] = self.theta_dot0
        return x

    def outputs_of(self, X, strain_row=None):
        """X: (..., 2N) states -> (..., 3) [theta, theta_dot, strain]."""
        sr = self.strain_row if strain_row is None else strain_row
        N = sr.shape[0]
        return np.stack([X[..., 0], X[..., N], X[..., :N] @ sr], axis=-1)

    def linear_response(self, t, M=None, K=None, D=None, strain_row=None):
        """Exact (matrix-exponential) free decay sampled at uniform t (t[0] = 0)."""
        A = self.first_order(M, K, D)
        N = A.shape[0] // 2
        dt = t[1] - t[0]
        Phi = expm(A * dt)
        X = np.empty((len(t), 2 * N))
        x = self.x0(N)
        for k in range(len(t)):
            X[k] = x
            x = Phi @ x
        return self.outputs_of(X, strain_row)

    def linear_at_times(self, times, M=None, K=None, D=None, strain_row=None):
        """Exact free decay at arbitrary (non-uniform) times, by eigen-decomposition."""
        A = self.first_order(M, K, D)
        N = A.shape[0] // 2
        lam, V = np.linalg.eig(A)
        c = np.linalg.solve(V, self.x0(N).astype(complex))
        X = np.real((V[None, :, :] * (np.exp(np.outer(times, lam)) * c)[:, None, :]).sum(-1))
        return self.outputs_of(X, strain_row)


# ----------------------------------------------------------------------------------------------
# batched fixed-step RK4 for the nonlinear truths

class Sim:
    """Fixed-step RK4 over a batch of B parameter sets (magnitudes of one effect).

    The mechanical part is M qdd = F with
      F = -K_rest q - D_rest qd                    (beam stiffness/damping, extra DOFs)
          + b_servo (T_m + c_b w_m)                (motor torque through the servo path)
          - e_motor (c_b + C_v) w_m                (back-EMF and viscous damping at the motor)
          + e_hub tau_hub + generalised-force hooks
    with w_m the motor speed (DOF i_motor), T_m = K_t i,
    i = isat((vsat(G K_p (-theta_fb)) - K_b w_m)/R_a).  For the paper's plant (i_motor = 0,
    e_motor = e_hub = [1, 0..], b_servo = [1, Gamma]) this reduces exactly to the linear K and D.
    Hooks customise theta_fb, vsat, isat, hub torques, generalised forces, extra first-order
    states (z blocks) and the sensors.
    """

    def __init__(self, plant, B, M=None, K=None, D=None, b_servo=None, e_hub=None,
                 strain_row=None, K_rest=None, D_rest=None, e_motor=None, i_motor=0):
        pl = plant
        self.pl = pl
        self.B = B
        self.M = pl.M if M is None else M
        N = self.M.shape[0]
        self.N = N
        self.b_servo = pl.b_servo if b_servo is None else b_servo
        self.e_hub = pl.e_hub if e_hub is None else e_hub
        self.e_motor = self.e_hub if e_motor is None else e_motor
        self.i_motor = i_motor
        self.strain_row = pl.strain_row if strain_row is None else strain_row
        if K_rest is None:
            K = pl.K if K is None else K
            K_rest = K.copy()
            K_rest[:, 0] -= pl.ks * self.b_servo        # remove the k_s [1; Gamma] column
        if D_rest is None:
            D = pl.D if D is None else D
            D_rest = D.copy()
            D_rest[0, 0] -= pl.p["cv"] + pl.cb
        self.K_rest, self.D_rest = K_rest, D_rest
        self.Minv = np.linalg.inv(self.M)
        self.cv = pl.p["cv"]
        self.theta_fb = None     # f(t, q) -> (B,) the feedback sensor reading
        self.vsat = None         # f(u) -> u       amplifier voltage
        self.isat = None         # f(i) -> i       armature current
        self.tau_hubs = []       # f(t, q, qd, z) -> (B,) torques on the hub
        self.gen_forces = []     # f(t, q, qd, z) -> (B, N) generalised forces
        self.z_blocks = []       # (n, z0 (B, n) or None, f(t, q, qd, z_block) -> dz_block)

    def add_states(self, n, f, z0=None):
        start = sum(b[0] for b in self.z_blocks)
        self.z_blocks.append((n, z0, f))
        return slice(start, start + n)

    def accel(self, t, q, qd, z, thfb):
        p = self.pl.p
        wm = qd[:, self.i_motor]
        u = p["amplifier_gain"] * p["kp"] * (-thfb)
        if self.vsat is not None:
            u = self.vsat(u)
        i = (u - p["kb"] * wm) / p["ra"]
        if self.isat is not None:
            i = self.isat(i)
        Tm = p["kt"] * i
        F = -(q @ self.K_rest.T) - (qd @ self.D_rest.T)
        F += np.outer(Tm + self.pl.cb * wm, self.b_servo)
        F -= np.outer((self.pl.cb + self.cv) * wm, self.e_motor)
        if self.tau_hubs:
            hub = 0.0
            for f in self.tau_hubs:
                hub = hub + f(t, q, qd, z)
            F += np.outer(hub, self.e_hub)
        for f in self.gen_forces:
            F += f(t, q, qd, z)
        return F @ self.Minv.T

    def run(self, T=30.0, h=1.0 / 1280, out_every=10, delay=None, zoh=None):
        """Integrate 0..T with step h; return outputs (B, n_out_samples, 3) at every out_every-th
        step.  delay: array (B,) of exact transport delays of theta in the feedback (needs
        delay >= 2h; Hermite interpolation of the stored grid, theta = theta(0) before t = 0);
        zoh: (n_s, n_l) integer arrays (B,) for a sampled-data controller with sampling period
        n_s*h and computation latency n_l*h (zero-order hold)."""
        B, N = self.B, self.N
        nsteps = int(round(T / h))
        q = np.zeros((B, N))
        qd = np.zeros((B, N))
        q[:, 0] = self.pl.theta0
        qd[:, 0] = self.pl.theta_dot0
        for i in range(N):
            if i != 0 and self.e_motor[i] == 1.0 and self.i_motor == i:
                q[:, i] = self.pl.theta0      # a separate motor DOF starts with the hub
        nz = sum(b[0] for b in self.z_blocks)
        z = np.zeros((B, nz))
        off = 0
        for n, z0, f in self.z_blocks:
            if z0 is not None:
                z[:, off:off + n] = z0
            off += n
        nout = nsteps // out_every + 1
        Y = np.empty((B, nout, 3))
        need_hist = delay is not None or zoh is not None
        if need_hist:
            H_th = np.zeros((nsteps + 1, B))
            H_thd = np.zeros((nsteps + 1, B))
        cols = np.arange(B)
        th0 = self.pl.theta0
        if delay is not None:
            delay = np.asarray(delay, float)
            assert np.all(delay >= 2 * h - 1e-15), "delay must be >= 2h"

        def hist_theta(s):
            u = np.maximum(s, 0.0) / h
            k = np.clip(np.floor(u).astype(int), 0, nsteps - 1)
            fr = u - k
            y0, y1 = H_th[k, cols], H_th[k + 1, cols]
            d0, d1 = H_thd[k, cols] * h, H_thd[k + 1, cols] * h
            f2 = fr * fr
            f3 = f2 * fr
            val = (2 * f3 - 3 * f2 + 1) * y0 + (f3 - 2 * f2 + fr) * d0 + (-2 * f3 + 3 * f2) * y1 + (f3 - f2) * d1
            return np.where(s > 0, val, th0)

        def zdot(t, q, qd, z):
            if nz == 0:
                return z
            out = np.empty_like(z)
            off = 0
            for n, z0, f in self.z_blocks:
                out[:, off:off + n] = f(t, q, qd, z[:, off:off + n])
                off += n
            return out

        def deriv(t, q, qd, z, held):
            if delay is not None:
                thfb = hist_theta(t - delay)
            elif zoh is not None:
                thfb = held
            elif self.theta_fb is not None:
                thfb = self.theta_fb(t, q)
            else:
                thfb = q[:, 0]
            return self.accel(t, q, qd, z, thfb), zdot(t, q, qd, z)

        def snapshot(j, q, qd):
            if j % out_every == 0:
                X = np.concatenate([q, qd], axis=1)
                Y[:, j // out_every, :] = self.pl.outputs_of(X, self.strain_row)
            if need_hist:
                H_th[j] = q[:, 0]
                H_thd[j] = qd[:, 0]

        held = None
        if zoh is not None:
            n_s, n_l = (np.asarray(a, int) for a in zoh)
        snapshot(0, q, qd)
        hz = nz > 0
        for j in range(nsteps):
            t = j * h
            if zoh is not None:
                # the sample applied during [t_j, t_j+1): the last one taken at k n_s with
                # k n_s + n_l <= j (before the first one arrives, theta(0))
                kk = np.floor_divide(j - n_l, n_s)
                idx = np.where(j - n_l >= 0, kk * n_s, 0)
                held = H_th[idx, cols]
            k1a, k1z = deriv(t, q, qd, z, held)
            q2, qd2 = q + 0.5 * h * qd, qd + 0.5 * h * k1a
            z2 = z + 0.5 * h * k1z if hz else z
            k2a, k2z = deriv(t + 0.5 * h, q2, qd2, z2, held)
            q3, qd3 = q + 0.5 * h * qd2, qd + 0.5 * h * k2a
            z3 = z + 0.5 * h * k2z if hz else z
            k3a, k3z = deriv(t + 0.5 * h, q3, qd3, z3, held)
            q4, qd4 = q + h * qd3, qd + h * k3a
            z4 = z + h * k3z if hz else z
            k4a, k4z = deriv(t + h, q4, qd4, z4, held)
            q = q + (h / 6.0) * (qd + 2 * qd2 + 2 * qd3 + qd4)
            qd = qd + (h / 6.0) * (k1a + 2 * k2a + 2 * k3a + k4a)
            if hz:
                z = z + (h / 6.0) * (k1z + 2 * k2z + 2 * k3z + k4z)
            snapshot(j + 1, q, qd)
        return Y

#!/usr/bin/env python3
"""Seeded truth generator for the `memid diagnose` study (independent of the Rust crates).

usage: python3 studies/diagnose/generate.py --out DIR --set dev|held [--seed N] [--jobs J]
                                            [--only SUBSTRING] [--list]

Writes DIR/truth.json, DIR/models/<case>.ron (the nominal model file given to the fit, with the
case's known initial angle) and DIR/data/<case>.csv (t,theta,theta_dot,strain at 128 Hz, 30 s).
Every case's random numbers come from numpy's default_rng([seed, crc32(case name)]), so a case is
reproduced exactly by its name and the seed, whatever else is generated.  See README.md.
"""
import argparse
import json
import math
import os
import re
import sys
import time
import zlib

import numpy as np
from scipy.signal import lfilter

sys.dont_write_bytecode = True          # keep the repository free of __pycache__
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from truthplant import NOMINAL, Plant, Sim  # noqa: E402

# ================================================================================================
# The dev / held-out split.  Every form below appears in exactly one set.
SPLIT = {
    "dev": {
        "A": ["clamp", "current_tanh", "vsat_sharp", "stribeck", "coulomb_smooth", "drag_p1.5",
              "drag_p2", "cubic_soft", "delay", "mode_inertia", "mode_stiffness",
              "offset_theta_dot", "offset_strain", "scale_theta", "scale_theta_dot",
              "drift_theta", "drift_strain", "quant_adc_theta", "quant_adc_theta_dot",
              "quant_adc_strain"],
        "A_seeds": 2,
        "B": ["white", "ar1_0.5", "ar1_0.8", "ar1_0.9", "damping_2x", "damping_0.5x",
              "hub_inertia_+20", "hub_inertia_-20", "motor_inertia_+15", "motor_inertia_-15",
              "ei_+10", "ei_-10"],
        "B_seeds": 5,
        "C": ["backlash", "hysteretic_beam", "amplitude_damping", "pot_nonlinearity",
              "step_torque", "time_jitter"],
        "D": [("clamp", "drag_p2"), ("delay", "offset_theta_dot"),
              ("stribeck", "quant_adc_theta"), ("mode_inertia", "scale_theta_dot")],
        "D_seeds": 2,
    },
    "held": {
        "A": ["vsat_soft", "dahl", "drag_p2.5", "cubic_hard", "zoh_delay", "mode_damping",
              "offset_theta", "scale_strain", "drift_theta_dot", "quant_after_theta",
              "quant_after_theta_dot", "quant_after_strain"],
        "A_seeds": 2,
        "B": ["uneven_levels", "ar1_0.7", "rho_+8", "rho_-8", "length_+3", "length_-3",
              "combined"],
        "B_seeds": 2,
        "C": ["cogging", "gravity", "tach_ripple", "torque_fade", "gauge_clip", "channel_skew",
              "crosstalk", "mains_hum"],
        "D": [("vsat_soft", "drag_p2.5"), ("zoh_delay", "offset_theta"),
              ("dahl", "quant_after_strain"), ("mode_damping", "scale_strain")],
        "D_seeds": 1,
    },
}
DEFAULT_SEED = {"dev": 20261123, "held": 70261123}
TARGETS = {"weak": 3.0, "medium": 10.0, "strong": 30.0}
QUANT_STEP_SIGMA = {"weak": (1.0, 1.5), "medium": (3.0, 4.5), "strong": (7.0, 10.0)}
OUTPUTS = ["theta", "theta_dot", "strain"]
RATE, DURATION = 128, 30.0
NS = int(RATE * DURATION) + 1            # 3841 samples
H_FINE, H_SEARCH = 1.0 / 1280, 1.0 / 640
HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURE = os.path.join(HERE, "..", "..", "fixtures", "slewing.ron")

# catalog names and accept lists per form
SAT = ["amplifier_saturation", "voltage_saturation"]
# A smooth limiter without a knee (tanh, u/sqrt(1+(u/V)^2)) is, while the demand stays near or
# below the limit, a softening cubic of the servo torque in theta (the back-EMF share of the
# demand is < 1 %): the same physics as cubic_stiffness, which is therefore accepted too.
SMOOTH_SAT = SAT + ["cubic_stiffness"]
FORM_EFFECT = {
    "clamp": ("amplifier_saturation", SAT), "current_tanh": ("amplifier_saturation", SMOOTH_SAT),
    "vsat_sharp": ("voltage_saturation", SAT), "vsat_soft": ("voltage_saturation", SMOOTH_SAT),
    "stribeck": ("coulomb_friction", ["coulomb_friction"]),
    "coulomb_smooth": ("coulomb_friction", ["coulomb_friction"]),
    "dahl": ("coulomb_friction", ["coulomb_friction"]),
    "drag_p1.5": ("quadratic_drag", ["quadratic_drag"]),
    "drag_p2": ("quadratic_drag", ["quadratic_drag"]),
    "drag_p2.5": ("quadratic_drag", ["quadratic_drag"]),
    "cubic_soft": ("cubic_stiffness", ["cubic_stiffness"]),
    "cubic_hard": ("cubic_stiffness", ["cubic_stiffness"]),
    "delay": ("time_delay", ["time_delay"]), "zoh_delay": ("time_delay", ["time_delay"]),
    "mode_inertia": ("unmodeled_mode", ["unmodeled_mode"]),
    "mode_stiffness": ("unmodeled_mode", ["unmodeled_mode"]),
    "mode_damping": ("unmodeled_mode", ["unmodeled_mode"]),
}
for _s in OUTPUTS:
    FORM_EFFECT[f"offset_{_s}"] = ("output_offset", ["output_offset"])
    FORM_EFFECT[f"scale_{_s}"] = ("sensor_scale", ["sensor_scale"])
    FORM_EFFECT[f"drift_{_s}"] = ("sensor_drift", ["sensor_drift"])
    FORM_EFFECT[f"quant_adc_{_s}"] = ("sensor_quantization", ["sensor_quantization"])
    FORM_EFFECT[f"quant_after_{_s}"] = ("sensor_quantization", ["sensor_quantization"])
C_ACCEPT = {
    "backlash": ["none", "backlash"], "hysteretic_beam": ["none"],
    "amplitude_damping": ["none"], "pot_nonlinearity": ["none"], "step_torque": ["none"],
    "time_jitter": ["none"], "cogging": ["none"], "gravity": ["none", "cubic_stiffness"],
    "tach_ripple": ["none"], "torque_fade": ["none"], "gauge_clip": ["none"],
    "channel_skew": ["none"], "crosstalk": ["none"], "mains_hum": ["none"],
}


def sensor_of(form):
    for s in ("theta_dot", "strain", "theta"):
        if form.endswith("_" + s):
            return s
    return None


def is_sensor_form(form):
    return form.split("_")[0] in ("offset", "scale", "drift", "quant")


# ================================================================================================
# nominal model file

def check_fixture():
    """The truth's nominal constants are typed in truthplant.NOMINAL; check them against the
    fixture so both describe the same rig."""
    txt = open(FIXTURE).read()
    want = {"length": "length", "ei_over_rho": "ei_over_rho", "mass_per_length": "rho",
            "hub_radius": "hub_radius", "thickness": "thickness",
            "torque_constant": "kt", "back_emf_constant": "kb", "armature_resistance": "ra",
            "amplifier_gain": "amplifier_gain", "position_gain": "kp", "viscous_damping": "cv",
            "hub_angle": "theta0"}
    for field, key in want.items():
        m = re.search(r"\b" + field + r":\s*([-0-9.eE+]+)", txt)
        assert m and abs(float(m.group(1)) - NOMINAL[key]) <= 1e-12 * abs(NOMINAL[key]), field
    inert = re.findall(r"inertia:\s*([-0-9.eE+]+)", txt)
    assert abs(float(inert[0]) - NOMINAL["hub_inertia"]) < 1e-15
    assert abs(float(inert[1]) - NOMINAL["motor_inertia"]) < 1e-15
    md = re.search(r"modal_damping:\s*\[([^\]]*)\]", txt).group(1)
    assert [float(x) for x in md.split(",") if x.strip()] == NOMINAL["modal_damping"]
    return txt


def model_text(fixture, name, theta0):
    txt = fixture.replace('name: "Garcia & Inman slewing experiment"', f'name: "diagnosis study case {name}"')
    txt, n = re.subn(r"hub_angle:\s*[-0-9.eE+]+,", f"hub_angle: {theta0!r},", txt)
    assert n == 1
    txt, n = re.subn(r'free:\s*\[[^\]]*\],', 'free: ["cv", "kp"],', txt)
    assert n == 1
    return txt


# ================================================================================================
# helpers

def rng_for(seed, name):
    return np.random.default_rng([seed, zlib.crc32(name.encode())])


def ratio_per_output(Y, Y0, sigma):
    """peak over time of |Y - Y0| / sigma, per output; Y (..., NS, 3)."""
    d = np.abs(np.asarray(Y) - np.asarray(Y0))
    r = d.max(axis=-2) / sigma
    return np.where(np.isfinite(r), r, 1e9)


def closed_loop_hz(plant, M=None, K=None, D=None):
    ev = np.linalg.eigvals(plant.first_order(M, K, D))
    ev = ev[ev.imag > 1e-9]
    return np.sort(np.abs(ev) / (2 * math.pi))


class Ctx:
    """Everything drawn for one case."""

    def __init__(self, name, rng, p, level, noise_kind, noise_rho, family):
        self.name, self.rng, self.p, self.family = name, rng, p, family
        self.plant = Plant(p)
        t = np.arange(NS) / RATE
        self.t = t
        self.Y0 = self.plant.linear_response(t)
        self.rms = np.sqrt(np.mean(self.Y0 ** 2, axis=0))
        self.level = np.broadcast_to(np.asarray(level, float), (3,)).copy()
        self.sigma = self.level * self.rms
        self.noise_kind, self.noise_rho = noise_kind, noise_rho
        pl = self.plant
        self.i0 = p["amplifier_gain"] * p["kp"] * p["theta0"] / p["ra"]   # initial current demand
        self.u0 = p["amplifier_gain"] * p["kp"] * p["theta0"]             # initial voltage demand
        self.T0 = pl.ks * p["theta0"]                                     # initial servo torque
        self.minv00 = np.linalg.inv(pl.M)[0, 0]


# ================================================================================================
# dynamic forms: each returns a configured batched simulation for magnitudes m (B,)

class DynForm:
    """A physical effect integrated by RK4.  draw() fixes the form's constants from the case's
    rng, bounds() gives the search range of the magnitude m, params(m) the truth record."""
    h_search = H_SEARCH
    monotone_note = ""

    def __init__(self, form, ctx):
        self.form, self.ctx = form, ctx
        self.c = {}
        self.draw()

    def draw(self):
        pass

    def params(self, m):
        raise NotImplementedError

    def configure(self, sim, m):
        raise NotImplementedError

    def make_sim(self, B):
        return Sim(self.ctx.plant, B)

    def simulate(self, m, h):
        m = np.asarray(m, float)
        sim = self.make_sim(len(m))
        self.configure(sim, m)
        return sim.run(T=DURATION, h=h, out_every=int(round(1 / (RATE * h))), **self.run_kwargs(m))

    def run_kwargs(self, m):
        return {}


def _inf_if_zero(x, v):
    return np.where(x > 0, v, np.inf)


class Clamp(DynForm):
    """Ideal armature-current clamp |i| <= I, I = i0 (1 - m), i0 the initial demand."""
    def bounds(self):
        return 1e-5, 0.97

    def params(self, m):
        return {"current_limit_A": self.ctx.i0 * (1 - m), "initial_demand_A": self.ctx.i0}

    def configure(self, sim, m):
        I = _inf_if_zero(m, self.ctx.i0 * (1 - m))
        sim.isat = lambda i: np.clip(i, -I, I)


class CurrentTanh(DynForm):
    """Smooth current limit i <- I tanh(i / I), I = i0 / m."""
    def bounds(self):
        return 1e-4, 6.0

    def params(self, m):
        return {"current_limit_A": self.ctx.i0 / m, "initial_demand_A": self.ctx.i0, "law": "I*tanh(i/I)"}

    def configure(self, sim, m):
        I = np.where(m > 0, self.ctx.i0 / np.maximum(m, 1e-300), 1e300)
        sim.isat = lambda i: I * np.tanh(i / I)


class VsatSharp(DynForm):
    """Amplifier output voltage clamp |e_a| <= V, V = u0 (1 - m); back-EMF still acts."""
    def bounds(self):
        return 1e-5, 0.97

    def params(self, m):
        return {"voltage_limit_V": self.ctx.u0 * (1 - m), "initial_demand_V": self.ctx.u0}

    def configure(self, sim, m):
        V = _inf_if_zero(m, self.ctx.u0 * (1 - m))
        sim.vsat = lambda u: np.clip(u, -V, V)


class VsatSoft(DynForm):
    """Soft amplifier voltage limit e_a = u / sqrt(1 + (u/V)^2), V = u0 / m."""
    def bounds(self):
        return 1e-4, 6.0

    def params(self, m):
        return {"voltage_limit_V": self.ctx.u0 / m, "initial_demand_V": self.ctx.u0, "law": "u/sqrt(1+(u/V)^2)"}

    def configure(self, sim, m):
        V = np.where(m > 0, self.ctx.u0 / np.maximum(m, 1e-300), 1e300)
        sim.vsat = lambda u: u / np.sqrt(1.0 + (u / V) ** 2)


def _smoothing(ctx, fpeak, want):
    """tanh smoothing velocity: `want`, raised if needed so the RK4 step stays well inside its
    stability region (slope fpeak/v_s times the hub's inverse inertia times h <= 1)."""
    return max(want, fpeak * ctx.minv00 * H_SEARCH / 1.0)


class Stribeck(DynForm):
    """tau = -[Fc + (Fs - Fc) exp(-(v/v_st)^2)] tanh(v/v_s) - c_f v, Fs = r Fc > Fc; the viscous
    part c_f is present in every run (it is part of the truth's total viscous damping)."""
    def draw(self):
        r = self.ctx.rng
        self.c = dict(peak_ratio=float(r.uniform(1.3, 2.2)), v_stribeck=float(r.uniform(0.005, 0.04)),
                      viscous_part=float(r.uniform(0.005, 0.03)), v_smooth_wanted=float(r.uniform(2e-4, 6e-4)))

    def bounds(self):
        return 1e-6, 0.3

    def fc(self, m):
        return m * self.ctx.T0

    def vs(self, m):
        return _smoothing(self.ctx, float(np.max(self.fc(np.atleast_1d(m)))) * self.c["peak_ratio"],
                          self.c["v_smooth_wanted"])

    def params(self, m):
        fc = self.fc(m)
        return {"Fc": fc, "Fs": fc * self.c["peak_ratio"], "v_stribeck": self.c["v_stribeck"],
                "v_smooth": self.vs(m), "viscous_part": self.c["viscous_part"]}

    def configure(self, sim, m):
        fc = self.fc(m)
        fs = fc * self.c["peak_ratio"]
        vst, cf = self.c["v_stribeck"], self.c["viscous_part"]
        vs = self.vs(m)
        sim.tau_hubs.append(lambda t, q, qd, z: -(fc + (fs - fc) * np.exp(-(qd[:, 0] / vst) ** 2))
                            * np.tanh(qd[:, 0] / vs) - cf * qd[:, 0])


class CoulombSmooth(DynForm):
    """Plain Coulomb friction -Fc tanh(v/v_s) with a tiny smoothing velocity."""
    def draw(self):
        self.c = dict(v_smooth_wanted=float(self.ctx.rng.uniform(2e-4, 1e-3)))

    def bounds(self):
        return 1e-6, 0.3

    def vs(self, m):
        return _smoothing(self.ctx, float(np.max(np.atleast_1d(m))) * self.ctx.T0, self.c["v_smooth_wanted"])

    def params(self, m):
        return {"Fc": m * self.ctx.T0, "v_smooth": self.vs(m)}

    def configure(self, sim, m):
        fc = m * self.ctx.T0
        vs = self.vs(m)
        sim.tau_hubs.append(lambda t, q, qd, z: -fc * np.tanh(qd[:, 0] / vs))


class Dahl(DynForm):
    """Dahl friction: state F, dF/dt = (Fc/x_p) v - (|v|/x_p) F, hub torque -F (held-out form)."""
    h_search = H_FINE

    def draw(self):
        self.c = dict(presliding_rad=float(self.ctx.rng.uniform(5e-4, 2e-3)))

    def bounds(self):
        return 1e-6, 0.3

    def params(self, m):
        return {"Fc": m * self.ctx.T0, "presliding_rad": self.c["presliding_rad"]}

    def configure(self, sim, m):
        fc = m * self.ctx.T0
        xp = self.c["presliding_rad"]
        sl = sim.add_states(1, lambda t, q, qd, z: ((fc / xp) * qd[:, 0] - np.abs(qd[:, 0]) / xp * z[:, 0])[:, None])
        sim.tau_hubs.append(lambda t, q, qd, z: -z[:, sl.start])


class Drag(DynForm):
    """tau = -c |v|^p sign v."""
    def draw(self):
        self.c = dict(exponent=float(self.form.split("_p")[1]))

    def bounds(self):
        return 1e-6, 30.0

    def params(self, m):
        return {"c": m, "exponent": self.c["exponent"]}

    def configure(self, sim, m):
        p = self.c["exponent"]
        sim.tau_hubs.append(lambda t, q, qd, z: -m * np.abs(qd[:, 0]) ** p * np.sign(qd[:, 0]))


class Cubic(DynForm):
    """tau = -k3 theta^3 at the hub; softening (k3 < 0, dev) or hardening (k3 > 0, held)."""
    def draw(self):
        self.c = dict(sign=-1.0 if self.form == "cubic_soft" else 1.0)

    def bounds(self):
        ks, th0 = self.ctx.plant.ks, self.ctx.p["theta0"]
        hi = 0.8 * ks / th0 ** 2 if self.c["sign"] < 0 else 30 * ks / th0 ** 2
        return 1e-6 * ks, hi

    def params(self, m):
        return {"k3": self.c["sign"] * m}

    def configure(self, sim, m):
        k3 = self.c["sign"] * m
        sim.tau_hubs.append(lambda t, q, qd, z: -k3 * q[:, 0] ** 3)


class Delay(DynForm):
    """Exact transport delay tau in the feedback: the controller sees theta(t - tau)."""
    def bounds(self):
        return 2 * H_SEARCH, 0.3

    def params(self, m):
        return {"delay_s": m}

    def configure(self, sim, m):
        pass

    def run_kwargs(self, m):
        return {"delay": np.asarray(m, float)}

    def simulate(self, m, h):
        m = np.asarray(m, float)
        sim = Sim(self.ctx.plant, len(m))
        # m == 0 is the undelayed loop: run it as a separate, delay-free batch member
        Y = sim.run(T=DURATION, h=h, out_every=int(round(1 / (RATE * h))),
                    delay=np.where(m > 0, np.maximum(m, 2 * h), 2 * h))
        if np.any(m == 0):
            Y0 = Sim(self.ctx.plant, 1).run(T=DURATION, h=h, out_every=int(round(1 / (RATE * h))))
            Y[m == 0] = Y0[0]
        return Y


class Backlash(DynForm):
    """Motor and hub as separate inertias joined by a stiff gear (k_g, contact damping c_g) with a
    dead band of total width b = m: tau_g = k_g dz(theta_m - theta) + c_g (w_m - w) in contact.
    The potentiometer and tachometer read the hub; C_v and the back-EMF act on the motor."""
    def draw(self):
        r = self.ctx.rng
        im = self.ctx.p["motor_inertia"]
        wg = 2 * math.pi * float(r.uniform(6.0, 9.0))
        self.c = dict(gear_stiffness=im * wg * wg, gear_damping=2 * 0.05 * math.sqrt(im * im * wg * wg))

    def bounds(self):
        return 1e-6, 0.05

    def params(self, m):
        return dict(dead_band_rad=m, **self.c)

    def make_sim(self, B):
        pl = self.ctx.plant
        n = pl.n
        N = n + 2
        im = pl.p["motor_inertia"]
        M = np.zeros((N, N))
        M[:n + 1, :n + 1] = pl.M
        M[0, 0] -= im
        M[N - 1, N - 1] = im
        K_rest = np.zeros((N, N))
        K_rest[1:n + 1, 1:n + 1] = np.diag(pl.modes["omega"] ** 2)
        D_rest = np.zeros((N, N))
        D_rest[1:n + 1, 1:n + 1] = np.diag(pl.p["modal_damping"])
        b_servo = np.concatenate([[0.0], pl.modes["gamma"], [1.0]])
        e_motor = np.zeros(N)
        e_motor[N - 1] = 1.0
        e_hub = np.zeros(N)
        e_hub[0] = 1.0
        sr = np.concatenate([pl.strain_row, [0.0]])
        return Sim(pl, B, M=M, b_servo=b_servo, e_hub=e_hub, e_motor=e_motor, i_motor=N - 1,
                   K_rest=K_rest, D_rest=D_rest, strain_row=sr)

    def configure(self, sim, m):
        kg, cg = self.c["gear_stiffness"], self.c["gear_damping"]
        half = 0.5 * m
        N = sim.N

        def gear(t, q, qd, z):
            d = q[:, N - 1] - q[:, 0]
            dz = np.where(d > half, d - half, np.where(d < -half, d + half, 0.0))
            contact = np.abs(d) > half
            tg = kg * dz + cg * (qd[:, N - 1] - qd[:, 0]) * contact
            F = np.zeros((len(d), N))
            F[:, 0] = tg
            F[:, N - 1] = -tg
            return F
        sim.gen_forces.append(gear)


def _relaxation_fit():
    """Coefficients a_k of sum_k a_k i w/(i w + b_k) whose imaginary part is ~1 over 3..150 rad/s
    (a causal, nearly frequency-independent loss factor)."""
    b = np.array([2.0, 10.0, 50.0, 250.0])
    w = np.geomspace(3.0, 150.0, 60)
    G = np.array([[(1j * wi / (1j * wi + bk)).imag for bk in b] for wi in w])
    a, *_ = np.linalg.lstsq(G, np.ones_like(w), rcond=None)
    return b, a


class HystereticBeam(DynForm):
    """Hysteretic (structural) damping of the beam: each flexible mode's restoring force gains
    eta w_i^2 sum_k a_k (q_i - r_ik), r_ik' = b_k (q_i - r_ik): a loss factor eta nearly
    independent of frequency over 3-150 rad/s (generalised Maxwell model)."""
    def bounds(self):
        return 1e-6, 0.3

    def params(self, m):
        b, a = _relaxation_fit()
        return {"loss_factor": m, "relaxation_rates": b.tolist(), "weights": a.tolist()}

    def configure(self, sim, m):
        b, a = _relaxation_fit()
        pl = self.ctx.plant
        n, nk = pl.n, len(b)
        w2 = pl.modes["omega"] ** 2
        N = sim.N
        sl = sim.add_states(n * nk, lambda t, q, qd, z: (np.repeat(q[:, 1:n + 1], nk, axis=1) - z) * np.tile(b, n))

        def force(t, q, qd, z):
            r = z[:, sl].reshape(len(q), n, nk)
            f = ((q[:, 1:n + 1, None] - r) * a).sum(-1) * w2 * m[:, None]
            F = np.zeros((len(q), N))
            F[:, 1:n + 1] = -f
            return F
        sim.gen_forces.append(force)


class AmplitudeDamping(DynForm):
    """Amplitude-dependent modal damping: mode i's damping 2 zeta_i w_i (1 + beta A_i/A_ref,i),
    A_i = sqrt(q_i^2 + (q_i'/w_i)^2), A_ref,i the mode's largest amplitude in the linear decay."""
    def draw(self):
        pl = self.ctx.plant
        A = pl.first_order()
        N = A.shape[0] // 2
        from scipy.linalg import expm
        Phi = expm(A / RATE)
        x = pl.x0()
        amp = np.zeros(pl.n)
        w = pl.modes["omega"]
        for _ in range(NS):
            amp = np.maximum(amp, np.sqrt(x[1:N] ** 2 + (x[N + 1:] / w) ** 2))
            x = Phi @ x
        self.c = dict(a_ref=amp.tolist())

    def bounds(self):
        return 1e-5, 50.0

    def params(self, m):
        return {"beta": m, "a_ref": self.c["a_ref"]}

    def configure(self, sim, m):
        pl = self.ctx.plant
        n, N = pl.n, sim.N
        w = pl.modes["omega"]
        c = np.asarray(pl.p["modal_damping"])
        aref = np.asarray(self.c["a_ref"])

        def force(t, q, qd, z):
            A = np.sqrt(q[:, 1:n + 1] ** 2 + (qd[:, 1:n + 1] / w) ** 2) / aref
            F = np.zeros((len(q), N))
            F[:, 1:n + 1] = -m[:, None] * c * A * qd[:, 1:n + 1]
            return F
        sim.gen_forces.append(force)


class PotNonlinearity(DynForm):
    """Potentiometer nonlinearity y = theta + a sin(2 pi theta / P); the loop feeds back the
    potentiometer, and the recorded theta column is the same reading."""
    def draw(self):
        self.c = dict(period_rad=float(self.ctx.rng.uniform(0.08, 0.25)))

    def bounds(self):
        return 1e-7, 0.45 * self.c["period_rad"] / (2 * math.pi)

    def params(self, m):
        return {"amplitude_rad": m, "period_rad": self.c["period_rad"]}

    def configure(self, sim, m):
        P = self.c["period_rad"]
        sim.theta_fb = lambda t, q: q[:, 0] + m * np.sin(2 * math.pi * q[:, 0] / P)

    def simulate(self, m, h):
        Y = DynForm.simulate(self, m, h)
        P = self.c["period_rad"]
        Y[:, :, 0] = Y[:, :, 0] + np.asarray(m)[:, None] * np.sin(2 * math.pi * Y[:, :, 0] / P)
        return Y


class StepTorque(DynForm):
    """A constant disturbance torque T switched on at t_on (on the sample grid)."""
    def draw(self):
        r = self.ctx.rng
        self.c = dict(t_on=round(float(r.uniform(5.0, 20.0)) * RATE) / RATE, sign=float(r.choice([-1.0, 1.0])))

    def bounds(self):
        return 1e-7, 0.5 * self.ctx.T0

    def params(self, m):
        return {"torque": self.c["sign"] * m, "t_on": self.c["t_on"]}

    def configure(self, sim, m):
        T, ton = self.c["sign"] * m, self.c["t_on"]
        sim.tau_hubs.append(lambda t, q, qd, z: T * (t >= ton - 1e-12))


class Cogging(DynForm):
    """Cogging torque -T_c sin(N theta) at the hub (held-out form)."""
    def draw(self):
        self.c = dict(teeth=int(self.ctx.rng.choice([24, 36, 48])))

    def bounds(self):
        return 1e-7, 0.5 * self.ctx.T0

    def params(self, m):
        return {"torque": m, "teeth": self.c["teeth"]}

    def configure(self, sim, m):
        N = self.c["teeth"]
        sim.tau_hubs.append(lambda t, q, qd, z: -m * np.sin(N * q[:, 0]))


class Gravity(DynForm):
    """A pendulum term -T_g sin(theta) (axis tilted from vertical; held-out form)."""
    def bounds(self):
        return 1e-7, 3.0 * self.ctx.plant.ks

    def params(self, m):
        return {"torque": m}

    def configure(self, sim, m):
        sim.tau_hubs.append(lambda t, q, qd, z: -m * np.sin(q[:, 0]))


class TorqueFade(DynForm):
    """The motor's torque constant fading as it warms, K_t (1 - m t/T) over the record (held-out
    form): the servo's torque and its back-EMF damping both weaken with time."""
    def bounds(self):
        return 1e-5, 0.6

    def params(self, m):
        return {"fade_over_record": m}

    def configure(self, sim, m):
        now = [0.0]

        def feedback(t, q):
            now[0] = t
            return q[:, 0]
        sim.theta_fb = feedback
        sim.isat = lambda i: i * (1.0 - m * now[0] / DURATION)


class Combined(DynForm):
    """Two dynamic forms at once (family D), each at its own magnitude."""
    def __init__(self, f1, f2, m1, m2):
        self.f1, self.f2, self.m1, self.m2 = f1, f2, m1, m2
        self.ctx = f1.ctx

    def simulate_pair(self, h):
        sim = Sim(self.ctx.plant, 1)
        self.f1.configure(sim, np.array([self.m1]))
        self.f2.configure(sim, np.array([self.m2]))
        kw = {}
        for f, m in ((self.f1, self.m1), (self.f2, self.m2)):
            kw.update(f.run_kwargs(np.array([m])))
        return sim.run(T=DURATION, h=h, out_every=int(round(1 / (RATE * h))), **kw)[0]


DYN = {"clamp": Clamp, "current_tanh": CurrentTanh, "vsat_sharp": VsatSharp, "vsat_soft": VsatSoft,
       "stribeck": Stribeck, "coulomb_smooth": CoulombSmooth, "dahl": Dahl,
       "drag_p1.5": Drag, "drag_p2": Drag, "drag_p2.5": Drag, "cubic_soft": Cubic,
       "cubic_hard": Cubic, "delay": Delay, "backlash": Backlash, "hysteretic_beam": HystereticBeam,
       "amplitude_damping": AmplitudeDamping, "pot_nonlinearity": PotNonlinearity,
       "step_torque": StepTorque, "cogging": Cogging, "gravity": Gravity, "torque_fade": TorqueFade}


def search_magnitude(form, target):
    """Smallest magnitude whose clean response differs from the effect-free one by `target` noise
    sigmas (peak over time, on the output where it is largest).  Two batched geometric scans at
    the search step, log-log interpolation, a fine-step check and one secant correction."""
    ctx = form.ctx
    lo, hi = form.bounds()
    h = form.h_search
    capped = False
    for _ in range(3):
        grid = np.concatenate([[0.0], np.geomspace(lo, hi, 23)])
        Y = form.simulate(grid, h)
        r = ratio_per_output(Y[1:], Y[0], ctx.sigma).max(-1)
        above = np.nonzero(r >= target)[0]
        if len(above) == 0:
            capped = True
            m_star = hi
            break
        i = above[0]
        if i == 0:
            lo = lo / 1e3
            continue
        g2 = np.concatenate([[0.0], np.geomspace(grid[i], grid[i + 1], 12)])
        Y2 = form.simulate(g2, h)
        r2 = ratio_per_output(Y2[1:], Y2[0], ctx.sigma).max(-1)
        j = np.nonzero(r2 >= target)[0][0] if np.any(r2 >= target) else len(r2) - 1
        if j == 0:
            m_star = g2[1]
        else:
            a, b = g2[j], g2[j + 1]
            ra, rb = max(r2[j - 1], 1e-12), max(r2[j], 1e-12)
            s = (math.log(target) - math.log(ra)) / max(math.log(rb) - math.log(ra), 1e-12)
            m_star = math.exp(math.log(a) + min(max(s, 0.0), 1.0) * (math.log(b) - math.log(a)))
        break
    else:
        m_star = lo
    # fine-step check (and one correction)
    for attempt in range(2):
        Yf = form.simulate(np.array([0.0, m_star]), H_FINE)
        rpo = ratio_per_output(Yf[1], Yf[0], ctx.sigma)
        achieved = float(rpo.max())
        if capped or abs(achieved / target - 1) < 0.08 or attempt == 1:
            break
        m_star = m_star * (target / max(achieved, 1e-12)) ** 1.0
        m_star = min(max(m_star, lo * 1e-3), hi)
    return m_star, Yf[1], Yf[0], rpo, capped


def search_zoh(ctx, target, frac):
    """Held-out delay form: a sampled-data controller (period n_s h, latency n_l = frac n_s, both
    whole steps of h = 1/1280 s).  Integer scan of n_s."""
    pl = ctx.plant
    cand = np.unique(np.round(np.geomspace(1, 480, 22)).astype(int))

    def run(ns):
        ns = np.asarray(ns, int)
        nl = np.round(frac * ns).astype(int)
        Y = Sim(pl, len(ns)).run(T=DURATION, h=H_FINE, out_every=10, zoh=(ns, nl))
        return Y

    Y0 = Sim(pl, 1).run(T=DURATION, h=H_FINE, out_every=10)[0]
    Y = run(cand)
    r = ratio_per_output(Y, Y0, ctx.sigma).max(-1)
    above = np.nonzero(r >= target)[0]
    if len(above) == 0:
        i = len(cand) - 1
        best = cand[i]
        return int(best), int(round(frac * best)), Y[i], Y0, ratio_per_output(Y[i], Y0, ctx.sigma), True
    i = above[0]
    lo = cand[i - 1] if i > 0 else 1
    fine = np.arange(lo, cand[i] + 1)
    if len(fine) > 40:
        fine = np.unique(np.round(np.geomspace(lo, cand[i], 40)).astype(int))
    Yf = run(fine)
    rf = ratio_per_output(Yf, Y0, ctx.sigma).max(-1)
    k = int(np.argmin(np.abs(np.log(np.maximum(rf, 1e-12) / target))))
    ns = int(fine[k])
    return ns, int(round(frac * ns)), Yf[k], Y0, ratio_per_output(Yf[k], Y0, ctx.sigma), False


# ================================================================================================
# linear forms: the unmodeled mode

def mode_matrices(ctx, kind, f_hz, zeta, c, zeta_b=0.0):
    pl = ctx.plant
    N = pl.n + 2
    w = 2 * math.pi * f_hz
    eM, eK, eD = np.zeros((N, N)), np.zeros((N, N)), np.zeros((N, N))
    eK[N - 1, N - 1] = w * w
    eD[N - 1, N - 1] = 2 * zeta * w
    if kind == "inertia":
        eM[0, N - 1] = eM[N - 1, 0] = c
    elif kind == "stiffness":
        eK[0, N - 1] = eK[N - 1, 0] = c
    else:
        # a dashpot between hub and mode: rank-one, positive semi-definite
        # [[c^2/b, c], [c, b]] with b = 2 zeta_b w the dashpot's share of the mode's damping;
        # its hub part c^2/b is viscous hub damping, i.e. part of the truth's C_v
        b = 2 * zeta_b * w
        eD[N - 1, N - 1] += b
        eD[0, N - 1] = eD[N - 1, 0] = c
        eD[0, 0] += c * c / b
    return pl.augmented(eM, eK, eD, 1)


HUB_DAMPING_LIMIT = 1.0   # damping-coupled mode: largest hub share c^2/b [N*m*s/rad]


def mode_limit(ctx, kind, f_hz, zeta, zeta_b=0.0):
    """Largest coupling keeping the coupled mass/stiffness/damping pair positive definite."""
    pl = ctx.plant
    w = 2 * math.pi * f_hz
    if kind == "inertia":
        schur = pl.M[0, 0] - float(np.sum(pl.modes["I"] ** 2))
        return 0.9 * math.sqrt(schur)
    if kind == "stiffness":
        return 0.9 * math.sqrt(pl.ks) * w
    return math.sqrt(HUB_DAMPING_LIMIT * 2 * zeta_b * w)


def draw_mode(ctx, kind, f_max=3.0):
    rng = ctx.rng
    f_model = closed_loop_hz(ctx.plant)
    f_file = closed_loop_hz(Plant(dict(NOMINAL, theta0=ctx.p["theta0"])))
    avoid = np.concatenate([f_model, f_file])
    for _ in range(1000):
        f = float(rng.uniform(0.3, f_max))
        if np.all(np.abs(f / avoid - 1) > 0.15):
            break
    zeta = float(rng.uniform(0.01, 0.05))
    zeta_b = float(rng.uniform(0.15, 0.35)) if kind == "damping" else 0.0
    return f, zeta, zeta_b


def search_mode(ctx, kind, target):
    """Coupling that puts the mode `target` sigmas above the noise.  If even the largest
    admissible coupling (positive-definite limit) falls short, the frequency and damping are
    drawn again (up to 12 times); the case is then 'capped' at the best draw."""
    pl = ctx.plant
    best = None
    for attempt in range(12):
        # redraws (only when the coupling limit is reached) narrow the band towards 0.3 Hz,
        # where a mode driven by the slow servo motion responds most
        f, zeta, zeta_b = draw_mode(ctx, kind, f_max=3.0 - 2.4 * attempt / 11)
        cmax = mode_limit(ctx, kind, f, zeta, zeta_b)
        sign = float(ctx.rng.choice([-1.0, 1.0]))

        def resp(c, f=f, zeta=zeta, sign=sign, zeta_b=zeta_b):
            M, K, D, bs, eh, sr = mode_matrices(ctx, kind, f, zeta, sign * c, zeta_b)
            return pl.linear_response(ctx.t, M, K, D, sr)

        def reference(c, f=f, zeta_b=zeta_b):
            # the effect-free response; for the damping-coupled mode its hub share c^2/b of
            # viscous damping counts as part of C_v, so the reference carries it too
            if kind != "damping" or c == 0:
                return ctx.Y0
            D = pl.D.copy()
            D[0, 0] += c * c / (2 * zeta_b * 2 * math.pi * f)
            return pl.linear_response(ctx.t, pl.M, pl.K, D)

        def ratio(c, resp=resp, reference=reference):
            return float(ratio_per_output(resp(c), reference(c), ctx.sigma).max())

        rmax = ratio(cmax)
        if best is None or rmax > best[0]:
            best = (rmax, f, zeta, zeta_b, sign, cmax, resp, ratio, reference)
        if rmax >= target:
            break
    rmax, f, zeta, zeta_b, sign, cmax, resp, ratio, reference = best
    lo, hi = 1e-9 * cmax, cmax
    capped = rmax < target
    if capped:
        c = hi
    else:
        c = log_bisect(ratio, target, lo, hi)
    draws = attempt + 1
    Y = resp(c)
    rpo = ratio_per_output(Y, reference(c), ctx.sigma)
    units = {"inertia": "sqrt(kg)*m", "stiffness": "N*m/sqrt(kg)", "damping": "N*m*s/sqrt(kg)"}[kind]
    allm = closed_loop_hz(pl, *mode_matrices(ctx, kind, f, zeta, sign * c, zeta_b)[:3])
    par = {"coupling_through": kind, "frequency_hz": f, "damping_ratio": zeta,
           "coupling": sign * c, "coupling_unit": units, "coupling_limit": cmax,
           "closed_loop_hz_with_mode": allm.tolist(), "draws": draws}
    if kind == "damping":
        b = 2 * zeta_b * 2 * math.pi * f
        par.update({"dashpot_mode_damping_ratio": zeta_b, "mode_damping_ratio_total": zeta + zeta_b,
                    "hub_viscous_damping_added": c * c / b,
                    "note": "D += [[c^2/b, c], [c, b]] on (theta, eta); c^2/b is counted in C_v"})
    return Y, rpo, capped, par


# ================================================================================================
# sensor forms (applied to the clean recording) and noise

def noise_series(ctx, n):
    rng = ctx.rng
    e = np.empty((n, 3))
    for o in range(3):
        w = rng.standard_normal(n)
        if ctx.noise_kind == "ar1":
            rho = ctx.noise_rho
            w[0] = w[0] / math.sqrt(1 - rho * rho)      # stationary start
            e[:, o] = lfilter([math.sqrt(1 - rho * rho)], [1.0, -rho], w)
        else:
            e[:, o] = w
    return e * ctx.sigma


def sensor_effect(ctx, form, strength, Yclean, may_move_level=True):
    """Parameters of a sensor form at a strength; returns (params, transform(Y, noise) -> Y)."""
    rng = ctx.rng
    s = sensor_of(form)
    o = OUTPUTS.index(s)
    kind = form.split("_")[0]
    target = TARGETS[strength]
    sig = ctx.sigma[o]
    t = ctx.t
    if kind == "offset":
        b = float(rng.choice([-1.0, 1.0])) * target * sig
        par = {"offset": b}

        def tr(Y, e):
            Y = Y + e
            Y[:, o] += b
            return Y
        ratio = abs(b) / sig
    elif kind == "scale":
        peak = float(np.max(np.abs(Yclean[:, o])))
        sgn = float(rng.choice([-1.0, 1.0]))
        sc = target * sig / peak
        if may_move_level and not 0.02 <= sc <= 0.10:
            # move the noise level (within 0.5-2 %) so the factor falls in 2-10 % where possible
            want = min(max(sc, 0.02), 0.10)
            lvl = min(max(want * peak / (target * ctx.rms[o]), 0.005), 0.02)
            ctx.level[o] = lvl
            ctx.sigma[o] = lvl * ctx.rms[o]
            sig = ctx.sigma[o]
            sc = target * sig / peak
        sc = sgn * sc
        par = {"scale": sc}

        def tr(Y, e):
            Y = Y.copy()
            Y[:, o] *= (1 + sc)
            return Y + e
        ratio = abs(sc) * peak / sig
    elif kind == "drift":
        d = float(rng.choice([-1.0, 1.0])) * target * sig / DURATION
        par = {"drift_per_s": d}

        def tr(Y, e):
            Y = Y + e
            Y[:, o] += d * t
            return Y
        ratio = abs(d) * DURATION / sig
    else:                                    # quantization
        after = form.startswith("quant_after")
        lo, hi = QUANT_STEP_SIGMA[strength]
        k = float(rng.uniform(lo, hi))
        step = k * sig
        par = {"step": step, "step_over_sigma": k,
               "noise": "after the quantizer" if after else "before the quantizer (ADC)"}

        def tr(Y, e):
            Ym = Y + e
            if after:
                Ym[:, o] = step * np.round(Y[:, o] / step) + e[:, o]
            else:
                Ym[:, o] = step * np.round(Ym[:, o] / step)
            return Ym
        ratio = float(np.max(np.abs(step * np.round(Yclean[:, o] / step) - Yclean[:, o]))) / sig
    rpo = np.zeros(3)
    rpo[o] = ratio
    par.update({"sensor": s})
    return par, tr, rpo


# ================================================================================================
# case construction

def draw_common(ctx_name, rng, family):
    p = dict(NOMINAL)
    p["modal_damping"] = list(NOMINAL["modal_damping"])
    p["cv"] = float(rng.uniform(0.05, 0.4))
    p["kp"] = float(NOMINAL["kp"] * rng.uniform(0.7, 1.3))
    p["modal_damping"] = [float(v * rng.uniform(0.6, 1.6)) for v in NOMINAL["modal_damping"]]
    p["theta0"] = float(rng.uniform(0.3, 0.8))
    level = float(rng.uniform(0.005, 0.02))
    if rng.uniform() < 0.5:
        kind, rho = "white", 0.0
    else:
        kind, rho = "ar1", float(rng.uniform(0.3, 0.9))
    return p, level, kind, rho


NULL_MISMATCH = {
    "damping_2x": ("modal_damping", 2.0), "damping_0.5x": ("modal_damping", 0.5),
    "hub_inertia_+20": ("hub_inertia", 1.2), "hub_inertia_-20": ("hub_inertia", 0.8),
    "motor_inertia_+15": ("motor_inertia", 1.15), "motor_inertia_-15": ("motor_inertia", 0.85),
    "ei_+10": ("ei_over_rho", 1.1), "ei_-10": ("ei_over_rho", 0.9),
    "rho_+8": ("rho", 1.08), "rho_-8": ("rho", 0.92),
    "length_+3": ("length", 1.03), "length_-3": ("length", 0.97),
}


def build_case(spec, seed):
    """spec: dict(name, family, forms, strength, rate, null_kind).  Returns (truth entry, Y, model
    theta0)."""
    name, fam = spec["name"], spec["family"]
    rng = rng_for(seed, name)
    p, level, nkind, nrho = draw_common(name, rng, fam)
    truth = {}
    if fam == "B":
        nk = spec["null_kind"]
        truth["null_kind"] = nk
        if nk.startswith("ar1_"):
            nkind, nrho = "ar1", float(nk.split("_")[1])
        elif nk == "white":
            nkind, nrho = "white", 0.0
        elif nk == "uneven_levels":
            level = [float(v) for v in rng.uniform(0.003, 0.03, 3)]
        elif nk == "combined":
            p["hub_inertia"] *= 1.10
            p["motor_inertia"] *= 0.92
            p["ei_over_rho"] *= 1.05
            p["modal_damping"] = [v * 1.5 / 1.0 for v in NOMINAL["modal_damping"]]
            truth["mismatch"] = {"hub_inertia": 1.10, "motor_inertia": 0.92, "ei_over_rho": 1.05,
                                 "modal_damping": 1.5}
        else:
            key, fac = NULL_MISMATCH[nk]
            if key == "modal_damping":
                p["modal_damping"] = [v * fac for v in NOMINAL["modal_damping"]]
            else:
                p[key] = NOMINAL[key] * fac
            truth["mismatch"] = {key: fac}
        if "level" in spec:
            level = spec["level"]
    ctx = Ctx(name, rng, p, level, nkind, nrho, fam)
    strength = spec.get("strength", "-")
    effects, Y = [], ctx.Y0.copy()
    transforms = []
    dyn_parts = []
    for form in spec["forms"]:
        tgt_strength = strength if fam in ("A", "C") else "medium"
        target = TARGETS.get(tgt_strength, 10.0)
        rec = {"form": form, "effect": FORM_EFFECT.get(form, ("none",))[0] if fam != "C" else "none"}
        if form in DYN:
            f = DYN[form](form, ctx)
            m, Yf, Y0f, rpo, capped = search_magnitude(f, target)
            rec.update(f.params(m))
            rec.update({"magnitude": m, "target_ratio": target, "achieved_ratio": float(rpo.max()),
                        "ratio_per_output": dict(zip(OUTPUTS, rpo.tolist())), "capped": capped})
            dyn_parts.append((f, m, Yf - Y0f))
        elif form == "zoh_delay":
            frac = float(rng.uniform(0.2, 1.0))
            ns, nl, Yf, Y0f, rpo, capped = search_zoh(ctx, target, frac)
            rec.update({"sample_period_s": ns * H_FINE, "latency_s": nl * H_FINE,
                        "effective_delay_s": (ns / 2 + nl) * H_FINE, "target_ratio": target,
                        "achieved_ratio": float(rpo.max()), "capped": capped,
                        "ratio_per_output": dict(zip(OUTPUTS, rpo.tolist()))})
            dyn_parts.append(("zoh", (ns, nl), Yf - Y0f))
        elif form.startswith("mode_"):
            Ym, rpo, capped, par = search_mode(ctx, form.split("_")[1], target)
            rec.update(par)
            rec.update({"target_ratio": target, "achieved_ratio": float(rpo.max()), "capped": capped,
                        "ratio_per_output": dict(zip(OUTPUTS, rpo.tolist()))})
            dyn_parts.append(("mode", None, Ym - ctx.Y0))
        elif form in READING_FORMS:
            rec.update(READING_FORMS[form](ctx, target))
            dyn_parts.append((form, None, rec.pop("_dY")))
        elif is_sensor_form(form):
            transforms.append((form, rec))
            continue
        else:
            raise ValueError(form)
        effects.append(rec)
    # clean record with every dynamic effect
    if len(dyn_parts) == 1:
        Y = ctx.Y0 + dyn_parts[0][2]
    elif len(dyn_parts) == 2:
        a, b = dyn_parts
        if isinstance(a[0], DynForm) and isinstance(b[0], DynForm):
            Y = Combined(a[0], b[0], a[1], b[1]).simulate_pair(H_FINE)
        else:
            raise ValueError("pairs of two dynamic effects must both be DynForms")
    for form, rec in transforms:
        par, tr, rpo = sensor_effect(ctx, form, strength if fam == "A" else "medium", Y, may_move_level=(fam == "A"))
        rec.update(par)
        if form.startswith("quant"):
            rec.update({"target_ratio": None, "achieved_ratio": float(rpo.max())})
        else:
            rec.update({"target_ratio": TARGETS[strength if fam == "A" else "medium"],
                        "achieved_ratio": float(rpo.max())})
        rec["ratio_per_output"] = dict(zip(OUTPUTS, rpo.tolist()))
        effects.append(rec)
        rec["_tr"] = tr
    e = noise_series(ctx, NS)
    Ymeas = Y.copy()
    applied = False
    for rec in effects:
        tr = rec.pop("_tr", None)
        if tr is not None:
            Ymeas = tr(Ymeas, e)
            applied = True
            e = np.zeros_like(e)              # noise enters once
    if not applied:
        Ymeas = Ymeas + e
    combined = ratio_per_output(Y, ctx.Y0, ctx.sigma)
    truth.update({
        "cv": p["cv"], "kp": p["kp"], "modal_damping": p["modal_damping"], "theta0": p["theta0"],
        "plant": {k: v for k, v in p.items()},
        "noise": {"kind": ctx.noise_kind, "rho": ctx.noise_rho, "level": ctx.level.tolist(),
                  "std": dict(zip(OUTPUTS, ctx.sigma.tolist())), "rms_clean": dict(zip(OUTPUTS, ctx.rms.tolist()))},
        "effects": effects,
        "dynamic_ratio_per_output": dict(zip(OUTPUTS, combined.tolist())),
        "seed": seed, "rng_key": [seed, zlib.crc32(name.encode())],
    })
    sens = [r["sensor"] for r in effects if "sensor" in r]
    if len(sens) == 1:
        truth["sensor"] = sens[0]
    return truth, Ymeas, ctx


def log_bisect(ratio, target, lo, hi):
    """The magnitude in [lo, hi] where ratio(m) reaches `target`: bisection in log m to 0.2 %."""
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if ratio(mid) >= target:
            hi = mid
        else:
            lo = mid
        if hi / lo < 1.002:
            break
    return math.sqrt(lo * hi)


def jitter(ctx, target):
    """Sampling-time jitter: sample k is taken at t_k + sigma_j eps_k (eps_k ~ N(0,1), common to
    the three channels; t_0 exact)."""
    eps = ctx.rng.standard_normal(NS)
    eps[0] = 0.0
    pl = ctx.plant

    def resp(sj):
        tt = np.maximum(ctx.t + sj * eps, 0.0)
        return pl.linear_at_times(tt)

    def ratio(sj):
        return float(ratio_per_output(resp(sj), ctx.Y0, ctx.sigma).max())
    sj = log_bisect(ratio, target, 1e-7, 0.05)
    Y = resp(sj)
    rpo = ratio_per_output(Y, ctx.Y0, ctx.sigma)
    return {"jitter_std_s": sj, "target_ratio": target, "achieved_ratio": float(rpo.max()),
            "ratio_per_output": dict(zip(OUTPUTS, rpo.tolist())), "_dY": Y - ctx.Y0}


def tach_ripple(ctx, target):
    """Tachometer commutator ripple: y = theta_dot (1 + a sin(N theta + phi))."""
    rng = ctx.rng
    N = int(rng.choice([11, 17, 23, 29]))
    phi = float(rng.uniform(0, 2 * math.pi))
    g = ctx.Y0[:, 1] * np.sin(N * ctx.Y0[:, 0] + phi)
    a = target * ctx.sigma[1] / float(np.max(np.abs(g)))
    dY = np.zeros_like(ctx.Y0)
    dY[:, 1] = a * g
    rpo = ratio_per_output(ctx.Y0 + dY, ctx.Y0, ctx.sigma)
    return {"amplitude": a, "segments": N, "phase": phi, "target_ratio": target,
            "achieved_ratio": float(rpo.max()), "ratio_per_output": dict(zip(OUTPUTS, rpo.tolist())),
            "_dY": dY}


def _reading_change(ctx, dY, **params):
    rpo = ratio_per_output(ctx.Y0 + dY, ctx.Y0, ctx.sigma)
    return dict(params, achieved_ratio=float(rpo.max()), ratio_per_output=dict(zip(OUTPUTS, rpo.tolist())),
                _dY=dY)


def gauge_clip(ctx, target):
    """The strain-gauge amplifier saturating: the reading clipped at +-L, L below the clean
    peak by `target` noise sigmas (held-out form)."""
    y = ctx.Y0[:, 2]
    L = float(np.max(np.abs(y))) - target * ctx.sigma[2]
    dY = np.zeros_like(ctx.Y0)
    dY[:, 2] = np.clip(y, -L, L) - y
    return _reading_change(ctx, dY, clip_level=L, target_ratio=target)


def channel_skew(ctx, target):
    """The strain channel sampled late by d (a multiplexed acquisition; held-out form): its
    sample k is the clean strain at t_k - d, d found by bisection for `target` sigmas."""
    pl = ctx.plant

    def change(d):
        dY = np.zeros_like(ctx.Y0)
        dY[:, 2] = pl.linear_at_times(np.maximum(ctx.t - d, 0.0))[:, 2] - ctx.Y0[:, 2]
        return dY
    d = log_bisect(lambda d: float(ratio_per_output(ctx.Y0 + change(d), ctx.Y0, ctx.sigma).max()),
                   target, 1e-7, 0.05)
    return _reading_change(ctx, change(d), skew_s=d, target_ratio=target)


def crosstalk(ctx, target):
    """The tachometer's signal picked up by the strain channel, y_strain + c theta_dot (held-out
    form), c of either sign for `target` sigmas at the largest rate."""
    sign = float(ctx.rng.choice([-1.0, 1.0]))
    c = sign * target * ctx.sigma[2] / float(np.max(np.abs(ctx.Y0[:, 1])))
    dY = np.zeros_like(ctx.Y0)
    dY[:, 2] = c * ctx.Y0[:, 1]
    return _reading_change(ctx, dY, coupling=c, target_ratio=target)


def mains_hum(ctx, target):
    """Mains pickup on the strain channel, a sin(2 pi f t + phi), f 50 or 60 Hz, a = `target`
    sigmas (held-out form; decimated to 12.8 Hz the anti-aliasing filter removes it)."""
    f = float(ctx.rng.choice([50.0, 60.0]))
    phi = float(ctx.rng.uniform(0, 2 * math.pi))
    a = target * ctx.sigma[2]
    dY = np.zeros_like(ctx.Y0)
    dY[:, 2] = a * np.sin(2 * math.pi * f * ctx.t + phi)
    return _reading_change(ctx, dY, amplitude=a, frequency_hz=f, phase=phi, target_ratio=target)


# Forms that change the clean readings directly (no simulation): each returns its parameters and
# the change `_dY` of the effect-free record.
READING_FORMS = {"time_jitter": jitter, "tach_ripple": tach_ripple, "gauge_clip": gauge_clip,
                 "channel_skew": channel_skew, "crosstalk": crosstalk, "mains_hum": mains_hum}


# ================================================================================================
# the case list

def case_specs(which):
    sp = SPLIT[which]
    specs = []
    for strength in ("weak", "medium", "strong"):
        for s in range(1, sp["A_seeds"] + 1):
            for form in sp["A"]:
                specs.append(dict(name=f"A_{form}_{strength}_s{s}", family="A", forms=[form],
                                  strength=strength, rate=128 if s % 2 == 0 else 12.8))
    levels = [0.005, 0.01, 0.02, None, None]
    for ki, nk in enumerate(sp["B"]):
        for s in range(1, sp["B_seeds"] + 1):
            spec = dict(name=f"B_{nk}_s{s}", family="B", forms=[], null_kind=nk,
                        rate=128 if (ki + s) % 2 == 0 else 12.8)
            lv = levels[(s - 1) % len(levels)]
            if lv is not None and nk != "uneven_levels":
                spec["level"] = lv
            specs.append(spec)
    for ci, form in enumerate(sp["C"]):
        for si, strength in enumerate(("medium", "strong")):
            # mains hum (50/60 Hz) is above the decimated band: read at 128 Hz both times
            rate = 128 if (ci + si) % 2 == 1 or form == "mains_hum" else 12.8
            specs.append(dict(name=f"C_{form}_{strength}", family="C", forms=[form], strength=strength,
                              rate=rate))
    for di, (f1, f2) in enumerate(sp["D"]):
        for s in range(1, sp["D_seeds"] + 1):
            specs.append(dict(name=f"D_{f1}+{f2}_s{s}", family="D", forms=[f1, f2], strength="medium",
                              rate=128 if (di + s) % 2 == 0 else 12.8))
    return specs


def entry_for(spec, truth):
    fam, forms = spec["family"], spec["forms"]
    e = {"name": spec["name"], "model": f"models/{spec['name']}.ron", "data": f"data/{spec['name']}.csv",
         "free": "cv,kp", "args": ["--decimate", "10"] if spec["rate"] == 12.8 else [],
         "rate_hz": spec["rate"], "family": fam, "strength": spec.get("strength", "-"), "forms": forms}
    if fam == "A":
        e["effect"], e["accept"] = FORM_EFFECT[forms[0]][0], list(FORM_EFFECT[forms[0]][1])
    elif fam == "B":
        e["effect"], e["accept"] = "none", ["none"]
        e["strength"] = "-"
    elif fam == "C":
        e["effect"], e["accept"] = "none", list(C_ACCEPT[forms[0]])
    else:
        a, b = FORM_EFFECT[forms[0]][0], FORM_EFFECT[forms[1]][0]
        e["effect"], e["second"] = a, b
        e["accept"] = [a, b] + sorted((set(FORM_EFFECT[forms[0]][1]) | set(FORM_EFFECT[forms[1]][1])) - {a, b})
    e["truth"] = truth
    return e


def write_csv(path, Y):
    t = np.arange(NS) / RATE
    rows = ["t,theta,theta_dot,strain"]
    for k in range(NS):
        rows.append(",".join(repr(float(v)) for v in (t[k], Y[k, 0], Y[k, 1], Y[k, 2])))
    with open(path, "w") as fh:
        fh.write("\n".join(rows) + "\n")


def _json_clean(x):
    if isinstance(x, dict):
        return {k: _json_clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_json_clean(v) for v in x]
    if isinstance(x, (np.floating,)):
        return float(x)
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, np.ndarray):
        return _json_clean(x.tolist())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    return x


def run_one(args):
    spec, seed, out, fixture = args
    t0 = time.time()
    truth, Y, ctx = build_case(spec, seed)
    write_csv(os.path.join(out, "data", spec["name"] + ".csv"), Y)
    with open(os.path.join(out, "models", spec["name"] + ".ron"), "w") as fh:
        fh.write(model_text(fixture, spec["name"], truth["theta0"]))
    truth["generation_s"] = time.time() - t0
    return _json_clean(entry_for(spec, truth))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--set", choices=["dev", "held"], required=True)
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--only", default=None, help="only cases whose name contains one of these (comma-separated)")
    ap.add_argument("--list", action="store_true", help="list the cases and exit")
    a = ap.parse_args()
    seed = DEFAULT_SEED[a.set] if a.seed is None else a.seed
    specs = case_specs(a.set)
    if a.only:
        specs = [s for s in specs if any(o in s["name"] for o in a.only.split(","))]
    if a.list:
        for s in specs:
            print(s["name"], s["family"], s.get("strength", "-"), s["rate"])
        print(len(specs), "cases")
        return
    repo = os.path.realpath(os.path.join(HERE, "..", ".."))
    out = os.path.realpath(a.out)
    if out == repo or out.startswith(repo + os.sep):
        sys.exit("refusing to write generated data inside the repository; use e.g. /tmp/study-dev")
    fixture = check_fixture()
    os.makedirs(os.path.join(out, "models"), exist_ok=True)
    os.makedirs(os.path.join(out, "data"), exist_ok=True)
    t0 = time.time()
    jobs = [(s, seed, out, fixture) for s in specs]
    cases = []
    if a.jobs > 1:
        from multiprocessing import Pool
        with Pool(a.jobs) as pool:
            for i, c in enumerate(pool.imap(run_one, jobs)):
                cases.append(c)
                _progress(i, len(jobs), c, t0)
    else:
        for i, j in enumerate(jobs):
            c = run_one(j)
            cases.append(c)
            _progress(i, len(jobs), c, t0)
    doc = {"set": a.set, "seed": seed, "generator": "studies/diagnose/generate.py",
           "rate_hz": RATE, "duration_s": DURATION, "split": SPLIT[a.set], "cases": cases}
    with open(os.path.join(out, "truth.json"), "w") as fh:
        json.dump(_json_clean(doc), fh, indent=1)
    print(f"wrote {len(cases)} cases to {out} in {time.time() - t0:.0f} s")


def _progress(i, n, c, t0):
    eff = c["truth"]["effects"]
    r = ", ".join(f"{e['form']} {e.get('achieved_ratio', 0):.2f}/{e.get('target_ratio') or '-'}"
                  + (" CAPPED" if e.get("capped") else "") for e in eff)
    print(f"[{i + 1}/{n} {time.time() - t0:6.0f}s] {c['name']:<44} {c['truth']['generation_s']:5.1f}s  {r}",
          flush=True)


if __name__ == "__main__":
    main()

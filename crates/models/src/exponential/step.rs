//! The kernel of the exponential integrator, for any model ẋ = A x + G f(x),
//! y = C x + H f(x) with a few nonlinear forces f (module docs in [`super`]).

use crate::ode::NonlinearError;
use expm::Response;
use faer::Mat;

/// The most substeps one simulation may take.
const MAX_SUBSTEPS: f64 = 1e8;

/// The linear parts of a model at P, or their derivatives with respect to one parameter.
pub(crate) struct Linear {
    /// A (n × n).
    pub a: Mat<f64>,
    /// G (n × m): how the forces enter the state equation.
    pub g: Mat<f64>,
    /// C (p × n).
    pub c: Mat<f64>,
    /// H (p × m): how the forces enter the outputs, if they do.
    pub h: Option<Mat<f64>>,
    /// x(0).
    pub x0: Vec<f64>,
}

/// The forces at a state with their derivatives, in flat buffers reused from step to step.
pub(crate) struct Forces {
    /// f (m).
    pub value: Vec<f64>,
    /// The states the forces depend on.
    pub states: Vec<usize>,
    /// ∂f/∂x_k (m each), one block per entry of `states`.
    pub by_state: Vec<f64>,
    /// ∂f/∂P_i (m each), one block per free parameter.
    pub by_parameter: Vec<f64>,
}

impl Forces {
    fn new(m: usize, j: usize) -> Self {
        Self { value: vec![0.0; m], states: Vec::new(), by_state: Vec::new(), by_parameter: vec![0.0; m * j] }
    }

    /// Sizes the buffers for m forces and j parameters, derivatives zeroed, no states.
    pub fn reset(&mut self, m: usize, j: usize) {
        self.value.resize(m, 0.0);
        self.states.clear();
        self.by_state.clear();
        self.by_parameter.clear();
        self.by_parameter.resize(m * j, 0.0);
    }

    /// f_x v + f_P_i into `out`.
    #[inline(always)]
    fn directional(&self, v: &[f64], i: usize, out: &mut [f64]) {
        match out.len() {
            1 => self.directional_fixed::<1>(v, i, out),
            2 => self.directional_fixed::<2>(v, i, out),
            _ => self.directional_any(v, i, out),
        }
    }

    #[inline(always)]
    fn directional_fixed<const M: usize>(&self, v: &[f64], i: usize, out: &mut [f64]) {
        let mut acc: [f64; M] = self.by_parameter[i * M..(i + 1) * M].try_into().expect("M entries");
        for (k, d) in self.states.iter().zip(self.by_state.chunks_exact(M)) {
            for q in 0..M {
                acc[q] += d[q] * v[*k];
            }
        }
        out.copy_from_slice(&acc);
    }

    fn directional_any(&self, v: &[f64], i: usize, out: &mut [f64]) {
        let m = out.len();
        out.copy_from_slice(&self.by_parameter[i * m..(i + 1) * m]);
        for (k, d) in self.states.iter().zip(self.by_state.chunks_exact(m)) {
            for (o, dk) in out.iter_mut().zip(d) {
                *o += dk * v[*k];
            }
        }
    }
}

/// A model's nonlinear forces.
pub(crate) trait Forcing {
    /// f at time `t` (the model's, from x(0)) and state `x` into `out` (with ∂f/∂x and ∂f/∂P_i
    /// if `with_derivatives`; `out` is reused).
    fn at(&mut self, t: f64, x: &[f64], with_derivatives: bool, out: &mut Forces);

    /// The sample interval [t_k, t_{k+1}] the next calls of [`at`](Self::at) fall in (`None`
    /// before the first sample): a forcing driven by measured inputs holds them by it, so that
    /// a step ending at t_{k+1} still sees the interval's u_k.
    fn interval(&mut self, _k: Option<usize>) {}
}

/// Row-major small dense matrix.
fn flat(m: &Mat<f64>) -> Vec<f64> {
    (0..m.nrows() * m.ncols()).map(|k| m[(k / m.ncols(), k % m.ncols())]).collect()
}

/// Column-major small dense matrix (for [`square_mul_add`]).
fn flat_columns(m: &Mat<f64>) -> Vec<f64> {
    (0..m.nrows() * m.ncols()).map(|k| m[(k % m.nrows(), k / m.nrows())]).collect()
}

/// y += M x for an n × n matrix stored column by column (`flat_columns`), n = `y.len()`.
///
/// Each row's sum is accumulated column by column from −0.0, the very sums in the very order
/// of a row's dot product (`Iterator::sum`), so the bits are those of the row-major kernel —
/// but the rows are independent lanes that run side by side in vector registers, where a
/// row's dot product is one dependent chain of additions. The state dimensions of the models
/// (two per mode and rigid body) are unrolled at compile time so the sums stay in registers.
fn square_mul_add(m: &[f64], x: &[f64], y: &mut [f64]) {
    match y.len() {
        2 => square_mul_add_fixed::<2>(m, x, y),
        4 => square_mul_add_fixed::<4>(m, x, y),
        6 => square_mul_add_fixed::<6>(m, x, y),
        8 => square_mul_add_fixed::<8>(m, x, y),
        10 => square_mul_add_fixed::<10>(m, x, y),
        12 => square_mul_add_fixed::<12>(m, x, y),
        14 => square_mul_add_fixed::<14>(m, x, y),
        16 => square_mul_add_fixed::<16>(m, x, y),
        n => {
            for (r, yr) in y.iter_mut().enumerate() {
                *yr += (0..n).map(|c| m[c * n + r] * x[c]).sum::<f64>();
            }
        }
    }
}

/// [`square_mul_add`] for N states known at compile time.
#[inline(always)]
fn square_mul_add_fixed<const N: usize>(m: &[f64], x: &[f64], y: &mut [f64]) {
    let mut acc = [-0.0_f64; N];
    for (column, xc) in m.chunks_exact(N).zip(&x[..N]) {
        let column: &[f64; N] = column.try_into().expect("N entries");
        for r in 0..N {
            acc[r] += column[r] * xc;
        }
    }
    for (yr, a) in y.iter_mut().zip(acc) {
        *yr += a;
    }
}

/// y += M x for a row-major r × c matrix (the few force columns unrolled: the gains G are
/// applied four times per substep and dominate the kernel's time).
#[inline(always)]
fn mul_add(m: &[f64], cols: usize, x: &[f64], y: &mut [f64]) {
    match cols {
        1 => mul_add_fixed::<1>(m, x, y),
        2 => mul_add_fixed::<2>(m, x, y),
        3 => mul_add_fixed::<3>(m, x, y),
        _ => {
            for (yr, row) in y.iter_mut().zip(m.chunks_exact(cols)) {
                *yr += row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
            }
        }
    }
}

/// [`mul_add`] for C columns known at compile time (the same sums in the same order).
#[inline(always)]
fn mul_add_fixed<const C: usize>(m: &[f64], x: &[f64], y: &mut [f64]) {
    let x: &[f64; C] = x[..C].try_into().expect("C entries");
    for (yr, row) in y.iter_mut().zip(m.chunks_exact(C)) {
        let mut acc = 0.0;
        for c in 0..C {
            acc += row[c] * x[c];
        }
        *yr += acc;
    }
}

/// The buffers of one step, allocated once per simulation.
struct Workspace {
    phi_x: Vec<f64>,
    c: Vec<f64>,
    u: Vec<f64>,
    ua: Vec<f64>,
    a: Vec<f64>,
    da: Vec<f64>,
    t_x: Forces,
    t_a: Forces,
}

impl Workspace {
    fn new(n: usize, m: usize, j: usize) -> Self {
        Self {
            phi_x: vec![0.0; n],
            c: vec![0.0; n * j],
            u: vec![0.0; m * j],
            ua: vec![0.0; m],
            a: vec![0.0; n],
            da: vec![0.0; n * j],
            t_x: Forces::new(m, j),
            t_a: Forces::new(m, j),
        }
    }
}

/// One step's matrices, flattened: Φ and ∂Φ/∂P_i column by column ([`square_mul_add`]), the
/// force gains row by row ([`mul_add`]).
struct Step {
    /// The step's length \[s\].
    h: f64,
    m: usize,
    phi: Vec<f64>,
    now: Vec<f64>,
    next: Vec<f64>,
    zoh: Vec<f64>,
    d_phi: Vec<Vec<f64>>,
    d_now: Vec<Vec<f64>>,
    d_next: Vec<Vec<f64>>,
    d_zoh: Vec<Vec<f64>>,
    /// Whether P_i moves Φ or the force gains at all (a force law's own constants do not):
    /// where it does not, their products with zero are skipped.
    moves: Vec<bool>,
}

impl Step {
    fn new(lin: &Linear, d: &[Linear], h: f64) -> Result<Self, NonlinearError> {
        let das: Vec<_> = d.iter().map(|m| m.a.as_ref()).collect();
        let dbs: Vec<_> = d.iter().map(|m| m.g.as_ref()).collect();
        let g = expm::step_gains(lin.a.as_ref(), &das, lin.g.as_ref(), &dbs, h)
            .map_err(|e| NonlinearError::Solver(format!("the step's exponential: {e}")))?;
        let zoh = &g.now + &g.next;
        Ok(Self {
            h,
            m: lin.g.ncols(),
            phi: flat_columns(&g.phi),
            now: flat(&g.now),
            next: flat(&g.next),
            zoh: flat(&zoh),
            d_phi: g.d_phi.iter().map(flat_columns).collect(),
            d_zoh: g.d_now.iter().zip(&g.d_next).map(|(a, b)| flat(&(a + b))).collect(),
            d_now: g.d_now.iter().map(flat).collect(),
            d_next: g.d_next.iter().map(flat).collect(),
            moves: (0..d.len())
                .map(|i| [&g.d_phi[i], &g.d_now[i], &g.d_next[i]].iter().any(|m| m.norm_max() != 0.0))
                .collect(),
        })
    }

    /// One step from time `t` of x (length n) and the sensitivities s (j columns of length n,
    /// stacked).
    fn advance(
        &self,
        t: f64,
        x: &mut [f64],
        s: &mut [f64],
        forcing: &mut dyn Forcing,
        sensitivities: bool,
        w: &mut Workspace,
    ) {
        let n = x.len();
        let m = self.m;
        let j = if sensitivities { s.len() / n } else { 0 };
        let Workspace { phi_x, c, u, ua, a, da, t_x, t_a } = w;
        forcing.at(t, x, sensitivities, t_x);
        // c_i = Φ s_i + Φ_i x (shared by predictor and corrector), Φ x.
        phi_x.fill(0.0);
        square_mul_add(&self.phi, x, phi_x);
        c[..n * j].fill(0.0);
        for i in 0..j {
            let (si, ci) = (&s[i * n..(i + 1) * n], &mut c[i * n..(i + 1) * n]);
            square_mul_add(&self.phi, si, ci);
            if self.moves[i] {
                square_mul_add(&self.d_phi[i], x, ci);
            }
            t_x.directional(si, i, &mut u[i * m..(i + 1) * m]);
        }
        // Predictor a = Φx + G f(x) and its derivatives.
        a.copy_from_slice(phi_x);
        mul_add(&self.zoh, m, &t_x.value, a);
        da[..n * j].copy_from_slice(&c[..n * j]);
        for i in 0..j {
            let dai = &mut da[i * n..(i + 1) * n];
            mul_add(&self.zoh, m, &u[i * m..(i + 1) * m], dai);
            if self.moves[i] {
                mul_add(&self.d_zoh[i], m, &t_x.value, dai);
            }
        }
        forcing.at(t + self.h, a, sensitivities, t_a);
        // Corrector.
        x.copy_from_slice(phi_x);
        mul_add(&self.now, m, &t_x.value, x);
        mul_add(&self.next, m, &t_a.value, x);
        for i in 0..j {
            let si = &mut s[i * n..(i + 1) * n];
            si.copy_from_slice(&c[i * n..(i + 1) * n]);
            mul_add(&self.now, m, &u[i * m..(i + 1) * m], si);
            if self.moves[i] {
                mul_add(&self.d_now[i], m, &t_x.value, si);
            }
            t_a.directional(&da[i * n..(i + 1) * n], i, ua);
            mul_add(&self.next, m, ua, si);
            if self.moves[i] {
                mul_add(&self.d_next[i], m, &t_a.value, si);
            }
        }
    }
}

/// Simulates `lin` with `forcing` from x(0) at the model's t = 0: fills `out` (K × p outputs,
/// (K·p) × j sensitivities, j = `d.len()` or none if `out` has no sensitivity columns) at
/// t_k = start + k·h, with substeps no longer than `max_step`.
pub(crate) fn integrate(
    lin: &Linear,
    d: &[Linear],
    forcing: &mut dyn Forcing,
    start: f64,
    h: f64,
    max_step: f64,
    out: &mut Response,
) -> Result<(), NonlinearError> {
    if !(h.is_finite() && h > 0.0 && start.is_finite() && start >= 0.0) {
        return Err(NonlinearError::Solver(format!("invalid grid: start {start} s, interval {h} s")));
    }
    if !(max_step.is_finite() && max_step > 0.0) {
        return Err(NonlinearError::Solver(format!("invalid substep {max_step} s")));
    }
    let n = lin.a.nrows();
    let m = lin.g.ncols();
    let wanted = out.sensitivities.ncols() == d.len() && !d.is_empty();
    let d = if wanted { d } else { &[] };
    let j = d.len();
    // Every substep of the record, counted before any is taken: a record too long or too
    // finely stepped ends in an error, not in hours of stepping.
    let per_sample = (h / max_step).ceil().max(1.0);
    let total = per_sample * out.outputs.nrows() as f64 + (start / max_step).ceil();
    if total > MAX_SUBSTEPS {
        return Err(NonlinearError::Solver(format!(
            "{total:.3e} substeps of at most {max_step} s for this record, beyond the {MAX_SUBSTEPS:.0e} budget; \
             shorten the record or lengthen the substep"
        )));
    }
    let substeps = per_sample as usize;
    let step = Step::new(lin, d, h / substeps as f64)?;
    let mut work = Workspace::new(n, m, j);
    let mut x = lin.x0.clone();
    let mut s: Vec<f64> = (0..j).flat_map(|i| d[i].x0.iter().copied()).collect();
    // From the model's t = 0 to the first sample: whole substeps, then the remainder.
    forcing.interval(None);
    if start > 0.0 {
        let sub = h / substeps as f64;
        let whole = (start / sub).floor() as usize;
        for i in 0..whole {
            step.advance(i as f64 * sub, &mut x, &mut s, forcing, wanted, &mut work);
        }
        let rest = start - whole as f64 * sub;
        if rest > 1e-12 * sub {
            Step::new(lin, d, rest)?.advance(whole as f64 * sub, &mut x, &mut s, forcing, wanted, &mut work);
        }
    }
    // C and ∂C/∂P_i row by row (each output's sums in the order of its dot product).
    let c = flat(&lin.c);
    let dc: Vec<Vec<f64>> = d.iter().map(|di| flat(&di.c)).collect();
    let p_out = lin.c.nrows();
    let k = out.outputs.nrows();
    let mut feed = Forces::new(m, j);
    let mut du = vec![0.0; m];
    for sample in 0..k {
        forcing.interval(Some(sample));
        if lin.h.is_some() {
            forcing.at(start + sample as f64 * h, &x, wanted, &mut feed);
        }
        for o in 0..p_out {
            let row = &c[o * n..(o + 1) * n];
            let mut y: f64 = row.iter().zip(&x).map(|(c, x)| c * x).sum();
            if let Some(hm) = &lin.h {
                y += (0..m).map(|q| hm[(o, q)] * feed.value[q]).sum::<f64>();
            }
            out.outputs[(sample, o)] = y;
            for i in 0..j {
                let si = &s[i * n..(i + 1) * n];
                let d_row = &dc[i][o * n..(o + 1) * n];
                let mut dy: f64 = row
                    .iter()
                    .zip(si)
                    .zip(d_row.iter().zip(&x))
                    .map(|((c, s), (dc, x))| c * s + dc * x)
                    .sum();
                if let (Some(hm), Some(dh)) = (&lin.h, &d[i].h) {
                    feed.directional(si, i, &mut du);
                    dy += (0..m).map(|q| hm[(o, q)] * du[q] + dh[(o, q)] * feed.value[q]).sum::<f64>();
                }
                out.sensitivities[(sample * p_out + o, i)] = dy;
            }
        }
        if sample + 1 < k {
            let at = start + sample as f64 * h;
            for i in 0..substeps {
                step.advance(at + i as f64 * step.h, &mut x, &mut s, forcing, wanted, &mut work);
            }
            if !x.iter().all(|v| v.is_finite()) {
                return Err(NonlinearError::Solver(format!(
                    "the response left the finite numbers at t = {} s: an effect is too strong for the record",
                    start + (sample + 1) as f64 * h
                )));
            }
        }
    }
    if !(out.outputs.as_ref().is_all_finite() && out.sensitivities.as_ref().is_all_finite()) {
        return Err(NonlinearError::Solver("the sensitivities left the finite numbers".into()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The column-major kernel gives the bits of a row's dot product (`Iterator::sum`), for
    /// the unrolled state dimensions and the general one alike.
    #[test]
    fn square_kernel_matches_the_row_dot_products_bit_for_bit() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        for n in 1..=19 {
            let m = Mat::<f64>::from_fn(n, n, |_, _| rng.random_range(-2.0..2.0));
            let x: Vec<f64> = (0..n).map(|_| rng.random_range(-3.0..3.0)).collect();
            let y0: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
            let want: Vec<f64> =
                (0..n).map(|r| y0[r] + (0..n).map(|c| m[(r, c)] * x[c]).sum::<f64>()).collect();
            let mut y = y0.clone();
            square_mul_add(&flat_columns(&m), &x, &mut y);
            for r in 0..n {
                assert_eq!(y[r].to_bits(), want[r].to_bits(), "n = {n}, row {r}");
            }
        }
    }
}

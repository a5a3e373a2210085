//! Fits under AR(1) noise (`Experiment::with_noise_correlation`): the error is the innovations'
//! weighted sum of squares, its sensitivities the same whitening of the model's, and the fit is
//! generalised least squares; and under noise of any spectrum given by its linear predictors
//! (`Experiment::with_noise_predictors`).

use faer::Mat;
use mem::{DerivativeCheck, Experiment, Fit, LinearResponse, Measurement, NoisePredictor, Problem};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use test_problems::{ModalFamily, simulate_measurement};

/// Stationary AR(1) noise of lag-one coefficient `rho` and standard deviation `sigma[o]`
/// added to each output of `clean`.
fn with_ar1(clean: &Measurement, rho: f64, sigma: &[f64], seed: u64) -> Measurement {
    let mut r = rand::rngs::StdRng::seed_from_u64(seed);
    let (k, p) = (clean.n_samples(), clean.n_outputs());
    let mut values = clean.values().clone();
    for o in 0..p {
        let mut e: f64 = StandardNormal.sample(&mut r);
        for t in 0..k {
            if t > 0 {
                let u: f64 = StandardNormal.sample(&mut r);
                e = rho * e + (1.0 - rho * rho).sqrt() * u;
            }
            values[(t, o)] += sigma[o] * e;
        }
    }
    Measurement::new(clean.names().to_vec(), clean.start(), clean.interval(), values).unwrap()
}

/// The record less the model's simulated outputs at `p` (K × p).
fn residual_at(model: &LinearResponse<ModalFamily>, data: &Measurement, p: &[f64]) -> Mat<f64> {
    let simulated = Measurement::simulate(model, p, data.interval(), data.n_samples()).unwrap();
    Mat::from_fn(data.n_samples(), data.n_outputs(), |k, o| {
        data.values()[(k, o)] - simulated.values()[(k, o)]
    })
}

/// The innovations' weighted sum of squares Σ_o w_o² Σ_k s_k u_k², u the AR(1) innovations
/// of the residual on segments of consecutive samples of positive weight — written out
/// separately from the crate's whitening.
fn innovations_error(residual: &Mat<f64>, rho: &[f64], weights: &[f64], samples: &[f64]) -> f64 {
    let mut total = 0.0;
    for o in 0..residual.ncols() {
        for k in 0..residual.nrows() {
            let e = residual[(k, o)];
            let u = if k == 0 || samples[k - 1] == 0.0 {
                (1.0 - rho[o] * rho[o]).sqrt() * e
            } else {
                e - rho[o] * residual[(k - 1, o)]
            };
            total += (weights[o] * samples[k] * u).powi(2);
        }
    }
    total
}

#[test]
fn the_error_is_the_innovations_sum_of_squares_on_each_segment() {
    let family = ModalFamily::new(3, 3, 2, 11);
    let model = LinearResponse(family.clone());
    let data = simulate_measurement(&model, &family.p_nominal, 0.05, 300, 0.02, 5);
    let p: Vec<f64> = family.p_nominal.iter().map(|v| v * 1.03).collect();
    let rho = vec![0.8, -0.3];
    let weights = vec![2.0, 0.5];
    // Alternate blocks of 25 samples, as the diagnosis's folds.
    let samples: Vec<f64> =
        (0..data.n_samples()).map(|k| if (k / 25) % 2 == 0 { 1.0 } else { 0.0 }).collect();
    let mut experiment = Experiment::new(&model, &data).with_sample_weights(samples.clone());
    experiment.weights = weights.clone();
    let experiment = experiment.with_noise_correlation(rho.clone());
    let once = Fit::new().with_max_iterations(1).unwrap().with_derivative_check(DerivativeCheck::Skip);
    let report = once.run(&Problem::unnamed(vec![experiment], &p).unwrap()).unwrap();
    let residual = residual_at(&model, &data, &p);
    let expected = innovations_error(&residual, &rho, &weights, &samples);
    let got = report.error_history[0];
    assert!((got / expected - 1.0).abs() < 1e-10, "{got} against {expected}");
    // White noise (ρ = 0) is the plain weighted error.
    let white = innovations_error(&residual, &[0.0, 0.0], &weights, &samples);
    assert!((expected / white - 1.0).abs() > 0.05, "the whitening changes the error here");
}

#[test]
fn the_whitened_sensitivities_agree_with_finite_differences_of_the_whitened_error() {
    let family = ModalFamily::new(3, 4, 2, 12);
    let model = LinearResponse(family.clone());
    let data = simulate_measurement(&model, &family.p_nominal, 0.05, 300, 0.01, 6);
    let start: Vec<f64> = family.p_nominal.iter().map(|v| v * 0.97).collect();
    let experiment = Experiment::normalized(&model, &data).with_noise_correlation(vec![0.9, 0.5]);
    // The fit's derivative check compares the analytic S with central differences of the
    // residual it minimises, here the whitened one: an error unless they agree.
    let fit = Fit::new().with_max_iterations(2).unwrap().with_derivative_check(DerivativeCheck::Error);
    fit.run(&Problem::unnamed(vec![experiment], &start).unwrap()).expect("the derivative check passes");
}

#[test]
fn the_whitened_fit_maximises_the_ar1_likelihood_the_plain_fit_does_not() {
    // Under AR(1) noise of ρ = 0.95 the plain fit minimises Σe², the whitened one the
    // innovations' Σu² (the AR(1) likelihood at fixed ρ). Each must end lower on its own
    // criterion than the other's estimate does; the likelihood is written out in this test.
    // (For a free decay, sums of damped sinusoids, the two estimates are about equally precise —
    // ordinary least squares is asymptotically efficient for such regressors (Grenander 1954) —
    // so what the whitening buys is a fit by the same likelihood a comparison scores.)
    let family = ModalFamily::new(2, 4, 2, 13);
    let model = LinearResponse(family.clone());
    let truth = family.p_nominal.clone();
    let clean = simulate_measurement(&model, &truth, 0.05, 400, 0.0, 1);
    let sigma = vec![0.02 * clean.values().norm_max(); 2];
    let rho = vec![0.95; 2];
    let data = with_ar1(&clean, rho[0], &sigma, 100);
    let start: Vec<f64> = truth.iter().map(|v| v * 1.02).collect();
    let fit = Fit::new().with_derivative_check(DerivativeCheck::Skip);
    let plain = fit.run(&Problem::unnamed(vec![Experiment::new(&model, &data)], &start).unwrap()).unwrap();
    let whitened = Experiment::new(&model, &data).with_noise_correlation(rho.clone());
    let whitened = fit.run(&Problem::unnamed(vec![whitened], &start).unwrap()).unwrap();
    let residual = |p: &[f64]| residual_at(&model, &data, p);
    let ones = vec![1.0; data.n_samples()];
    let innovations = |p: &[f64]| innovations_error(&residual(p), &rho, &[1.0, 1.0], &ones);
    let squares = |p: &[f64]| residual(p).squared_norm_l2();
    assert!(innovations(&whitened.parameters) < innovations(&plain.parameters));
    assert!(squares(&plain.parameters) < squares(&whitened.parameters));
    assert!(
        ((whitened.error_history.last().unwrap()) / innovations(&whitened.parameters) - 1.0).abs() < 1e-9
    );
}

#[test]
fn a_correlation_outside_the_unit_interval_is_rejected() {
    let family = ModalFamily::new(2, 2, 1, 3);
    let model = LinearResponse(family.clone());
    let data = simulate_measurement(&model, &family.p_nominal, 0.1, 50, 0.0, 1);
    for bad in [1.0, -1.5, f64::NAN] {
        let experiment = Experiment::new(&model, &data).with_noise_correlation(vec![bad]);
        let error = Problem::unnamed(vec![experiment], &family.p_nominal).err().unwrap();
        assert!(error.to_string().contains("noise correlation"), "{error}");
    }
    let experiment = Experiment::new(&model, &data).with_noise_correlation(vec![0.5, 0.5]);
    assert!(Problem::unnamed(vec![experiment], &family.p_nominal).is_err());
}

/// An AR(q) predictor's error: per output the scaled innovations of the residual on segments
/// of consecutive samples of positive weight, from the Yule–Walker coefficients of each order
/// solved here by a dense solve (not the crate's Levinson–Durbin recursion).
fn predicted_error(residual: &Mat<f64>, gamma: &[f64], samples: &[f64]) -> f64 {
    use faer::linalg::solvers::Solve;
    let q = gamma.len() - 1;
    // Order m: Γ_m a = (γ₁…γ_m), v_m = γ₀ − aᵀ(γ₁…γ_m).
    let order = |m: usize| -> (Vec<f64>, f64) {
        if m == 0 {
            return (Vec::new(), gamma[0]);
        }
        let g = Mat::<f64>::from_fn(m, m, |i, j| gamma[i.abs_diff(j)]);
        let b = Mat::<f64>::from_fn(m, 1, |i, _| gamma[i + 1]);
        let a = g.llt(faer::Side::Lower).expect("positive definite").solve(&b);
        let a: Vec<f64> = (0..m).map(|i| a[(i, 0)]).collect();
        let v = gamma[0] - a.iter().zip(&gamma[1..]).map(|(x, y)| x * y).sum::<f64>();
        (a, v)
    };
    let orders: Vec<(Vec<f64>, f64)> = (0..=q).map(order).collect();
    let mut total = 0.0;
    for o in 0..residual.ncols() {
        let mut depth = 0usize;
        for k in 0..residual.nrows() {
            if k > 0 && samples[k - 1] == 0.0 {
                depth = 0;
            }
            let (a, v) = &orders[depth];
            let predicted: f64 = a.iter().enumerate().map(|(i, c)| c * residual[(k - 1 - i, o)]).sum();
            let u = (residual[(k, o)] - predicted) * (orders[q].1 / v).sqrt();
            total += (samples[k] * u).powi(2);
            depth = (depth + 1).min(q);
        }
    }
    total
}

#[test]
fn under_a_coloured_predictor_the_error_is_its_innovations_sum_of_squares() {
    let family = ModalFamily::new(3, 3, 2, 15);
    let model = LinearResponse(family.clone());
    let data = simulate_measurement(&model, &family.p_nominal, 0.05, 300, 0.02, 8);
    let p: Vec<f64> = family.p_nominal.iter().map(|v| v * 0.98).collect();
    // A resonant autocovariance: a damped cosine, γ_l = 0.9^l cos(0.6 l).
    let gamma: Vec<f64> = (0..=6).map(|l| 0.9_f64.powi(l) * (0.6 * l as f64).cos()).collect();
    let predictor = NoisePredictor::of_autocovariance(&gamma).expect("positive definite");
    let samples: Vec<f64> =
        (0..data.n_samples()).map(|k| if (k / 40) % 2 == 1 { 1.0 } else { 0.0 }).collect();
    let experiment = Experiment::new(&model, &data)
        .with_sample_weights(samples.clone())
        .with_noise_predictors(vec![predictor.clone(), predictor]);
    let once = Fit::new().with_max_iterations(1).unwrap().with_derivative_check(DerivativeCheck::Skip);
    let report = once.run(&Problem::unnamed(vec![experiment], &p).unwrap()).unwrap();
    let residual = residual_at(&model, &data, &p);
    let expected = predicted_error(&residual, &gamma, &samples);
    let got = report.error_history[0];
    assert!((got / expected - 1.0).abs() < 1e-10, "{got} against {expected}");
    // The analytic S, whitened alike, agrees with central differences of that error.
    let experiment = Experiment::normalized(&model, &data).with_noise_predictors(vec![
        NoisePredictor::of_autocovariance(&gamma).unwrap(),
        NoisePredictor::of_autocovariance(&gamma[..3]).unwrap(),
    ]);
    let fit = Fit::new().with_max_iterations(2).unwrap().with_derivative_check(DerivativeCheck::Error);
    fit.run(&Problem::unnamed(vec![experiment], &p).unwrap()).expect("the derivative check passes");
}

#[test]
fn predictors_must_be_one_per_output_and_not_beside_a_correlation() {
    let family = ModalFamily::new(2, 2, 2, 3);
    let model = LinearResponse(family.clone());
    let data = simulate_measurement(&model, &family.p_nominal, 0.1, 50, 0.0, 1);
    let one = || NoisePredictor::ar1(0.5).unwrap();
    let short = Experiment::new(&model, &data).with_noise_predictors(vec![one()]);
    let error = Problem::unnamed(vec![short], &family.p_nominal).err().unwrap();
    assert!(error.to_string().contains("one noise predictor per output"), "{error}");
    let both = Experiment::new(&model, &data)
        .with_noise_predictors(vec![one(), one()])
        .with_noise_correlation(vec![0.5, 0.5]);
    let error = Problem::unnamed(vec![both], &family.p_nominal).err().unwrap();
    assert!(error.to_string().contains("not both"), "{error}");
}

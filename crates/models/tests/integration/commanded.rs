//! A slewing model driven by a commanded hub angle θ_ref (`inputs: [ReferenceAngle]`, Eq. 17):
//! by linearity, a step of θ_ref from rest is θ_ref plus the free decay from θ(0) = −θ_ref; its
//! sensitivities (through B = k_s M⁻¹ servo vector, which depends on K_p) match central
//! differences; and a fit recovers C_v and K_p from a commanded slew.

use mem::{Hold, Measurement, sampled_response};
use models::Model;
use plant::SlewingModel;

fn model(hub_angle: f64, driven: bool) -> Model {
    let mut text = plant::PAPER_MODEL_RON.replace("hub_angle: 0.5,", &format!("hub_angle: {hub_angle},"));
    if driven {
        text = text.replace("    bounds: {", "    inputs: [ReferenceAngle],\n    bounds: {");
    }
    assert!(text.contains(&format!("hub_angle: {hub_angle},")));
    Model::Slewing(SlewingModel::from_ron(&text, "slew.ron").unwrap())
}

/// A record of zeros for the outputs with the command `reference(t)`.
fn command(k: usize, h: f64, reference: impl Fn(f64) -> f64) -> Measurement {
    let names = ["theta", "theta_dot", "strain", "theta_ref"].map(String::from).to_vec();
    let values = faer::Mat::from_fn(k, 4, |r, c| if c == 3 { reference(r as f64 * h) } else { 0.0 });
    Measurement::new(names, 0.0, h, values).unwrap().with_inputs(&["theta_ref"], Hold::Zero).unwrap()
}

#[test]
fn a_step_command_is_the_shifted_free_decay() {
    let (k, h) = (385, 1.0 / 12.8);
    let driven = model(0.0, true).response(&[]).unwrap();
    let step = sampled_response(driven.as_ref(), &command(k, h, |_| 0.5), &[]).unwrap().outputs;
    let free = model(-0.5, false).response(&[]).unwrap();
    let mut decay = expm::Response::zeros(k, 3, 0);
    free.respond(&[], &mem::Grid::free(h), &mut decay).unwrap();
    for r in 0..k {
        assert!((step[(r, 0)] - (decay.outputs[(r, 0)] + 0.5)).abs() < 1e-12, "theta at {r}");
        assert!((step[(r, 1)] - decay.outputs[(r, 1)]).abs() < 1e-12, "theta_dot at {r}");
        assert!((step[(r, 2)] - decay.outputs[(r, 2)]).abs() < 1e-9, "strain at {r}");
    }
}

#[test]
fn commanded_sensitivities_match_central_differences() {
    let (k, h) = (200, 1.0 / 12.8);
    let data = command(k, h, |t| 0.4 * (0.7 * t).sin());
    let response = model(0.0, true).response(&["cv", "kp"]).unwrap();
    let p = [0.08, 7.5];
    let exact = sampled_response(response.as_ref(), &data, &p).unwrap();
    for i in 0..2 {
        let step = 1e-6 * p[i];
        let at = |sign: f64| {
            let mut q = p;
            q[i] += sign * step;
            sampled_response(response.as_ref(), &data, &q).unwrap().outputs
        };
        let (plus, minus) = (at(1.0), at(-1.0));
        let scale =
            (0..exact.sensitivities.nrows()).map(|r| exact.sensitivities[(r, i)].abs()).fold(0.0, f64::max);
        for r in 0..k {
            for o in 0..3 {
                let fd = (plus[(r, o)] - minus[(r, o)]) / (2.0 * step);
                assert!(
                    (fd - exact.sensitivities[(r * 3 + o, i)]).abs() < 1e-6 * scale,
                    "P{i} sample {r} output {o}"
                );
            }
        }
    }
}

#[test]
fn a_commanded_slew_fits_back_its_truth() {
    let (k, h) = (385, 1.0 / 12.8);
    let reference = |t: f64| 0.5 * (0.6 * t).sin() + if t > 10.0 { 0.3 } else { 0.0 };
    let command = command(k, h, reference);
    let truth = model(0.0, true).response(&["cv", "kp"]).unwrap();
    let clean = sampled_response(truth.as_ref(), &command, &[0.2, 7.0]).unwrap().outputs;
    let mut r = test_problems::rng(11);
    let sigma = [1e-3, 3e-3, 0.2];
    let values = faer::Mat::from_fn(k, 4, |t, c| {
        if c == 3 {
            reference(t as f64 * h)
        } else {
            clean[(t, c)] + sigma[c] * rand::Rng::sample::<f64, _>(&mut r, rand_distr::StandardNormal)
        }
    });
    let names = ["theta", "theta_dot", "strain", "theta_ref"].map(String::from).to_vec();
    let data =
        Measurement::new(names, 0.0, h, values).unwrap().with_inputs(&["theta_ref"], Hold::Zero).unwrap();
    let outcome = models::fit(&model(0.0, true), &data, &models::FitRequest::new(&["cv", "kp"])).unwrap();
    for (i, truth) in [0.2, 7.0].into_iter().enumerate() {
        let value = outcome.report.parameters[i];
        let se = outcome.report.std_error(i).unwrap();
        assert!(
            (value - truth).abs() < 3.0 * se && (value / truth - 1.0).abs() < 0.02,
            "P{i}: {value} ± {se}"
        );
    }
}

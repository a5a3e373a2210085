//! Runs paper-size Gauss–Newton steps in a loop, for a profiler (development aid).
use memid_benches::{SIZES, family};
fn main() {
    let size = SIZES[0];
    let fam = family(size);
    let model = mem::LinearResponse(fam.clone());
    let data = test_problems::simulate_measurement(&model, &fam.p_nominal, 1.0 / 12.8, size.samples, 0.01, 1);
    let experiments = [mem::Experiment::normalized(&model, &data)];
    let mut acc = 0.0;
    for _ in 0..100_000 {
        acc += mem::gauss_newton_step(&experiments, &fam.p_nominal, 1e-10).unwrap().error;
    }
    println!("{acc}");
}

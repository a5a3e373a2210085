//! The reference every candidate is scored against (step 1 of the module's list): the baseline
//! fit, then the model's own linear parameters freed beside it where the data determine them,
//! then the secondary mismatch parameters joined one at a time.

use super::answer::last_error;
use super::mismatch;
use super::run::Fitted;
use super::{DiagnoseOptions, Observe};
use crate::WorkflowError;
use mem::Measurement;
use models::Model;

/// The baseline and the reference fitted to one record.
pub(super) struct References {
    /// The user's model with the user's free parameters fitted.
    pub baseline: Fitted,
    /// The baseline with the determined mismatch parameters free too (the secondary ones
    /// included, where they joined).
    pub reference: Fitted,
    /// The reference's free parameters.
    pub free: Vec<String>,
    /// The mismatch parameters in the reference (primary, then the secondary that joined).
    pub mismatch: Vec<String>,
    /// The reference without the secondary parameters, and its free parameters.
    pub primary: (Fitted, Vec<String>),
    /// The secondary mismatch parameters that joined.
    pub joined: Vec<String>,
}

/// Fits the baseline and the reference of `model` to `data`, telling `observer` of each fit.
pub(super) fn fit(
    model: &Model,
    data: &Measurement,
    options: &DiagnoseOptions,
    observer: &dyn Observe,
) -> Result<References, WorkflowError> {
    observer.progress("baseline", 0, 2);
    let baseline = Fitted::converged(model, data, &options.free, 100)?;
    observer.progress("baseline", 1, 2);
    // The reference every candidate is scored against: the baseline with the model's own
    // linear parameters free too, so that a mismatch is absorbed before any effect is tried.
    let candidates = mismatch::mismatch_parameters(model, &options.free);
    let from = mismatch::with_mismatch_bounds(baseline.outcome.fitted.clone());
    let all_free: Vec<String> = options.free.iter().chain(&candidates).cloned().collect();
    let trial_reference = Fitted::full(&from, data, &all_free, 100)?;
    // The mismatch parameters the data determine stay free; the others keep the model file's
    // values (a flat direction, or one run to its bound, only misleads every refit after it),
    // and the reference is refitted with the determined ones from the baseline.
    let mut mismatch: Vec<String> =
        candidates.into_iter().filter(|name| mismatch::determined(&trial_reference.outcome, name)).collect();
    let mut free: Vec<String> = options.free.iter().chain(&mismatch).cloned().collect();
    let mut reference =
        if free.len() == all_free.len() { trial_reference } else { Fitted::full(&from, data, &free, 100)? };
    // The secondary ones join one at a time, only where the data determine them and they leave
    // the others determined (a mass per length freed beside two inertias can make all three
    // undetermined, and then none would absorb an inertia mismatch).
    let primary = (Fitted { outcome: reference.outcome.clone() }, free.clone());
    let mut joined: Vec<String> = Vec::new();
    for name in mismatch::secondary_mismatch_parameters(model, &options.free) {
        let mut with = free.clone();
        with.push(name.clone());
        if let Ok(fit) = Fitted::full(&from, data, &with, 100)
            && mismatch.iter().chain([&name]).all(|n| mismatch::determined(&fit.outcome, n))
            && last_error(&fit.outcome) <= last_error(&reference.outcome)
        {
            reference = fit;
            free = with;
            mismatch.push(name.clone());
            joined.push(name);
        }
    }
    observer.progress("baseline", 2, 2);
    Ok(References { baseline, reference, free, mismatch, primary, joined })
}

//! Which parameter combinations the data do not determine, told in words.
//!
//! Detection is scale-free: the singular values of the column-equilibrated S (each free
//! parameter's column divided by its norm) measure how nearly the columns are dependent,
//! whatever the parameters' units or sizes — a parameter near zero (an initial velocity) is not
//! flagged for being small. A direction whose singular value lies below `threshold`·σ_max is
//! undetermined. It is then expressed in relative changes, δP_i/max(|P_i|, typical_i), to name
//! the combination: "scaling m1, m2, k1, k2 together leaves the outputs unchanged".

use crate::Problem;
use crate::solve::StepSolver;
use serde::Serialize;

/// A direction in parameter space that the data do not determine.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Combination {
    /// σ_i/σ_max of the column-equilibrated S.
    pub ratio: f64,
    /// The direction in relative changes δP_i/max(|P_i|, typical_i), largest magnitude 1, the
    /// first component of at least half that size positive;
    /// one entry per problem parameter (0 for those held on a bound).
    pub direction: Vec<f64>,
    /// The parameters with a component of at least 5 % (of the equilibrated direction).
    pub parameters: Vec<String>,
    /// "∏ P_i^{v_i}", e.g. `cv^0.71 · kp^-0.71`.
    pub description: String,
    /// The combination in words.
    pub sentence: String,
    #[serde(skip)]
    involved: Vec<usize>,
}

impl Combination {
    /// Whether problem parameter i takes part.
    pub fn involves(&self, i: usize) -> bool {
        self.involved.contains(&i)
    }
}

/// Identifiability of the parameters from the data at the final P.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Identifiability {
    /// Singular values of the column-equilibrated S (free parameters), divided by the largest.
    pub relative_singular_values: Vec<f64>,
    /// σ_max/σ_min of that matrix (None: infinite).
    pub condition_number: Option<f64>,
    /// Combinations whose ratio lies below the threshold.
    pub undetermined: Vec<Combination>,
    /// The threshold used.
    pub threshold: f64,
}

/// A component counts as taking part in a combination from this size on (equilibrated units).
const INVOLVED: f64 = 0.05;

pub(crate) fn analyse(
    problem: &Problem<'_>,
    p: &[f64],
    free: &[usize],
    solver: Option<&StepSolver>,
    threshold: f64,
) -> Identifiability {
    let Some(solver) = solver else {
        return Identifiability {
            relative_singular_values: Vec::new(),
            condition_number: None,
            undetermined: Vec::new(),
            threshold,
        };
    };
    let sv = &solver.singular_values;
    let max = sv.first().copied().unwrap_or(0.0);
    let relative: Vec<f64> = sv.iter().map(|x| if max > 0.0 { x / max } else { 0.0 }).collect();
    let min = sv.last().copied().unwrap_or(0.0);
    let names = problem.names();
    let undetermined = (0..free.len())
        .filter(|&d| relative[d] < threshold)
        .map(|d| {
            let equilibrated: Vec<f64> = (0..free.len()).map(|c| solver.v[(c, d)]).collect();
            let involved: Vec<usize> =
                (0..free.len()).filter(|&c| equilibrated[c].abs() >= INVOLVED).map(|c| free[c]).collect();
            // δP_c = ṽ_c/D_c; relative: δP_c/scale_c.
            let mut direction = vec![0.0; p.len()];
            for (c, &i) in free.iter().enumerate() {
                if equilibrated[c].abs() >= INVOLVED {
                    direction[i] = equilibrated[c] / (solver.scale[c] * problem.parameters[i].scale(p[i]));
                }
            }
            // Sign convention: the first component of at least half the largest is +; largest |·| is 1.
            let largest = direction.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            if let Some(lead) = direction.iter().copied().find(|x| x.abs() >= 0.5 * largest)
                && largest > 0.0
            {
                let factor = lead.signum() / largest;
                direction.iter_mut().for_each(|x| *x *= factor);
            }
            let description = involved
                .iter()
                .map(|&i| format!("{}^{:.2}", names[i], direction[i]))
                .collect::<Vec<_>>()
                .join(" · ");
            let sentence = sentence(&names, &involved, &direction);
            Combination {
                ratio: relative[d],
                parameters: involved.iter().map(|&i| names[i].clone()).collect(),
                direction,
                description,
                sentence,
                involved,
            }
        })
        .collect();
    Identifiability {
        relative_singular_values: relative,
        condition_number: (min > 0.0).then(|| max / min),
        undetermined,
        threshold,
    }
}

fn list(names: &[String], members: &[usize]) -> String {
    let quoted: Vec<String> = members.iter().map(|&i| names[i].clone()).collect();
    match quoted.len() {
        0 => String::new(),
        1 => quoted[0].clone(),
        n => format!("{} and {}", quoted[..n - 1].join(", "), quoted[n - 1]),
    }
}

/// The combination in words, from the relative direction (largest component +1).
fn sentence(names: &[String], involved: &[usize], direction: &[f64]) -> String {
    if involved.len() == 1 {
        return format!("`{}` does not change the outputs", names[involved[0]]);
    }
    let equal = involved.iter().all(|&i| (direction[i].abs() - 1.0).abs() < 0.2);
    let up: Vec<usize> = involved.iter().copied().filter(|&i| direction[i] > 0.0).collect();
    let down: Vec<usize> = involved.iter().copied().filter(|&i| direction[i] < 0.0).collect();
    if equal && down.is_empty() {
        return format!("scaling {} together leaves the outputs unchanged", list(names, &up));
    }
    if equal && involved.len() == 2 {
        let (a, b) = (names[up[0]].clone(), names[down[0]].clone());
        return format!(
            "raising {a} and lowering {b} by the same factor leaves the outputs unchanged: only the product {a}·{b} is determined"
        );
    }
    if equal {
        return format!(
            "raising {} while lowering {} by the same factor leaves the outputs unchanged",
            list(names, &up),
            list(names, &down)
        );
    }
    let terms: Vec<String> = involved.iter().map(|&i| format!("{} {:+.2}", names[i], direction[i])).collect();
    format!(
        "changing the parameters in the relative proportions ({}) leaves the outputs unchanged",
        terms.join(", ")
    )
}

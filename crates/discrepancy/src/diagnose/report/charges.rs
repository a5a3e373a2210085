//! What a rival's account of a named sensor scale asks of the model file beside the scale's, in
//! words ([`Departures`]).

use super::super::Departures;

/// A number of nats as the answer prints it: one decimal, or "under 0.1" where that would read 0.0.
fn nats(x: f64) -> String {
    if x.abs() < 0.05 { "under 0.1".to_string() } else { format!("{x:.1}") }
}

/// What a rival of a named scale asks of the model file beyond the scale (`d`'s charge is
/// positive), the file's values it moves named where any moved by more than 1 %.
pub(super) fn asks_more(d: &Departures, rival: &str) -> String {
    let moved: Vec<String> = d.moved.iter().map(|m| m.described(true)).collect();
    format!(
        "it asks more of the model file{}: with each value known to {:.0} %, {} nats more than the calibration \
         error, which is the simpler account; if the sensor's calibration is known, check `{rival}`",
        if moved.is_empty() { String::new() } else { format!(" ({})", moved.join(", ")) },
        100.0 * d.tolerance,
        nats(d.charge()),
    )
}

/// What a rival that unseats a named scale asks of the model file less than the scale (`d`'s
/// charge is negative), the other file values the scale's refit moves named where any moved by
/// more than 1 %.
pub(super) fn asks_less(d: &Departures, rival: &str) -> String {
    let moved: Vec<String> = d.moved.iter().filter(|m| m.name != rival).map(|m| m.described(false)).collect();
    format!(
        "with each value of the model file known to {:.0} %, it asks {} nats less of it than the calibration error{}",
        100.0 * d.tolerance,
        nats(-d.charge()),
        if moved.is_empty() { String::new() } else { format!(", whose refit moves {}", moved.join(", ")) },
    )
}

#[cfg(test)]
mod tests {
    use super::super::super::Moved;
    use super::*;

    fn departures(rival: f64, effect: f64, moved: Vec<Moved>) -> Departures {
        Departures { rival, effect, tolerance: 0.05, moved }
    }

    #[test]
    fn a_rival_that_moves_no_file_value_by_a_percent_lists_none() {
        let more = asks_more(&departures(0.04, 0.0, Vec::new()), "m2");
        assert!(!more.contains("()") && more.contains("under 0.1 nats more"), "{more}");
        let less = asks_less(&departures(0.0, 0.02, Vec::new()), "m3");
        assert!(!less.contains("moves") && less.contains("under 0.1 nats less"), "{less}");
    }

    #[test]
    fn the_file_values_a_refit_moves_are_named() {
        let moved = vec![
            Moved { name: "rho".into(), file: 0.5, rival: 0.6, effect: 0.55 },
            Moved { name: "length".into(), file: 1.0, rival: 1.05, effect: 1.0 },
        ];
        let more = asks_more(&departures(6.0, 0.0, moved.clone()), "length");
        assert!(
            more.contains("(`rho` +20.0 %, `length` +5.0 %)") && more.contains("6.0 nats more"),
            "{more}"
        );
        let less = asks_less(&departures(0.0, 3.0, moved), "length");
        assert!(
            less.ends_with("whose refit moves `rho` +10.0 %") && less.contains("3.0 nats less"),
            "{less}"
        );
    }
}

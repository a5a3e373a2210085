//! A CSV record (`t,<columns>`): reading must answer Ok or a located error, never panic; a record
//! that reads must write itself back as a CSV that reads to the same names and values, and
//! splitting off its first column as an input must not panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mem::{Hold, Measurement};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(record) = Measurement::from_csv(text, "fuzz.csv") else { return };
    let written = record.to_csv();
    let again = Measurement::from_csv(&written, "written.csv")
        .unwrap_or_else(|e| panic!("a record's own CSV does not read: {e}\n{written}"));
    assert_eq!(record.names(), again.names());
    assert_eq!(record.n_samples(), again.n_samples());
    let (a, b) = (record.values(), again.values());
    for k in 0..a.nrows() {
        for o in 0..a.ncols() {
            assert!(
                a[(k, o)] == b[(k, o)],
                "sample {k}, column {o}: {} written back as {}",
                a[(k, o)],
                b[(k, o)]
            );
        }
    }
    if let Some(first) = record.names().first().cloned() {
        let _ = record.with_inputs(&[first.as_str()], Hold::Zero);
    }
});

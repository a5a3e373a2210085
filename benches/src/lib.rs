//! Criterion benches of memid (`cargo bench -p memid-benches`). The bench targets live in
//! `benches/benches/`; the models they measure come from the shared `test-problems` crate.

//! The integration tests of `models`, one binary (a test binary per file cost a link and
//! its own copy of the generic code of the dependencies in every cold build: docs/performance.md).
//! Each module is one topic; `cargo test -p models --test integration -- <module>::` runs one.

mod agreement;
mod backlash;
mod commanded;
mod common;
mod coverage;
mod exponential;
mod paper_runs;
mod sensors;
mod structure_appendage;
mod structure_effects;
mod structure_forced_effects;

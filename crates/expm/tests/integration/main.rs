//! The integration tests of `expm`, one binary (a test binary per file cost a link and
//! its own copy of the generic code of the dependencies in every cold build: docs/performance.md).
//! Each module is one topic; `cargo test -p expm --test integration -- <module>::` runs one.

mod closed_form;
mod errors;
mod forced;
mod forced_large;
mod modal;
mod oracles;
mod propagator;
mod reference;
mod structured;

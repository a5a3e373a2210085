//! The integration tests of `beam_modes`, one binary (a test binary per file cost a link and
//! its own copy of the generic code of the dependencies in every cold build: docs/performance.md).
//! Each module is one topic; `cargo test -p beam-modes --test integration -- <module>::` runs one.

mod derivatives;
mod errors;
mod roots;
mod shapes;

//! The integration tests of `structure`, one binary (a test binary per file cost a link and
//! its own copy of the generic code of the dependencies in every cold build: docs/performance.md).
//! Each module is one topic; `cargo test -p structure --test integration -- <module>::` runs one.

mod common;
mod derivatives;
mod docs;
mod errors;
mod expr;
mod fixtures;

//! The integration tests of `mem`, one binary (a test binary per file cost a link and
//! its own copy of the generic code of the dependencies in every cold build: docs/performance.md).
//! Each module is one topic; `cargo test -p mem --test integration -- <module>::` runs one.

mod correlated;
mod data;
mod quantized;
mod robustness;
mod twin;

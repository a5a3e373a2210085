//! The integration tests of `plant`, one binary (a test binary per file cost a link and
//! its own copy of the generic code of the dependencies in every cold build: docs/performance.md).
//! Each module is one topic; `cargo test -p plant --test integration -- <module>::` runs one.

mod derivatives;
mod effects;
mod files;
mod physics;
mod table2;

//! The integration tests of `memid`, one binary (a test binary per file cost a link and
//! its own copy of the generic code of the dependencies in every cold build: docs/performance.md).
//! Each module is one topic; `cargo test -p memid --test integration -- <module>::` runs one.

mod cli;
mod reliability;
mod structures;

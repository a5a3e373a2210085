//! One module per subcommand.

pub mod demo;
pub mod diagnose;
pub mod era;
pub mod fit;
pub mod modal;
pub mod model;
pub mod model_args;
pub mod simulate;

//! One module per subcommand.

pub mod demo;
pub mod diagnose;
pub mod era;
pub mod fit;
pub mod modal;
pub mod model;
pub mod model_args;
pub mod simulate;

/// A count of at least one (`--decimate`, `--order`), refused at parsing with a one-line error
/// that names the flag.
pub fn at_least_one(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err("must be a whole number ≥ 1".into()),
    }
}

//! The crate's one error type. Every fallible public function returns
//! [`Result<T>`]; nothing in the library panics on bad input.

use std::fmt;

/// Errors returned by deeprep.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// An input had the wrong length or shape.
    Shape {
        /// What was being read.
        what: String,
        /// What was expected, in words.
        expected: String,
        /// What was found.
        found: String,
    },
    /// A value was not finite (NaN or infinite).
    NotFinite {
        /// What was being read.
        what: String,
        /// Index of the first offending element.
        index: usize,
    },
    /// A representation vector lies on the set where its decoding map is
    /// undefined (for example a zero 6D column, or parallel 6D columns).
    Degenerate {
        /// Which map.
        what: String,
        /// Index of the offending element within a batch (0 for single calls).
        index: usize,
    },
    /// A name (representation, Euler order, joint...) was not recognized.
    UnknownName {
        /// What kind of name.
        kind: String,
        /// The name given.
        name: String,
        /// The accepted names.
        accepted: String,
    },
    /// A text format could not be parsed.
    Parse {
        /// 1-based line number.
        line: usize,
        /// What went wrong and what was expected.
        message: String,
    },
    /// A model could not be loaded or run.
    Model(String),
    /// Anything else that is the caller's input at fault.
    Invalid(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Shape {
                what,
                expected,
                found,
            } => write!(f, "{what}: expected {expected}, found {found}"),
            Error::NotFinite { what, index } => {
                write!(f, "{what}: element {index} is not finite (NaN or infinity)")
            }
            Error::Degenerate { what, index } => write!(
                f,
                "{what}: element {index} is degenerate (its decoding map is undefined there)"
            ),
            Error::UnknownName {
                kind,
                name,
                accepted,
            } => write!(f, "unknown {kind} '{name}'; accepted: {accepted}"),
            Error::Parse { line, message } => write!(f, "line {line}: {message}"),
            Error::Model(m) => write!(f, "model: {m}"),
            Error::Invalid(m) => write!(f, "{m}"),
        }
    }
}

impl std::error::Error for Error {}

/// Shorthand for `Result<T, deeprep::Error>`.
pub type Result<T> = std::result::Result<T, Error>;

/// The one rule for numeric options (CLI flags, wasm and JS arguments): a
/// number inside `[lo, hi]`. NaN is refused, and so is an infinity unless a
/// bound is infinite (`hi = f64::INFINITY` where infinity means "never", as
/// the hair's curl threshold). Every front-end reports the same message:
/// "NAME must be a number in [LO, HI], found V".
pub fn check_option(name: &str, value: f64, lo: f64, hi: f64) -> Result<()> {
    if value.is_nan() || value < lo || value > hi {
        return Err(Error::Invalid(format!(
            "{name} must be a number in [{lo}, {hi}], found {value}"
        )));
    }
    Ok(())
}

/// Checks that every element of `xs` is finite.
pub fn check_finite(what: &str, xs: &[f32]) -> Result<()> {
    match xs.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(Error::NotFinite {
            what: what.to_string(),
            index,
        }),
        None => Ok(()),
    }
}

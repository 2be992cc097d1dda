//! What the commands share: the typed error, output, option parsing.

use super::USAGE;
use std::io::Write as _;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// The arguments do not fit any command's form: the usage is shown.
    Usage,
    /// A message for the user (what was wrong, with the file or option).
    Failed(String),
}

impl From<String> for CliError {
    fn from(m: String) -> Self {
        CliError::Failed(m)
    }
}

impl From<&str> for CliError {
    fn from(m: &str) -> Self {
        CliError::Failed(m.to_string())
    }
}

/// Prints the whole output at once; a closed pipe (e.g. `| head`) is not an error.
pub fn emit(s: &str) {
    let _ = std::io::stdout().lock().write_all(s.as_bytes());
}

/// Parses `--key value` pairs against the allowed keys.
pub fn options<'a>(
    rest: &[&'a str],
    allowed: &[&str],
) -> Result<std::collections::HashMap<String, &'a str>, String> {
    let mut out = std::collections::HashMap::new();
    let mut i = 0;
    while i < rest.len() {
        let key = rest[i].trim_start_matches("--");
        if !rest[i].starts_with("--") || !allowed.contains(&key) {
            return Err(format!("unknown option '{}'\n{USAGE}", rest[i]));
        }
        let val = rest
            .get(i + 1)
            .ok_or_else(|| format!("{} needs a value", rest[i]))?;
        out.insert(key.to_string(), *val);
        i += 2;
    }
    Ok(out)
}

pub fn parse_opt<T: std::str::FromStr>(
    o: &std::collections::HashMap<String, &str>,
    key: &str,
    default: T,
) -> Result<T, String> {
    match o.get(key) {
        None => Ok(default),
        Some(v) => v.parse().map_err(|_| format!("--{key}: cannot read '{v}'")),
    }
}

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

/// Prints the whole output at once. A closed pipe (e.g. `| head`) is not an
/// error; any other failure to write (a full disk, `> /dev/full`) is.
pub fn emit(s: &str) -> Result<(), String> {
    let mut out = std::io::stdout().lock();
    match out.write_all(s.as_bytes()).and_then(|_| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(format!("standard output: {e}"))
        }
        _ => Ok(()),
    }
}

/// The value after option `args[i]`: an error when there is none or when
/// the next word is another option (`--from-bvh -o x.bvh` must not read a
/// file named `-o`). A negative number is a value.
pub fn value_of(args: &[&str], i: usize) -> Result<String, String> {
    match args.get(i + 1) {
        None => Err(format!("{} needs a value", args[i])),
        Some(v) if is_option(v) => {
            Err(format!("{} needs a value, found the option '{v}'", args[i]))
        }
        Some(v) => Ok(v.to_string()),
    }
}

/// Whether a word is an option name (`-o`, `--out`), not a value such as
/// `-1` or `-0.5`.
fn is_option(v: &str) -> bool {
    v.starts_with('-')
        && v.len() > 1
        && !v[1..].starts_with(|c: char| c.is_ascii_digit() || c == '.')
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
        value_of(rest, i)?;
        out.insert(key.to_string(), rest[i + 1]);
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

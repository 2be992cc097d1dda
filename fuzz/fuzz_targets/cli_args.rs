//! The CLI's option parsing (crate/src/bin/deeprep/args.rs, compiled here
//! from its source): words split from the input at NUL bytes go through
//! `options` against a fixed list, `value_of` at every position and
//! `parse_opt` for numbers. Each gives a value or a message, never a panic,
//! and never takes an option name as a value.
#![no_main]
use libfuzzer_sys::fuzz_target;

/// What args.rs appends to an unknown option's message (`super::USAGE`).
const USAGE: &str = "usage: deeprep ...";
#[allow(dead_code)]
#[path = "../../crate/src/bin/deeprep/args.rs"]
mod args;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let words: Vec<&str> = text.split('\0').collect();
    for i in 0..words.len() {
        if let Ok(v) = args::value_of(&words, i) {
            assert_eq!(v, words[i + 1]);
            assert!(!(v.starts_with("--") && v.len() > 2), "{v}");
        }
    }
    if let Ok(o) = args::options(&words, &["out", "count", "seed", "fps", "yaw"]) {
        let _ = args::parse_opt::<usize>(&o, "count", 1);
        let _ = args::parse_opt::<f32>(&o, "yaw", 0.0);
        let _ = args::parse_opt::<u64>(&o, "seed", 1);
    }
});

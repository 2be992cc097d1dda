//! The in-betweening networks' manifest (motion::manifest): JSON, the BVH
//! skeleton inside it, Table D.1 rows and the normalization, checked.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = deeprep::motion::manifest::parse(text);
});

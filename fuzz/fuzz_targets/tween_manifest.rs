//! The in-betweening networks' manifests, as the request planner reads them
//! without the runtime: the generator's (motion::manifest: JSON, the BVH
//! skeleton inside it, Table D.1 rows and the normalization, checked) and
//! the conditional network's planner view (motion::cond).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = deeprep::motion::manifest::parse(text);
    let _ = deeprep::motion::cond::info_of_manifest(text);
});

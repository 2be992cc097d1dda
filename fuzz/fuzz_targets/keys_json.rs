//! The keys file (motion::keys) on the thesis skeleton, then SLERP+LERP
//! between its keys when they are valid for the length it asks.
#![no_main]
use deeprep::motion::{baseline, keys};
use deeprep::skeleton::Bvh;
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

static MANIFEST: &str = include_str!("../../models/onnx/tween_generator.manifest.json");

fuzz_target!(|data: &[u8]| {
    static TPL: OnceLock<Bvh> = OnceLock::new();
    let tpl = TPL.get_or_init(|| {
        let m: serde_json::Value = serde_json::from_str(MANIFEST).expect("the bundled manifest");
        Bvh::parse(m["skeleton_bvh"].as_str().expect("skeleton_bvh")).expect("the bundled skeleton")
    });
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(file) = keys::from_json(text, tpl) else { return };
    let frames = file.frames.unwrap_or(64).min(4096);
    let _ = baseline::slerp_lerp(&file.keys, frames);
});

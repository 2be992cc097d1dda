//! Synthesis requests (motion::Request::validate): a length and a variation
//! from the first eight bytes, keys from a keys file in the rest, on the
//! thesis skeleton; a valid request is then interpolated (SLERP+LERP).
#![no_main]
use deeprep::motion::{baseline, keys, Request};
use deeprep::skeleton::Bvh;
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

static MANIFEST: &str = include_str!("../../models/onnx/tween_generator.manifest.json");

fuzz_target!(|data: &[u8]| {
    static TPL: OnceLock<Bvh> = OnceLock::new();
    let tpl = TPL.get_or_init(|| {
        deeprep::motion::manifest::parse(MANIFEST)
            .expect("the bundled manifest")
            .template
    });
    if data.len() < 8 {
        return;
    }
    let frames = u32::from_le_bytes([data[0], data[1], data[2], data[3]]) as usize;
    let variation = f32::from_le_bytes([data[4], data[5], data[6], data[7]]);
    let Ok(text) = std::str::from_utf8(&data[8..]) else { return };
    let Ok(file) = keys::from_json(text, tpl) else { return };
    let req = Request {
        keys: file.keys,
        frames,
        dna: None,
        post_process: true,
        foot_lock: None,
        variation: Some(variation),
    };
    if req.validate(tpl.joints.len(), 1.0).is_ok() && frames <= 4096 {
        baseline::slerp_lerp(&req.keys, frames).expect("a valid request interpolates");
    }
});

//! Issue 49: one rule for numeric arguments in every wasm class.

use super::*;

/// Issue 49: the numeric arguments of every class that takes them follow
/// one rule (`error::check_option`: a number in the documented range, NaN
/// and infinities refused with "NAME must be a number in [LO, HI], found
/// V"); the viewer's camera ignores non-finite drags instead of keeping them.
#[wasm_bindgen_test]
fn numeric_arguments_follow_one_rule_in_every_class() {
    use deeprep::wasm::{dna_frames_of_pool, HairLab, Inbetweener};
    use wasm_bindgen::JsError;
    let message = |e: JsError| {
        let v = JsValue::from(e);
        js_sys::Reflect::get(&v, &"message".into())
            .unwrap()
            .as_string()
            .unwrap()
    };
    let bad = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 1e30];
    // Inbetweener: variation
    let m = Inbetweener::new(TWEEN_GENERATOR, TWEEN_PATH, TWEEN_MANIFEST).unwrap();
    let tpl = deeprep::wasm::BvhClip::parse(&m.skeleton_bvh()).unwrap();
    let row = vec![0.0f32; tpl.channel_count()];
    let two: Vec<f32> = row.iter().chain(&row).copied().collect();
    for v in bad {
        let opts = synth_options(&[("variation", JsValue::from_f64(v))]);
        let e = message(m.synthesize(&[0, 10], &two, 20, Some(opts)).err().unwrap());
        assert!(
            e.contains("variation") && e.contains("must be a number in [0, 2]"),
            "{v}: {e}"
        );
    }
    // Motion DNA seeds
    for v in [f64::NAN, f64::INFINITY, -1.0, 1e30, 0.5] {
        let e = message(dna_frames_of_pool(10, 100, v).err().unwrap());
        assert!(
            e.contains("seed must be an integer in [0, 9007199254740992]"),
            "{v}: {e}"
        );
    }
    // HairLab: yaw, smoothing, curl threshold, blend weight
    let hair = HairLab::new(HAIR_FEATURES, HAIR_STRANDS, HAIR_MANIFEST).unwrap();
    for v in [f32::NAN, f32::INFINITY, -1000.0, 1e30] {
        let e = message(hair.test_image("M-wavy", 1, v).err().unwrap());
        assert!(
            e.contains("yaw (degrees) must be a number in [-360, 360]"),
            "{v}: {e}"
        );
    }
    let feats = hair
        .features(&hair.test_image("M-wavy", 1, 0.0).unwrap())
        .unwrap();
    for v in [f32::NAN, f32::INFINITY, -1.0, 1e30] {
        let e = message(hair.strands(&feats, 100, v, 15.0).err().unwrap());
        assert!(
            e.contains("smooth (sigma in samples) must be a number in [0, 50]"),
            "{v}: {e}"
        );
    }
    for v in [f32::NAN, -1.0, f32::NEG_INFINITY] {
        let e = message(hair.strands(&feats, 100, 1.5, v).err().unwrap());
        assert!(
            e.contains("curl (threshold in 1/m) must be a number in [0, inf]"),
            "{v}: {e}"
        );
    }
    // infinity is the documented "never curl"
    assert!(hair.strands(&feats, 100, 1.5, f32::INFINITY).is_ok());
    for v in [f32::NAN, f32::INFINITY, -1e30, 1e30] {
        let e = message(HairLab::blend_features(&feats, &feats, v).err().unwrap());
        assert!(
            e.contains("blend t must be a number in [-1, 2]"),
            "{v}: {e}"
        );
    }
    // strand counts: the same rule
    let e = message(hair.strands(&feats, 0, 1.5, 15.0).err().unwrap());
    assert!(
        e.contains("strands must be a number in [1, 200000], found 0"),
        "{e}"
    );
}

//! BVH to keys and motion on the SLERP path: FK of every frame, whole-pose
//! keys from the first and last frame, SLERP+LERP and zero-velocity between
//! them, and the result written back as BVH on the clip's skeleton.
#![no_main]
use deeprep::motion::{baseline, Keyframe};
use deeprep::skeleton::{fk, Bvh};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(b) = Bvh::parse_bytes(data) else { return };
    let n = b.frame_count();
    if n == 0 {
        return;
    }
    fk::positions(&b, 0, n).expect("FK of parsed frames");
    let last = n - 1;
    let k0 = Keyframe::from_bvh(&b, 0, 0).expect("key from frame 0");
    let k1 = Keyframe::from_bvh(&b, last, 1 + last % 64).expect("key from the last frame");
    let frames = 2 + last % 64;
    for m in [
        baseline::slerp_lerp(&[k0.clone(), k1.clone()], frames),
        baseline::zero_velocity(&[k0, k1], frames),
    ] {
        // a parsed clip may hold coordinates beyond what the key checks take
        // (±1e6 units): an error, as for any key
        let m = match m {
            Ok(m) => m,
            Err(e) => {
                assert!(e.to_string().contains("beyond"), "interpolation: {e}");
                continue;
            }
        };
        let out = m.to_bvh(&b, b.frame_time).expect("motion to BVH");
        let _ = out.write();
    }
});

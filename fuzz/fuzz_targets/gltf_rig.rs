//! glTF rig loading, its rest pose, one pose per clip and a random pose.
#![no_main]
use deeprep::mesh::Rig;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(rig) = Rig::from_glb(data) else { return };
    let _ = rig.rest_pose();
    for k in 0..rig.animations.len().min(4) {
        let d = rig.animations[k].duration;
        let _ = rig.animation_pose(k, d * 0.5);
    }
    let mut rng = deeprep::rng::Rng::new(1);
    let _ = rig.jittered_locals(&mut rng, 0.3);
});

//! In-betweening a clip on another humanoid skeleton (issue 53): retargeted
//! onto the model's, synthesized, and the result back onto the user's.

use super::*;
use deeprep::motion::clip::OnModel;

fn cmu_hips_walk() -> Option<Bvh> {
    let p = root().join("../shared/data/cmu-extra/other-skeletons/cmu-hips/walk/02_01.bvh");
    if !p.is_file() {
        eprintln!(
            "SKIP: ../shared/data/cmu-extra is absent; in-betweening on another skeleton skipped"
        );
        return None;
    }
    Some(Bvh::parse(&std::fs::read_to_string(p).unwrap()).unwrap())
}

fn global(b: &Bvh, f: usize) -> Vec<deeprep::skeleton::retarget::Vec3> {
    deeprep::skeleton::fk::global_pose(b, b.frame(f)).positions
}

/// The clip onto the model's skeleton and straight back (no synthesis):
/// every joint where it was, within 0.2 of the clip's units (its hips
/// stand about 18 high, the model's 100: about 1 model unit, the issue's
/// bound). The feet placed by IK on the model's proportions leave the
/// knees a little off on the way back (0.13 units at worst).
#[test]
fn a_motionbuilder_clip_goes_onto_the_model_and_back() {
    let Some(user) = cmu_hips_walk() else { return };
    let Some(m) = models() else { return };
    let on = OnModel::new(&user, &m.template).unwrap();
    assert!(on.retargeted());
    assert_eq!(on.clip.joints, m.template.joints);
    let frames = user.frame_count();
    // keys at the ends only, so that every frame between is retargeted back
    let ck = deeprep::motion::clip::clip_keys(&on.clip, &[0, frames - 1], false).unwrap();
    let back = on.back(&user, on.clip.clone(), &ck).unwrap();
    assert_eq!(back.joints, user.joints);
    let mut worst = 0f64;
    for f in 0..frames {
        let (a, b) = (global(&user, f), global(&back, f));
        for j in 0..user.joints.len() {
            worst = worst.max(a[j].distance(b[j]));
        }
    }
    assert!(worst < 0.2, "the round trip moved a joint by {worst} units");
}

/// `deeprep inbetween --from-bvh` on the MotionBuilder-style clip: the
/// output has the input's hierarchy, its keys and the frames outside the
/// span are the input's, and the synthesized frames join them without a
/// jump (no joint moves further in one frame than twice the input's
/// fastest joint does).
#[test]
fn the_cli_inbetweens_a_clip_on_another_skeleton() {
    let Some(user) = cmu_hips_walk() else { return };
    if models().is_none() {
        return;
    }
    let tmp = std::env::temp_dir().join(format!("deeprep_retargeted_{}.bvh", std::process::id()));
    let clip = root().join("../shared/data/cmu-extra/other-skeletons/cmu-hips/walk/02_01.bvh");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
        .args([
            "inbetween",
            "--from-bvh",
            clip.to_str().unwrap(),
            "--keys",
            "60,120,180",
        ])
        .args(["--models", root().join("models/onnx").to_str().unwrap()])
        .args(["-o", tmp.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("retargeted"), "{err}");
    let out = Bvh::parse(&std::fs::read_to_string(&tmp).unwrap()).unwrap();
    std::fs::remove_file(&tmp).ok();
    assert_eq!(out.joints, user.joints);
    assert_eq!(out.frame_count(), user.frame_count());
    let c = user.channel_count();
    for f in (0..60).chain([120]).chain(180..user.frame_count()) {
        assert_eq!(
            out.motion[f * c..(f + 1) * c],
            user.motion[f * c..(f + 1) * c],
            "frame {f}"
        );
    }
    let step = |b: &Bvh, f: usize| {
        let (p, q) = (global(b, f), global(b, f + 1));
        p.iter()
            .zip(&q)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max)
    };
    let fastest = (0..user.frame_count() - 1)
        .map(|f| step(&user, f))
        .fold(0.0, f64::max);
    let worst = (59..181).map(|f| step(&out, f)).fold(0.0, f64::max);
    assert!(
        worst <= 2.0 * fastest,
        "a synthesized frame jumps {worst} units (the input's fastest joint: {fastest})"
    );
    // and the synthesized frames are not the input's: the motion was made
    let moved = (61..120)
        .map(|f| global(&out, f)[0].distance(global(&user, f)[0]))
        .fold(0.0, f64::max);
    assert!(moved > 1e-3);
}

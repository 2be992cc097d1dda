//! The generator pipeline end to end: keys exact after post-processing.

use super::*;

#[test]
fn the_model_pipeline_hits_keys_exactly_after_post_processing() {
    let Some(m) = models() else { return };
    let j = m.joints();
    // Keys: three poses of the model's own rest skeleton, turned and moved.
    let mut keys = Vec::new();
    for (i, f) in [0usize, 90, 200].iter().enumerate() {
        let mut b: Bvh = m.template.clone();
        let mut ch = vec![0.0f32; b.channel_count()];
        ch[0] = 40.0 * i as f32;
        ch[1] = 85.0;
        ch[3] = 30.0 * i as f32; // Zrotation of the root
        b.motion = ch;
        keys.push(Keyframe::from_bvh(&b, 0, *f).unwrap());
    }
    let req = Request {
        keys: keys.clone(),
        frames: 230,
        dna: None,
        post_process: true,
        foot_lock: Some(FootLock::default()),
        variation: None,
    };
    let out = m.synthesize(&req, &|| 0.0).unwrap();
    assert_eq!(out.motion.len(), 230);
    assert_eq!(out.motion.rotations[0].len(), j);
    assert!(out.key_error.root < 1e-6, "{:?}", out.key_error);
    assert!(out.key_error.local < 1e-3, "{:?}", out.key_error);
    for k in &keys {
        for (a, b) in out.motion.rotations[k.frame]
            .iter()
            .zip(k.rotations.as_ref().unwrap())
        {
            let r: &Mat3<f64> = a;
            assert!(geodesic_distance(r, b) < 1e-6);
        }
    }
    // Every frame is finite and writes as BVH with the requested frame count.
    let bvh = out.motion.to_bvh(&m.template, 1.0 / 60.0).unwrap();
    assert_eq!(Bvh::parse(&bvh.write()).unwrap().frame_count(), 230);
    assert!(bvh.motion.iter().all(|v| v.is_finite()));
    // Bad requests.
    let far = Request {
        keys: vec![
            keys[0].clone(),
            Keyframe {
                frame: 700,
                ..keys[1].clone()
            },
        ],
        frames: 800,
        dna: None,
        post_process: true,
        foot_lock: Some(FootLock::default()),
        variation: None,
    };
    // a 700-frame gap runs hierarchically (Sec. 5.4.3): critical keys
    // inside it, every key exact after post-processing
    let out = m.synthesize(&far, &|| 0.0).unwrap();
    assert_eq!(out.motion.len(), 800);
    assert!(
        !out.critical_frames.is_empty() && out.critical_frames.iter().all(|&f| f > 0 && f < 700)
    );
    assert!(
        out.key_error.root < 1e-6 && out.key_error.local < 1e-3,
        "{:?}",
        out.key_error
    );
    // beyond 3,000 frames: an error that names both limits
    let too_far = Request {
        keys: vec![
            keys[0].clone(),
            Keyframe {
                frame: 3100,
                ..keys[1].clone()
            },
        ],
        frames: 3200,
        ..far.clone()
    };
    let e = m.synthesize(&too_far, &|| 0.0).unwrap_err().to_string();
    assert!(e.contains("600 frames") && e.contains("3000"), "{e}");
    let zero = Request {
        frames: 0,
        ..req.clone()
    };
    assert!(m.synthesize(&zero, &|| 0.0).is_err());
    for v in [f32::NAN, -0.1, 2.5] {
        let bad = Request {
            variation: Some(v),
            ..req.clone()
        };
        let e = m.synthesize(&bad, &|| 0.0).unwrap_err().to_string();
        assert!(e.contains("variation"), "{v}: {e}");
    }
    // Variation 0 is SLERP+LERP: before any post-processing the pose is
    // SLERP between the keys' rotations and the root path the keys' root
    // positions interpolated linearly; both differ from the networks'
    // output, and a half variation lies between them.
    let raw = |variation: f32| {
        m.synthesize(
            &Request {
                variation: Some(variation),
                post_process: false,
                ..req.clone()
            },
            &|| 0.0,
        )
        .unwrap()
    };
    let (base, full, half) = (raw(0.0), raw(1.0), raw(0.5));
    let plain = slerp_lerp(&keys, 230).unwrap();
    for t in 0..230 {
        for jj in 0..j {
            let (b, p) = (&base.motion.rotations[t][jj], &plain.rotations[t][jj]);
            assert!(geodesic_distance(b, p) < 1e-6, "frame {t} joint {jj}");
            let (h, f) = (&half.motion.rotations[t][jj], &full.motion.rotations[t][jj]);
            let (to_plain, to_full) = (geodesic_distance(h, p), geodesic_distance(h, f));
            assert!(
                (to_plain - to_full).abs() < 1e-6,
                "frame {t} joint {jj}: half way"
            );
        }
    }
    let moved = base
        .motion
        .rotations
        .iter()
        .zip(&full.motion.rotations)
        .flat_map(|(a, b)| a.iter().zip(b))
        .map(|(a, b)| geodesic_distance(a, b))
        .fold(0.0f64, f64::max);
    assert!(
        moved > 1e-2,
        "the correction changes the motion ({moved} rad)"
    );
    let (mut lerp_err, mut path_moved) = (0.0f64, 0.0f64);
    for t in 0..=200 {
        let (a, b) = if t <= 90 { (0, 1) } else { (1, 2) };
        let s = (t - keys[a].frame) as f64 / (keys[b].frame - keys[a].frame) as f64;
        for c in 0..3 {
            let want = keys[a].positions[c] as f64 * (1.0 - s) + keys[b].positions[c] as f64 * s;
            lerp_err = lerp_err.max((base.motion.root[t][c] - want).abs());
            path_moved = path_moved.max((full.motion.root[t][c] - want).abs());
        }
    }
    assert!(
        lerp_err < 1e-4,
        "variation 0 root path off the lerp by {lerp_err}"
    );
    assert!(path_moved > 1e-2, "the learned root path is not the lerp");
    // Without a variation the request takes the model's default.
    let dflt = raw(m.default_variation);
    let none = m
        .synthesize(
            &Request {
                variation: None,
                post_process: false,
                ..req.clone()
            },
            &|| 0.0,
        )
        .unwrap();
    assert_eq!(dflt.motion.root, none.motion.root);
    let bad_dna = Request {
        dna: Some(vec![vec![0.0; 5]]),
        ..req
    };
    assert!(m
        .synthesize(&bad_dna, &|| 0.0)
        .unwrap_err()
        .to_string()
        .contains("Motion DNA"));
}

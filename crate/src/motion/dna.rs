//! Seeded Motion DNA (thesis Sec. 5.2.5): which frames of a DNA source clip
//! steer the generator.
//!
//! Training feeds each window's *representative frames*: the frames of
//! largest joint-rotation change from their neighbours, at least
//! [`MIN_SPACING`] frames apart, one per [`FRAMES_PER_DNA`] frames of the
//! window (the rule of `train/deeprep_train/motion/dna.py`, which training
//! applies to RC angles; tests/parity/test_dna.py checks the two sides agree
//! on a shared fixture). [`pick_dna_frames`] does
//! the same on a window of the source clip chosen by a seed, so a seed gives
//! a different but repeatable style, drawn the way training drew it.

use super::Keyframe;
use crate::error::{Error, Result};
use crate::rng::Rng;
use crate::skeleton::Bvh;

/// Training's representative-frame count: one per this many frames.
pub const FRAMES_PER_DNA: usize = 180;
/// Minimum spacing of representative frames, in frames.
pub const MIN_SPACING: usize = 30;

/// How far (in a pass' frames) each DNA pose steers the conditional
/// network's output when its manifest says `dna_window`: half a training
/// window (480 frames), so each frame pools about the 2-3 poses a training
/// window held. `train/deeprep_train/motion/dna.py`'s `DNA_WINDOW`.
pub const DNA_WINDOW: usize = 240;

/// How much each of `poses` DNA poses steers each frame of an output of
/// `frames` frames: the poses are spread evenly over the output in the
/// order given (pose `j` at frame `(2j + 1) * frames / (2 * poses)`), each
/// weighing `1 - distance / radius` on the frames within `radius` of its
/// place (a tent, so the code changes smoothly from frame to frame),
/// normalized to sum 1 on every frame; a frame no tent reaches takes its
/// nearest pose (the earlier on a tie). Row-major `[poses, frames]`: the
/// conditional network's `dna_w` input. `motion.dna.frame_weights` in the
/// training code is the same rule (tests/parity/test_dna.py).
pub fn frame_weights(poses: usize, frames: usize, radius: usize) -> Vec<f32> {
    let mut w = vec![0.0f32; poses * frames];
    if poses == 0 {
        return w;
    }
    let at: Vec<f64> = (0..poses)
        .map(|j| (2 * j + 1) as f64 * frames as f64 / (2 * poses) as f64)
        .collect();
    let mut col = vec![0.0f64; poses];
    for t in 0..frames {
        let mut nearest = 0;
        let mut total = 0.0f64;
        for (j, &a) in at.iter().enumerate() {
            let d = (t as f64 - a).abs();
            col[j] = if radius > 0 {
                (1.0 - d / radius as f64).max(0.0)
            } else {
                0.0
            };
            total += col[j];
            if d < (t as f64 - at[nearest]).abs() {
                nearest = j;
            }
        }
        if total == 0.0 {
            col[nearest] = 1.0;
            total = 1.0;
        }
        for j in 0..poses {
            w[j * frames + t] = (col[j] / total) as f32;
        }
    }
    w
}

/// How many DNA frames training used for a window of `frames` frames.
pub fn dna_count(frames: usize) -> usize {
    (frames / FRAMES_PER_DNA).max(1)
}

/// Representative frames of `poses` (whole-pose keys with rotations, one
/// per frame): the `count` frames of largest change of the non-root local
/// rotations between their two neighbours, at least [`MIN_SPACING`] apart,
/// in frame order. Fewer when the clip is too short to space them.
pub fn representative_frames(poses: &[Keyframe], count: usize) -> Result<Vec<usize>> {
    let rots = poses
        .iter()
        .enumerate()
        .map(|(i, k)| {
            k.rotations
                .as_ref()
                .ok_or_else(|| Error::Invalid(format!("DNA frame {i} has no rotations")))
        })
        .collect::<Result<Vec<_>>>()?;
    let n = rots.len();
    let mut change = vec![0.0f64; n];
    for t in 1..n.saturating_sub(1) {
        let (a, b) = (rots[t - 1], rots[t + 1]);
        change[t] = a
            .iter()
            .zip(b.iter())
            .skip(1)
            .map(|(ra, rb)| {
                ra.iter()
                    .flatten()
                    .zip(rb.iter().flatten())
                    .map(|(x, y)| (x - y) * (x - y))
                    .sum::<f64>()
            })
            .sum::<f64>()
            .sqrt();
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| change[j].total_cmp(&change[i]).then(i.cmp(&j)));
    let mut picked: Vec<usize> = Vec::with_capacity(count);
    for i in order {
        if picked.len() == count {
            break;
        }
        if picked.iter().all(|&j| i.abs_diff(j) >= MIN_SPACING) {
            picked.push(i);
        }
    }
    picked.sort_unstable();
    Ok(picked)
}

/// Seeded DNA for an output of `frames` frames from a source clip `poses`:
/// a window of `frames` source frames (the whole clip when shorter) placed
/// by `seed`, then [`dna_count`]`(frames)` frames drawn by the seed from the
/// window's twice as many [`representative_frames`]. Training takes the
/// window's most representative frames; the draw among twice as many is
/// what makes seeds differ when the window has little room to move (a clip
/// about as long as the output). Returns indices into `poses`, in frame
/// order. Equal seeds give equal frames.
pub fn pick_dna_frames(poses: &[Keyframe], frames: usize, seed: u64) -> Result<Vec<usize>> {
    if poses.is_empty() {
        return Err(Error::Invalid("the DNA source has no frames".into()));
    }
    let count = dna_count(frames);
    let len = frames.min(poses.len()).max(1);
    let mut rng = Rng::new(seed);
    let start = (rng.uniform() * (poses.len() - len + 1) as f64) as usize;
    let start = start.min(poses.len() - len);
    let mut pool = representative_frames(&poses[start..start + len], 2 * count)?;
    // the first `count` of a seeded shuffle (Fisher-Yates), in frame order
    for i in 0..pool.len().min(count) {
        let j = i + rng.below(pool.len() - i);
        pool.swap(i, j);
    }
    pool.truncate(count);
    pool.sort_unstable();
    Ok(pool.into_iter().map(|i| i + start).collect())
}

/// Seeded DNA from every frame of a clip on the model's skeleton:
/// [`pick_dna_frames`] on its poses. What `deeprep inbetween --dna CLIP.bvh
/// --seed S` and the sketch page (on an imported clip) both draw.
pub fn pick_from_clip(clip: &Bvh, frames: usize, seed: u64) -> Result<Vec<usize>> {
    if let Some(i) = clip.motion.iter().position(|v| !v.is_finite()) {
        let c = clip.channel_count().max(1);
        return Err(Error::Invalid(format!(
            "DNA frame {} has a non-finite channel value (channel {})",
            i / c,
            i % c
        )));
    }
    let poses = (0..clip.frame_count())
        .map(|f| Keyframe::from_bvh(clip, f, f))
        .collect::<Result<Vec<_>>>()?;
    pick_dna_frames(&poses, frames, seed)
}

/// Seeded DNA from a pool of `pool` unrelated poses (a pose library, not a
/// clip: there are no neighbouring frames to measure change between):
/// [`dna_count`]`(frames)` indices drawn uniformly by the same generator as
/// [`pick_dna_frames`], repeats allowed. Equal seeds give equal picks.
pub fn pick_from_pool(pool: usize, frames: usize, seed: u64) -> Result<Vec<usize>> {
    if pool == 0 {
        return Err(Error::Invalid("the DNA pool has no poses".into()));
    }
    let mut rng = Rng::new(seed);
    Ok((0..dna_count(frames))
        .map(|_| ((rng.uniform() * pool as f64) as usize).min(pool - 1))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::Mat3;

    fn rot_z(a: f64) -> Mat3<f64> {
        let (s, c) = a.sin_cos();
        [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    }

    /// A two-joint clip whose second joint turns by `speed(t)` per frame.
    fn clip(n: usize, speed: impl Fn(usize) -> f64) -> Vec<Keyframe> {
        let mut a = 0.0;
        (0..n)
            .map(|t| {
                a += speed(t);
                Keyframe {
                    frame: t,
                    positions: vec![0.0; 6],
                    mask: vec![true; 6],
                    rotations: Some(vec![rot_z(0.3 * t as f64), rot_z(a)]),
                }
            })
            .collect()
    }

    #[test]
    fn picks_the_fastest_frames_spaced_apart() {
        // bursts of rotation at frames 50 and 140, slow elsewhere; the root
        // turns fast everywhere and must not count
        let poses = clip(200, |t| if t == 50 || t == 140 { 0.5 } else { 0.01 });
        let f = representative_frames(&poses, 2).unwrap();
        assert!(
            f.len() == 2 && f[0].abs_diff(50) <= 1 && f[1].abs_diff(140) <= 1,
            "{f:?}"
        );
        // spacing: a third pick cannot sit next to a burst
        let f = representative_frames(&poses, 3).unwrap();
        assert!(f.windows(2).all(|w| w[1] - w[0] >= MIN_SPACING), "{f:?}");
    }

    #[test]
    fn seeds_are_repeatable_and_vary() {
        let poses = clip(2000, |t| {
            0.01 + 0.2 * ((t as f64) * 0.37).sin().abs().powi(8)
        });
        let a = pick_dna_frames(&poses, 360, 1).unwrap();
        assert_eq!(a.len(), dna_count(360));
        assert_eq!(a, pick_dna_frames(&poses, 360, 1).unwrap());
        let others: Vec<_> = (2..6)
            .map(|s| pick_dna_frames(&poses, 360, s).unwrap())
            .collect();
        assert!(others.iter().any(|o| *o != a), "{a:?} {others:?}");
        // a clip as long as the output (no room for the window): seeds
        // still differ, drawing among its most representative frames
        let whole: Vec<_> = (1..6)
            .map(|s| pick_dna_frames(&poses[..720], 720, s).unwrap())
            .collect();
        assert!(whole.iter().all(|p| p.len() == dna_count(720)), "{whole:?}");
        assert!(whole.iter().any(|p| *p != whole[0]), "{whole:?}");
        assert_eq!(whole[0], pick_dna_frames(&poses[..720], 720, 1).unwrap());
        let pool = representative_frames(&poses[..720], 2 * dna_count(720)).unwrap();
        assert!(whole.iter().flatten().all(|i| pool.contains(i)));
        // all inside the clip, also when the output is longer than the source
        let long = pick_dna_frames(&poses[..100], 900, 3).unwrap();
        assert!(
            !long.is_empty() && long.iter().all(|&i| i < 100),
            "{long:?}"
        );
    }

    #[test]
    fn pool_picks_are_seeded_in_range_and_counted_like_clips() {
        let a = pick_from_pool(6, 900, 7).unwrap();
        assert_eq!(a.len(), dna_count(900));
        assert!(a.iter().all(|&i| i < 6), "{a:?}");
        assert_eq!(a, pick_from_pool(6, 900, 7).unwrap());
        let others: Vec<_> = (8..14)
            .map(|s| pick_from_pool(6, 900, s).unwrap())
            .collect();
        assert!(others.iter().any(|o| *o != a), "{a:?} {others:?}");
        assert!(pick_from_pool(0, 100, 0).is_err());
    }

    #[test]
    fn frame_weights_spread_the_poses_in_order() {
        // 3 poses over 600 frames sit at 100, 300, 500
        let w = frame_weights(3, 600, 200);
        let at = |j: usize, t: usize| w[j * 600 + t];
        // each frame's weights sum to 1
        for t in 0..600 {
            let s: f32 = (0..3).map(|j| at(j, t)).sum();
            assert!((s - 1.0).abs() < 1e-6, "frame {t}: {s}");
        }
        // a frame at a pose's place is mostly that pose; halfway, two poses equally
        assert_eq!((at(0, 0), at(1, 0), at(2, 0)), (1.0, 0.0, 0.0));
        assert!(at(1, 300) > 0.6 && (at(0, 300) - at(2, 300)).abs() < 1e-6);
        assert!((at(0, 200) - at(1, 200)).abs() < 1e-6 && at(2, 200) == 0.0);
        // smooth: no weight moves by more than 1 / radius-ish between frames
        for j in 0..3 {
            for t in 1..600 {
                assert!((at(j, t) - at(j, t - 1)).abs() < 0.02, "pose {j} frame {t}");
            }
        }
        // no tent reaches: the nearest pose only, the earlier on a tie (frame 200)
        let w = frame_weights(3, 600, 0);
        for t in 0..600 {
            assert_eq!(
                (0..3).map(|j| w[j * 600 + t]).sum::<f32>(),
                1.0,
                "frame {t}"
            );
        }
        assert_eq!((w[200], w[600 + 200]), (1.0, 0.0));
        assert!(frame_weights(1, 50, 10).iter().all(|&v| v == 1.0));
        assert!(frame_weights(0, 50, 240).is_empty());
        assert!(frame_weights(2, 0, 240).is_empty());
    }

    #[test]
    fn errors_are_clear() {
        assert!(pick_dna_frames(&[], 100, 0).is_err());
        let mut poses = clip(10, |_| 0.1);
        poses[3].rotations = None;
        let e = representative_frames(&poses, 1).unwrap_err().to_string();
        assert!(e.contains("frame 3"), "{e}");
    }
}

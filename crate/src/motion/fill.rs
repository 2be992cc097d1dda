//! Filling gaps in captured motion (`deeprep inbetween --from-bvh CLIP
//! --fill START-END`, JS `client.fillGaps`): the frames of each gap are
//! synthesized from the known frames around it (its context), every other
//! frame is kept exactly as it was.
//!
//! A gap `START-END` (inclusive) needs a known frame before and after it;
//! gaps are filled in order, so a later gap's context may hold an earlier
//! gap's filled frames. What a method sees of the context is [`Context`]:
//! `before` frames before the gap and `after` frames after it, given to the
//! networks as whole-pose keys (each frame a key), and to the Hermite curve
//! as the end tangents.
//!
//! The methods:
//! - the networks and SLERP+LERP through [`super::serve`], with the context
//!   frames as keys;
//! - [`hermite`]: a cubic Hermite curve from the last frame before the gap
//!   to the first after it, whose end tangents are the context's velocities
//!   (what an editor's spline gives when it sees the neighbouring keys):
//!   per coordinate for the root, in the tangent space of the first end's
//!   rotation for each joint.

use super::clip::ClipKeys;
use super::{Keyframe, Motion};
use crate::error::{Error, Result};
use crate::rotation::{from_glam_f64, to_glam_f64, Mat3};
use crate::skeleton::Bvh;
use glam::{DQuat, DVec3};

/// Frames `start..=end` of a clip to synthesize.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Gap {
    /// First frame synthesized.
    pub start: usize,
    /// Last frame synthesized.
    pub end: usize,
}

impl Gap {
    /// Parses `START-END` (inclusive frame numbers of the clip).
    pub fn parse(s: &str) -> Result<Gap> {
        let bad = || {
            Error::Invalid(format!(
                "a gap is START-END, two frame numbers of the clip (e.g. 200-260), found '{s}'"
            ))
        };
        let (a, b) = s.trim().split_once('-').ok_or_else(bad)?;
        let start = a.trim().parse().map_err(|_| bad())?;
        let end = b.trim().parse().map_err(|_| bad())?;
        Ok(Gap { start, end })
    }

    /// Frames in the gap.
    pub fn len(&self) -> usize {
        self.end + 1 - self.start
    }

    /// Never true for a checked gap.
    pub fn is_empty(&self) -> bool {
        self.end < self.start
    }
}

/// The known frames a fill reads on each side of a gap.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Context {
    /// Frames before the gap (at least 1).
    pub before: usize,
    /// Frames after the gap (at least 1).
    pub after: usize,
}

/// The fill's default context: the benchmark's (20 frames before, 1 after:
/// LaFAN1's protocol at 60 fps).
pub const DEFAULT_CONTEXT: Context = Context {
    before: 20,
    after: 1,
};

/// The longest gap `method` "model" fills with the context-tangent Hermite
/// curve; longer gaps go to the networks. Chosen on training takes (every
/// 4th training clip, 20 frames of context before and 1 after, `train/
/// deeprep_train/motion/fill_eval.py --split train --every 4`): L2P of the
/// curve against the network 0.42 / 0.83 at 10 frames and 2.04 / 2.26 at
/// 30, the network ahead from 60 (3.17 against 4.31) and 90 (3.72 against
/// 5.84). The networks were never trained with context, and at short gaps
/// the curve through the context's velocities is the better fill.
pub const HERMITE_MAX_GAP: usize = 45;

/// The gap lengths a gap-filling network's manifest gives it
/// (`fill_from..=fill_up_to`, `fill_from` 1 when absent), checked; `None`
/// when it names none.
pub fn band(from: Option<usize>, up_to: Option<usize>) -> Result<Option<(usize, usize)>> {
    match (from, up_to) {
        (None, None) => Ok(None),
        (from, Some(hi)) => {
            let lo = from.unwrap_or(1);
            if lo == 0 || lo > hi {
                return Err(Error::Invalid(format!(
                    "fill_from {lo} and fill_up_to {hi} must satisfy 1 <= fill_from <= fill_up_to"
                )));
            }
            Ok(Some((lo, hi)))
        }
        (Some(_), None) => Err(Error::Invalid("fill_from without fill_up_to".into())),
    }
}

/// The loaded gap-filling networks' bands, as [`method_for`] reads them:
/// `fill-mlp` (`tween_fill_mlp`, the short-gap network over the gap's
/// edges, [`super::fill_mlp`]), `fill` (`tween_fill`, the conditional
/// network's line) and `fill-long` (`tween_fill_long`, the residual network
/// fine-tuned on long gaps).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Bands {
    /// `fill-mlp`'s band, when it is loaded.
    pub fill_mlp: Option<(usize, usize)>,
    /// `fill`'s band, when it is loaded and its manifest gives one.
    pub fill: Option<(usize, usize)>,
    /// `fill-long`'s band, likewise.
    pub fill_long: Option<(usize, usize)>,
}

/// What fills a gap of `len` frames when `method` is asked: "model" is the
/// gap-filling network whose band (its manifest's `fill_from..=fill_up_to`)
/// holds the gap's length where one is loaded ("fill-mlp", then "fill",
/// then "fill-long"),
/// else "hermite" up to [`HERMITE_MAX_GAP`] frames and the networks'
/// default beyond; every other method is itself.
pub fn method_for(method: &str, len: usize, bands: Bands) -> &str {
    let holds = |b: Option<(usize, usize)>| b.is_some_and(|(lo, hi)| (lo..=hi).contains(&len));
    match method {
        "model" if holds(bands.fill_mlp) => "fill-mlp",
        "model" if holds(bands.fill) => "fill",
        "model" if holds(bands.fill_long) => "fill-long",
        "model" if len <= HERMITE_MAX_GAP => "hermite",
        _ => method,
    }
}

/// Most context frames on a side.
pub const MAX_CONTEXT: usize = 600;

impl Context {
    /// Parses `B` or `B,A` (`B` frames before, `A` after; `A` defaults to 1).
    pub fn parse(s: &str) -> Result<Context> {
        let bad = || {
            Error::Invalid(format!(
                "the context is B or B,A: known frames before and after each gap, 1 to {MAX_CONTEXT} (e.g. 20,1), found '{s}'"
            ))
        };
        let mut it = s.split(',').map(|v| v.trim().parse::<usize>());
        let before = it.next().ok_or_else(bad)?.map_err(|_| bad())?;
        let after = match it.next() {
            Some(v) => v.map_err(|_| bad())?,
            None => 1,
        };
        if it.next().is_some()
            || !(1..=MAX_CONTEXT).contains(&before)
            || !(1..=MAX_CONTEXT).contains(&after)
        {
            return Err(bad());
        }
        Ok(Context { before, after })
    }
}

/// Checks gaps against a clip of `frames` frames and sorts them: each
/// inside the clip, in order (start ≤ end), with a known frame on each side
/// (not touching the clip's first or last frame), none overlapping or
/// touching another (two gaps with no known frame between them are one).
pub fn check(frames: usize, gaps: &[Gap]) -> Result<Vec<Gap>> {
    if gaps.is_empty() {
        return Err(Error::Invalid("no gap to fill".into()));
    }
    for g in gaps {
        let name = format!("gap {}-{}", g.start, g.end);
        if g.start > g.end {
            return Err(Error::Invalid(format!(
                "{name} is reversed: give the first frame first ({}-{})",
                g.end, g.start
            )));
        }
        if g.end >= frames {
            return Err(Error::Invalid(format!(
                "{name} is outside the clip's {frames} frames (0-{})",
                frames.saturating_sub(1)
            )));
        }
        if g.start == 0 || g.end + 1 == frames {
            return Err(Error::Invalid(format!(
                "{name} touches the clip's {} frame: a fill needs a known frame on each side (frames 1-{} can be filled)",
                if g.start == 0 { "first" } else { "last" },
                frames.saturating_sub(2)
            )));
        }
    }
    let mut sorted = gaps.to_vec();
    sorted.sort_by_key(|g| g.start);
    for w in sorted.windows(2) {
        if w[1].start <= w[0].end + 1 {
            return Err(Error::Invalid(format!(
                "gaps {}-{} and {}-{} overlap or touch: give them as one gap, or leave a known frame between them",
                w[0].start, w[0].end, w[1].start, w[1].end
            )));
        }
    }
    Ok(sorted)
}

/// The frames of `clip` a fill of `gap` takes as keys: up to `ctx.before`
/// before it and `ctx.after` after it (fewer at the clip's ends).
pub fn key_frames(gap: Gap, ctx: Context, frames: usize) -> Vec<usize> {
    let lo = gap.start.saturating_sub(ctx.before);
    let hi = (gap.end + ctx.after).min(frames - 1);
    (lo..gap.start).chain(gap.end + 1..=hi).collect()
}

/// Fills every gap of `clip` in order. `synth(clip, keys, gap)` makes the motion
/// of one gap's key span (the [`ClipKeys`] of [`key_frames`] on the clip as
/// filled so far, [`ClipKeys::frames`] long). Returns the clip with the
/// gaps' frames synthesized and every other frame's row exactly the
/// input's.
pub fn fill(
    clip: &Bvh,
    gaps: &[Gap],
    ctx: Context,
    synth: &mut dyn FnMut(&Bvh, &ClipKeys, Gap) -> Result<Motion>,
) -> Result<Bvh> {
    let gaps = check(clip.frame_count(), gaps)?;
    let mut out = clip.clone();
    for g in &gaps {
        let frames = key_frames(*g, ctx, out.frame_count());
        let ck = super::clip::clip_keys(&out, &frames, false)?;
        let motion = synth(&out, &ck, *g)?;
        let spliced = super::clip::splice(&out, &ck, &motion)?;
        let c = out.channel_count();
        out.motion[g.start * c..(g.end + 1) * c]
            .copy_from_slice(&spliced.motion[g.start * c..(g.end + 1) * c]);
    }
    Ok(out)
}

/// A fill made by [`fill`] on `on_model`'s clip (or on `user` itself when
/// `on_model` is `None`) as the user gets it: on their skeleton (retargeted
/// back when the clip was retargeted), every frame outside the gaps their
/// own row, and as text: `user_text` (the file the clip was read from) with
/// only the gaps' lines rewritten, or the whole clip written when that text
/// is not one line a frame.
pub fn on_user(
    user: &Bvh,
    user_text: &[u8],
    filled: Bvh,
    on_model: Option<&super::clip::OnModel>,
    gaps: &[Gap],
) -> Result<(Bvh, String)> {
    let mut out = match on_model {
        Some(m) => m.back_whole(user, filled)?,
        None => filled,
    };
    let inside = |f: usize| gaps.iter().any(|g| (g.start..=g.end).contains(&f));
    super::clip::keep_rows(&mut out, user, &|f| !inside(f));
    let text = std::str::from_utf8(user_text)
        .ok()
        .and_then(|t| out.rewrite_frames(t, &inside))
        .unwrap_or_else(|| out.write());
    Ok((out, text))
}

/// Hermite basis at `u` in [0, 1]: (h00, h10, h01, h11).
fn basis(u: f64) -> [f64; 4] {
    let (u2, u3) = (u * u, u * u * u);
    [
        2.0 * u3 - 3.0 * u2 + 1.0,
        u3 - 2.0 * u2 + u,
        -2.0 * u3 + 3.0 * u2,
        u3 - u2,
    ]
}

fn quat(m: &Mat3<f64>) -> DQuat {
    DQuat::from_mat3(&to_glam_f64(m)).normalize()
}

/// A whole-pose key's rotations as unit quaternions (`None` for a key
/// without rotations).
pub(crate) fn key_quats(k: &Keyframe) -> Option<Vec<DQuat>> {
    Some(k.rotations.as_ref()?.iter().map(quat).collect())
}

/// The ends of a gap for [`hermite_curve`]: the root position and every
/// joint's rotation at the frame before the gap (`a`) and after it (`b`),
/// and at the context frames beside them (`a - 1`, `b + 1`) where known.
pub struct HermiteEnds<'a> {
    /// Root positions at `a` and `b`.
    pub root: [DVec3; 2],
    /// Rotations at `a` and `b`.
    pub rot: [&'a [DQuat]; 2],
    /// Root and rotations at `a - 1`.
    pub prev: Option<(DVec3, &'a [DQuat])>,
    /// Root and rotations at `b + 1`.
    pub next: Option<(DVec3, &'a [DQuat])>,
}

/// The rotation from `x` to `y` as a scaled axis (the short arc): the
/// tangent at `x` that [`hermite_curve`] and the short-gap network
/// ([`super::fill_mlp`]) work in; `cond.py`'s `_step` is its twin.
pub(crate) fn step(x: DQuat, y: DQuat) -> DVec3 {
    let y = if x.dot(y) < 0.0 { -y } else { y };
    (x.inverse() * y).normalize().to_scaled_axis()
}

/// The context-tangent Hermite curve over a gap of `n = b - a` frames: the
/// root and each rotation at frames `a + 1 .. b` (n - 1 of them). The end
/// tangents are the context's velocities, the step from `a - 1` to `a` and
/// from `b` to `b + 1`, or the chord (the mean velocity across the gap)
/// where that frame is not known; per coordinate for the root, in the
/// tangent space of the rotation at `a` for each joint. `train/.../cond.py`'s
/// `hermite_base` is its twin (the conditional network's base over gaps
/// with context).
pub fn hermite_curve(e: &HermiteEnds, n: usize) -> Vec<(DVec3, Vec<DQuat>)> {
    let nf = n as f64;
    let [pa, pb] = e.root;
    let chord = (pb - pa) / nf;
    let va = e.prev.map_or(chord, |(p, _)| pa - p);
    let vb = e.next.map_or(chord, |(q, _)| q - pb);
    let [qa, qb] = e.rot;
    // per joint, in the tangent space at qa: the end point, the two tangents
    let joints: Vec<(DVec3, DVec3, DVec3)> = (0..qa.len())
        .map(|j| {
            let w1 = step(qa[j], qb[j]);
            let t0 = e.prev.map_or(w1 / nf, |(_, p)| step(p[j], qa[j]));
            let t1 = e.next.map_or(w1 / nf, |(_, q)| step(qb[j], q[j]));
            (w1, t0, t1)
        })
        .collect();
    (1..n)
        .map(|f| {
            let [h00, h10, h01, h11] = basis(f as f64 / nf);
            let p = pa * h00 + va * (nf * h10) + pb * h01 + vb * (nf * h11);
            let r = joints
                .iter()
                .zip(qa)
                .map(|((w1, t0, t1), q0)| {
                    let w = *t0 * (nf * h10) + *w1 * h01 + *t1 * (nf * h11);
                    (*q0 * DQuat::from_scaled_axis(w)).normalize()
                })
                .collect();
            (p, r)
        })
        .collect()
}

/// The gap in one gap's key span (`ck`, as [`fill`] gives it): the one
/// break in its run of key frames, as (the index of the last key before
/// it, that key's frame `a`, the first frame after it `b`).
pub(crate) fn gap_of(ck: &ClipKeys) -> Result<(usize, usize, usize)> {
    let frames = &ck.clip_frames;
    let at = frames
        .windows(2)
        .position(|w| w[1] > w[0] + 1)
        .ok_or_else(|| Error::Invalid("a fill's keys leave no gap".into()))?;
    Ok((at, frames[at], frames[at + 1]))
}

/// A known frame of `clip` as a fill reads it: the root position and every
/// joint's rotation (a whole pose).
pub(crate) fn known_frame(clip: &Bvh, f: usize) -> Result<(DVec3, Vec<DQuat>)> {
    let k = Keyframe::from_bvh(clip, f, 0)?;
    let q = key_quats(&k).ok_or_else(|| Error::Invalid("a fill needs whole poses".into()))?;
    let p = &k.positions;
    Ok((DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64), q))
}

/// One gap's key span (`ck` on `clip`) as a motion: the context frames as
/// they are, the gap's frames (`a + 1 .. b`, `gap`: each root and every
/// joint's rotation) as a fill made them.
pub(crate) fn span_motion(
    clip: &Bvh,
    ck: &ClipKeys,
    (a, b): (usize, usize),
    gap: Vec<(DVec3, Vec<DQuat>)>,
) -> Result<Motion> {
    let mut gap = gap.into_iter();
    let mut m = Motion {
        root: Vec::with_capacity(ck.frames()),
        rotations: Vec::with_capacity(ck.frames()),
    };
    for f in ck.first..=ck.last {
        if f <= a || f >= b {
            let k = Keyframe::from_bvh(clip, f, 0)?;
            m.root.push([0, 1, 2].map(|i| k.positions[i] as f64));
            m.rotations.push(k.rotations.unwrap_or_default());
            continue;
        }
        let (p, r) = gap
            .next()
            .ok_or_else(|| Error::Invalid("a fill's gap ended early".into()))?;
        m.root.push(p.to_array());
        m.rotations.push(
            r.iter()
                .map(|q| from_glam_f64(&glam::DMat3::from_quat(*q)))
                .collect(),
        );
    }
    Ok(m)
}

/// The context-tangent Hermite curve over one gap's key span (`ck` on
/// `clip`): the context frames as they are, the gap's frames on
/// [`hermite_curve`] from the last frame before it to the first after it
/// (the first step after it read when two frames after are known).
pub fn hermite(clip: &Bvh, ck: &ClipKeys) -> Result<Motion> {
    let frames = &ck.clip_frames;
    let (at, a, b) = gap_of(ck)?;
    let ((ra, qa), (rb, qb)) = (known_frame(clip, a)?, known_frame(clip, b)?);
    let prev = (at > 0)
        .then(|| known_frame(clip, frames[at - 1]))
        .transpose()?;
    let next = (at + 2 < frames.len())
        .then(|| known_frame(clip, frames[at + 2]))
        .transpose()?;
    let ends = HermiteEnds {
        root: [ra, rb],
        rot: [&qa, &qb],
        prev: prev.as_ref().map(|(r, q)| (*r, q.as_slice())),
        next: next.as_ref().map(|(r, q)| (*r, q.as_slice())),
    };
    span_motion(clip, ck, (a, b), hermite_curve(&ends, b - a))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_parse_and_check() {
        assert_eq!(
            Gap::parse("200-260").unwrap(),
            Gap {
                start: 200,
                end: 260
            }
        );
        assert!(Gap::parse("200").is_err() && Gap::parse("a-b").is_err());
        let e = |g: &[(usize, usize)]| {
            let gaps: Vec<Gap> = g.iter().map(|&(start, end)| Gap { start, end }).collect();
            check(100, &gaps).unwrap_err().to_string()
        };
        assert!(e(&[(50, 40)]).contains("reversed"));
        assert!(e(&[(90, 120)]).contains("outside"));
        assert!(e(&[(0, 10)]).contains("first"));
        assert!(e(&[(80, 99)]).contains("last"));
        assert!(e(&[(10, 20), (15, 30)]).contains("overlap"));
        assert!(e(&[(10, 20), (21, 30)]).contains("touch"));
        let ok = check(
            100,
            &[Gap { start: 50, end: 60 }, Gap { start: 10, end: 20 }],
        )
        .unwrap();
        assert_eq!(ok[0].start, 10);
        assert_eq!(
            Context::parse("20").unwrap(),
            Context {
                before: 20,
                after: 1
            }
        );
        assert_eq!(
            Context::parse("20,20").unwrap(),
            Context {
                before: 20,
                after: 20
            }
        );
        assert!(
            Context::parse("0").is_err()
                && Context::parse("1,2,3").is_err()
                && Context::parse("x").is_err()
        );
    }

    #[test]
    fn the_model_fill_chooses_by_gap_length() {
        let none = Bands::default();
        let fill = |b| Bands {
            fill: Some(b),
            ..Bands::default()
        };
        assert_eq!(method_for("model", 10, none), "hermite");
        assert_eq!(method_for("model", HERMITE_MAX_GAP + 1, none), "model");
        // a gap-filling network takes the gaps its manifest claims
        assert_eq!(method_for("model", 10, fill((1, 45))), "fill");
        assert_eq!(method_for("model", 45, fill((1, 45))), "fill");
        assert_eq!(method_for("model", 46, fill((1, 45))), "model");
        assert_eq!(method_for("model", 120, fill((1, 180))), "fill");
        // below its range: the curve, as without it
        assert_eq!(method_for("model", 20, fill((21, 45))), "hermite");
        assert_eq!(method_for("model", 21, fill((21, 45))), "fill");
        // the long-gap network beside it takes its own band, the residual
        // network what is left beyond both
        let both = Bands {
            fill: Some((25, 45)),
            fill_long: Some((46, 120)),
            ..Bands::default()
        };
        assert_eq!(method_for("model", 24, both), "hermite");
        assert_eq!(method_for("model", 45, both), "fill");
        assert_eq!(method_for("model", 46, both), "fill-long");
        assert_eq!(method_for("model", 120, both), "fill-long");
        assert_eq!(method_for("model", 121, both), "model");
        // a named method is itself
        assert_eq!(method_for("hermite", 500, both), "hermite");
        assert_eq!(method_for("residual", 60, both), "residual");
        // the short-gap network takes its band first, where it overlaps
        // the others'; the rest stays theirs
        let three = Bands {
            fill_mlp: Some((10, 30)),
            ..both
        };
        assert_eq!(method_for("model", 9, three), "hermite");
        assert_eq!(method_for("model", 10, three), "fill-mlp");
        assert_eq!(method_for("model", 30, three), "fill-mlp");
        assert_eq!(method_for("model", 31, three), "fill");
        assert_eq!(method_for("model", 46, three), "fill-long");
        assert_eq!(method_for("fill", 20, three), "fill");
    }

    #[test]
    fn a_band_is_checked() {
        assert_eq!(band(None, None).unwrap(), None);
        assert_eq!(band(None, Some(45)).unwrap(), Some((1, 45)));
        assert_eq!(band(Some(46), Some(120)).unwrap(), Some((46, 120)));
        for (from, up_to) in [(Some(0), Some(4)), (Some(50), Some(40)), (Some(3), None)] {
            assert!(band(from, up_to).is_err(), "{from:?} {up_to:?}");
        }
    }

    #[test]
    fn key_frames_take_the_context_around_the_gap() {
        let g = Gap { start: 10, end: 19 };
        assert_eq!(
            key_frames(
                g,
                Context {
                    before: 3,
                    after: 2
                },
                100
            ),
            vec![7, 8, 9, 20, 21]
        );
        assert_eq!(
            key_frames(
                g,
                Context {
                    before: 30,
                    after: 1
                },
                21
            ),
            (0..10).chain([20]).collect::<Vec<_>>()
        );
    }
}

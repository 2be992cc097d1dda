//! The dense keyframe input format (thesis Fig. 5.3), with a per-coordinate
//! mask for partial keys. Mirrors `dense_input` in train/deeprep_train/motion/nets.py.

use super::spline::KeySpline;
use super::Keyframe;

/// Normalization constants, from the model manifest.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Norm {
    /// BVH units per network unit.
    pub scale: f32,
    /// Frames per distance-transform unit.
    pub dt_norm: f32,
    /// Distance-transform clip, frames.
    pub dt_clip: f32,
}

/// The x/z reference that root positions are taken relative to: the mean
/// root x and z over keys that give them (0 if none does).
pub fn root_reference(keys: &[Keyframe]) -> [f32; 2] {
    let (mut sx, mut sz, mut n) = (0.0f64, 0.0f64, 0usize);
    for k in keys.iter().filter(|k| k.mask[0] && k.mask[2]) {
        sx += k.positions[0] as f64;
        sz += k.positions[2] as f64;
        n += 1;
    }
    if n == 0 {
        [0.0, 0.0]
    } else {
        [(sx / n as f64) as f32, (sz / n as f64) as f32]
    }
}

/// The network-space pose of a key (`joints × 3`, divided by scale, root x/z
/// relative to `reference`).
pub fn key_pose(k: &Keyframe, reference: [f32; 2], norm: &Norm) -> Vec<f32> {
    let mut p: Vec<f32> = k.positions.clone();
    p[0] -= reference[0];
    p[2] -= reference[1];
    p.iter().map(|v| v / norm.scale).collect()
}

/// Builds the dense input `[2P, frames]` (row-major: channel, then frame)
/// for keyframe positions: per coordinate, the value at the nearest frame
/// where it is given (ties go to the earlier frame), then the distance to it
/// in frames / `dt_norm`, clipped at `dt_clip`. Coordinates no key gives are
/// 0 with distance `dt_clip`.
pub fn dense_input(keys: &[Keyframe], frames: usize, norm: &Norm) -> Vec<f32> {
    let reference = root_reference(keys);
    let rows: Vec<(usize, Vec<f32>, Vec<bool>)> = keys
        .iter()
        .map(|k| (k.frame, key_pose(k, reference, norm), k.mask.clone()))
        .collect();
    let width = keys.first().map_or(0, |k| k.positions.len());
    dense_channels(&rows, width, frames, norm)
}

/// The dense format for any per-frame vectors: `rows` are (frame, values,
/// mask), sorted by frame, each `width` long. Returns `[2·width, frames]`.
pub fn dense_channels(
    rows: &[(usize, Vec<f32>, Vec<bool>)],
    width: usize,
    frames: usize,
    norm: &Norm,
) -> Vec<f32> {
    let p = width;
    let mut out = vec![0.0f32; 2 * p * frames];
    for c in 0..p {
        let given: Vec<usize> = (0..rows.len()).filter(|&i| rows[i].2[c]).collect();
        let (vals, dists) = out.split_at_mut(p * frames);
        let vrow = &mut vals[c * frames..(c + 1) * frames];
        let drow = &mut dists[c * frames..(c + 1) * frames];
        if given.is_empty() {
            drow.iter_mut()
                .for_each(|d| *d = norm.dt_clip / norm.dt_norm);
            continue;
        }
        let mut g = 0; // index into `given` of the last row at or before t
        for t in 0..frames {
            while g + 1 < given.len() && rows[given[g + 1]].0 <= t {
                g += 1;
            }
            let a = given[g];
            let fa = rows[a].0;
            let (src, dist) = if fa <= t {
                match given.get(g + 1) {
                    Some(&b) if rows[b].0 - t < t - fa => (b, rows[b].0 - t),
                    _ => (a, t - fa),
                }
            } else {
                (a, fa - t) // t is before every row that gives c
            };
            vrow[t] = rows[src].1[c];
            drow[t] = (dist as f32).min(norm.dt_clip) / norm.dt_norm;
        }
    }
    out
}

/// Fills `[width, frames]`: per channel, `curve` built from the `(frame,
/// value)` rows that give the channel, sampled at every frame; 0 where no
/// row gives it.
fn per_channel<C: Fn(f64) -> f64>(
    rows: &[(usize, Vec<f32>, Vec<bool>)],
    width: usize,
    frames: usize,
    curve: impl Fn(Vec<(f64, f64)>) -> C,
) -> Vec<f32> {
    let mut out = vec![0.0f32; width * frames];
    for c in 0..width {
        let keys: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.2[c])
            .map(|r| (r.0 as f64, r.1[c] as f64))
            .collect();
        if keys.is_empty() {
            continue;
        }
        let f = curve(keys);
        for (t, v) in out[c * frames..(c + 1) * frames].iter_mut().enumerate() {
            *v = f(t as f64) as f32;
        }
    }
    out
}

/// Per channel, linear interpolation between the previous and the next row
/// that gives the channel (held before the first and after the last; 0
/// where no row gives it). Rows must be sorted by frame. Returns `[width,
/// frames]`. Mirrors `interp_channels` in train/deeprep_train/motion/nets.py.
pub fn interp_channels(
    rows: &[(usize, Vec<f32>, Vec<bool>)],
    width: usize,
    frames: usize,
) -> Vec<f32> {
    per_channel(rows, width, frames, |keys| {
        move |t: f64| {
            let b = keys.partition_point(|k| k.0 <= t);
            if b == 0 {
                return keys[0].1; // before the first row
            }
            if b == keys.len() {
                return keys[b - 1].1; // at or after the last row
            }
            let ((ta, va), (tb, vb)) = (keys[b - 1], keys[b]);
            va + (t - ta) / (tb - ta) * (vb - va)
        }
    })
}

/// Per channel, a [`KeySpline`] through the rows that give the channel
/// (uniform Catmull-Rom when they are evenly spaced, C1 otherwise). Held
/// before the first and after the last row; 0 where no row gives it. Rows
/// must be sorted by frame. Returns `[width, frames]`. Mirrors
/// `spline_channels` in train/deeprep_train/motion/nets.py.
pub fn spline_channels(
    rows: &[(usize, Vec<f32>, Vec<bool>)],
    width: usize,
    frames: usize,
) -> Vec<f32> {
    per_channel(rows, width, frames, |keys| {
        let s = KeySpline::new(keys);
        move |t| s.at(t)
    })
}

/// What the generator corrects between whole-pose keys (the manifest's
/// `base`; models exported before it existed are [`Base::Linear`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Base {
    /// Raw RC-FK values, [`interp_channels`].
    #[default]
    Linear,
    /// Raw RC-FK values, [`spline_channels`].
    Spline,
    /// Root 6D raw; Euler channels linear in range position `tanh(v)`,
    /// i.e. linear in angle.
    AngleLinear,
    /// As [`Base::AngleLinear`], on a spline.
    AngleSpline,
}

/// The base the generator corrects: `rows` (whole-pose keys' raw RC-FK
/// values, root 6D first) interpolated as `base` says. Returns `[width,
/// frames]`. Mirrors `base_channels` in train/deeprep_train/motion/nets.py.
pub fn base_channels(
    rows: &[(usize, Vec<f32>, Vec<bool>)],
    width: usize,
    frames: usize,
    base: Base,
) -> Vec<f32> {
    let spline = matches!(base, Base::Spline | Base::AngleSpline);
    let between = |r: &[(usize, Vec<f32>, Vec<bool>)]| {
        if spline {
            spline_channels(r, width, frames)
        } else {
            interp_channels(r, width, frames)
        }
    };
    if matches!(base, Base::Linear | Base::Spline) {
        return between(rows);
    }
    let to_angle: Vec<_> = rows
        .iter()
        .map(|(f, v, m)| {
            let mut v = v.clone();
            v.iter_mut().skip(6).for_each(|x| *x = x.tanh());
            (*f, v, m.clone())
        })
        .collect();
    let mut out = between(&to_angle);
    let lim = crate::rcfk::V_CLIP.tanh() as f32;
    out.iter_mut()
        .skip(6 * frames)
        .for_each(|x| *x = x.clamp(-lim, lim).atanh());
    out
}

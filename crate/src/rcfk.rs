//! Range-Constrained Forward Kinematics (thesis Sec. 5.2.3, Table D.1).
//!
//! Every non-root joint rotates in a local frame whose z axis runs along its
//! child bone (the mean of the child bones where there are several). The
//! network outputs unconstrained values `v`; each Euler angle is
//! `u = α + (β − α)(tanh v + 1)/2 ∈ [α, β]`. Eq. 5.3 as printed,
//! `u = (α − β) tanh v + (α − β)/2`, does not land in [α, β] (for α = −45°,
//! β = 45° it spans [−135°, 45°]); this is its evident intent, tanh mapped
//! onto the range. The local rotation `R^l_l` multiplies the elementary
//! rotations in the joint's intrinsic order (X1Z2Y3 for most joints, Y1X2Z3
//! for the forearms), and the rotation in the BVH joint frame is
//! `R^w_l = M_lw R^l_l M_wl`. The root (hip) uses the continuous 6D
//! representation.
//!
//! The thesis fixes only the local z axis. Here local x is world X made
//! perpendicular to z, except for bones that run along X (the arms), whose
//! local y is world Y made perpendicular to z. The forearms take local y
//! from the elbow's hinge axis, fitted to the CMU data by
//! `train/deeprep_train/motion/fit_frames.py` (the table's `frame` field, see [`FrameRule`]):
//! there the elbow is an exact hinge, so Table D.1's forearm ranges (no
//! bending about x) hold to within 0.1° on average. The frames are
//! right-handed.
//!
//! The ranges and orders are data (`crate/data/table_d1.json`, shared with
//! the PyTorch layer in train/), not code branches.

use crate::error::{Error, Result};
use crate::rotation::euler::{euler_to_matrix, matrix_to_euler, EulerOrder};
use crate::rotation::sixd::{matrix_to_6d, sixd_to_matrix};
use crate::rotation::{cross, dot, from_cols, mul, mul_vec, norm, transpose, Mat3};
use crate::skeleton::Bvh;
use serde::Deserialize;

/// Bound on |v| when rotations are mapped back into the raw space.
pub const V_CLIP: f64 = 3.0;

/// Table D.1 as shipped with the crate.
pub const TABLE_D1_JSON: &str = include_str!("../data/table_d1.json");

#[derive(Deserialize)]
struct TableDoc {
    joints: Vec<TableRow>,
}

/// One row of the range table.
#[derive(Clone, Debug, Deserialize)]
pub struct TableRow {
    /// Joint name.
    pub joint: String,
    /// Range of the rotation about local x, degrees; `None` for End Sites.
    pub x: Option<[f64; 2]>,
    /// Range about local y.
    pub y: Option<[f64; 2]>,
    /// Range about local z.
    pub z: Option<[f64; 2]>,
    /// Intrinsic order, lower case as in the table ("xzy", "yxz").
    pub order: String,
    /// How the local x/y axes are chosen (this project's field, not the
    /// thesis'): "x" (default), "z", or `{"y": [..]}` (an explicit local y,
    /// the hinge axis fitted to the data); see [`FrameRule`].
    #[serde(default)]
    pub frame: Option<FrameSpec>,
}

/// The `frame` field of a table row, as written in the JSON.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum FrameSpec {
    /// A named rule: "x" or "z".
    Rule(String),
    /// An explicit local y axis in the joint's BVH coordinates.
    Axis {
        /// The axis; it is made perpendicular to the bone and normalized.
        y: [f64; 3],
    },
}

/// Parses a range table (the format of `table_d1.json`).
pub fn parse_table(json: &str) -> Result<Vec<TableRow>> {
    let doc: TableDoc =
        serde_json::from_str(json).map_err(|e| Error::Invalid(format!("range table: {e}")))?;
    Ok(doc.joints)
}

/// A skeleton prepared for RC-FK.
#[derive(Clone, Debug)]
pub struct RcSkeleton {
    /// Joint names (BVH order, End Sites included).
    pub names: Vec<String>,
    /// Parent per joint.
    pub parents: Vec<Option<usize>>,
    /// Rest offsets.
    pub offsets: Vec<[f64; 3]>,
    /// `M_lw` per joint: columns are the local x, y, z axes in the BVH frame.
    pub frames: Vec<Mat3<f64>>,
    /// The joints that the network rotates (non-root, with channels), in
    /// output order.
    pub rotating: Vec<usize>,
    /// Per rotating joint: `[[αx, βx], [αy, βy], [αz, βz]]` in radians.
    pub ranges: Vec<[[f64; 2]; 3]>,
    /// Per rotating joint: intrinsic Euler order.
    pub orders: Vec<EulerOrder>,
}

/// Range violations of one joint over a clip, from [`RcSkeleton::inverse`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Violation {
    /// Joint name.
    pub joint: String,
    /// Frames where any angle was outside its range.
    pub frames: usize,
    /// Largest excess, degrees.
    pub max_deg: f64,
    /// Mean excess over all frames and axes, degrees.
    pub mean_deg: f64,
}

/// Range-constrained angles of one frame.
#[derive(Clone, Debug)]
pub struct RcFrame {
    /// Root rotation in 6D.
    pub root_6d: [f64; 6],
    /// Root position.
    pub root_pos: [f64; 3],
    /// Per rotating joint, `[ux, uy, uz]` in radians, clamped to the ranges.
    pub angles: Vec<[f64; 3]>,
    /// Per rotating joint, how far (radians) each angle was outside its range.
    pub excess: Vec<[f64; 3]>,
}

/// How a joint's local x/y axes are picked around its bone axis z.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum FrameRule {
    /// Local x is world X made perpendicular to z; for bones along X (|z·X| ≥
    /// 0.7), local y is world Y made perpendicular to z.
    WorldX,
    /// Local x is world Z (forward) made perpendicular to z.
    WorldZ,
    /// Local y is the given axis made perpendicular to z (a hinge axis fitted
    /// to the data, `train/deeprep_train/motion/fit_frames.py`); local x = y × z.
    AxisY([f64; 3]),
}

/// The local frame `M_lw` of a joint whose child bones have mean direction
/// `d`, by the default rule ([`FrameRule::WorldX`]).
pub fn local_frame(d: [f64; 3]) -> Mat3<f64> {
    local_frame_with(d, FrameRule::WorldX)
}

/// The local frame `M_lw` (columns x, y, z; right-handed) of a joint whose
/// child bones have mean direction `d`.
pub fn local_frame_with(d: [f64; 3], rule: FrameRule) -> Mat3<f64> {
    let n = norm(&d);
    if n < 1e-9 {
        return crate::rotation::identity();
    }
    let z = [d[0] / n, d[1] / n, d[2] / n];
    let perp = |r: [f64; 3]| {
        let k = dot(&r, &z);
        let v = [r[0] - k * z[0], r[1] - k * z[1], r[2] - k * z[2]];
        let m = norm(&v);
        [v[0] / m, v[1] / m, v[2] / m]
    };
    if let FrameRule::AxisY(a) = rule {
        let y = perp(a);
        if y.iter().all(|v| v.is_finite()) {
            let x = cross(&y, &z);
            return from_cols(x, y, z);
        }
    }
    if rule == FrameRule::WorldZ && z[2].abs() < 0.7 {
        let x = perp([0.0, 0.0, 1.0]);
        let y = cross(&z, &x);
        from_cols(x, y, z)
    } else if z[0].abs() < 0.7 {
        let x = perp([1.0, 0.0, 0.0]);
        let y = cross(&z, &x);
        from_cols(x, y, z)
    } else {
        let y = perp([0.0, 1.0, 0.0]);
        let x = cross(&y, &z);
        from_cols(x, y, z)
    }
}

impl RcSkeleton {
    /// Prepares a BVH skeleton with a range table (see [`TABLE_D1_JSON`]).
    /// Every joint with channels except the root must be in the table.
    pub fn new(bvh: &Bvh, table: &[TableRow]) -> Result<Self> {
        let n = bvh.joints.len();
        if n == 0 {
            return Err(Error::Invalid("RC-FK: the skeleton has no joints".into()));
        }
        let children = bvh.children();
        let offsets: Vec<[f64; 3]> = bvh
            .joints
            .iter()
            .map(|j| j.offset.map(|v| v as f64))
            .collect();
        let rule_of = |name: &str| -> Result<FrameRule> {
            match table
                .iter()
                .find(|r| r.joint == name)
                .and_then(|r| r.frame.as_ref())
            {
                None => Ok(FrameRule::WorldX),
                Some(FrameSpec::Rule(r)) if r == "x" => Ok(FrameRule::WorldX),
                Some(FrameSpec::Rule(r)) if r == "z" => Ok(FrameRule::WorldZ),
                Some(FrameSpec::Axis { y }) if y.iter().all(|v| v.is_finite()) => {
                    Ok(FrameRule::AxisY(*y))
                }
                Some(other) => Err(Error::Invalid(format!(
                    "RC-FK: joint '{name}' has an unknown frame rule {other:?} (\"x\", \"z\" or {{\"y\": [x, y, z]}})"
                ))),
            }
        };
        let frames = (0..n)
            .map(|j| {
                let mut d = [0.0; 3];
                for &c in &children[j] {
                    for k in 0..3 {
                        d[k] += offsets[c][k] / children[j].len() as f64;
                    }
                }
                Ok(local_frame_with(d, rule_of(&bvh.joints[j].name)?))
            })
            .collect::<Result<Vec<_>>>()?;
        let mut rotating = Vec::new();
        let mut ranges = Vec::new();
        let mut orders = Vec::new();
        for (i, j) in bvh.joints.iter().enumerate() {
            if j.parent.is_none() || j.end_site || j.channels.is_empty() {
                continue;
            }
            let row = table.iter().find(|r| r.joint == j.name).ok_or_else(|| {
                Error::Invalid(format!(
                    "RC-FK: joint '{}' is not in the range table",
                    j.name
                ))
            })?;
            let rad = |r: Option<[f64; 2]>| -> Result<[f64; 2]> {
                let r = r.ok_or_else(|| {
                    Error::Invalid(format!("RC-FK: joint '{}' has no range", j.name))
                })?;
                Ok([r[0].to_radians(), r[1].to_radians()])
            };
            rotating.push(i);
            ranges.push([rad(row.x)?, rad(row.y)?, rad(row.z)?]);
            orders.push(EulerOrder::intrinsic(&row.order)?);
        }
        Ok(RcSkeleton {
            names: bvh.joints.iter().map(|j| j.name.clone()).collect(),
            parents: bvh.joints.iter().map(|j| j.parent).collect(),
            offsets,
            frames,
            rotating,
            ranges,
            orders,
        })
    }

    /// The thesis skeleton's table (Table D.1).
    pub fn thesis(bvh: &Bvh) -> Result<Self> {
        Self::new(bvh, &parse_table(TABLE_D1_JSON)?)
    }

    /// Numbers per frame of network output: 6 (root 6D) + 3 per rotating joint.
    pub fn output_dim(&self) -> usize {
        6 + 3 * self.rotating.len()
    }

    /// Local rotation (BVH joint frame) of rotating joint `k` from angles
    /// `[ux, uy, uz]` in radians (not clamped).
    pub fn rotation_for(&self, k: usize, u: [f64; 3]) -> Mat3<f64> {
        self.rotation_from_angles(k, u)
    }

    /// Local rotation in the BVH joint frame from angles `[ux, uy, uz]`.
    fn rotation_from_angles(&self, k: usize, u: [f64; 3]) -> Mat3<f64> {
        let o = self.orders[k];
        let seq = [
            u[o.axes[0] as usize],
            u[o.axes[1] as usize],
            u[o.axes[2] as usize],
        ];
        let rl = euler_to_matrix(&seq, o);
        let m = &self.frames[self.rotating[k]];
        mul(&mul(m, &rl), &transpose(m))
    }

    /// Local rotations (BVH joint frames) of one frame of network output:
    /// `raw` = root 6D then `v` per rotating joint (mapped through tanh onto
    /// the ranges). Joints that do not rotate get the identity.
    pub fn local_rotations(&self, raw: &[f32]) -> Result<Vec<Mat3<f64>>> {
        if raw.len() != self.output_dim() {
            return Err(Error::Shape {
                what: "RC-FK frame".into(),
                expected: format!(
                    "{} numbers (6 + 3 × {} joints)",
                    self.output_dim(),
                    self.rotating.len()
                ),
                found: format!("{}", raw.len()),
            });
        }
        crate::error::check_finite("RC-FK frame", raw)?;
        let r6: [f64; 6] = std::array::from_fn(|i| raw[i] as f64);
        let root = sixd_to_matrix(&r6)?;
        let mut local = vec![crate::rotation::identity::<f64>(); self.names.len()];
        local[0] = root;
        for (k, &j) in self.rotating.iter().enumerate() {
            let mut u = [0.0; 3];
            for a in 0..3 {
                let v = raw[6 + 3 * k + a] as f64;
                let [lo, hi] = self.ranges[k][a];
                u[a] = lo + (hi - lo) * (v.tanh() + 1.0) / 2.0;
            }
            local[j] = self.rotation_from_angles(k, u);
        }
        Ok(local)
    }

    /// RC-FK of one frame: `raw` = root 6D then `v` per rotating joint
    /// (unconstrained; mapped through tanh). Returns global positions,
    /// `joints × 3`.
    pub fn forward(&self, raw: &[f32], root_pos: [f32; 3]) -> Result<Vec<f32>> {
        let local = self.local_rotations(raw)?;
        Ok(self.fk(&local, root_pos.map(|v| v as f64)))
    }

    /// Plain FK from local rotations (BVH frame) and a root position.
    pub fn fk(&self, local: &[Mat3<f64>], root_pos: [f64; 3]) -> Vec<f32> {
        let n = self.names.len();
        let mut rot = vec![crate::rotation::identity::<f64>(); n];
        let mut pos = vec![[0.0f64; 3]; n];
        for j in 0..n {
            match self.parents[j] {
                None => {
                    rot[j] = local[j];
                    let o = self.offsets[j];
                    pos[j] = [o[0] + root_pos[0], o[1] + root_pos[1], o[2] + root_pos[2]];
                }
                Some(p) => {
                    let t = mul_vec(&rot[p], &self.offsets[j]);
                    pos[j] = [pos[p][0] + t[0], pos[p][1] + t[1], pos[p][2] + t[2]];
                    rot[j] = mul(&rot[p], &local[j]);
                }
            }
        }
        pos.iter().flat_map(|p| p.map(|v| v as f32)).collect()
    }

    /// The inverse map for one BVH frame: range-constrained Euler angles per
    /// rotating joint (clamped), how far each was outside, the root 6D and
    /// position. Of the two Euler solutions of a rotation, the one closer to
    /// the ranges is taken.
    pub fn inverse(&self, bvh: &Bvh, frame: usize) -> Result<RcFrame> {
        if frame >= bvh.frame_count() {
            return Err(Error::Invalid(format!(
                "frame {frame} is outside the clip's {} frames",
                bvh.frame_count()
            )));
        }
        if bvh.joints.len() != self.names.len() {
            return Err(Error::Shape {
                what: "RC-FK inverse".into(),
                expected: format!("a skeleton of {} joints", self.names.len()),
                found: format!("{}", bvh.joints.len()),
            });
        }
        let pose = crate::skeleton::Pose::read(bvh, bvh.frame(frame));
        let t0 = pose.translations[0];
        let root_pos = [
            t0.x - self.offsets[0][0],
            t0.y - self.offsets[0][1],
            t0.z - self.offsets[0][2],
        ];
        let local = pose.rotation_matrices();
        let mut angles = Vec::with_capacity(self.rotating.len());
        let mut excess = Vec::with_capacity(self.rotating.len());
        for k in 0..self.rotating.len() {
            let (c, e) = self.angles_of(k, &local[self.rotating[k]]);
            angles.push(c);
            excess.push(e);
        }
        Ok(RcFrame {
            root_6d: matrix_to_6d(&local[0]),
            root_pos,
            angles,
            excess,
        })
    }

    /// The range-constrained angles `[ux, uy, uz]` (radians, clamped) of
    /// rotating joint `k` whose local rotation (BVH joint frame) is `r`, and
    /// how far each was outside its range. Of the two Euler solutions, the
    /// one closer to the ranges is taken.
    pub fn angles_of(&self, k: usize, r: &Mat3<f64>) -> ([f64; 3], [f64; 3]) {
        let m = &self.frames[self.rotating[k]];
        let rl = mul(&mul(&transpose(m), r), m);
        let o = self.orders[k];
        let s = matrix_to_euler(&rl, o);
        let pi = std::f64::consts::PI;
        let wrap = |a: f64| {
            if a > pi {
                a - 2.0 * pi
            } else if a < -pi {
                a + 2.0 * pi
            } else {
                a
            }
        };
        let alt = [wrap(s[0] + pi), wrap(pi - s[1]), wrap(s[2] + pi)];
        let by_axis = |seq: [f64; 3]| {
            let mut u = [0.0; 3];
            for (slot, ax) in o.axes.iter().enumerate() {
                u[*ax as usize] = seq[slot];
            }
            u
        };
        let measure = |u: [f64; 3]| {
            let mut c = [0.0; 3];
            let mut e = [0.0; 3];
            for a in 0..3 {
                let [lo, hi] = self.ranges[k][a];
                c[a] = u[a].clamp(lo, hi);
                e[a] = (u[a] - c[a]).abs();
            }
            (c, e)
        };
        let (c1, e1) = measure(by_axis(s));
        let (c2, e2) = measure(by_axis(alt));
        if e2.iter().sum::<f64>() < e1.iter().sum::<f64>() {
            (c2, e2)
        } else {
            (c1, e1)
        }
    }

    /// The generator's raw space for a pose given by local rotations: root
    /// 6D, then per rotating joint `v = atanh(2(u − α)/(β − α) − 1)` with
    /// `|v| ≤ V_CLIP` (0 for zero-width ranges), `u` the clamped angles.
    /// Mirrors `rc_to_raw` in train/deeprep_train/motion/nets.py.
    pub fn raw_from_rotations(&self, local: &[Mat3<f64>]) -> Vec<f32> {
        let mut out = Vec::with_capacity(self.output_dim());
        out.extend(matrix_to_6d(&local[0]).iter().map(|v| *v as f32));
        let lim = V_CLIP.tanh();
        for k in 0..self.rotating.len() {
            let (u, _) = self.angles_of(k, &local[self.rotating[k]]);
            for a in 0..3 {
                let [lo, hi] = self.ranges[k][a];
                let v = if hi > lo {
                    (2.0 * (u[a] - lo) / (hi - lo) - 1.0)
                        .clamp(-lim, lim)
                        .atanh()
                } else {
                    0.0
                };
                out.push(v as f32);
            }
        }
        out
    }

    /// Range violations per rotating joint over a whole clip.
    pub fn violations(&self, bvh: &Bvh) -> Result<Vec<Violation>> {
        let mut out: Vec<Violation> = self
            .rotating
            .iter()
            .map(|&j| Violation {
                joint: self.names[j].clone(),
                ..Default::default()
            })
            .collect();
        let frames = bvh.frame_count();
        for f in 0..frames {
            let r = self.inverse(bvh, f)?;
            for (k, e) in r.excess.iter().enumerate() {
                let m = e.iter().cloned().fold(0.0, f64::max).to_degrees();
                if m > 1e-6 {
                    out[k].frames += 1;
                }
                out[k].max_deg = out[k].max_deg.max(m);
                out[k].mean_deg +=
                    e.iter().sum::<f64>().to_degrees() / (3.0 * frames.max(1) as f64);
            }
        }
        Ok(out)
    }

    /// Positions of a frame rebuilt from its clamped angles (what RC-FK can
    /// represent of the clip).
    pub fn reconstruct(&self, r: &RcFrame) -> Result<Vec<f32>> {
        let mut local = vec![crate::rotation::identity::<f64>(); self.names.len()];
        local[0] = sixd_to_matrix(&r.root_6d)?;
        for (k, &j) in self.rotating.iter().enumerate() {
            local[j] = self.rotation_from_angles(k, r.angles[k]);
        }
        Ok(self.fk(&local, r.root_pos))
    }
}

//! Inverse kinematics from joint positions (thesis Sec. 4.4.3, Table 5.1).
//!
//! A small MLP, trained in `train/deeprep_train/ik/train.py` and exported by
//! `train/deeprep_train/ik/export.py`, maps the joint positions of a pose (hip at the
//! origin, world orientation) to one rotation per joint in the
//! representation named by its manifest; this module runs it with tract and
//! decodes the values into BVH joint rotations:
//!
//! - `rc`: root 6D plus range-constrained Euler angles through
//!   [`RcSkeleton`] (Table D.1), the project's RC-FK;
//! - `6d`: 6D per joint with channels (eq. C.2–C.3);
//! - `quat`: a quaternion `[w, x, y, z]` per joint (normalized);
//! - `euler`: angles `Rz · Rx · Ry` per joint (the CMU channel order).
//!
//! Use it to lift a pose given as joint positions (drawn, or from a 3-D
//! pose estimator) to a skeleton that can be animated and exported as BVH.

use crate::error::{check_finite, Error, Result};
use crate::motion::Motion;
use crate::rcfk::{RcSkeleton, TableRow};
use crate::rotation::euler::{euler_to_matrix, EulerOrder};
use crate::rotation::quat::quat_to_matrix;
use crate::rotation::sixd::sixd_to_matrix;
use crate::rotation::{identity, Mat3};
use crate::runtime::{Model, TensorF32};
use crate::skeleton::{fk, Bvh};
use serde::Deserialize;

/// How the network's outputs encode rotations.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum IkRepresentation {
    /// Root 6D and range-constrained Euler angles (RC-FK).
    Rc,
    /// 6D per joint.
    SixD,
    /// Quaternion `[w, x, y, z]` per joint.
    Quat,
    /// Euler angles `Rz · Rx · Ry` (radians) per joint.
    Euler,
}

impl IkRepresentation {
    /// Parses the manifest's name: "rc", "6d", "quat" or "euler".
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "rc" => Ok(Self::Rc),
            "6d" => Ok(Self::SixD),
            "quat" => Ok(Self::Quat),
            "euler" => Ok(Self::Euler),
            other => Err(Error::Invalid(format!(
                "IK manifest: unknown representation '{other}' (rc, 6d, quat or euler)"
            ))),
        }
    }
}

#[derive(Deserialize)]
struct Manifest {
    representation: String,
    skeleton_bvh: String,
    #[serde(default)]
    range_table: Option<Vec<TableRow>>,
}

/// The result of [`IkModel::solve`].
#[derive(Clone, Debug)]
pub struct IkSolution {
    /// Root positions (the input hips) and local rotations per frame.
    pub motion: Motion,
    /// The same poses as a BVH clip on the model's skeleton (60 fps).
    pub bvh: Bvh,
    /// Forward kinematics of the solution: global positions, flat
    /// `frames × joints × 3`.
    pub positions: Vec<f32>,
    /// Mean distance between input and reconstructed joints (file units).
    pub mean_error: f64,
    /// Largest such distance.
    pub max_error: f64,
}

/// A loaded IK network with its skeleton.
pub struct IkModel {
    model: Model,
    rep: IkRepresentation,
    template: Bvh,
    rc: Option<RcSkeleton>,
    /// Joints with rotation channels, in output order (non-RC forms).
    channel_joints: Vec<usize>,
}

impl IkModel {
    /// Loads the network from ONNX bytes and its manifest JSON.
    pub fn new(onnx: &[u8], manifest_json: &str) -> Result<Self> {
        let m: Manifest = serde_json::from_str(manifest_json)
            .map_err(|e| Error::Invalid(format!("IK manifest: {e}")))?;
        let rep = IkRepresentation::parse(&m.representation)?;
        let template = Bvh::parse(&m.skeleton_bvh)?;
        let rc = match rep {
            IkRepresentation::Rc => {
                let table = m.range_table.as_ref().ok_or_else(|| {
                    Error::Invalid("IK manifest: representation 'rc' needs a range_table".into())
                })?;
                Some(RcSkeleton::new(&template, table)?)
            }
            _ => None,
        };
        let channel_joints = template
            .joints
            .iter()
            .enumerate()
            .filter(|(_, j)| j.channels.iter().any(|c| c.is_rotation()))
            .map(|(i, _)| i)
            .collect();
        Ok(IkModel {
            model: Model::from_onnx_bytes(onnx)?,
            rep,
            template,
            rc,
            channel_joints,
        })
    }

    /// Loads `ik.onnx` and `ik.manifest.json` from a folder.
    pub fn load_dir(dir: &std::path::Path) -> Result<Self> {
        let read = |n: &str| crate::runtime::read_file(dir, n);
        let manifest = String::from_utf8(read("ik.manifest.json")?)
            .map_err(|e| Error::Invalid(format!("ik.manifest.json: {e}")))?;
        Self::new(&read("ik.onnx")?, &manifest)
    }

    /// The representation the network outputs.
    pub fn representation(&self) -> IkRepresentation {
        self.rep
    }

    /// The skeleton (hierarchy and offsets; no motion).
    pub fn skeleton(&self) -> &Bvh {
        &self.template
    }

    /// Joints per pose (End Sites included).
    pub fn joints(&self) -> usize {
        self.template.joints.len()
    }

    /// Numbers per frame of network output.
    pub fn output_dim(&self) -> usize {
        match self.rep {
            IkRepresentation::Rc => self.rc.as_ref().map_or(0, |r| r.output_dim()),
            IkRepresentation::SixD => 6 * self.channel_joints.len(),
            IkRepresentation::Quat => 4 * self.channel_joints.len(),
            IkRepresentation::Euler => 3 * self.channel_joints.len(),
        }
    }

    /// Raw network outputs for `frames` poses of global joint positions
    /// (flat `frames × joints × 3`; each pose is moved so that its hip is
    /// at the origin first, as in training).
    pub fn run_raw(&self, positions: &[f32], frames: usize) -> Result<Vec<f32>> {
        let j = self.joints();
        if frames == 0 {
            return Err(Error::Invalid("IK: no frames".into()));
        }
        // checked: a frame count from the caller must not wrap (32-bit wasm)
        if frames.checked_mul(j * 3) != Some(positions.len()) {
            return Err(Error::Shape {
                what: "IK positions".into(),
                expected: format!("{frames} frames × {j} joints × 3 numbers"),
                found: format!("{}", positions.len()),
            });
        }
        check_finite("IK positions", positions)?;
        let mut centred = positions.to_vec();
        for f in 0..frames {
            let hip = [
                positions[f * j * 3],
                positions[f * j * 3 + 1],
                positions[f * j * 3 + 2],
            ];
            for k in 0..j {
                for a in 0..3 {
                    centred[(f * j + k) * 3 + a] -= hip[a];
                }
            }
        }
        let out = self
            .model
            .run(&[TensorF32::new(centred, vec![frames, j * 3])?])?;
        let out = out
            .into_iter()
            .next()
            .ok_or_else(|| Error::Invalid("IK model returned no output".into()))?;
        if out.data.len() != frames * self.output_dim() {
            return Err(Error::Shape {
                what: "IK model output".into(),
                expected: format!("{frames} × {}", self.output_dim()),
                found: format!("{:?}", out.shape),
            });
        }
        Ok(out.data)
    }

    /// Local rotations (BVH joint frames) of one frame of network output.
    pub fn decode(&self, raw: &[f32]) -> Result<Vec<Mat3<f64>>> {
        if raw.len() != self.output_dim() {
            return Err(Error::Shape {
                what: "IK frame".into(),
                expected: format!("{}", self.output_dim()),
                found: format!("{}", raw.len()),
            });
        }
        if let Some(rc) = &self.rc {
            return rc.local_rotations(raw);
        }
        let mut local = vec![identity::<f64>(); self.joints()];
        let zxy = EulerOrder::intrinsic("zxy")?;
        for (k, &j) in self.channel_joints.iter().enumerate() {
            local[j] = match self.rep {
                IkRepresentation::SixD => {
                    let r: [f64; 6] = std::array::from_fn(|i| raw[6 * k + i] as f64);
                    sixd_to_matrix(&r)?
                }
                IkRepresentation::Quat => {
                    let [w, x, y, z]: [f64; 4] = std::array::from_fn(|i| raw[4 * k + i] as f64);
                    quat_to_matrix(&[x, y, z, w])?
                }
                IkRepresentation::Euler => {
                    let a: [f64; 3] = std::array::from_fn(|i| raw[3 * k + i] as f64);
                    euler_to_matrix(&a, zxy)
                }
                IkRepresentation::Rc => unreachable!("handled above"),
            };
        }
        Ok(local)
    }

    /// Solves IK for `frames` poses of global joint positions (flat
    /// `frames × joints × 3`, this skeleton's joint order, file units). The
    /// root of the result sits at each input hip.
    pub fn solve(&self, positions: &[f32], frames: usize) -> Result<IkSolution> {
        let raw = self.run_raw(positions, frames)?;
        let d = self.output_dim();
        let j = self.joints();
        let mut motion = Motion {
            root: Vec::with_capacity(frames),
            rotations: Vec::with_capacity(frames),
        };
        for f in 0..frames {
            let p = &positions[f * j * 3..f * j * 3 + 3];
            motion.root.push([p[0] as f64, p[1] as f64, p[2] as f64]);
            motion
                .rotations
                .push(self.decode(&raw[f * d..(f + 1) * d])?);
        }
        let bvh = motion.to_bvh(&self.template, 1.0 / 60.0)?;
        let rec = fk::positions(&bvh, 0, frames)?;
        let (mut sum, mut max) = (0.0f64, 0.0f64);
        for (a, b) in rec.chunks(3).zip(positions.chunks(3)) {
            let e = (((a[0] - b[0]) as f64).powi(2)
                + ((a[1] - b[1]) as f64).powi(2)
                + ((a[2] - b[2]) as f64).powi(2))
            .sqrt();
            sum += e;
            max = max.max(e);
        }
        Ok(IkSolution {
            motion,
            bvh,
            positions: rec,
            mean_error: sum / (frames * j) as f64,
            max_error: max,
        })
    }

    /// [`Self::solve`], written as a BVH clip on the model's skeleton.
    pub fn solve_to_bvh(&self, positions: &[f32], frames: usize, frame_time: f64) -> Result<Bvh> {
        let mut bvh = self.solve(positions, frames)?.bvh;
        bvh.frame_time = frame_time;
        Ok(bvh)
    }
}

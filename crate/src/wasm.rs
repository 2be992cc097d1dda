//! The wasm-bindgen layer: thin wrappers that turn [`crate::Error`] into JS
//! `Error`s. All logic lives in the pure-Rust modules.

use crate::rotation::batch::{self, Repr};
use crate::rotation::curves;
use crate::rotation::euler::Axis;
use crate::runtime::{Model, TensorF32};
use wasm_bindgen::prelude::*;

/// Sends Rust panic messages to the browser console (a panic is a bug: the
/// API returns `Error`s for bad input).
fn install_panic_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        std::panic::set_hook(Box::new(|info| {
            web_sys::console::error_1(&format!("deeprep panicked: {info}").into());
        }));
    });
}

/// Runs when the module is instantiated (every page and worker that calls
/// `init()`), so a panic anywhere is reported on the console with its
/// message before the instance traps.
#[wasm_bindgen(start)]
pub fn start() {
    install_panic_hook();
}

fn js_err(e: crate::Error) -> JsError {
    JsError::new(&e.to_string())
}

fn parse_axis(axis: &str) -> Result<Axis, JsError> {
    match axis {
        "x" | "X" => Ok(Axis::X),
        "y" | "Y" => Ok(Axis::Y),
        "z" | "Z" => Ok(Axis::Z),
        _ => Err(JsError::new(&format!(
            "unknown axis '{axis}'; accepted: x, y, z"
        ))),
    }
}

/// The crate version.
#[wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// Numbers per rotation in a representation (`"6d"` → 6).
#[wasm_bindgen(js_name = rotationDim)]
pub fn rotation_dim(repr: &str) -> Result<usize, JsError> {
    Ok(Repr::parse(repr).map_err(js_err)?.dim())
}

/// Converts a batch of rotations, e.g. `convertRotations("quat", "6d", q)`.
/// Names: matrix, 6d, 5d, quat, quat_gq, quat_gu, axis_angle, rodrigues,
/// euler:XYZ (upper case intrinsic, lower case extrinsic).
#[wasm_bindgen(js_name = convertRotations)]
pub fn convert_rotations(from: &str, to: &str, input: &[f32]) -> Result<Vec<f32>, JsError> {
    let f = Repr::parse(from).map_err(js_err)?;
    let t = Repr::parse(to).map_err(js_err)?;
    batch::convert(f, t, input).map_err(js_err)
}

/// Geodesic distances (radians, eq. 4.12) between two batches.
#[wasm_bindgen(js_name = geodesicDistances)]
pub fn geodesic_distances(repr: &str, a: &[f32], b: &[f32]) -> Result<Vec<f32>, JsError> {
    let r = Repr::parse(repr).map_err(js_err)?;
    batch::geodesic(r, a, b).map_err(js_err)
}

/// The rotation circle about `axis` ("x", "y", "z") in `repr`, `steps`
/// samples (Figure C.1's input).
#[wasm_bindgen(js_name = rotationCircle)]
pub fn rotation_circle(repr: &str, axis: &str, steps: usize) -> Result<Vec<f32>, JsError> {
    let r = Repr::parse(repr).map_err(js_err)?;
    curves::rotation_circle(r, parse_axis(axis)?, steps).map_err(js_err)
}

/// PCA to 2-D of `points` with `dim` numbers per row.
#[wasm_bindgen(js_name = pca2d)]
pub fn pca_2d(points: &[f32], dim: usize) -> Result<Vec<f32>, JsError> {
    curves::pca_2d(points, dim).map_err(js_err)
}

/// An ONNX model run by tract.
#[wasm_bindgen]
pub struct OnnxModel {
    inner: Model,
}

#[wasm_bindgen]
impl OnnxModel {
    /// Parses a model from the bytes of an .onnx file.
    #[wasm_bindgen(constructor)]
    pub fn new(bytes: &[u8]) -> Result<OnnxModel, JsError> {
        Ok(OnnxModel {
            inner: Model::from_onnx_bytes(bytes).map_err(js_err)?,
        })
    }

    /// Runs a single-input model; returns its first output, flattened.
    pub fn run(&self, input: &[f32], shape: &[u32]) -> Result<Vec<f32>, JsError> {
        let t = TensorF32::new(input.to_vec(), shape.iter().map(|d| *d as usize).collect())
            .map_err(js_err)?;
        let mut out = self.inner.run(&[t]).map_err(js_err)?;
        if out.is_empty() {
            return Err(JsError::new("model produced no output"));
        }
        Ok(out.swap_remove(0).data)
    }
}

/// A BVH clip: skeleton plus motion.
#[wasm_bindgen]
pub struct BvhClip {
    inner: crate::skeleton::Bvh,
}

#[wasm_bindgen]
impl BvhClip {
    /// Parses BVH text. Throws an `Error` naming the line on malformed input.
    pub fn parse(text: &str) -> Result<BvhClip, JsError> {
        Ok(BvhClip {
            inner: crate::skeleton::Bvh::parse(text).map_err(js_err)?,
        })
    }

    /// Parses BVH bytes (for example a file's `ArrayBuffer` as `Uint8Array`).
    #[wasm_bindgen(js_name = fromBytes)]
    pub fn from_bytes(bytes: &[u8]) -> Result<BvhClip, JsError> {
        Ok(BvhClip {
            inner: crate::skeleton::Bvh::parse_bytes(bytes).map_err(js_err)?,
        })
    }

    /// Joint names in file order (End Sites are `<parent>_Nub`).
    #[wasm_bindgen(getter, js_name = jointNames)]
    pub fn joint_names(&self) -> Vec<String> {
        self.inner.joints.iter().map(|j| j.name.clone()).collect()
    }

    /// Parent index per joint (−1 for the root).
    #[wasm_bindgen(getter)]
    pub fn parents(&self) -> Vec<i32> {
        self.inner
            .joints
            .iter()
            .map(|j| j.parent.map_or(-1, |p| p as i32))
            .collect()
    }

    /// Rest offsets, `joints × 3`.
    #[wasm_bindgen(getter)]
    pub fn offsets(&self) -> Vec<f32> {
        self.inner.joints.iter().flat_map(|j| j.offset).collect()
    }

    /// Number of frames.
    #[wasm_bindgen(getter, js_name = frameCount)]
    pub fn frame_count(&self) -> usize {
        self.inner.frame_count()
    }

    /// Seconds per frame.
    #[wasm_bindgen(getter, js_name = frameTime)]
    pub fn frame_time(&self) -> f64 {
        self.inner.frame_time
    }

    /// Channels per frame.
    #[wasm_bindgen(getter, js_name = channelCount)]
    pub fn channel_count(&self) -> usize {
        self.inner.channel_count()
    }

    /// All channel values, `frames × channels`.
    #[wasm_bindgen(getter)]
    pub fn motion(&self) -> Vec<f32> {
        self.inner.motion.clone()
    }

    /// Global joint positions for frames `[start, end)`, `frames × joints × 3`.
    #[wasm_bindgen(js_name = fkPositions)]
    pub fn fk_positions(&self, start: usize, end: usize) -> Result<Vec<f32>, JsError> {
        crate::skeleton::fk::positions(&self.inner, start, end).map_err(js_err)
    }

    /// Writes the clip as BVH text.
    #[wasm_bindgen(js_name = toBvh)]
    pub fn to_bvh(&self) -> String {
        self.inner.write()
    }
}

/// The in-betweening models (generator + path predictor) with their
/// skeleton, ready to synthesize.
#[wasm_bindgen]
pub struct Inbetweener {
    inner: crate::motion::pipeline::TweenModels,
    residual: Option<crate::motion::residual::ResidualModel>,
}

/// One synthesized motion.
#[wasm_bindgen]
pub struct InbetweenResult {
    bvh: String,
    positions: Vec<f32>,
    frames: usize,
    frame_time: f64,
    tracks: crate::skeleton::fk::LocalTracks,
    times: Vec<f64>,
    key_error: Vec<f64>,
}

impl InbetweenResult {
    fn new(
        b: &crate::skeleton::Bvh,
        times: Vec<f64>,
        key_error: Vec<f64>,
    ) -> Result<InbetweenResult, JsError> {
        Ok(InbetweenResult {
            bvh: b.write(),
            positions: crate::skeleton::fk::positions(b, 0, b.frame_count()).map_err(js_err)?,
            frames: b.frame_count(),
            frame_time: b.frame_time,
            tracks: crate::skeleton::fk::local_tracks(b),
            times,
            key_error,
        })
    }
}

#[wasm_bindgen]
impl InbetweenResult {
    /// The motion as BVH text (60 fps, the model's skeleton).
    #[wasm_bindgen(getter)]
    pub fn bvh(&self) -> String {
        self.bvh.clone()
    }
    /// Global joint positions, `frames × joints × 3`.
    #[wasm_bindgen(getter)]
    pub fn positions(&self) -> Vec<f32> {
        self.positions.clone()
    }
    /// Number of frames.
    #[wasm_bindgen(getter)]
    pub fn frames(&self) -> usize {
        self.frames
    }
    /// Seconds per frame.
    #[wasm_bindgen(getter, js_name = frameTime)]
    pub fn frame_time(&self) -> f64 {
        self.frame_time
    }
    /// Local translations (offset plus position channels), `frames × joints × 3`.
    #[wasm_bindgen(getter)]
    pub fn translations(&self) -> Vec<f32> {
        self.tracks.translations.clone()
    }
    /// Local rotations as quaternions `[x, y, z, w]`, `frames × joints × 4`.
    #[wasm_bindgen(getter)]
    pub fn quaternions(&self) -> Vec<f32> {
        self.tracks.quaternions.clone()
    }
    /// Milliseconds per stage: generator, RC-FK, path, post-processing.
    #[wasm_bindgen(getter)]
    pub fn times(&self) -> Vec<f64> {
        self.times.clone()
    }
    /// Mean key errors: root and joints before post-processing, then after.
    #[wasm_bindgen(getter, js_name = keyError)]
    pub fn key_error(&self) -> Vec<f64> {
        self.key_error.clone()
    }
}

fn keys_from_channels(
    template: &crate::skeleton::Bvh,
    key_frames: &[u32],
    key_channels: &[f32],
) -> Result<Vec<crate::motion::Keyframe>, JsError> {
    let c = template.channel_count();
    if key_channels.len() != key_frames.len() * c {
        return Err(JsError::new(&format!(
            "keyChannels: expected {} numbers ({} keys × {c} channels), found {}",
            key_frames.len() * c,
            key_frames.len(),
            key_channels.len()
        )));
    }
    let mut one = template.clone();
    key_frames
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            one.motion = key_channels[i * c..(i + 1) * c].to_vec();
            crate::motion::Keyframe::from_bvh(&one, 0, f as usize).map_err(js_err)
        })
        .collect()
}

fn result_from(
    template: &crate::skeleton::Bvh,
    motion: &crate::motion::Motion,
    times: Vec<f64>,
    key_error: Vec<f64>,
) -> Result<InbetweenResult, JsError> {
    let bvh = motion.to_bvh(template, 1.0 / 60.0).map_err(js_err)?;
    InbetweenResult::new(&bvh, times, key_error)
}

#[wasm_bindgen]
impl Inbetweener {
    /// Loads the models: the bytes of tween_generator.onnx and
    /// tween_path.onnx, and the text of tween_generator.manifest.json.
    #[wasm_bindgen(constructor)]
    pub fn new(generator: &[u8], path: &[u8], manifest: &str) -> Result<Inbetweener, JsError> {
        Ok(Inbetweener {
            inner: crate::motion::pipeline::TweenModels::new(generator, path, manifest)
                .map_err(js_err)?,
            residual: None,
        })
    }

    /// The variation `synthesize` uses when given none: the manifest's,
    /// chosen for this model on training takes.
    #[wasm_bindgen(getter, js_name = defaultVariation)]
    pub fn default_variation(&self) -> f32 {
        self.inner.default_variation
    }

    /// The model's skeleton as BVH text with no frames.
    #[wasm_bindgen(getter, js_name = skeletonBvh)]
    pub fn skeleton_bvh(&self) -> String {
        self.inner.template.write()
    }

    /// Synthesizes `frames` frames through whole-pose keys given as BVH
    /// channel rows of the model's skeleton (`keyChannels`: keys × channels)
    /// at `keyFrames` (sorted, unique, < frames, at most 600 apart).
    /// `dnaChannels` (optional, may be empty): Motion DNA poses as channel
    /// rows; their root rotation is removed. Empty: the keys serve as DNA.
    /// `postProcess`: make the keys exact; false returns the networks' raw
    /// motion. `footLock` (optional, default false; only with
    /// `postProcess`): then pin feet in contact with the floor
    /// (`motion::feet`).
    /// `variation` (optional, in [0, 2]): how much of the networks'
    /// departure from SLERP+LERP to keep, in the pose and the root path; 1
    /// is the networks as trained, 0 SLERP+LERP; absent: the model's
    /// default (`defaultVariation`).
    pub fn synthesize(
        &self,
        key_frames: &[u32],
        key_channels: &[f32],
        frames: usize,
        post_process: bool,
        dna_channels: &[f32],
        variation: Option<f32>,
        foot_lock: Option<bool>,
    ) -> Result<InbetweenResult, JsError> {
        let keys = keys_from_channels(&self.inner.template, key_frames, key_channels)?;
        let dna = if dna_channels.is_empty() {
            None
        } else {
            let c = self.inner.template.channel_count();
            let n = dna_channels.len() / c;
            let frames_idx: Vec<u32> = (0..n as u32).collect();
            let poses = keys_from_channels(&self.inner.template, &frames_idx, dna_channels)?;
            Some(poses.iter().map(crate::motion::dna_pose).collect())
        };
        let req = crate::motion::pipeline::Request {
            keys,
            frames,
            dna,
            post_process,
            foot_lock: (post_process && foot_lock.unwrap_or(false))
                .then(crate::motion::feet::FootLock::default),
            variation,
        };
        let now = || js_sys::Date::now();
        let out = self.inner.synthesize(&req, &now).map_err(js_err)?;
        let t = &out.times;
        result_from(
            &self.inner.template,
            &out.motion,
            vec![t.generator_ms, t.rcfk_ms, t.path_ms, t.post_ms],
            vec![
                out.key_error_raw.root,
                out.key_error_raw.local,
                out.key_error.root,
                out.key_error.local,
            ],
        )
    }

    /// Range-constrained angles (degrees) of one joint in a channel row, then
    /// its ranges: `[ux, uy, uz, αx, βx, αy, βy, αz, βz]`. Errors for joints
    /// that RC-FK does not rotate (the root, End Sites).
    #[wasm_bindgen(js_name = rcAngles)]
    pub fn rc_angles(&self, channels: &[f32], joint: usize) -> Result<Vec<f64>, JsError> {
        let k = self.rotating_index(joint)?;
        let mut one = self.inner.template.clone();
        one.motion = channels.to_vec();
        if one.motion.len() != one.channel_count() {
            return Err(JsError::new(&format!(
                "expected {} channels, found {}",
                one.channel_count(),
                channels.len()
            )));
        }
        let r = self.inner.rc.inverse(&one, 0).map_err(js_err)?;
        let mut out: Vec<f64> = r.angles[k].iter().map(|a| a.to_degrees()).collect();
        for rg in &self.inner.rc.ranges[k] {
            out.extend(rg.iter().map(|a| a.to_degrees()));
        }
        Ok(out)
    }

    /// Sets one joint's range-constrained angles (degrees, clamped to the
    /// ranges) in a channel row; returns the new row.
    #[wasm_bindgen(js_name = setRcAngles)]
    pub fn set_rc_angles(
        &self,
        channels: &[f32],
        joint: usize,
        angles: &[f64],
    ) -> Result<Vec<f32>, JsError> {
        let k = self.rotating_index(joint)?;
        if angles.len() != 3 || angles.iter().any(|a| !a.is_finite()) {
            return Err(JsError::new(
                "setRcAngles: expected 3 finite angles (degrees)",
            ));
        }
        let mut one = self.inner.template.clone();
        if channels.len() != one.channel_count() {
            return Err(JsError::new(&format!(
                "expected {} channels, found {}",
                one.channel_count(),
                channels.len()
            )));
        }
        one.motion = channels.to_vec();
        let u: [f64; 3] = std::array::from_fn(|a| {
            let [lo, hi] = self.inner.rc.ranges[k][a];
            angles[a].to_radians().clamp(lo, hi)
        });
        let m = self.inner.rc.rotation_for(k, u);
        let key = crate::motion::Keyframe::from_bvh(&one, 0, 0).map_err(js_err)?;
        let mut rots = key.rotations.unwrap_or_default();
        rots[joint] = m;
        let motion = crate::motion::Motion {
            root: vec![[
                key.positions[0] as f64,
                key.positions[1] as f64,
                key.positions[2] as f64,
            ]],
            rotations: vec![rots],
        };
        Ok(motion
            .to_bvh(&self.inner.template, 1.0 / 60.0)
            .map_err(js_err)?
            .motion)
    }

    fn rotating_index(&self, joint: usize) -> Result<usize, JsError> {
        self.inner
            .rc
            .rotating
            .iter()
            .position(|&j| j == joint)
            .ok_or_else(|| {
                JsError::new(&format!(
                    "joint {joint} is not rotated by RC-FK (the root and End Sites are not)"
                ))
            })
    }

    /// In-betweening inside a user's clip (BVH bytes on the model's
    /// skeleton, any frame rate): whole-pose keys from its frames
    /// `keyFrames` (the clip's own numbering), the motion between the first
    /// and last key synthesized at 60 fps (`method` "model" or "slerp"),
    /// then returned at the clip's frame rate and length, every other frame
    /// and the keys themselves unchanged.
    #[wasm_bindgen(js_name = synthesizeFromBvh)]
    pub fn synthesize_from_bvh(
        &self,
        bvh: &[u8],
        key_frames: &[u32],
        method: &str,
        post_process: bool,
        variation: Option<f32>,
        foot_lock: Option<bool>,
    ) -> Result<InbetweenResult, JsError> {
        use crate::motion::clip;
        let b = crate::skeleton::Bvh::parse_bytes(bvh).map_err(js_err)?;
        clip::check_skeleton(&b, &self.inner.template).map_err(js_err)?;
        let frames: Vec<usize> = key_frames.iter().map(|&f| f as usize).collect();
        let ck = clip::clip_keys(&b, &frames, true).map_err(js_err)?;
        let (motion, times, key_error) = match method {
            "slerp" => (
                crate::motion::baseline::slerp_lerp(&ck.keys, ck.frames()).map_err(js_err)?,
                vec![0.0; 4],
                vec![0.0; 4],
            ),
            "model" => {
                let req = crate::motion::pipeline::Request {
                    keys: ck.keys.clone(),
                    frames: ck.frames(),
                    dna: None,
                    post_process,
                    foot_lock: (post_process && foot_lock.unwrap_or(false))
                        .then(crate::motion::feet::FootLock::default),
                    variation,
                };
                let out = self
                    .inner
                    .synthesize(&req, &|| js_sys::Date::now())
                    .map_err(js_err)?;
                let (t, e) = (&out.times, (&out.key_error_raw, &out.key_error));
                (
                    out.motion.clone(),
                    vec![t.generator_ms, t.rcfk_ms, t.path_ms, t.post_ms],
                    vec![e.0.root, e.0.local, e.1.root, e.1.local],
                )
            }
            m => {
                return Err(JsError::new(&format!(
                    "unknown method '{m}'; accepted: model, slerp"
                )))
            }
        };
        let out = clip::splice(&b, &ck, &motion).map_err(js_err)?;
        InbetweenResult::new(&out, times, key_error)
    }

    /// Adds the supervised residual network (the bytes of
    /// `tween_residual.onnx` and its manifest's text), which
    /// [`Inbetweener::residual`] runs.
    #[wasm_bindgen(js_name = setResidual)]
    pub fn set_residual(&mut self, onnx: &[u8], manifest: &str) -> Result<(), JsError> {
        let m = crate::motion::residual::ResidualModel::new(onnx, manifest).map_err(js_err)?;
        crate::motion::clip::check_skeleton(&m.template, &self.inner.template).map_err(js_err)?;
        self.residual = Some(m);
        Ok(())
    }

    /// Whether [`Inbetweener::set_residual`] has loaded the residual network.
    #[wasm_bindgen(getter, js_name = hasResidual)]
    pub fn has_residual(&self) -> bool {
        self.residual.is_some()
    }

    /// The supervised residual on SLERP+LERP (issue 19, stage 1) between
    /// whole-pose keys; `variation` (default 1) scales its correction, 0
    /// being SLERP+LERP. Keys are exact by construction.
    pub fn residual(
        &self,
        key_frames: &[u32],
        key_channels: &[f32],
        frames: usize,
        variation: Option<f32>,
    ) -> Result<InbetweenResult, JsError> {
        let r = self
            .residual
            .as_ref()
            .ok_or_else(|| JsError::new("the residual network is not loaded (setResidual)"))?;
        let keys = keys_from_channels(&self.inner.template, key_frames, key_channels)?;
        let t0 = js_sys::Date::now();
        let m = r
            .synthesize(&keys, frames, variation.unwrap_or(1.0))
            .map_err(js_err)?;
        let ms = js_sys::Date::now() - t0;
        result_from(
            &self.inner.template,
            &m,
            vec![ms, 0.0, 0.0, 0.0],
            vec![0.0; 4],
        )
    }

    /// The SLERP+LERP baseline on the same inputs (labelled as such in UIs).
    pub fn interpolate(
        &self,
        key_frames: &[u32],
        key_channels: &[f32],
        frames: usize,
    ) -> Result<InbetweenResult, JsError> {
        let keys = keys_from_channels(&self.inner.template, key_frames, key_channels)?;
        let t0 = js_sys::Date::now();
        let m = crate::motion::baseline::slerp_lerp(&keys, frames).map_err(js_err)?;
        let ms = js_sys::Date::now() - t0;
        result_from(
            &self.inner.template,
            &m,
            vec![ms, 0.0, 0.0, 0.0],
            vec![0.0; 4],
        )
    }
}

/// IK from joint positions (thesis Sec. 4.4.3): lifts poses given as global
/// joint positions to joint rotations on the model's skeleton.
#[wasm_bindgen]
pub struct IkSolver {
    inner: crate::ik::IkModel,
}

/// The result of [`IkSolver::solve`].
#[wasm_bindgen]
pub struct IkResult {
    bvh: String,
    channels: Vec<f32>,
    positions: Vec<f32>,
    mean_error: f64,
    max_error: f64,
}

#[wasm_bindgen]
impl IkResult {
    /// The poses as a BVH clip on the model's skeleton.
    #[wasm_bindgen(getter)]
    pub fn bvh(&self) -> String {
        self.bvh.clone()
    }
    /// BVH channel values, `frames × channelCount`.
    #[wasm_bindgen(getter)]
    pub fn channels(&self) -> Vec<f32> {
        self.channels.clone()
    }
    /// Forward kinematics of the solution, `frames × joints × 3`.
    #[wasm_bindgen(getter)]
    pub fn positions(&self) -> Vec<f32> {
        self.positions.clone()
    }
    /// Mean distance between input and reconstructed joints (BVH units).
    #[wasm_bindgen(getter, js_name = meanError)]
    pub fn mean_error(&self) -> f64 {
        self.mean_error
    }
    /// Largest such distance.
    #[wasm_bindgen(getter, js_name = maxError)]
    pub fn max_error(&self) -> f64 {
        self.max_error
    }
}

#[wasm_bindgen]
impl IkSolver {
    /// Loads `ik.onnx` (bytes) with `ik.manifest.json` (text).
    #[wasm_bindgen(constructor)]
    pub fn new(onnx: &[u8], manifest: &str) -> Result<IkSolver, JsError> {
        Ok(IkSolver {
            inner: crate::ik::IkModel::new(onnx, manifest).map_err(js_err)?,
        })
    }
    /// The skeleton as BVH text (no frames); joint order of the inputs.
    #[wasm_bindgen(getter, js_name = skeletonBvh)]
    pub fn skeleton_bvh(&self) -> String {
        self.inner.skeleton().write()
    }
    /// Joints per pose.
    #[wasm_bindgen(getter)]
    pub fn joints(&self) -> usize {
        self.inner.joints()
    }
    /// Solves `frames` poses of global joint positions (`frames × joints × 3`).
    pub fn solve(&self, positions: &[f32], frames: usize) -> Result<IkResult, JsError> {
        let sol = self.inner.solve(positions, frames).map_err(js_err)?;
        Ok(IkResult {
            bvh: sol.bvh.write(),
            channels: sol.bvh.motion,
            positions: sol.positions,
            mean_error: sol.mean_error,
            max_error: sol.max_error,
        })
    }
}

/// The mesh autoencoder (thesis ch. 2) with the rig it was trained on
/// (RobotExpressive.glb): poses the robot, encodes its welded mesh into a
/// few latent vertices, decodes, and edits one latent vertex's code (Fig. 2.7).
/// Positions are flat `vertices × 3` arrays of the welded mesh.
#[wasm_bindgen]
pub struct MeshLab {
    rig: crate::mesh::Rig,
    topo: crate::mesh::Topology,
    codec: crate::mesh::MeshCodec,
}

fn flat3(p: &[[f32; 3]]) -> Vec<f32> {
    p.iter().flat_map(|v| v.iter().copied()).collect()
}

#[wasm_bindgen]
impl MeshLab {
    /// Loads the rig (`.glb` bytes) and the autoencoder (encoder and decoder
    /// `.onnx` bytes, `mesh_autoencoder.manifest.json` text). Fails when the
    /// rig's welded mesh is not the one the model was trained on.
    #[wasm_bindgen(constructor)]
    pub fn new(
        glb: &[u8],
        encoder: &[u8],
        decoder: &[u8],
        manifest: &str,
    ) -> Result<MeshLab, JsError> {
        install_panic_hook();
        let rig = crate::mesh::Rig::from_glb(glb).map_err(js_err)?;
        let topo = crate::mesh::Topology::robot(&rig).map_err(js_err)?;
        let codec = crate::mesh::MeshCodec::new(encoder, decoder, manifest).map_err(js_err)?;
        if topo.rest.len() != codec.vertices() || topo.levels.len() + 1 != codec.levels() {
            return Err(JsError::new(&format!(
                "this glTF welds to {} vertices in {} levels; the mesh model was trained on RobotExpressive.glb ({} vertices, {} levels)",
                topo.rest.len(),
                topo.levels.len() + 1,
                codec.vertices(),
                codec.levels()
            )));
        }
        Ok(MeshLab { rig, topo, codec })
    }

    /// Welded vertex count.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.topo.rest.len()
    }

    /// Triangles over welded vertices (3 indices each).
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Vec<u32> {
        self.topo
            .triangles
            .iter()
            .flat_map(|t| t.map(|i| i as u32))
            .collect()
    }

    /// The animation clips' names.
    #[wasm_bindgen(getter, js_name = clipNames)]
    pub fn clip_names(&self) -> Vec<String> {
        self.rig.animations.iter().map(|a| a.name.clone()).collect()
    }

    /// The clips' durations in seconds.
    #[wasm_bindgen(getter, js_name = clipDurations)]
    pub fn clip_durations(&self) -> Vec<f32> {
        self.rig.animations.iter().map(|a| a.duration).collect()
    }

    /// Welded vertex index of each latent vertex.
    #[wasm_bindgen(getter, js_name = latentVertices)]
    pub fn latent_vertices(&self) -> Vec<u32> {
        self.topo
            .latent_vertices()
            .into_iter()
            .map(|v| v as u32)
            .collect()
    }

    /// For each latent vertex, the rig node it was seeded at ("" when the
    /// sampler chose it).
    #[wasm_bindgen(getter, js_name = latentNames)]
    pub fn latent_names(&self) -> Vec<String> {
        self.topo
            .latent_vertices()
            .iter()
            .map(|v| {
                self.topo
                    .seeds
                    .iter()
                    .find(|s| s.1 == *v)
                    .map_or(String::new(), |s| s.0.clone())
            })
            .collect()
    }

    /// Per welded vertex, the latent vertex nearest by graph distance.
    #[wasm_bindgen(getter, js_name = latentRegions)]
    pub fn latent_regions(&self) -> Vec<u32> {
        self.topo
            .latent_regions()
            .into_iter()
            .map(|v| v as u32)
            .collect()
    }

    /// Latent codes per latent vertex.
    #[wasm_bindgen(getter, js_name = latentChannels)]
    pub fn latent_channels(&self) -> usize {
        self.codec.latent_shape().1
    }

    /// The rest pose.
    #[wasm_bindgen(js_name = restPose)]
    pub fn rest_pose(&self) -> Vec<f32> {
        flat3(&self.topo.rest)
    }

    /// Clip `clip` at `time` seconds (clamped to the clip).
    #[wasm_bindgen(js_name = clipPose)]
    pub fn clip_pose(&self, clip: usize, time: f32) -> Result<Vec<f32>, JsError> {
        let p = self.rig.animation_pose(clip, time).map_err(js_err)?;
        Ok(flat3(&self.topo.weld_pose(&p).map_err(js_err)?))
    }

    /// A random pose like the training set's: a random clip frame with every
    /// joint turned up to `maxDegrees` (30 in training).
    #[wasm_bindgen(js_name = randomPose)]
    pub fn random_pose(&self, seed: u32, max_degrees: f32) -> Result<Vec<f32>, JsError> {
        let mut rng = crate::rng::Rng::new(seed as u64);
        let (local, _, _) = self
            .rig
            .jittered_locals(&mut rng, max_degrees.to_radians())
            .map_err(js_err)?;
        let p = self.rig.pose(&local).map_err(js_err)?;
        Ok(flat3(&self.topo.weld_pose(&p).map_err(js_err)?))
    }

    /// Latent codes (latent vertices × channels) of a welded pose.
    pub fn encode(&self, positions: &[f32]) -> Result<Vec<f32>, JsError> {
        let p = points3(positions, "encode")?;
        self.codec.encode(&p).map_err(js_err)
    }

    /// Welded positions from latent codes.
    pub fn decode(&self, codes: &[f32]) -> Result<Vec<f32>, JsError> {
        Ok(flat3(&self.codec.decode(codes).map_err(js_err)?))
    }

    /// Codes `a` with latent vertex `vertex` blended towards `b` by `t`.
    #[wasm_bindgen(js_name = blendOne)]
    pub fn blend_one(
        &self,
        a: &[f32],
        b: &[f32],
        vertex: usize,
        t: f32,
    ) -> Result<Vec<f32>, JsError> {
        self.codec.blend_one(a, b, vertex, t).map_err(js_err)
    }
}

/// HairNet (thesis ch. 3) with its reconstruction: strand features from a
/// 3 × 256 × 256 orientation image, bilinear upsampling to any strand
/// count, strand MLPs, smoothing and curl restoration; plus the project's
/// procedural test hair and its renders, and feature-space interpolation.
#[wasm_bindgen]
pub struct HairLab {
    model: crate::hair::HairModel,
    body: crate::hair::Body,
}

#[wasm_bindgen]
impl HairLab {
    /// Loads `hair_features.onnx`, `hair_strands.onnx` (bytes) and
    /// `hair_features.manifest.json` (text).
    #[wasm_bindgen(constructor)]
    pub fn new(features: &[u8], strands: &[u8], manifest: &str) -> Result<HairLab, JsError> {
        install_panic_hook();
        Ok(HairLab {
            model: crate::hair::HairModel::new(features, strands, manifest).map_err(js_err)?,
            body: crate::hair::Body::default(),
        })
    }

    /// The hair classes' names (e.g. "M-curly").
    #[wasm_bindgen(js_name = classNames)]
    pub fn class_names() -> Vec<String> {
        crate::hair::HairClass::all()
            .iter()
            .map(|c| c.name())
            .collect()
    }

    /// A procedural hair of class `class` (seeded) rendered from `yawDeg`
    /// as the network's 3 × 256 × 256 input; `testHair` gives its strands.
    #[wasm_bindgen(js_name = testImage)]
    pub fn test_image(&self, class: &str, seed: u32, yaw_deg: f32) -> Result<Vec<f32>, JsError> {
        let h = self.test_hair_inner(class, seed)?;
        let view = crate::hair::View {
            yaw: yaw_deg.to_radians(),
            noise: 0.1,
            ..Default::default()
        };
        let mut rng = crate::rng::Rng::new(seed as u64 ^ 0x5eed);
        let r = crate::hair::render(&h.points, &self.body, &view, 256, &mut rng).map_err(js_err)?;
        Ok(r.image)
    }

    /// The same procedural hair's strands (1024 × 100 × 3, absolute metres).
    #[wasm_bindgen(js_name = testHair)]
    pub fn test_hair(&self, class: &str, seed: u32) -> Result<Vec<f32>, JsError> {
        Ok(flat3(&self.test_hair_inner(class, seed)?.points))
    }

    fn test_hair_inner(&self, class: &str, seed: u32) -> Result<crate::hair::Hair, JsError> {
        let c = crate::hair::HairClass::all()
            .into_iter()
            .find(|c| c.name() == class)
            .ok_or_else(|| JsError::new(&format!("unknown hair class '{class}'")))?;
        let mut rng = crate::rng::Rng::new(seed as u64);
        let style = crate::hair::Style::random(c, &mut rng);
        crate::hair::Hair::generate(
            &style,
            &crate::hair::Scalp::default(),
            &self.body,
            crate::hair::GRID,
            &mut rng,
        )
        .map_err(js_err)
    }

    /// The network input (3 × 256 × 256) from a photo (Sec. 3.2.1): `grey`
    /// values and a `hair` mask (and optionally a `body` mask; empty for
    /// none), each `width` × `height`, mask values above 0.5 set. A Gabor
    /// filter bank finds the strand orientation at each hair pixel.
    #[wasm_bindgen(js_name = photoInput)]
    pub fn photo_input(
        &self,
        grey: &[f32],
        hair: &[f32],
        body: &[f32],
        width: usize,
        height: usize,
    ) -> Result<Vec<f32>, JsError> {
        let body = (!body.is_empty()).then_some(body);
        crate::hair::orientation::network_input(
            grey,
            hair,
            body,
            width,
            height,
            &crate::hair::orientation::Gabor::default(),
        )
        .map_err(js_err)
    }

    /// Strand features (C × 32 × 32) of an image.
    pub fn features(&self, image: &[f32]) -> Result<Vec<f32>, JsError> {
        self.model.features(image).map_err(js_err)
    }

    /// Strands (count × 100 × 3, absolute metres) from strand features:
    /// upsampled to `count`, decoded, smoothed (`smoothSigma` samples) and
    /// curled where the predicted curvature asks (`curlThreshold`, 1/m;
    /// Infinity disables).
    pub fn strands(
        &self,
        features: &[f32],
        count: usize,
        smooth_sigma: f32,
        curl_threshold: f32,
    ) -> Result<Vec<f32>, JsError> {
        let opts = crate::hair::Reconstruct {
            strands: count,
            smooth_sigma,
            curl_threshold,
        };
        Ok(flat3(
            &self
                .model
                .strands_from_features(features, &opts)
                .map_err(js_err)?
                .points,
        ))
    }

    /// Opens a WebGPU device and uploads the strand MLPs for
    /// [`GpuHairDecoder`]: a Promise that rejects where WebGPU compute is
    /// unavailable (then use `strands`, the CPU path).
    #[wasm_bindgen(js_name = openGpu)]
    pub fn open_gpu(&self) -> js_sys::Promise {
        let weights = self.model.head_weights().clone();
        let decoding = self.model.decoding();
        let channels = self.model.channels();
        wasm_bindgen_futures::future_to_promise(async move {
            let fail = |m: String| JsValue::from(JsError::new(&m));
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
            desc.backends = wgpu::Backends::BROWSER_WEBGPU;
            let instance = wgpu::Instance::new(desc);
            let adapter = instance
                .request_adapter(&wgpu::RequestAdapterOptions::default())
                .await
                .map_err(|e| fail(format!("no WebGPU adapter: {e}")))?;
            let (device, queue) = adapter
                .request_device(&wgpu::DeviceDescriptor {
                    label: Some("deeprep hair decoder"),
                    required_limits: wgpu::Limits::downlevel_defaults()
                        .using_resolution(adapter.limits()),
                    ..Default::default()
                })
                .await
                .map_err(|e| fail(format!("WebGPU device: {e}")))?;
            let decoder = crate::hair::gpu::GpuStrandDecoder::new(&device, &weights)
                .map_err(|e| fail(e.to_string()))?;
            Ok(GpuHairDecoder {
                device,
                queue,
                decoder: std::rc::Rc::new(decoder),
                decoding,
                channels,
            }
            .into())
        })
    }

    /// Fig. B.2: (1 − t)·a + t·b in strand-feature space.
    #[wasm_bindgen(js_name = blendFeatures)]
    pub fn blend_features(a: &[f32], b: &[f32], t: f32) -> Result<Vec<f32>, JsError> {
        crate::hair::blend_features(a, b, t).map_err(js_err)
    }

    /// Eq. 3.3's collision error of strands (absolute, 100 points each).
    #[wasm_bindgen(js_name = collisionError)]
    pub fn collision_error(&self, points: &[f32]) -> Result<f32, JsError> {
        let p = points3(points, "strands")?;
        Ok(self.body.collision_error(&p, crate::hair::POINTS))
    }

    /// The body's four ellipsoids as a mesh: positions (× 3) then use `bodyTriangles`.
    #[wasm_bindgen(js_name = bodyPositions)]
    pub fn body_positions(&self) -> Vec<f32> {
        flat3(&self.body.mesh().0)
    }

    /// Triangles of `bodyPositions`.
    #[wasm_bindgen(js_name = bodyTriangles)]
    pub fn body_triangles(&self) -> Vec<u32> {
        self.body.mesh().1
    }
}

/// HairNet's strand MLPs on WebGPU compute (a WGSL shader, one invocation
/// per strand), for tens of thousands of strands at once. Open it with
/// `HairLab.openGpu()`; where WebGPU is missing, use `HairLab.strands`.
#[wasm_bindgen]
pub struct GpuHairDecoder {
    device: wgpu::Device,
    queue: wgpu::Queue,
    decoder: std::rc::Rc<crate::hair::gpu::GpuStrandDecoder>,
    decoding: crate::hair::StrandDecoding,
    channels: usize,
}

#[wasm_bindgen]
impl GpuHairDecoder {
    /// Like `HairLab.strands`, decoded on the GPU: a Promise of the strands
    /// (count × 100 × 3, absolute metres).
    pub fn strands(
        &self,
        features: &[f32],
        count: usize,
        smooth_sigma: f32,
        curl_threshold: f32,
    ) -> Result<js_sys::Promise, JsError> {
        if count == 0 || count > 200_000 {
            return Err(JsError::new(&format!(
                "hair: {count} strands requested (1..=200000)"
            )));
        }
        let uv = crate::hair::HairModel::strand_uv(count);
        let feats =
            crate::hair::upsample::upsample(features, self.channels, crate::hair::GRID, &uv)
                .map_err(js_err)?;
        let pending = self
            .decoder
            .dispatch(&self.device, &self.queue, &feats, uv.len())
            .map_err(js_err)?;
        let decoding = self.decoding;
        let opts = crate::hair::Reconstruct {
            strands: count,
            smooth_sigma,
            curl_threshold,
        };
        Ok(wasm_bindgen_futures::future_to_promise(async move {
            let buffer = pending.readback.clone();
            let mapped = js_sys::Promise::new(&mut |resolve, reject| {
                buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
                    let _ = match r {
                        Ok(()) => resolve.call0(&JsValue::NULL),
                        Err(e) => reject.call1(
                            &JsValue::NULL,
                            &JsValue::from_str(&format!("GPU readback: {e}")),
                        ),
                    };
                });
            });
            wasm_bindgen_futures::JsFuture::from(mapped).await?;
            let err = |e: crate::Error| JsValue::from(JsError::new(&e.to_string()));
            let n = uv.len();
            let (pos, curv) = pending.read().map_err(err)?;
            let (local, curvature) = decoding.outputs_to_strands(&pos, &curv, n).map_err(err)?;
            let s = decoding.finish(uv, &local, curvature, &opts).map_err(err)?;
            Ok(js_sys::Float32Array::from(flat3(&s.points).as_slice()).into())
        }))
    }
}

/// The wgpu viewer on a canvas: WebGPU when the browser offers it, WebGL2
/// otherwise (or when forced). It draws the current pose, keyframe poses in
/// a second color, the root trajectory as dots on the ground, and a grid.
#[wasm_bindgen]
pub struct Viewer {
    _instance: wgpu::Instance,
    _adapter: wgpu::Adapter,
    lost: std::sync::Arc<std::sync::atomic::AtomicBool>,
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    renderer: crate::viewer::Renderer,
    scene: crate::viewer::Scene,
    camera: crate::viewer::OrbitCamera,
    parents: Vec<Option<usize>>,
    selected: Option<usize>,
    backend: String,
    strands_revision: u64,
}

/// Per-vertex values in [0, max] as ramp colors (empty: none).
fn value_colors(values: &[f32], max: f32, n: usize) -> Result<Vec<[f32; 4]>, JsError> {
    if values.is_empty() {
        return Ok(Vec::new());
    }
    if values.len() != n {
        return Err(JsError::new(&format!(
            "viewer: {} values for {n} vertices",
            values.len()
        )));
    }
    if !(max.is_finite() && max > 0.0) {
        return Err(JsError::new(&format!(
            "viewer: the color scale's maximum must be positive, got {max}"
        )));
    }
    Ok(values
        .iter()
        .map(|v| crate::viewer::scene::colors::ramp(v / max))
        .collect())
}

fn parents_from(parents: &[i32]) -> Vec<Option<usize>> {
    parents
        .iter()
        .map(|&p| if p < 0 { None } else { Some(p as usize) })
        .collect()
}

fn points3(flat: &[f32], what: &str) -> Result<Vec<[f32; 3]>, JsError> {
    if flat.len() % 3 != 0 {
        return Err(JsError::new(&format!(
            "{what}: expected a multiple of 3 numbers, found {}",
            flat.len()
        )));
    }
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

#[wasm_bindgen]
impl Viewer {
    /// Opens the viewer on `canvas`. `forceWebgl2` skips WebGPU.
    pub async fn create(
        canvas: web_sys::HtmlCanvasElement,
        force_webgl2: bool,
    ) -> Result<Viewer, JsError> {
        install_panic_hook();
        // WebGPU first: ask for an adapter before touching the canvas, so that
        // the canvas is still free for WebGL2 when WebGPU is unavailable.
        // (wgpu's detection helper requests and drops a second adapter; in
        // Chromium that lost the device once the dropped one was collected.)
        let (w, h) = (canvas.width().max(1), canvas.height().max(1));
        let mut found = None;
        if !force_webgl2 {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
            desc.backends = wgpu::Backends::BROWSER_WEBGPU;
            let instance = wgpu::Instance::new(desc);
            if let Ok(adapter) = instance
                .request_adapter(&wgpu::RequestAdapterOptions::default())
                .await
            {
                found = Some((instance, adapter));
            }
        }
        let (instance, surface, adapter) = match found {
            Some((instance, adapter)) => {
                let surface = instance
                    .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
                    .map_err(|e| JsError::new(&format!("viewer: cannot use the canvas: {e}")))?;
                (instance, surface, adapter)
            }
            None => {
                let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
                desc.backends = wgpu::Backends::GL;
                let instance = wgpu::Instance::new(desc);
                let surface = instance
                    .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
                    .map_err(|e| JsError::new(&format!("viewer: cannot use the canvas: {e}")))?;
                let adapter = instance
                    .request_adapter(&wgpu::RequestAdapterOptions {
                        compatible_surface: Some(&surface),
                        ..Default::default()
                    })
                    .await
                    .map_err(|e| {
                        JsError::new(&format!("viewer: no WebGPU or WebGL2 adapter: {e}"))
                    })?;
                (instance, surface, adapter)
            }
        };
        let info = adapter.get_info();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("deeprep viewer"),
                required_limits: wgpu::Limits::downlevel_webgl2_defaults()
                    .using_resolution(adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| JsError::new(&format!("viewer: GPU device: {e}")))?;
        let lost = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            flag.store(true, std::sync::atomic::Ordering::SeqCst);
            web_sys::console::warn_1(
                &format!("deeprep viewer: GPU device lost ({reason:?}): {message}").into(),
            );
        });
        let mut config = surface
            .get_default_config(&adapter, w, h)
            .ok_or_else(|| JsError::new("viewer: the canvas surface is not supported"))?;
        // The renderer's colors are display values: prefer a non-sRGB target
        // so that WebGPU and WebGL2 show the same picture.
        if let Some(f) = surface
            .get_capabilities(&adapter)
            .formats
            .iter()
            .find(|f| !f.is_srgb())
        {
            config.format = *f;
        }
        surface.configure(&device, &config);
        let renderer = crate::viewer::Renderer::new(&device, config.format);
        let backend = match info.backend {
            wgpu::Backend::BrowserWebGpu => "webgpu".to_string(),
            wgpu::Backend::Gl => "webgl2".to_string(),
            other => format!("{other:?}").to_lowercase(),
        };
        Ok(Viewer {
            _instance: instance,
            _adapter: adapter,
            lost,
            surface,
            device,
            queue,
            config,
            renderer,
            scene: crate::viewer::Scene::default(),
            camera: crate::viewer::OrbitCamera::default(),
            parents: Vec::new(),
            selected: None,
            backend,
            strands_revision: 0,
        })
    }

    /// "webgpu" or "webgl2".
    #[wasm_bindgen(getter)]
    pub fn backend(&self) -> String {
        self.backend.clone()
    }

    /// True once the GPU device is lost (the browser reset the GPU, or a
    /// headless browser could not present a WebGPU canvas): draw nothing
    /// more and open a new viewer, e.g. with WebGL2 on a fresh canvas.
    #[wasm_bindgen(getter, js_name = deviceLost)]
    pub fn device_lost(&self) -> bool {
        self.lost.load(std::sync::atomic::Ordering::SeqCst)
    }

    /// Sets the skeleton's parents (−1 for the root); call before poses.
    #[wasm_bindgen(js_name = setParents)]
    pub fn set_parents(&mut self, parents: &[i32]) {
        self.parents = parents_from(parents);
    }

    /// Sets the drawn poses: `pose` (global positions, joints × 3; may be
    /// empty) and `keys` (key poses, k × joints × 3, in the key color).
    #[wasm_bindgen(js_name = setPoses)]
    pub fn set_poses(&mut self, pose: &[f32], keys: &[f32]) -> Result<(), JsError> {
        use crate::viewer::scene::colors;
        let j = self.parents.len();
        if j == 0 {
            return Err(JsError::new("viewer: call setParents first"));
        }
        if keys.len() % (3 * j) != 0 || (!pose.is_empty() && pose.len() != 3 * j) {
            return Err(JsError::new(&format!(
                "viewer: poses must have {j} joints × 3 numbers (pose {}, keys {})",
                pose.len(),
                keys.len()
            )));
        }
        self.scene.skeletons.clear();
        if !pose.is_empty() {
            self.scene.skeletons.push(crate::viewer::SkeletonPose::new(
                points3(pose, "pose")?,
                self.parents.clone(),
                colors::POSE,
            ));
        }
        for k in keys.chunks_exact(3 * j) {
            let mut s = crate::viewer::SkeletonPose::new(
                points3(k, "keys")?,
                self.parents.clone(),
                colors::KEY,
            );
            s.joint_radius *= 0.8;
            s.bone_radius *= 0.8;
            self.scene.skeletons.push(s);
        }
        if let (Some(sel), false) = (self.selected, pose.is_empty()) {
            if sel < j {
                let p = [pose[3 * sel], pose[3 * sel + 1], pose[3 * sel + 2]];
                let mut s = crate::viewer::SkeletonPose::new(vec![p], vec![None], colors::SELECTED);
                s.joint_radius *= 1.8;
                self.scene.skeletons.push(s);
            }
        }
        Ok(())
    }

    /// The root trajectory (points × 3), drawn as dots on the ground.
    #[wasm_bindgen(js_name = setTrajectory)]
    pub fn set_trajectory(&mut self, points: &[f32]) -> Result<(), JsError> {
        self.scene.trajectory = points3(points, "trajectory")?;
        Ok(())
    }

    /// Highlights a joint of the current pose (−1: none); takes effect at the next `setPoses`.
    #[wasm_bindgen(js_name = setSelected)]
    pub fn set_selected(&mut self, joint: i32) {
        self.selected = (joint >= 0).then_some(joint as usize);
    }

    /// Orbits by pixel deltas.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.camera.orbit(-dx * 0.008, dy * 0.008);
    }

    /// Pans by pixel deltas.
    pub fn pan(&mut self, dx: f32, dy: f32) {
        self.camera.pan(dx, dy, self.config.height as f32);
    }

    /// Zooms: the distance is multiplied by `factor`.
    pub fn zoom(&mut self, factor: f32) {
        self.camera.zoom(factor);
    }

    /// Draws one triangle mesh (replacing any other): `positions` (vertices
    /// × 3), `triangles` (vertex indices, 3 per triangle), and optionally a
    /// value per vertex shown as colors from blue-grey (0) to red (`max` and
    /// above); empty `values` draw the mesh in one color.
    #[wasm_bindgen(js_name = setMesh)]
    pub fn set_mesh(
        &mut self,
        positions: &[f32],
        triangles: &[u32],
        values: &[f32],
        max: f32,
    ) -> Result<(), JsError> {
        let pts = points3(positions, "mesh")?;
        if triangles.len() % 3 != 0 {
            return Err(JsError::new("viewer: triangles need 3 indices each"));
        }
        if let Some(&bad) = triangles.iter().find(|&&i| i as usize >= pts.len()) {
            return Err(JsError::new(&format!(
                "viewer: triangle index {bad} is out of range ({} vertices)",
                pts.len()
            )));
        }
        let mut m = crate::viewer::TriMesh::new(pts, triangles.to_vec(), [0.78, 0.8, 0.86, 1.0]);
        m.vertex_colors = value_colors(values, max, m.positions.len())?;
        if !m.vertex_colors.is_empty() {
            m.color = [1.0; 4];
        }
        self.scene.meshes = vec![m];
        Ok(())
    }

    /// Draws strands (`strandLength` points each, × 3) as lines in `color`
    /// (RGBA, 0..1), replacing any others; empty `points` clears them. The
    /// GPU buffer is rebuilt only when this is called.
    #[wasm_bindgen(js_name = setStrands)]
    pub fn set_strands(
        &mut self,
        points: &[f32],
        strand_length: usize,
        color: &[f32],
    ) -> Result<(), JsError> {
        let pts = points3(points, "strands")?;
        if strand_length < 2 || pts.len() % strand_length != 0 {
            return Err(JsError::new(&format!(
                "viewer: {} strand points are not whole strands of {strand_length}",
                pts.len()
            )));
        }
        let c: [f32; 4] = match color {
            [r, g, b, a] => [*r, *g, *b, *a],
            [r, g, b] => [*r, *g, *b, 1.0],
            _ => return Err(JsError::new("viewer: strand color must be RGB or RGBA")),
        };
        self.strands_revision += 1;
        self.scene.strips = if pts.is_empty() {
            Vec::new()
        } else {
            vec![crate::viewer::LineStrips {
                points: pts,
                strip_len: strand_length,
                color: c,
                revision: self.strands_revision,
            }]
        };
        Ok(())
    }

    /// Removes the mesh.
    #[wasm_bindgen(js_name = clearMesh)]
    pub fn clear_mesh(&mut self) {
        self.scene.meshes.clear();
    }

    /// Draws marker spheres of `radius` at `points` (× 3) in place of any
    /// skeleton poses, e.g. a mesh's latent vertices; `highlight` (−1: none)
    /// is drawn larger in the selection color. `pickJoint` then picks markers.
    #[wasm_bindgen(js_name = setMarkers)]
    pub fn set_markers(
        &mut self,
        points: &[f32],
        radius: f32,
        highlight: i32,
    ) -> Result<(), JsError> {
        use crate::viewer::scene::colors;
        if !(radius.is_finite() && radius > 0.0) {
            return Err(JsError::new(&format!(
                "viewer: marker radius must be positive, got {radius}"
            )));
        }
        let pts = points3(points, "markers")?;
        let mut s =
            crate::viewer::SkeletonPose::new(pts.clone(), vec![None; pts.len()], colors::LATENT);
        s.joint_radius = radius;
        self.scene.skeletons = vec![s];
        if let Some(p) = usize::try_from(highlight).ok().and_then(|h| pts.get(h)) {
            let mut h = crate::viewer::SkeletonPose::new(vec![*p], vec![None], colors::SELECTED);
            h.joint_radius = radius * 1.5;
            self.scene.skeletons.push(h);
        }
        Ok(())
    }

    /// Sets the ground grid: half-width `extent` and line spacing `step`
    /// (world units) at height `height`; `extent` 0 hides it.
    #[wasm_bindgen(js_name = setGrid)]
    pub fn set_grid(&mut self, extent: f32, step: f32, height: f32) -> Result<(), JsError> {
        if extent == 0.0 {
            self.scene.grid = None;
            return Ok(());
        }
        if !(extent > 0.0
            && step > 0.0
            && extent.is_finite()
            && height.is_finite()
            && extent / step <= 1000.0)
        {
            return Err(JsError::new(&format!(
                "viewer: grid extent {extent} and step {step} must be positive (at most 1000 lines a side)"
            )));
        }
        self.scene.grid = Some(crate::viewer::Grid {
            extent,
            step,
            height,
        });
        Ok(())
    }

    /// Aims the camera at everything drawn: poses, markers, the trajectory and the mesh.
    pub fn frame(&mut self) {
        let mut pts: Vec<[f32; 3]> = self
            .scene
            .skeletons
            .iter()
            .flat_map(|s| s.positions.iter().copied())
            .collect();
        pts.extend(self.scene.trajectory.iter().copied());
        pts.extend(
            self.scene
                .meshes
                .iter()
                .flat_map(|m| m.positions.iter().copied()),
        );
        self.camera.frame(&pts);
    }

    /// The joint of the current pose under canvas pixel (x, y), or −1.
    #[wasm_bindgen(js_name = pickJoint)]
    pub fn pick_joint(&self, x: f32, y: f32) -> i32 {
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        match crate::viewer::pick_joint(&self.scene, &self.camera, x, y, w, h, 2.5) {
            Some((0, j)) if !self.scene.skeletons.is_empty() => j as i32,
            _ => -1,
        }
    }

    /// Where the ray through canvas pixel (x, y) meets the ground (y = 0):
    /// [x, 0, z], or an empty array when it does not.
    #[wasm_bindgen(js_name = groundPoint)]
    pub fn ground_point(&self, x: f32, y: f32) -> Vec<f32> {
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        let (o, d) = self.camera.ray(x, y, w, h);
        if d.y.abs() < 1e-6 {
            return Vec::new();
        }
        let t = -o.y / d.y;
        if t <= 0.0 {
            return Vec::new();
        }
        let p = o + d * t;
        vec![p.x, 0.0, p.z]
    }

    /// Where the ray through canvas pixel (x, y) meets the plane through
    /// (px, py, pz) that faces the camera: for dragging a joint in the view
    /// plane. Empty when the ray runs parallel to it.
    #[wasm_bindgen(js_name = planePoint)]
    pub fn plane_point(&self, x: f32, y: f32, px: f32, py: f32, pz: f32) -> Vec<f32> {
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        let (o, d) = self.camera.ray(x, y, w, h);
        let p = glam::Vec3::new(px, py, pz);
        let n = (self.camera.target - self.camera.eye()).normalize();
        let denom = d.dot(n);
        if denom.abs() < 1e-6 {
            return Vec::new();
        }
        let t = (p - o).dot(n) / denom;
        let q = o + d * t;
        vec![q.x, q.y, q.z]
    }

    /// Canvas pixel (x, y) of a world point, or an empty array behind the camera.
    #[wasm_bindgen(js_name = projectPoint)]
    pub fn project_point(&self, px: f32, py: f32, pz: f32) -> Vec<f32> {
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        self.camera
            .project([px, py, pz], w, h)
            .map_or(Vec::new(), |p| vec![p[0], p[1]])
    }

    /// Matches the canvas size (pixels).
    pub fn resize(&mut self, width: u32, height: u32) {
        let (w, h) = (width.max(1), height.max(1));
        if (w, h) != (self.config.width, self.config.height) {
            self.config.width = w;
            self.config.height = h;
            self.surface.configure(&self.device, &self.config);
        }
    }

    /// Draws one frame.
    pub fn render(&mut self) -> Result<(), JsError> {
        if self.device_lost() {
            return Err(JsError::new(
                "viewer: the GPU device was lost; open a new viewer",
            ));
        }
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.device, &self.config);
                return Ok(());
            }
            _ => return Ok(()),
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        self.renderer.render(
            &self.device,
            &self.queue,
            &view,
            self.config.width,
            self.config.height,
            &self.scene,
            &self.camera,
        );
        self.queue.present(frame);
        Ok(())
    }
}

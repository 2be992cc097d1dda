//! In-betweening (ch. 5): the networks, the residual network, SLERP+LERP, clips.

use super::js_err;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

use crate::motion::serve::Request;

// a user's clip: in-betweened, gaps filled, retargeted
mod clips;

/// The in-betweening models (generator + path predictor) with their
/// skeleton, ready to synthesize.
#[wasm_bindgen]
pub struct Inbetweener {
    inner: crate::motion::pipeline::TweenModels,
    residual: Option<crate::motion::residual::ResidualModel>,
    cond: Option<crate::motion::cond::CondModel>,
    cond_dna: Option<crate::motion::cond::CondModel>,
    fill: Option<crate::motion::cond::CondModel>,
    fill_long: Option<crate::motion::residual::ResidualModel>,
    fill_mlp: Option<crate::motion::fill_mlp::FillMlp>,
}

/// One synthesized motion.
#[wasm_bindgen]
pub struct InbetweenResult {
    text: std::cell::RefCell<Text>,
    positions: Vec<f32>,
    frames: usize,
    frame_time: f64,
    tracks: crate::skeleton::fk::LocalTracks,
    times: Vec<f64>,
    key_error: Vec<f64>,
    critical_frames: Vec<u32>,
    method: &'static str,
    variation: f32,
}

/// A result's BVH text: given, or written from its motion when first read
/// (issue 23: the Euler angles and the text were about a sixth of a
/// 2,048-frame synthesis, and a page that plays the tracks never reads it).
enum Text {
    Written(String),
    /// The motion at 60 fps on the model's skeleton, until written.
    Pending {
        motion: crate::motion::Motion,
        template: crate::skeleton::Bvh,
    },
}

/// Global joint positions (FK on `skeleton`) and local tracks of `poses`,
/// in one pass; and their number.
fn positions_and_tracks(
    skeleton: &crate::skeleton::Bvh,
    poses: impl Iterator<Item = crate::skeleton::Pose>,
) -> (Vec<f32>, crate::skeleton::fk::LocalTracks, usize) {
    let (n, joints) = (poses.size_hint().0, skeleton.joints.len());
    let mut positions = Vec::with_capacity(n * joints * 3);
    let mut tracks = crate::skeleton::fk::LocalTracks::with_capacity(n, joints);
    let mut frames = 0;
    for pose in poses {
        for p in pose.global(skeleton).positions {
            positions.extend_from_slice(&[p.x as f32, p.y as f32, p.z as f32]);
        }
        tracks.push(&pose);
        frames += 1;
    }
    (positions, tracks, frames)
}

#[wasm_bindgen]
impl InbetweenResult {
    /// The motion as BVH text (60 fps, the model's skeleton; a clip's rate
    /// for `synthesizeFromBvh`). Written on the first read, which for a
    /// synthesis costs about as much as its Euler angles and text (tens of
    /// milliseconds at 2,048 frames); later reads copy it.
    #[wasm_bindgen(getter)]
    pub fn bvh(&self) -> Result<String, JsError> {
        let mut text = self.text.borrow_mut();
        let s = match &*text {
            Text::Written(s) => return Ok(s.clone()),
            Text::Pending { motion, template } => {
                motion.to_bvh(template, FRAME_TIME).map_err(js_err)?.write()
            }
        };
        // the text replaces the motion; a failed write keeps it
        *text = Text::Written(s.clone());
        Ok(s)
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
    /// How the networks ran: empty when directly; the frames of the
    /// critical keys made first when a gap over 600 frames made the
    /// synthesis hierarchical (`TweenModels::synthesize`).
    #[wasm_bindgen(getter, js_name = criticalFrames)]
    pub fn critical_frames(&self) -> Vec<u32> {
        self.critical_frames.clone()
    }

    /// The pipeline that made this motion: "residual" (the residual
    /// network), "generator" (generator, RC-FK, path predictor), "slerp"
    /// (SLERP+LERP) or "zerovel", as `motion::plan` chose it: the "model"
    /// method runs the residual network where its manifest makes it the
    /// default and it takes the keys (whole poses, no DNA), else the generator.
    /// For `fillGaps`, what filled the last gap: one of those, "hermite" (the
    /// Hermite curve) or "fill-mlp" (the short-gap fill network).
    #[wasm_bindgen(getter)]
    pub fn method(&self) -> String {
        self.method.into()
    }

    /// The variation it ran at (`motion::plan`: the request's, else the
    /// chosen pipeline's default; 0 for SLERP+LERP).
    #[wasm_bindgen(getter)]
    pub fn variation(&self) -> f32 {
        self.variation
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

/// Seconds per frame of a synthesized motion.
const FRAME_TIME: f64 = 1.0 / 60.0;

/// The result of a synthesized `motion` on `template`'s skeleton: positions
/// and tracks from the motion's own matrices (the BVH's FK without turning
/// Euler angles back into matrices), the BVH text when first read.
fn result_from(
    template: &crate::skeleton::Bvh,
    motion: crate::motion::Motion,
    method: &'static str,
    times: Vec<f64>,
    key_error: Vec<f64>,
    variation: f32,
) -> Result<InbetweenResult, JsError> {
    let (positions, tracks, frames) =
        positions_and_tracks(template, motion.poses(template).map_err(js_err)?);
    Ok(InbetweenResult {
        text: std::cell::RefCell::new(Text::Pending {
            motion,
            template: template.clone(),
        }),
        positions,
        frames,
        frame_time: FRAME_TIME,
        tracks,
        times,
        key_error,
        critical_frames: Vec::new(),
        method,
        variation,
    })
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
            cond: None,
            cond_dna: None,
            fill: None,
            fill_long: None,
            fill_mlp: None,
        })
    }

    /// Prepares the networks for requests of any length, so that the first
    /// request of each length does not wait for tract to optimize a plan
    /// for it (a worker calls this once after loading; see
    /// `runtime::Model::prepare_any_shape`).
    #[wasm_bindgen(js_name = prepareAnyLength)]
    pub fn prepare_any_length(&self) -> Result<(), JsError> {
        self.inner.prepare_any_length().map_err(js_err)?;
        for r in [&self.residual, &self.fill_long].into_iter().flatten() {
            r.prepare_any_length().map_err(js_err)?;
        }
        for c in [&self.cond, &self.cond_dna, &self.fill]
            .into_iter()
            .flatten()
        {
            c.prepare_any_length().map_err(js_err)?;
        }
        Ok(())
    }

    /// The variation `synthesize` uses when given none: the manifest's,
    /// chosen for this model on training takes (the residual network's when
    /// it is the model for whole-pose keys, see `residualIsDefault`).
    #[wasm_bindgen(getter, js_name = defaultVariation)]
    pub fn default_variation(&self) -> f32 {
        match &self.residual {
            Some(r) if r.info().default_for_whole_pose_keys => r.info().variation,
            _ => self.inner.default_variation,
        }
    }

    /// The model's skeleton as BVH text with no frames.
    #[wasm_bindgen(getter, js_name = skeletonBvh)]
    pub fn skeleton_bvh(&self) -> String {
        self.inner.template.write()
    }

    /// Synthesizes `frames` frames through whole-pose keys given as BVH
    /// channel rows of the model's skeleton (`keyChannels`: keys × channels)
    /// at `keyFrames` (sorted, unique, < frames, at most 3,000 apart; gaps over
    /// 600 run hierarchically, see `criticalFrames`). `options` (optional, a
    /// [`SynthesizeOptions`] object): `post` (default true: make the keys
    /// exact; false returns the networks' raw motion), `dna` (Motion DNA
    /// poses as channel rows, root rotation removed; absent or empty: the
    /// keys serve as DNA), `variation` (in [0, 2]: how much of the networks'
    /// departure from SLERP+LERP to keep, in the pose and the root path; 1 is
    /// the networks as trained, 0 SLERP+LERP; absent: `defaultVariation`),
    /// `footLock` (default false; only with `post`: pin feet in contact with
    /// the floor, `motion::feet`). An unknown option or a value of the wrong
    /// type is an error, not ignored.
    pub fn synthesize(
        &self,
        key_frames: &[u32],
        key_channels: &[f32],
        frames: usize,
        options: Option<SynthesizeOptions>,
    ) -> Result<InbetweenResult, JsError> {
        let opts = Options::read(options.as_deref().unwrap_or(&JsValue::UNDEFINED))?;
        let keys = keys_from_channels(&self.inner.template, key_frames, key_channels)?;
        let dna = if opts.dna.is_empty() {
            None
        } else {
            let c = self.inner.template.channel_count();
            let n = opts.dna.len() / c;
            let frames_idx: Vec<u32> = (0..n as u32).collect();
            let poses = keys_from_channels(&self.inner.template, &frames_idx, &opts.dna)?;
            Some(poses.iter().map(crate::motion::dna_pose).collect())
        };
        self.run(Request {
            method: "model".into(),
            keys,
            frames,
            dna,
            post_process: opts.post,
            variation: opts.variation,
            foot_lock: opts.foot_lock,
            seed: None,
        })
    }

    /// Range-constrained angles (degrees) of one joint in a channel row, then
    /// its ranges: `[ux, uy, uz, αx, βx, αy, βy, αz, βz]`. Errors for joints
    /// that RC-FK does not rotate (the root, End Sites).
    #[wasm_bindgen(js_name = rcAngles)]
    pub fn rc_angles(&self, channels: &[f32], joint: usize) -> Result<Vec<f64>, JsError> {
        let a = crate::motion::edit::joint_angles(
            &self.inner.rc,
            &self.inner.template,
            channels,
            joint,
        )
        .map_err(js_err)?;
        Ok(a.angles
            .into_iter()
            .chain(a.ranges.into_iter().flatten())
            .collect())
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
        let angles: [f64; 3] = angles
            .try_into()
            .map_err(|_| JsError::new("setRcAngles: expected 3 finite angles (degrees)"))?;
        crate::motion::edit::set_joint_angles(
            &self.inner.rc,
            &self.inner.template,
            channels,
            joint,
            angles,
        )
        .map_err(js_err)
    }

    /// Adds the supervised residual network (the bytes of
    /// `tween_residual.onnx` and its manifest's text), which
    /// [`Inbetweener::residual`] runs.
    #[wasm_bindgen(js_name = setResidual)]
    pub fn set_residual(&mut self, onnx: &[u8], manifest: &str) -> Result<(), JsError> {
        self.residual = Some(self.residual_model(onnx, manifest)?);
        Ok(())
    }

    /// Whether the loaded residual network is the `model` method's for
    /// whole-pose keys (its manifest says so); false when none is loaded.
    #[wasm_bindgen(getter, js_name = residualIsDefault)]
    pub fn residual_is_default(&self) -> bool {
        self.residual
            .as_ref()
            .is_some_and(|r| r.info().default_for_whole_pose_keys)
    }

    /// Adds the conditional network (the bytes of `tween_cond.onnx` and its
    /// manifest's text), which method `cond` runs, and `model` for root-only
    /// and 2-D keys when its manifest makes it the default for them.
    #[wasm_bindgen(js_name = setCond)]
    pub fn set_cond(&mut self, onnx: &[u8], manifest: &str) -> Result<(), JsError> {
        self.cond = Some(self.cond_model(onnx, manifest)?);
        Ok(())
    }

    /// Whether [`Inbetweener::set_cond`] has loaded the conditional network.
    #[wasm_bindgen(getter, js_name = hasCond)]
    pub fn has_cond(&self) -> bool {
        self.cond.is_some()
    }

    /// Adds the DNA network (the bytes of `tween_cond_dna.onnx` and its
    /// manifest's text, a conditional network trained with Motion DNA):
    /// method `cond` runs it for requests with DNA, and `model` too when its
    /// manifest makes it the default for DNA (`default_for_dna`).
    #[wasm_bindgen(js_name = setCondDna)]
    pub fn set_cond_dna(&mut self, onnx: &[u8], manifest: &str) -> Result<(), JsError> {
        let m = self.cond_model(onnx, manifest)?;
        m.info().as_dna_network().map_err(js_err)?;
        self.cond_dna = Some(m);
        Ok(())
    }

    /// Whether [`Inbetweener::set_cond_dna`] has loaded the DNA network.
    #[wasm_bindgen(getter, js_name = hasCondDna)]
    pub fn has_cond_dna(&self) -> bool {
        self.cond_dna.is_some()
    }

    /// Adds the gap-filling network (the bytes of `tween_fill.onnx` and its
    /// manifest's text): `fillGaps` runs it for method `fill`, and for
    /// method `model` on the gaps its manifest gives it (`fill_from`..=`fill_up_to`).
    #[wasm_bindgen(js_name = setFill)]
    pub fn set_fill(&mut self, onnx: &[u8], manifest: &str) -> Result<(), JsError> {
        self.fill = Some(self.cond_model(onnx, manifest)?);
        Ok(())
    }

    /// Whether [`Inbetweener::set_fill`] has loaded the gap-filling network.
    #[wasm_bindgen(getter, js_name = hasFill)]
    pub fn has_fill(&self) -> bool {
        self.fill.is_some()
    }

    /// Adds the long-gap filling network (the bytes of `tween_fill_long.onnx`
    /// and its manifest's text: a residual network trained on gaps in
    /// captured motion): `fillGaps` runs it for method `fill-long`, and for
    /// method `model` on the gaps its manifest gives it (`fill_from`..=`fill_up_to`).
    #[wasm_bindgen(js_name = setFillLong)]
    pub fn set_fill_long(&mut self, onnx: &[u8], manifest: &str) -> Result<(), JsError> {
        let m = self.residual_model(onnx, manifest)?;
        m.info().as_fill_long_network().map_err(js_err)?;
        self.fill_long = Some(m);
        Ok(())
    }

    /// Whether [`Inbetweener::set_fill_long`] has loaded the long-gap filling network.
    #[wasm_bindgen(getter, js_name = hasFillLong)]
    pub fn has_fill_long(&self) -> bool {
        self.fill_long.is_some()
    }

    /// Adds the short-gap fill network (the bytes of `tween_fill_mlp.onnx`
    /// and its manifest's text: an MLP over the gap's edges on the Hermite
    /// curve, `motion::fill_mlp`): `fillGaps` runs it for method `fill-mlp`,
    /// and for method `model` on the gaps its manifest gives it, before the
    /// other networks' bands. Its manifest must give a band.
    #[wasm_bindgen(js_name = setFillMlp)]
    pub fn set_fill_mlp(&mut self, onnx: &[u8], manifest: &str) -> Result<(), JsError> {
        self.fill_mlp =
            Some(crate::motion::fill_mlp::FillMlp::new(onnx, manifest).map_err(js_err)?);
        Ok(())
    }

    /// Whether [`Inbetweener::set_fill_mlp`] has loaded the short-gap fill network.
    #[wasm_bindgen(getter, js_name = hasFillMlp)]
    pub fn has_fill_mlp(&self) -> bool {
        self.fill_mlp.is_some()
    }

    /// Whether [`Inbetweener::set_residual`] has loaded the residual network.
    #[wasm_bindgen(getter, js_name = hasResidual)]
    pub fn has_residual(&self) -> bool {
        self.residual.is_some()
    }

    /// Runs the code a request runs, so that the first request is not the
    /// one that brings the wasm code up to speed: `rounds` syntheses of
    /// `motion::keys::warm_up_keys` (512 frames, whole poses every 240) by
    /// the `model` method, then, with `generator` and when the residual
    /// network is the model for whole poses, a short one by the generator on
    /// the first two keys' root positions 63 frames apart (what partial keys
    /// run). The npm worker calls it after
    /// [`Inbetweener::prepare_any_length`], before it reports ready and then
    /// a round at a time when idle (`WARM_UP_ROUNDS` in
    /// `web/lib/wasm-features.js`).
    ///
    /// Why: V8 runs a wasm function's first calls on its baseline compiler's
    /// code and switches to optimized code only at a call after it has run
    /// enough, so a request that is the first to run a stretch of code at
    /// length runs it slowly (with V8's flags `--no-liftoff
    /// --no-wasm-lazy-compilation` the gap was gone). Measured in headless
    /// Chromium with a training on the other core (README, Speed): the first
    /// 512-frame synthesis took 1.5-1.8x a warm one after the 64-frame
    /// rest-pose synthesis this replaces, 1.3-1.6x after 2 rounds here and
    /// 0.7-1.4x after 5 (1.0-1.35x at 1,024-4,096 frames).
    #[wasm_bindgen(js_name = warmUp)]
    pub fn warm_up(&self, rounds: u32, generator: bool) -> Result<(), JsError> {
        use crate::motion::keys::{warm_up_keys, KeyKind, WARM_UP_FRAMES};
        let keys = warm_up_keys(&self.inner.template).map_err(js_err)?;
        for _ in 0..rounds {
            self.run(Request::model(keys.clone(), WARM_UP_FRAMES))?;
        }
        if generator && self.residual_is_default() {
            let first = KeyKind::Root.of(&keys[0]).map_err(js_err)?;
            let mut second = KeyKind::Root.of(&keys[1]).map_err(js_err)?;
            second.frame = 63;
            self.run(Request::model(vec![first, second], 64))?;
        }
        Ok(())
    }

    /// Builds and keeps the residual network's own plan for `frames` frames,
    /// which then serves that length instead of the plan for any length
    /// ([`Inbetweener::prepare_any_length`]): 11-18% faster at 2,048-4,096
    /// frames (0-13% at 1,024), but 100-360 ms to build and run once (see
    /// `runtime::Model::prepare_shape`), so the npm worker calls it when idle
    /// after a synthesis of that length (the four most recent lengths are
    /// kept). Returns whether a plan was built: false
    /// when no residual network is loaded or that length's plan is kept
    /// already.
    #[wasm_bindgen(js_name = prepareLength)]
    pub fn prepare_length(&self, frames: usize) -> Result<bool, JsError> {
        match &self.residual {
            Some(r) => r.prepare_length(frames).map_err(js_err),
            None => Ok(false),
        }
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
        let keys = keys_from_channels(&self.inner.template, key_frames, key_channels)?;
        self.run(Request {
            method: "residual".into(),
            variation,
            ..Request::model(keys, frames)
        })
    }

    /// The SLERP+LERP baseline on the same inputs (labelled as such in UIs).
    pub fn interpolate(
        &self,
        key_frames: &[u32],
        key_channels: &[f32],
        frames: usize,
    ) -> Result<InbetweenResult, JsError> {
        let keys = keys_from_channels(&self.inner.template, key_frames, key_channels)?;
        self.run(Request {
            method: "slerp".into(),
            ..Request::model(keys, frames)
        })
    }

    /// Runs a whole request given as JSON (`motion::keys::RequestDoc`):
    /// `{"frames": N, "keys": [...], "method": "model" | "residual" | "cond" |
    /// "slerp", "post", "footLock", "variation", "dna"}`, where each key is
    /// a whole pose (`{"frame", "channels"}`), the root's position only
    /// (`{"frame", "root": [x, y, z]}`) or 2-D joints (`{"frame", "xy",
    /// "root"}`), as in keys files.
    #[wasm_bindgen(js_name = synthesizeRequest)]
    pub fn synthesize_request(&self, request: &str) -> Result<InbetweenResult, JsError> {
        let doc = crate::motion::keys::request_from_json(request, &self.inner.template)
            .map_err(js_err)?;
        let frames = doc
            .file
            .frames
            .ok_or_else(|| JsError::new("request: \"frames\" is required"))?;
        let keys = doc.file.keys;
        self.run(Request {
            method: doc.method,
            keys,
            frames,
            dna: doc.dna,
            post_process: doc.post,
            variation: doc.variation,
            foot_lock: doc.foot_lock,
            seed: doc.seed,
        })
    }
}

impl Request {
    /// The `model` method on `keys` with every other option at its default.
    fn model(keys: Vec<crate::motion::Keyframe>, frames: usize) -> Request {
        Request {
            method: "model".into(),
            keys,
            frames,
            dna: None,
            post_process: true,
            variation: None,
            foot_lock: false,
            seed: None,
        }
    }
}

impl Inbetweener {
    /// A residual network (the whole-pose or the long-gap filling one) on
    /// the model's skeleton, prepared for any length.
    fn residual_model(
        &self,
        onnx: &[u8],
        manifest: &str,
    ) -> Result<crate::motion::residual::ResidualModel, JsError> {
        let m = crate::motion::residual::ResidualModel::new(onnx, manifest).map_err(js_err)?;
        crate::motion::clip::check_skeleton(&m.template, &self.inner.template).map_err(js_err)?;
        m.prepare_any_length().map_err(js_err)?;
        Ok(m)
    }

    /// A conditional network (the conditional or the gap-filling one) on
    /// this model's skeleton, prepared for requests of any length.
    fn cond_model(
        &self,
        onnx: &[u8],
        manifest: &str,
    ) -> Result<crate::motion::cond::CondModel, JsError> {
        let m = crate::motion::cond::CondModel::new(onnx, manifest).map_err(js_err)?;
        crate::motion::clip::check_skeleton(&m.template, &self.inner.template).map_err(js_err)?;
        m.prepare_any_length().map_err(js_err)?;
        Ok(m)
    }

    /// The loaded networks, as `motion::serve` takes them.
    fn models(&self) -> crate::motion::serve::Models<'_> {
        crate::motion::serve::Models {
            generator: Some(&self.inner),
            residual: self.residual.as_ref(),
            cond: self.cond.as_ref(),
            cond_dna: self.cond_dna.as_ref(),
            fill: self.fill.as_ref(),
            fill_long: self.fill_long.as_ref(),
        }
    }

    /// Plans a request (`motion::plan`) and runs it (`motion::serve`).
    fn run(&self, req: Request) -> Result<InbetweenResult, JsError> {
        let s = crate::motion::serve::serve(&self.models(), req, &|| js_sys::Date::now())
            .map_err(js_err)?;
        let mut r = result_from(
            &self.inner.template,
            s.motion,
            s.plan.pipeline.name(),
            s.stage_ms.to_vec(),
            s.key_error.to_vec(),
            s.plan.variation,
        )?;
        r.critical_frames = s.critical_frames.iter().map(|&f| f as u32).collect();
        Ok(r)
    }
}

#[wasm_bindgen(typescript_custom_section)]
const SYNTHESIZE_OPTIONS_TS: &str = r#"
/** Options of `Inbetweener.synthesize`; every field is optional. */
export interface SynthesizeOptions {
  /** Make the keys exact (default true); false returns the networks' raw motion. */
  post?: boolean;
  /** Motion DNA poses as channel rows (poses × channels); absent or empty: the keys serve as DNA. */
  dna?: Float32Array | number[];
  /** Share of the networks' departure from SLERP+LERP, in [0, 2]; absent: `defaultVariation`. */
  variation?: number;
  /** Pin feet in contact with the floor (default false; only with `post`). */
  footLock?: boolean;
}
"#;

#[wasm_bindgen]
extern "C" {
    /// The options object of [`Inbetweener::synthesize`] (a plain JS object;
    /// `undefined` for the defaults).
    #[wasm_bindgen(typescript_type = "SynthesizeOptions")]
    pub type SynthesizeOptions;
}

/// [`SynthesizeOptions`] read and checked.
struct Options {
    post: bool,
    dna: Vec<f32>,
    variation: Option<f32>,
    foot_lock: bool,
}

impl Options {
    const KNOWN: [&'static str; 4] = ["post", "dna", "variation", "footLock"];

    fn read(v: &JsValue) -> Result<Options, JsError> {
        let mut o = Options {
            post: true,
            dna: Vec::new(),
            variation: None,
            foot_lock: false,
        };
        if v.is_undefined() || v.is_null() {
            return Ok(o);
        }
        if !v.is_object() || js_sys::Array::is_array(v) {
            return Err(JsError::new(
                "synthesize: options must be an object such as { post: true, variation: 1 }",
            ));
        }
        for k in js_sys::Object::keys(v.unchecked_ref::<js_sys::Object>()).iter() {
            let k = k.as_string().unwrap_or_default();
            if !Self::KNOWN.contains(&k.as_str()) {
                return Err(JsError::new(&format!(
                    "synthesize: unknown option '{k}' (known: {})",
                    Self::KNOWN.join(", ")
                )));
            }
        }
        let get =
            |k: &str| js_sys::Reflect::get(v, &JsValue::from_str(k)).unwrap_or(JsValue::UNDEFINED);
        let bool_of = |k: &str, x: JsValue| {
            x.as_bool()
                .ok_or_else(|| JsError::new(&format!("synthesize: option '{k}' must be a boolean")))
        };
        let x = get("post");
        if !x.is_undefined() {
            o.post = bool_of("post", x)?;
        }
        let x = get("footLock");
        if !x.is_undefined() {
            o.foot_lock = bool_of("footLock", x)?;
        }
        let x = get("variation");
        if !x.is_undefined() {
            o.variation =
                Some(x.as_f64().ok_or_else(|| {
                    JsError::new("synthesize: option 'variation' must be a number")
                })? as f32);
        }
        let x = get("dna");
        if !x.is_undefined() {
            o.dna = if let Some(a) = x.dyn_ref::<js_sys::Float32Array>() {
                a.to_vec()
            } else if js_sys::Array::is_array(&x) {
                js_sys::Array::from(&x)
                    .iter()
                    .map(|e| e.as_f64().map(|f| f as f32))
                    .collect::<Option<Vec<f32>>>()
                    .ok_or_else(|| JsError::new("synthesize: option 'dna' must hold numbers"))?
            } else {
                return Err(JsError::new(
                    "synthesize: option 'dna' must be a Float32Array or an array of numbers",
                ));
            };
        }
        Ok(o)
    }
}

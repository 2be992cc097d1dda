//! The Inbetweener's calls on a user's whole clip: in-betweening inside it
//! (`synthesizeFromBvh`), filling its gaps (`fillGaps`) and retargeting it
//! (`retarget`).

use super::{positions_and_tracks, InbetweenResult, Inbetweener, Text};
use crate::motion::serve::Request;
use crate::wasm::js_err;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
impl Inbetweener {
    /// In-betweening inside a user's clip (BVH bytes on the model's
    /// skeleton or another humanoid's, retargeted onto the model's and the
    /// result back; any frame rate): whole-pose keys from its frames
    /// `keyFrames` (the clip's own numbering), the motion between the first
    /// and last key synthesized at 60 fps (`method`: "model", "generator",
    /// "residual", "cond", "slerp" or "zerovel", planned as for `synthesize` and the
    /// CLI's `--from-bvh`),
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
        let user = crate::skeleton::Bvh::parse_bytes(bvh).map_err(js_err)?;
        // another humanoid skeleton is retargeted onto the model's and back
        let on_model = clip::OnModel::new(&user, &self.inner.template).map_err(js_err)?;
        let b = &on_model.clip;
        let frames: Vec<usize> = key_frames.iter().map(|&f| f as usize).collect();
        let ck = clip::clip_keys(b, &frames, true).map_err(js_err)?;
        // the planner decides, as for the CLI's --from-bvh (the residual
        // network for whole-pose keys where its manifest says so)
        let served = crate::motion::serve::serve(
            &self.models(),
            Request {
                method: method.into(),
                post_process,
                variation,
                foot_lock: foot_lock.unwrap_or(false),
                ..Request::model(ck.keys.clone(), ck.frames())
            },
            &|| js_sys::Date::now(),
        )
        .map_err(js_err)?;
        let motion = &served.motion;
        let out = clip::splice(b, &ck, motion).map_err(js_err)?;
        let out = on_model.back(&user, out, &ck).map_err(js_err)?;
        let poses = (0..out.frame_count()).map(|f| crate::skeleton::Pose::read(&out, out.frame(f)));
        let (positions, tracks, frames) = positions_and_tracks(&out, poses);
        Ok(InbetweenResult {
            text: std::cell::RefCell::new(Text::Written(out.write())),
            positions,
            frames,
            frame_time: out.frame_time,
            tracks,
            times: served.stage_ms.to_vec(),
            key_error: served.key_error.to_vec(),
            critical_frames: served.critical_frames.iter().map(|&f| f as u32).collect(),
            method: served.plan.pipeline.name(),
            variation: served.plan.variation,
        })
    }

    /// Fills gaps in a clip (BVH bytes on the model's skeleton or another
    /// humanoid's, any frame rate; `motion::fill`): `gaps` holds inclusive
    /// `[start, end]` frame pairs of the clip; each gap's frames are
    /// synthesized from `before` frames before it and `after` after it
    /// (whole-pose keys; the defaults 20 and 1), by `method` ("model",
    /// "fill", "fill-long", "residual", "generator", "cond", "slerp",
    /// "zerovel" or "hermite"; `model` is a gap-filling network on the gaps
    /// its manifest gives it when `setFill` / `setFillLong` loaded one,
    /// else the Hermite curve up to 45 frames and the default network
    /// beyond); every other frame is returned exactly as it was.
    #[wasm_bindgen(js_name = fillGaps)]
    pub fn fill_gaps(
        &self,
        bvh: &[u8],
        gaps: &[u32],
        method: &str,
        before: Option<u32>,
        after: Option<u32>,
    ) -> Result<InbetweenResult, JsError> {
        use crate::motion::clip;
        use crate::motion::fill::{self, Context, Gap};
        let user = crate::skeleton::Bvh::parse_bytes(bvh).map_err(js_err)?;
        if !gaps.len().is_multiple_of(2) {
            return Err(JsError::new("gaps are [start, end] pairs"));
        }
        let gaps: Vec<Gap> = gaps
            .chunks(2)
            .map(|g| Gap {
                start: g[0] as usize,
                end: g[1] as usize,
            })
            .collect();
        let ctx = Context::parse(&format!(
            "{},{}",
            before.unwrap_or(fill::DEFAULT_CONTEXT.before as u32),
            after.unwrap_or(fill::DEFAULT_CONTEXT.after as u32)
        ))
        .map_err(js_err)?;
        let network = crate::motion::plan::runs_network(method);
        let on_model = if network {
            Some(clip::OnModel::new(&user, &self.inner.template).map_err(js_err)?)
        } else {
            None
        };
        let b = on_model.as_ref().map_or(&user, |m| &m.clip);
        let mut plan = None;
        let mut stage_ms = [0.0; 4];
        let bands = fill::Bands {
            fill_mlp: self.fill_mlp.as_ref().map(|f| f.band()),
            fill: self.fill.as_ref().and_then(|f| f.info().fill_gaps),
            fill_long: self.fill_long.as_ref().and_then(|f| f.info().fill_gaps),
        };
        // the method that filled the last gap (a network's pipeline, or a fill
        // of its own: the curve or the short-gap network)
        let mut last = "hermite";
        let filled = fill::fill(b, &gaps, ctx, &mut |c, ck, gap| {
            let method = fill::method_for(method, gap.len(), bands);
            if method == "hermite" {
                last = "hermite";
                return fill::hermite(c, ck);
            }
            if method == "fill-mlp" {
                let net = self.fill_mlp.as_ref().ok_or_else(|| {
                    crate::error::Error::Invalid(
                        "method fill-mlp: the short-gap fill network is not loaded (setFillMlp)"
                            .into(),
                    )
                })?;
                last = "fill-mlp";
                return net.fill(c, ck);
            }
            let served = crate::motion::serve::serve(
                &self.models(),
                Request {
                    method: method.into(),
                    ..Request::model(ck.keys.clone(), ck.frames())
                },
                &|| js_sys::Date::now(),
            )?;
            for (t, s) in stage_ms.iter_mut().zip(served.stage_ms) {
                *t += s;
            }
            plan = Some(served.plan);
            last = served.plan.pipeline.name();
            Ok(served.motion)
        })
        .map_err(js_err)?;
        let (out, text) =
            fill::on_user(&user, bvh, filled, on_model.as_ref(), &gaps).map_err(js_err)?;
        let poses = (0..out.frame_count()).map(|f| crate::skeleton::Pose::read(&out, out.frame(f)));
        let (positions, tracks, frames) = positions_and_tracks(&out, poses);
        Ok(InbetweenResult {
            text: std::cell::RefCell::new(Text::Written(text)),
            positions,
            frames,
            frame_time: out.frame_time,
            tracks,
            times: stage_ms.to_vec(),
            key_error: vec![0.0; 4],
            critical_frames: Vec::new(),
            method: last,
            variation: plan.as_ref().map_or(0.0, |p| p.variation),
        })
    }

    /// A humanoid clip (BVH bytes) retargeted onto another skeleton: the
    /// skeleton of `target` (BVH bytes; its motion is ignored) or, without
    /// it, the model's. `map` is a JSON role map (`{"leftShin": "Knee_L"}`)
    /// replacing roles found in the clip by name. Returns BVH text at the
    /// clip's frame rate.
    pub fn retarget(
        &self,
        bvh: &[u8],
        target: Option<Vec<u8>>,
        map: Option<String>,
    ) -> Result<String, JsError> {
        use crate::skeleton::Bvh;
        let src = Bvh::parse_bytes(bvh).map_err(js_err)?;
        let to = match &target {
            Some(t) => Bvh::parse_bytes(t).map_err(js_err)?,
            None => self.inner.template.clone(),
        };
        let overrides = match &map {
            Some(m) => crate::skeleton::retarget::parse_map(m).map_err(js_err)?,
            None => Default::default(),
        };
        let (out, _) =
            crate::motion::clip::retarget(&src, &to, Some(&self.inner.template), &overrides)
                .map_err(js_err)?;
        Ok(out.write())
    }
}

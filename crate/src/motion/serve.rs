//! Runs an in-betweening request by the pipeline [`plan`](super::plan)
//! chose: the one execution path behind the CLI and the wasm
//! `Inbetweener`, so that both run what they planned the same way.

use super::cond::CondModel;
use super::feet::{lock_feet, FootLock, FootLockStats};
use super::pipeline::TweenModels;
use super::plan::{plan, Ask, Loaded, Pipeline, Plan};
use super::residual::ResidualModel;
use super::{baseline, Keyframe, Motion};
use crate::error::{Error, Result};

/// The networks a front-end has loaded (any may be absent).
#[derive(Clone, Copy, Default)]
pub struct Models<'a> {
    /// The generator pipeline.
    pub generator: Option<&'a TweenModels>,
    /// The residual network.
    pub residual: Option<&'a ResidualModel>,
    /// The conditional network.
    pub cond: Option<&'a CondModel>,
    /// The DNA network (`tween_cond_dna`: requests with Motion DNA).
    pub cond_dna: Option<&'a CondModel>,
    /// The gap-filling network (a conditional network trained on gaps).
    pub fill: Option<&'a CondModel>,
    /// The long-gap filling network (a residual network trained on gaps).
    pub fill_long: Option<&'a ResidualModel>,
}

impl Models<'_> {
    /// What the planner needs of them.
    pub fn loaded(&self) -> Loaded {
        Loaded {
            generator: self.generator.map(|g| g.default_variation),
            residual: self.residual.map(|r| r.info()),
            cond: self.cond.map(|c| c.info()),
            cond_dna: self.cond_dna.map(|c| c.info()),
            fill: self.fill.map(|c| c.info()),
            fill_long: self.fill_long.map(|r| r.info()),
        }
    }
}

/// A request in the form every front-end reads.
#[derive(Clone, Debug)]
pub struct Request {
    /// `model`, `generator`, `residual`, `cond`, `fill`, `fill-long`, `slerp` or `zerovel`.
    pub method: String,
    /// The keys.
    pub keys: Vec<Keyframe>,
    /// Frames to make.
    pub frames: usize,
    /// Motion DNA poses, if any.
    pub dna: Option<Vec<Vec<f32>>>,
    /// Make the keys exact.
    pub post_process: bool,
    /// The variation asked for (absent: the planned pipeline's default).
    pub variation: Option<f32>,
    /// Pin feet in contact with the floor (only with post-processing).
    pub foot_lock: bool,
    /// The conditional network's noise draw (`None`: zero noise, its
    /// seedless output); the other pipelines take none.
    pub seed: Option<u64>,
}

impl Request {
    /// The planner's view of it.
    pub fn ask(&self) -> Ask<'_> {
        Ask {
            method: &self.method,
            keys: &self.keys,
            dna: self.dna.is_some(),
            post_process: self.post_process,
            variation: self.variation,
        }
    }
}

/// A served request.
#[derive(Clone, Debug)]
pub struct Served {
    /// The motion (60 fps, the model's skeleton).
    pub motion: Motion,
    /// What ran, at which variation.
    pub plan: Plan,
    /// Milliseconds per stage: generator (or the one stage of the others;
    /// the conditional network's), RC-FK, path, post-processing (the
    /// generator's and the conditional network's).
    pub stage_ms: [f64; 4],
    /// Key errors (BVH units): root and joints before post-processing,
    /// then after (the generator and the conditional network; zeros for the
    /// others, whose keys are exact by construction).
    pub key_error: [f64; 4],
    /// The critical frames a hierarchical synthesis made first (the
    /// generator's or the conditional network's).
    pub critical_frames: Vec<usize>,
    /// Foot locking's work, when asked.
    pub feet: Option<FootLockStats>,
}

/// Plans `req` against `models` and runs it. `now_ms` is a clock in
/// milliseconds (stage times).
pub fn serve(models: &Models, req: Request, now_ms: &dyn Fn() -> f64) -> Result<Served> {
    let p = plan(&req.ask(), &models.loaded())?;
    run(models, p, req, now_ms)
}

/// Runs `req` by an already made plan `p`.
pub fn run(models: &Models, p: Plan, req: Request, now_ms: &dyn Fn() -> f64) -> Result<Served> {
    let missing = |what: &str| Error::Invalid(format!("the {what} is not loaded"));
    let t0 = now_ms();
    let one_stage = |motion: Motion, feet: Option<FootLockStats>| Served {
        motion,
        plan: p,
        stage_ms: [now_ms() - t0, 0.0, 0.0, 0.0],
        key_error: [0.0; 4],
        critical_frames: Vec::new(),
        feet,
    };
    match p.pipeline {
        Pipeline::Residual | Pipeline::FillLong => {
            let r = match p.pipeline {
                Pipeline::FillLong => models
                    .fill_long
                    .ok_or_else(|| missing("long-gap filling network"))?,
                _ => models.residual.ok_or_else(|| missing("residual network"))?,
            };
            let mut m = r.synthesize(&req.keys, req.frames, p.variation)?;
            let feet = (req.foot_lock && req.post_process)
                .then(|| lock_feet(&mut m, &r.template, &req.keys, &FootLock::default()));
            Ok(one_stage(m, feet))
        }
        Pipeline::Cond | Pipeline::CondDna | Pipeline::Fill => {
            let c = match p.pipeline {
                Pipeline::Fill => models.fill.ok_or_else(|| missing("gap-filling network"))?,
                Pipeline::CondDna => models.cond_dna.ok_or_else(|| missing("DNA network"))?,
                _ => models.cond.ok_or_else(|| missing("conditional network"))?,
            };
            let (mut m, critical_frames) = c.synthesize_dna(
                &req.keys,
                req.frames,
                p.variation,
                req.seed,
                req.dna.as_deref(),
            )?;
            let t_net = now_ms();
            let before = super::pipeline::key_error(&m, &req.keys, &c.parents, &c.offsets);
            if req.post_process && req.keys.iter().any(super::xy::is_xy_key) {
                // 2-D keys become rotation keys fitted to the output, then
                // exact (poses and root positions are exact already)
                let pinned = super::xy::pin_xy_keys(&m, &c.template, &req.keys);
                super::post::make_keys_exact(&mut m, &pinned);
            }
            let feet = (req.foot_lock && req.post_process)
                .then(|| lock_feet(&mut m, &c.template, &req.keys, &FootLock::default()));
            let after = super::pipeline::key_error(&m, &req.keys, &c.parents, &c.offsets);
            Ok(Served {
                motion: m,
                plan: p,
                stage_ms: [t_net - t0, 0.0, 0.0, now_ms() - t_net],
                // root and joints before post-processing (what the network
                // gave: root positions and poses exact, 2-D keys not), then after
                key_error: [before.root, before.local, after.root, after.local],
                critical_frames,
                feet,
            })
        }
        Pipeline::Generator => {
            let g = models.generator.ok_or_else(|| missing("generator"))?;
            let foot_lock = (req.post_process && req.foot_lock).then(FootLock::default);
            let locking = foot_lock.is_some();
            let r = super::pipeline::Request {
                keys: req.keys,
                frames: req.frames,
                dna: req.dna,
                post_process: req.post_process,
                foot_lock,
                variation: Some(p.variation),
            };
            let out = g.synthesize(&r, now_ms)?;
            let (t, a, b) = (&out.times, &out.key_error_raw, &out.key_error);
            Ok(Served {
                motion: out.motion,
                plan: p,
                stage_ms: [t.generator_ms, t.rcfk_ms, t.path_ms, t.post_ms],
                key_error: [a.root, a.local, b.root, b.local],
                critical_frames: out.critical_frames,
                feet: locking.then_some(out.foot_lock),
            })
        }
        Pipeline::Slerp => Ok(one_stage(
            baseline::slerp_lerp(&req.keys, req.frames)?,
            None,
        )),
        Pipeline::ZeroVelocity => Ok(one_stage(
            baseline::zero_velocity(&req.keys, req.frames)?,
            None,
        )),
    }
}

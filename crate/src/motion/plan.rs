//! The one place that decides which pipeline serves an in-betweening
//! request, and at which variation.
//!
//! The CLI (`deeprep inbetween`), the wasm `Inbetweener` (`synthesize`,
//! `synthesizeRequest`, `synthesizeFromBvh`, and so the npm worker and the
//! sketching page) all call [`plan`]; none decides on its own. The rules:
//!
//! - `model` (the default method): the residual network when it is loaded,
//!   its manifest makes it the model for whole-pose keys, post-processing
//!   is on, every key is a whole pose with rotations, no Motion DNA is
//!   given (it has no DNA input) and no two keys are more than
//!   [`MAX_GAP`](super::MAX_GAP) frames apart; else the conditional
//!   network when it is loaded, its manifest makes it the model for
//!   partial keys, post-processing is on and it takes the keys
//!   ([`cond_takes`]: whole poses, root positions and 2-D keys of every
//!   joint, no DNA, no gap over `MAX_GAP`); else the conditional network
//!   when its manifest makes it the model for root keys, post-processing is
//!   on and the keys are root positions, alone or with whole poses
//!   ([`root_keys`]: no DNA, no gap over `MAX_GAP`); else the conditional
//!   network when its manifest makes it the model for long gaps and every key is a
//!   whole pose with rotations, without DNA, with a gap over `MAX_GAP`
//!   ([`long_gap_keys`]: its hierarchy); requests with Motion DNA go to the
//!   DNA network (`tween_cond_dna`) when it is loaded, its manifest makes it
//!   the model for DNA, post-processing is on and it takes the keys
//!   ([`dna_keys`]: no gap over `MAX_GAP`); otherwise the generator
//!   pipeline (other partial keys, DNA, long gaps).
//! - `generator`, `residual`, `cond`: that pipeline (the residual network
//!   takes whole-pose keys only, no DNA, and always makes keys exact; the
//!   conditional network takes what [`cond_takes`] accepts; with Motion DNA
//!   `cond` runs the DNA network, `tween_cond_dna`, when it is loaded, else
//!   the conditional network if its manifest says it takes DNA).
//! - `fill`: the gap-filling network (a conditional network trained on
//!   gaps in captured motion, `tween_fill`), whole-pose keys only; the
//!   `model` fill ([`super::fill::method_for`]) sends it the gaps its
//!   manifest claims. `fill-long`: the long-gap filling network (the
//!   residual network fine-tuned on gaps, `tween_fill_long`), likewise.
//! - `slerp`, `zerovel`: the interpolation baselines (variation 0).
//!
//! The variation is the request's when it gives one, else the chosen
//! pipeline's own default (each manifest's, picked on training takes), so
//! root-only keys never run the generator at the residual network's
//! default; it is checked by [`check_variation`](super::check_variation).

pub use super::cond::{cond_takes, dna_keys, long_gap_keys, root_keys, CondInfo};
use super::{check_variation, Keyframe, MAX_GAP};
use crate::error::{Error, Result};

/// A pipeline that can serve a request.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Pipeline {
    /// The supervised residual network on SLERP+LERP (whole-pose keys).
    Residual,
    /// The conditional network (whole-pose, root-only and 2-D keys).
    Cond,
    /// The conditional network trained with Motion DNA (`tween_cond_dna`),
    /// for requests with DNA.
    CondDna,
    /// The gap-filling network (whole-pose keys around gaps).
    Fill,
    /// The long-gap filling network (a residual network; whole-pose keys
    /// around gaps).
    FillLong,
    /// The generator, RC-FK, path predictor and post-processing (Fig. 5.1).
    Generator,
    /// SLERP+LERP interpolation.
    Slerp,
    /// Zero-velocity (hold each key).
    ZeroVelocity,
}

impl Pipeline {
    /// The name results and messages carry: "residual", "generator",
    /// "slerp", "zerovel", "cond", "cond-dna", "fill" or "fill-long".
    pub fn name(self) -> &'static str {
        match self {
            Pipeline::Residual => "residual",
            Pipeline::Cond => "cond",
            Pipeline::CondDna => "cond-dna",
            Pipeline::Fill => "fill",
            Pipeline::FillLong => "fill-long",
            Pipeline::Generator => "generator",
            Pipeline::Slerp => "slerp",
            Pipeline::ZeroVelocity => "zerovel",
        }
    }
}

/// The methods a request may name.
pub const METHODS: [&str; 8] = [
    "model",
    "generator",
    "residual",
    "cond",
    "fill",
    "fill-long",
    "slerp",
    "zerovel",
];

/// What is loaded, as the planner needs it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Loaded {
    /// The generator's default variation (its manifest's); `None` when the
    /// generator is not loaded.
    pub generator: Option<f32>,
    /// The residual network, when loaded.
    pub residual: Option<ResidualInfo>,
    /// The conditional network, when loaded.
    pub cond: Option<CondInfo>,
    /// The DNA network (a conditional network with a DNA input, for
    /// requests with Motion DNA), when loaded.
    pub cond_dna: Option<CondInfo>,
    /// The gap-filling network, when loaded.
    pub fill: Option<CondInfo>,
    /// The long-gap filling network, when loaded.
    pub fill_long: Option<ResidualInfo>,
}

/// The residual network's manifest, as the planner needs it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ResidualInfo {
    /// Its default variation.
    pub variation: f32,
    /// Whether the `model` method runs it for the keys it takes.
    pub default_for_whole_pose_keys: bool,
    /// A gap-filling network's band (`fill_from..=fill_up_to`).
    pub fill_gaps: Option<(usize, usize)>,
}

impl ResidualInfo {
    /// This network as the long-gap filling network (`tween_fill_long`):
    /// an error unless its manifest gives a band, without which the `model`
    /// fill would never run it.
    pub fn as_fill_long_network(self) -> Result<Self> {
        if self.fill_gaps.is_some() {
            Ok(self)
        } else {
            Err(Error::Invalid(
                "the long-gap filling network's manifest gives no band (fill_up_to)".into(),
            ))
        }
    }
}

/// Whether `method` runs a network (on the model's skeleton: a clip on
/// another skeleton is retargeted onto it first), for requests with keys
/// ([`METHODS`]) and for fills (`fill-mlp` too, [`super::fill::method_for`]).
pub fn runs_network(method: &str) -> bool {
    matches!(
        method,
        "model" | "generator" | "residual" | "cond" | "fill" | "fill-long" | "fill-mlp"
    )
}

/// A request, as the planner needs it.
#[derive(Copy, Clone, Debug)]
pub struct Ask<'a> {
    /// `model`, `generator`, `residual`, `cond`, `fill`, `fill-long`, `slerp` or `zerovel`.
    pub method: &'a str,
    /// The keys.
    pub keys: &'a [Keyframe],
    /// Whether Motion DNA poses are given.
    pub dna: bool,
    /// Whether post-processing (exact keys) is on.
    pub post_process: bool,
    /// The variation asked for, if any.
    pub variation: Option<f32>,
}

/// What runs.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Plan {
    /// The pipeline.
    pub pipeline: Pipeline,
    /// The variation it runs at (0 for the baselines, which have none).
    pub variation: f32,
}

/// Whether the residual network can take `keys`: every key a whole pose
/// with rotations, no DNA, no gap over [`MAX_GAP`] frames (longer gaps go
/// to the generator's hierarchical synthesis).
pub fn residual_takes(keys: &[Keyframe], dna: bool) -> bool {
    !dna && !keys.is_empty()
        && keys
            .iter()
            .all(|k| k.rotations.is_some() && k.is_whole_pose())
        && keys
            .windows(2)
            .all(|w| w[1].frame.abs_diff(w[0].frame) <= MAX_GAP)
}

/// Decides the pipeline and variation of a request (the rules above).
pub fn plan(ask: &Ask, loaded: &Loaded) -> Result<Plan> {
    let generator = || {
        loaded.generator.ok_or_else(|| {
            Error::Invalid(
                "the generator is not loaded; method slerp interpolates without it".into(),
            )
        })
    };
    let chosen = |pipeline: Pipeline, default: f32| -> Result<Plan> {
        let variation = ask.variation.unwrap_or(default);
        check_variation(variation)?;
        Ok(Plan {
            pipeline,
            variation,
        })
    };
    match ask.method {
        "model" => match (loaded.residual, loaded.cond, loaded.cond_dna) {
            (_, _, Some(d))
                if d.default_for_dna && ask.post_process && dna_keys(ask.keys, ask.dna) =>
            {
                chosen(Pipeline::CondDna, d.variation)
            }
            (Some(r), _, _)
                if r.default_for_whole_pose_keys
                    && ask.post_process
                    && residual_takes(ask.keys, ask.dna) =>
            {
                chosen(Pipeline::Residual, r.variation)
            }
            (_, Some(c), _)
                if c.default_for_partial_keys
                    && ask.post_process
                    && cond_takes(ask.keys, ask.dna) =>
            {
                chosen(Pipeline::Cond, c.variation)
            }
            (_, Some(c), _)
                if c.default_for_root_keys && ask.post_process && root_keys(ask.keys, ask.dna) =>
            {
                chosen(Pipeline::Cond, c.variation)
            }
            (_, Some(c), _)
                if c.default_for_long_gaps
                    && ask.post_process
                    && long_gap_keys(ask.keys, ask.dna) =>
            {
                chosen(Pipeline::Cond, c.variation)
            }
            _ => chosen(Pipeline::Generator, generator()?),
        },
        "generator" => chosen(Pipeline::Generator, generator()?),
        "residual" => {
            let r = loaded
                .residual
                .ok_or_else(|| Error::Invalid("the residual network is not loaded".into()))?;
            if ask.dna || !ask.post_process {
                return Err(Error::Invalid(
                    "method residual takes no Motion DNA and always makes keys exact (no post-processing switch)"
                        .into(),
                ));
            }
            chosen(Pipeline::Residual, r.variation)
        }
        "cond" => {
            if let Some(d) = loaded.cond_dna.filter(|_| ask.dna) {
                return chosen(Pipeline::CondDna, d.variation);
            }
            let c = loaded
                .cond
                .ok_or_else(|| Error::Invalid("the conditional network is not loaded".into()))?;
            if ask.dna && !c.dna {
                return Err(Error::Invalid(
                    "method cond takes Motion DNA only from a network trained with it (the DNA network \
                     tween_cond_dna, or a conditional network whose manifest says dna); method generator does"
                        .into(),
                ));
            }
            chosen(Pipeline::Cond, c.variation)
        }
        "fill" | "fill-long" => {
            let network = match ask.method {
                "fill" => loaded.fill.map(|f| (Pipeline::Fill, f.variation)),
                _ => loaded.fill_long.map(|f| (Pipeline::FillLong, f.variation)),
            };
            let (pipeline, variation) = network.ok_or_else(|| {
                Error::Invalid(format!(
                    "the {} network is not loaded",
                    match ask.method {
                        "fill" => "gap-filling",
                        _ => "long-gap filling",
                    }
                ))
            })?;
            if !residual_takes(ask.keys, ask.dna) || !ask.post_process {
                return Err(Error::Invalid(format!(
                    "method {} takes whole-pose keys (the frames around a gap) without Motion DNA, \
                     no two more than {MAX_GAP} frames apart, and keeps them exact",
                    ask.method
                )));
            }
            chosen(pipeline, variation)
        }
        "slerp" => chosen(Pipeline::Slerp, 0.0),
        "zerovel" => chosen(Pipeline::ZeroVelocity, 0.0),
        other => Err(Error::Invalid(format!(
            "unknown method '{other}' ({})",
            METHODS.join(", ")
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn which_methods_run_a_network() {
        for m in METHODS {
            assert_eq!(runs_network(m), !matches!(m, "slerp" | "zerovel"), "{m}");
        }
        assert!(runs_network("fill-mlp"));
        assert!(!runs_network("hermite") && !runs_network("nonsense"));
    }

    #[test]
    fn a_long_gap_filling_network_needs_a_band() {
        let r = ResidualInfo {
            variation: 1.0,
            default_for_whole_pose_keys: false,
            fill_gaps: None,
        };
        let e = r.as_fill_long_network().unwrap_err().to_string();
        assert!(e.contains("no band"), "{e}");
        let banded = ResidualInfo {
            fill_gaps: Some((46, 120)),
            ..r
        };
        assert_eq!(banded.as_fill_long_network().unwrap(), banded);
    }
    use crate::rotation::Mat3;

    fn pose(frame: usize) -> Keyframe {
        let eye: Mat3<f64> = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        Keyframe {
            frame,
            positions: vec![0.0; 6],
            mask: vec![true; 6],
            rotations: Some(vec![eye; 2]),
        }
    }

    fn root(frame: usize) -> Keyframe {
        Keyframe::root_only(frame, [0.0, 50.0, 0.0], 2)
    }

    const LOADED: Loaded = Loaded {
        generator: Some(0.25),
        residual: Some(ResidualInfo {
            variation: 1.0,
            default_for_whole_pose_keys: true,
            fill_gaps: None,
        }),
        cond: None,
        cond_dna: None,
        fill: None,
        fill_long: None,
    };

    fn ask<'a>(method: &'a str, keys: &'a [Keyframe]) -> Ask<'a> {
        Ask {
            method,
            keys,
            dna: false,
            post_process: true,
            variation: None,
        }
    }

    #[test]
    fn whole_pose_keys_go_to_the_residual_network_and_the_rest_to_the_generator() {
        let poses = [pose(0), pose(60)];
        let p = plan(&ask("model", &poses), &LOADED).unwrap();
        assert_eq!((p.pipeline, p.variation), (Pipeline::Residual, 1.0));
        // root-only keys: the generator, at the generator's own default
        let roots = [root(0), root(60)];
        let p = plan(&ask("model", &roots), &LOADED).unwrap();
        assert_eq!((p.pipeline, p.variation), (Pipeline::Generator, 0.25));
        // a mix, DNA, post-processing off, a gap over MAX_GAP: the generator
        let mixed = [pose(0), root(60)];
        assert_eq!(
            plan(&ask("model", &mixed), &LOADED).unwrap().pipeline,
            Pipeline::Generator
        );
        let dna = Ask {
            dna: true,
            ..ask("model", &poses)
        };
        assert_eq!(plan(&dna, &LOADED).unwrap().variation, 0.25);
        let raw = Ask {
            post_process: false,
            ..ask("model", &poses)
        };
        assert_eq!(plan(&raw, &LOADED).unwrap().pipeline, Pipeline::Generator);
        let far = [pose(0), pose(MAX_GAP + 1)];
        assert_eq!(
            plan(&ask("model", &far), &LOADED).unwrap().pipeline,
            Pipeline::Generator
        );
        // a residual network that is not the default, or none
        let not_default = Loaded {
            residual: Some(ResidualInfo {
                variation: 1.0,
                default_for_whole_pose_keys: false,
                fill_gaps: None,
            }),
            ..LOADED
        };
        assert_eq!(
            plan(&ask("model", &poses), &not_default).unwrap().pipeline,
            Pipeline::Generator
        );
        let none = Loaded {
            residual: None,
            ..LOADED
        };
        assert_eq!(
            plan(&ask("model", &poses), &none).unwrap().pipeline,
            Pipeline::Generator
        );
    }

    #[test]
    fn an_asked_variation_is_kept_and_checked() {
        let roots = [root(0), root(60)];
        let a = Ask {
            variation: Some(0.7),
            ..ask("model", &roots)
        };
        assert_eq!(plan(&a, &LOADED).unwrap().variation, 0.7);
        for v in [f32::NAN, -0.1, 2.5, f32::INFINITY] {
            let a = Ask {
                variation: Some(v),
                ..ask("model", &roots)
            };
            let e = plan(&a, &LOADED).unwrap_err().to_string();
            assert!(e.contains("must be a number in [0, 2]"), "{e}");
        }
    }

    #[test]
    fn named_methods_and_their_errors() {
        let poses = [pose(0), pose(60)];
        for (m, want) in [
            ("generator", Pipeline::Generator),
            ("residual", Pipeline::Residual),
            ("slerp", Pipeline::Slerp),
            ("zerovel", Pipeline::ZeroVelocity),
        ] {
            assert_eq!(
                plan(&ask(m, &poses), &LOADED).unwrap().pipeline,
                want,
                "{m}"
            );
        }
        assert_eq!(plan(&ask("slerp", &poses), &LOADED).unwrap().variation, 0.0);
        let e = plan(&ask("fast", &poses), &LOADED).unwrap_err().to_string();
        assert!(
            e.contains("unknown method 'fast'") && e.contains("zerovel"),
            "{e}"
        );
        let dna = Ask {
            dna: true,
            ..ask("residual", &poses)
        };
        assert!(plan(&dna, &LOADED).is_err());
        let none = Loaded {
            residual: None,
            generator: None,
            cond: None,
            cond_dna: None,
            fill: None,
            fill_long: None,
        };
        assert!(plan(&ask("residual", &poses), &none).is_err());
        assert!(plan(&ask("model", &poses), &none).is_err());
        assert!(plan(&ask("slerp", &poses), &none).is_ok());
    }

    #[test]
    fn method_cond_takes_dna_when_its_manifest_says_so() {
        let with_dna = |dna| Loaded {
            cond: Some(CondInfo {
                variation: 1.0,
                default_for_partial_keys: false,
                default_for_long_gaps: false,
                default_for_root_keys: false,
                default_for_dna: false,
                fill_gaps: None,
                dna,
            }),
            ..LOADED
        };
        let roots = [root(0), root(60)];
        let cond = Ask {
            dna: true,
            ..ask("cond", &roots)
        };
        let e = plan(&cond, &with_dna(false)).unwrap_err().to_string();
        assert!(e.contains("Motion DNA") && e.contains("generator"), "{e}");
        assert_eq!(
            plan(&cond, &with_dna(true)).unwrap().pipeline,
            Pipeline::Cond
        );
        // `model` keeps DNA requests for the generator
        let model = Ask {
            dna: true,
            ..ask("model", &roots)
        };
        assert_eq!(
            plan(&model, &with_dna(true)).unwrap().pipeline,
            Pipeline::Generator
        );
    }

    #[test]
    fn requests_with_dna_go_to_the_dna_network_when_it_is_loaded() {
        let info = |dna, default_for_dna| CondInfo {
            variation: 0.7,
            default_for_partial_keys: false,
            default_for_long_gaps: false,
            default_for_root_keys: false,
            default_for_dna,
            fill_gaps: None,
            dna,
        };
        let loaded = |default_for_dna| Loaded {
            cond: Some(info(false, false)),
            cond_dna: Some(info(true, default_for_dna)),
            ..LOADED
        };
        let roots = [root(0), root(60)];
        let with_dna = |method| Ask {
            dna: true,
            ..ask(method, &roots)
        };
        // method cond with DNA: the DNA network at its own variation;
        // without DNA: the conditional network
        let p = plan(&with_dna("cond"), &loaded(false)).unwrap();
        assert_eq!((p.pipeline, p.variation), (Pipeline::CondDna, 0.7));
        assert_eq!(p.pipeline.name(), "cond-dna");
        assert_eq!(
            plan(&ask("cond", &roots), &loaded(false)).unwrap().pipeline,
            Pipeline::Cond
        );
        // model: the DNA network only when its manifest says so
        assert_eq!(
            plan(&with_dna("model"), &loaded(false)).unwrap().pipeline,
            Pipeline::Generator
        );
        assert_eq!(
            plan(&with_dna("model"), &loaded(true)).unwrap().pipeline,
            Pipeline::CondDna
        );
        // ... and never without DNA, with post-processing off, or over a
        // gap its single pass cannot take (the generator's hierarchy)
        assert_eq!(
            plan(&ask("model", &roots), &loaded(true)).unwrap().pipeline,
            Pipeline::Generator
        );
        let raw = Ask {
            post_process: false,
            ..with_dna("model")
        };
        assert_eq!(
            plan(&raw, &loaded(true)).unwrap().pipeline,
            Pipeline::Generator
        );
        let far = [root(0), root(MAX_GAP + 1)];
        let far = Ask {
            dna: true,
            ..ask("model", &far)
        };
        assert_eq!(
            plan(&far, &loaded(true)).unwrap().pipeline,
            Pipeline::Generator
        );
        // the generator takes DNA by name whatever is loaded
        assert_eq!(
            plan(&with_dna("generator"), &loaded(true))
                .unwrap()
                .pipeline,
            Pipeline::Generator
        );
    }

    #[test]
    fn partial_keys_go_to_the_conditional_network_when_its_manifest_says_so() {
        let with_cond = |default_for_partial_keys| Loaded {
            cond: Some(CondInfo {
                variation: 0.9,
                default_for_partial_keys,
                default_for_long_gaps: false,
                default_for_root_keys: false,
                default_for_dna: false,
                fill_gaps: None,
                dna: false,
            }),
            ..LOADED
        };
        let roots = [root(0), root(60)];
        let p = plan(&ask("model", &roots), &with_cond(true)).unwrap();
        assert_eq!((p.pipeline, p.variation), (Pipeline::Cond, 0.9));
        // not its default: the generator; asked for by name: it runs
        let p = plan(&ask("model", &roots), &with_cond(false)).unwrap();
        assert_eq!(p.pipeline, Pipeline::Generator);
        let p = plan(&ask("cond", &roots), &with_cond(false)).unwrap();
        assert_eq!(p.pipeline, Pipeline::Cond);
        // whole poses stay with the residual network; DNA, a gap over
        // MAX_GAP and keys it cannot read go to the generator
        let poses = [pose(0), pose(60)];
        let p = plan(&ask("model", &poses), &with_cond(true)).unwrap();
        assert_eq!(p.pipeline, Pipeline::Residual);
        let dna = Ask {
            dna: true,
            ..ask("model", &roots)
        };
        assert_eq!(
            plan(&dna, &with_cond(true)).unwrap().pipeline,
            Pipeline::Generator
        );
        let far = [root(0), root(MAX_GAP + 1)];
        assert_eq!(
            plan(&ask("model", &far), &with_cond(true))
                .unwrap()
                .pipeline,
            Pipeline::Generator
        );
        let mut some_joints = root(30);
        some_joints.mask[3] = true;
        let odd = [root(0), some_joints];
        assert_eq!(
            plan(&ask("model", &odd), &with_cond(true))
                .unwrap()
                .pipeline,
            Pipeline::Generator
        );
        // named without it loaded, or with DNA: errors
        let e = plan(&ask("cond", &roots), &LOADED).unwrap_err().to_string();
        assert!(e.contains("conditional network is not loaded"), "{e}");
        let dna = Ask {
            dna: true,
            ..ask("cond", &roots)
        };
        assert!(plan(&dna, &with_cond(true)).is_err());
    }

    #[test]
    fn long_whole_pose_gaps_go_to_the_conditional_network_when_its_manifest_says_so() {
        let with_cond = |default_for_long_gaps| Loaded {
            cond: Some(CondInfo {
                variation: 0.8,
                default_for_partial_keys: false,
                default_for_long_gaps,
                default_for_root_keys: false,
                default_for_dna: false,
                fill_gaps: None,
                dna: false,
            }),
            ..LOADED
        };
        let far = [pose(0), pose(MAX_GAP + 1)];
        let p = plan(&ask("model", &far), &with_cond(true)).unwrap();
        assert_eq!((p.pipeline, p.variation), (Pipeline::Cond, 0.8));
        // without the flag: the generator's hierarchy, as before
        let p = plan(&ask("model", &far), &with_cond(false)).unwrap();
        assert_eq!(p.pipeline, Pipeline::Generator);
        // short gaps stay with the residual network; DNA, no post-processing
        // and partial keys are not what the flag covers
        let near = [pose(0), pose(MAX_GAP)];
        let p = plan(&ask("model", &near), &with_cond(true)).unwrap();
        assert_eq!(p.pipeline, Pipeline::Residual);
        let dna = Ask {
            dna: true,
            ..ask("model", &far)
        };
        assert_eq!(
            plan(&dna, &with_cond(true)).unwrap().pipeline,
            Pipeline::Generator
        );
        let raw = Ask {
            post_process: false,
            ..ask("model", &far)
        };
        assert_eq!(
            plan(&raw, &with_cond(true)).unwrap().pipeline,
            Pipeline::Generator
        );
        let roots = [root(0), root(MAX_GAP + 1)];
        assert_eq!(
            plan(&ask("model", &roots), &with_cond(true))
                .unwrap()
                .pipeline,
            Pipeline::Generator
        );
    }

    #[test]
    fn root_keys_go_to_the_conditional_network_when_its_manifest_says_so() {
        let with_cond = |default_for_root_keys| Loaded {
            cond: Some(CondInfo {
                variation: 0.7,
                default_for_partial_keys: false,
                default_for_long_gaps: false,
                default_for_root_keys,
                default_for_dna: false,
                fill_gaps: None,
                dna: false,
            }),
            ..LOADED
        };
        // a root path, alone or after a whole pose (the sketching page's)
        for keys in [vec![root(0), root(60)], vec![pose(0), root(60), root(120)]] {
            let p = plan(&ask("model", &keys), &with_cond(true)).unwrap();
            assert_eq!((p.pipeline, p.variation), (Pipeline::Cond, 0.7));
            let p = plan(&ask("model", &keys), &with_cond(false)).unwrap();
            assert_eq!(p.pipeline, Pipeline::Generator);
        }
        // whole poses stay with the residual network; 2-D keys, DNA, no
        // post-processing and a gap over MAX_GAP are not what the flag covers
        let poses = [pose(0), pose(60)];
        let p = plan(&ask("model", &poses), &with_cond(true)).unwrap();
        assert_eq!(p.pipeline, Pipeline::Residual);
        let xy = Keyframe::xy(
            60,
            &[Some([0.0, 50.0]), Some([1.0, 60.0])],
            Some([0.0, 50.0, 0.0]),
        )
        .unwrap();
        let flat = [root(0), xy];
        assert_eq!(
            crate::motion::cond::classify(&flat[1]),
            Some(crate::motion::cond::KeyClass::Xy)
        );
        let p = plan(&ask("model", &flat), &with_cond(true)).unwrap();
        assert_eq!(p.pipeline, Pipeline::Generator);
        let roots = [root(0), root(60)];
        let dna = Ask {
            dna: true,
            ..ask("model", &roots)
        };
        assert_eq!(
            plan(&dna, &with_cond(true)).unwrap().pipeline,
            Pipeline::Generator
        );
        let raw = Ask {
            post_process: false,
            ..ask("model", &roots)
        };
        assert_eq!(
            plan(&raw, &with_cond(true)).unwrap().pipeline,
            Pipeline::Generator
        );
        let far = [root(0), root(MAX_GAP + 1)];
        assert_eq!(
            plan(&ask("model", &far), &with_cond(true))
                .unwrap()
                .pipeline,
            Pipeline::Generator
        );
    }

    #[test]
    fn the_fill_method_runs_the_gap_filling_network_on_whole_poses_only() {
        let with_fill = Loaded {
            fill: Some(CondInfo {
                variation: 1.0,
                default_for_partial_keys: false,
                default_for_long_gaps: false,
                default_for_root_keys: false,
                default_for_dna: false,
                fill_gaps: Some((1, 45)),
                dna: false,
            }),
            ..LOADED
        };
        let poses = [pose(0), pose(1), pose(40)];
        let p = plan(&ask("fill", &poses), &with_fill).unwrap();
        assert_eq!((p.pipeline, p.variation), (Pipeline::Fill, 1.0));
        assert_eq!(p.pipeline.name(), "fill");
        // `model` never plans it: the fill chooses it by gap length
        let p = plan(&ask("model", &poses), &with_fill).unwrap();
        assert_eq!(p.pipeline, Pipeline::Residual);
        let e = plan(&ask("fill", &poses), &LOADED).unwrap_err().to_string();
        assert!(e.contains("gap-filling network is not loaded"), "{e}");
        let roots = [root(0), root(60)];
        let e = plan(&ask("fill", &roots), &with_fill)
            .unwrap_err()
            .to_string();
        assert!(e.contains("whole-pose keys"), "{e}");
        let raw = Ask {
            post_process: false,
            ..ask("fill", &poses)
        };
        assert!(plan(&raw, &with_fill).is_err());
    }

    #[test]
    fn the_fill_long_method_runs_the_long_gap_network_on_whole_poses_only() {
        let with_long = Loaded {
            fill_long: Some(ResidualInfo {
                variation: 1.0,
                default_for_whole_pose_keys: false,
                fill_gaps: Some((46, 120)),
            }),
            ..LOADED
        };
        let poses = [pose(0), pose(1), pose(90)];
        let p = plan(&ask("fill-long", &poses), &with_long).unwrap();
        assert_eq!((p.pipeline, p.variation), (Pipeline::FillLong, 1.0));
        assert_eq!(p.pipeline.name(), "fill-long");
        // `model` never plans it: the fill chooses it by gap length
        let p = plan(&ask("model", &poses), &with_long).unwrap();
        assert_eq!(p.pipeline, Pipeline::Residual);
        let e = plan(&ask("fill-long", &poses), &LOADED)
            .unwrap_err()
            .to_string();
        assert!(e.contains("long-gap filling network is not loaded"), "{e}");
        let roots = [root(0), root(60)];
        let e = plan(&ask("fill-long", &roots), &with_long)
            .unwrap_err()
            .to_string();
        assert!(e.contains("method fill-long takes whole-pose keys"), "{e}");
        let dna = Ask {
            dna: true,
            ..ask("fill-long", &poses)
        };
        assert!(plan(&dna, &with_long).is_err());
    }
}

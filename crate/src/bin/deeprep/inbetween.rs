//! `deeprep inbetween`: keys from a clip or a keys file to motion.

use super::args::CliError;
use super::bvh::load;
use super::USAGE;

/// `deeprep inbetween ...`.
pub fn run(rest: &[&str]) -> Result<(), CliError> {
    Ok(inbetween(rest)?)
}

#[derive(Clone)]
struct Opts {
    from_bvh: Option<String>,
    keys: Option<String>,
    keys_json: Option<String>,
    frames: Option<usize>,
    out: Option<String>,
    method: String,
    models: String,
    post: bool,
    foot_lock: bool,
    variation: Option<f32>,
    dna: Option<String>,
    seed: Option<u64>,
    key_kind: String,
    skeleton: bool,
    fill: Vec<String>,
    context: Option<String>,
}

fn parse_inbetween(args: &[&str]) -> Result<Opts, String> {
    let mut o = Opts {
        from_bvh: None,
        keys: None,
        keys_json: None,
        frames: None,
        out: None,
        method: "model".into(),
        models: "models/onnx".into(),
        post: true,
        foot_lock: false,
        variation: None,
        dna: None,
        seed: None,
        key_kind: "pose".into(),
        skeleton: false,
        fill: Vec::new(),
        context: None,
    };
    let mut i = 0;
    while i < args.len() {
        let next = |i: usize| super::args::value_of(args, i);
        match args[i] {
            "--from-bvh" => o.from_bvh = Some(next(i)?),
            "--fill" => o.fill.push(next(i)?),
            "--context" => o.context = Some(next(i)?),
            "--keys" => o.keys = Some(next(i)?),
            "--frames" => {
                o.frames = Some(
                    next(i)?
                        .parse()
                        .map_err(|_| "--frames expects a number".to_string())?,
                )
            }
            "-o" | "--out" => o.out = Some(next(i)?),
            "--method" => o.method = next(i)?,
            "--dna" => o.dna = Some(next(i)?),
            "--seed" => {
                o.seed = Some(
                    next(i)?
                        .parse()
                        .map_err(|_| "--seed expects a non-negative integer".to_string())?,
                )
            }
            "--variation" => {
                o.variation = Some(
                    next(i)?
                        .parse()
                        .map_err(|_| "--variation expects a number in [0, 2]".to_string())?,
                )
            }
            "--models" => o.models = next(i)?,
            "--key-kind" => o.key_kind = next(i)?,
            "--skeleton" => {
                o.skeleton = true;
                i += 1;
                continue;
            }
            "--no-post" => {
                o.post = false;
                i += 1;
                continue;
            }
            "--foot-lock" => {
                o.foot_lock = true;
                i += 1;
                continue;
            }
            "--no-foot-lock" => {
                o.foot_lock = false;
                i += 1;
                continue;
            }
            a if !a.starts_with('-') && o.keys_json.is_none() => {
                o.keys_json = Some(a.to_string());
                i += 1;
                continue;
            }
            a => return Err(format!("unknown option '{a}'\n{USAGE}")),
        }
        i += 2;
    }
    Ok(o)
}

/// The text of `name` in the models folder, `None` when the folder lacks it.
fn read_manifest(o: &Opts, name: &str) -> Result<Option<String>, String> {
    let p = std::path::Path::new(&o.models).join(name);
    if !p.exists() {
        return Ok(None);
    }
    std::fs::read_to_string(&p)
        .map(Some)
        .map_err(|e| format!("{}: {e}", p.display()))
}

/// What the models folder holds, for the planner (`motion::plan`): the
/// generator's default variation and the other networks' manifests, each
/// absent when its files are (interpolation needs none).
fn loaded(o: &Opts) -> Result<deeprep::motion::plan::Loaded, String> {
    let read = |name: &str| read_manifest(o, name);
    let generator = match read("tween_generator.manifest.json")? {
        Some(t) => Some(
            deeprep::motion::manifest::parse(&t)
                .map_err(|e| e.to_string())?
                .variation,
        ),
        None => None,
    };
    let residual_info = |name: &str| -> Result<_, String> {
        match read(name)? {
            Some(t) => Ok(Some(
                deeprep::motion::residual::info_of_manifest(&t)
                    .map_err(|e| format!("{name}: {e}"))?,
            )),
            None => Ok(None),
        }
    };
    let cond_info = |name: &str| -> Result<_, String> {
        match read(name)? {
            Some(t) => Ok(Some(
                deeprep::motion::cond::info_of_manifest(&t).map_err(|e| format!("{name}: {e}"))?,
            )),
            None => Ok(None),
        }
    };
    Ok(deeprep::motion::plan::Loaded {
        generator,
        residual: residual_info("tween_residual.manifest.json")?,
        cond: cond_info("tween_cond.manifest.json")?,
        cond_dna: cond_info("tween_cond_dna.manifest.json")?
            .map(|d| d.as_dna_network())
            .transpose()
            .map_err(|e| format!("tween_cond_dna.manifest.json: {e}"))?,
        fill: cond_info("tween_fill.manifest.json")?,
        fill_long: residual_info("tween_fill_long.manifest.json")?
            .map(|r| r.as_fill_long_network())
            .transpose()
            .map_err(|e| format!("tween_fill_long.manifest.json: {e}"))?,
    })
}

/// Plans the request (`motion::plan`, as the wasm API and the page do),
/// loads what the plan runs, and runs it (`motion::serve`).
fn synthesize(
    o: &Opts,
    keys: &[deeprep::motion::Keyframe],
    frames: usize,
    dna: Option<Vec<Vec<f32>>>,
) -> Result<(deeprep::motion::Motion, String), String> {
    use deeprep::motion::plan::Pipeline;
    use deeprep::motion::serve::{run, Models, Request};
    use deeprep::motion::{cond::CondModel, pipeline::TweenModels, residual::ResidualModel};
    let req = Request {
        method: o.method.clone(),
        keys: keys.to_vec(),
        frames,
        dna,
        post_process: o.post,
        variation: o.variation,
        foot_lock: o.foot_lock,
        seed: o.seed.filter(|_| o.dna.is_none()),
    };
    let plan = deeprep::motion::plan::plan(&req.ask(), &loaded(o)?).map_err(|e| e.to_string())?;
    let dir = std::path::Path::new(&o.models);
    // only what the plan runs is loaded
    let runs = |p: Pipeline| plan.pipeline == p;
    let generator = runs(Pipeline::Generator)
        .then(|| TweenModels::load_dir(dir))
        .transpose()
        .map_err(|e| e.to_string())?;
    let residual = runs(Pipeline::Residual)
        .then(|| ResidualModel::load_dir(dir))
        .transpose()
        .map_err(|e| e.to_string())?;
    let cond = runs(Pipeline::Cond)
        .then(|| CondModel::load_named(dir, "tween_cond"))
        .transpose()
        .map_err(|e| e.to_string())?;
    let cond_dna = runs(Pipeline::CondDna)
        .then(|| CondModel::load_named(dir, "tween_cond_dna"))
        .transpose()
        .map_err(|e| e.to_string())?;
    let fill = runs(Pipeline::Fill)
        .then(|| CondModel::load_named(dir, "tween_fill"))
        .transpose()
        .map_err(|e| e.to_string())?;
    let fill_long = runs(Pipeline::FillLong)
        .then(|| ResidualModel::load_named(dir, "tween_fill_long"))
        .transpose()
        .map_err(|e| e.to_string())?;
    let models = Models {
        generator: generator.as_ref(),
        residual: residual.as_ref(),
        cond: cond.as_ref(),
        cond_dna: cond_dna.as_ref(),
        fill: fill.as_ref(),
        fill_long: fill_long.as_ref(),
    };
    let start = std::time::Instant::now();
    let clock = move || start.elapsed().as_secs_f64() * 1000.0;
    let s = run(&models, plan, req, &clock).map_err(|e| e.to_string())?;
    let t = s.stage_ms;
    let mut info = format!(
        "pipeline {} at variation {:.2} (motion::plan)",
        plan.pipeline.name(),
        plan.variation
    );
    match plan.pipeline {
        Pipeline::Generator => {
            let e = s.key_error;
            info += &format!(
                "; key error before post-processing: root {:.3}, joints {:.3}; after: root {:.3}, joints {:.3}; stages ms: generator {:.1}, rc-fk {:.1}, path {:.1}, post {:.1}",
                e[0], e[1], e[2], e[3], t[0], t[1], t[2], t[3]
            );
        }
        Pipeline::Cond | Pipeline::CondDna | Pipeline::Fill => {
            let e = s.key_error;
            info += &format!(
                "; key error before post-processing: root {:.3}, joints {:.3}; after: root {:.3}, joints {:.3}; stages ms: network {:.1}, post {:.1}",
                e[0], e[1], e[2], e[3], t[0], t[3]
            );
        }
        _ => info += &format!("; {:.1} ms", t[0]),
    }
    if !s.critical_frames.is_empty() {
        // the gap over which each pipeline runs hierarchically
        let over = match plan.pipeline {
            Pipeline::Generator => deeprep::motion::MAX_GAP,
            _ => deeprep::motion::cond::HIER_GAP,
        };
        info += &format!(
            "; hierarchical (a gap over {over} frames): critical keys made first at frames {:?}",
            s.critical_frames
        );
    }
    if let Some(f) = s.feet {
        info += &format!(
            "; feet: {} contacts pinned over {} frames",
            f.contacts, f.frames
        );
    }
    Ok((s.motion, info))
}

/// Motion DNA poses from `--dna`: frames `F1,F2,...` of the `--from-bvh`
/// clip, or every frame of a BVH file on the model's skeleton; with
/// `--seed`, the representative frames of a seeded window of that file
/// (`motion::dna::pick_dna_frames`) for an output of `out_frames` frames.
fn dna_poses(
    o: &Opts,
    clip: Option<&deeprep::skeleton::Bvh>,
    out_frames: usize,
) -> Result<Option<Vec<Vec<f32>>>, String> {
    use deeprep::motion::{dna_pose, Keyframe};
    let Some(spec) = &o.dna else {
        return match o.seed {
            // without DNA, a seed is the conditional network's noise draw
            Some(_) if o.method == "cond" => Ok(None),
            Some(_) => Err("--seed draws Motion DNA from a clip: give --dna DNA.bvh (without DNA the motion is deterministic; --method cond takes a seed as its noise draw)".into()),
            None => Ok(None),
        };
    };
    let frames: Option<Vec<usize>> = spec.split(',').map(|s| s.trim().parse().ok()).collect();
    let file;
    let (bvh, frames) = match frames {
        Some(_) if o.seed.is_some() => {
            return Err("--seed draws DNA frames from a --dna DNA.bvh file; with --dna F1,F2,... the frames are already chosen".into());
        }
        Some(f) => (
            clip.ok_or(
                "--dna F1,F2,... takes frames of the --from-bvh clip; give a BVH file otherwise",
            )?,
            f,
        ),
        None => {
            file = load(spec)?;
            let tpl = model_skeleton(o)?;
            deeprep::motion::clip::check_skeleton(&file, &tpl)
                .map_err(|e| format!("--dna {spec}: {e}"))?;
            let picked = match o.seed {
                Some(seed) => deeprep::motion::dna::pick_from_clip(&file, out_frames, seed)
                    .map_err(|e| format!("--dna {spec}: {e}"))?,
                None => (0..file.frame_count()).collect(),
            };
            (&file, picked)
        }
    };
    if frames.is_empty() {
        return Err(format!("--dna {spec}: no poses"));
    }
    frames
        .iter()
        .map(|&f| {
            Keyframe::from_bvh(bvh, f, 0)
                .map(|k| dna_pose(&k))
                .map_err(|e| format!("--dna {spec}: frame {f}: {e}"))
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// The networks' skeleton (the generator's manifest; the residual
/// network's is the same).
fn model_skeleton(o: &Opts) -> Result<deeprep::skeleton::Bvh, String> {
    super::bvh::model_skeleton(&o.models)
}

/// `--from-bvh CLIP --fill START-END ...`: each gap's frames synthesized
/// from the context around it (`motion::fill`), every other frame kept.
fn fill(
    o: &Opts,
    clip: &str,
    user: &deeprep::skeleton::Bvh,
    b: &deeprep::skeleton::Bvh,
    on_model: Option<&deeprep::motion::clip::OnModel>,
) -> Result<(), String> {
    use deeprep::motion::fill::{self, Context, Gap};
    if o.keys.is_some() || o.dna.is_some() || o.key_kind != "pose" {
        return Err("--fill takes the frames around each gap as whole-pose keys: leave out --keys, --dna and --key-kind".into());
    }
    let gaps: Vec<Gap> = o
        .fill
        .iter()
        .map(|s| Gap::parse(s).map_err(|e| format!("--fill: {e}")))
        .collect::<Result<_, _>>()?;
    let ctx = match &o.context {
        Some(c) => Context::parse(c).map_err(|e| format!("--context: {e}"))?,
        None => fill::DEFAULT_CONTEXT,
    };
    let mut info: Vec<String> = Vec::new();
    let l = loaded(o)?;
    // the short-gap network: its band from its manifest; loaded on the
    // first gap that runs it
    let dir = std::path::Path::new(&o.models);
    let fill_mlp = read_manifest(o, "tween_fill_mlp.manifest.json")?
        .map(|t| deeprep::motion::fill_mlp::band_of_manifest(&t))
        .transpose()
        .map_err(|e| format!("tween_fill_mlp.manifest.json: {e}"))?;
    let bands = fill::Bands {
        fill_mlp,
        fill: l.fill.and_then(|f| f.fill_gaps),
        fill_long: l.fill_long.and_then(|f| f.fill_gaps),
    };
    let mut mlp: Option<deeprep::motion::fill_mlp::FillMlp> = None;
    let filled = fill::fill(b, &gaps, ctx, &mut |clip, ck, gap| {
        let method = fill::method_for(&o.method, gap.len(), bands);
        if method == "hermite" {
            info.push(format!(
                "{}-{}: a cubic Hermite curve with the context's tangents",
                gap.start, gap.end
            ));
            return fill::hermite(clip, ck);
        }
        if method == "fill-mlp" {
            let net = match &mut mlp {
                Some(net) => net,
                None => mlp.insert(deeprep::motion::fill_mlp::FillMlp::load_named(
                    dir,
                    "tween_fill_mlp",
                )?),
            };
            info.push(format!(
                "{}-{}: the short-gap fill network (tween_fill_mlp) on the Hermite curve",
                gap.start, gap.end
            ));
            return net.fill(clip, ck);
        }
        let asked = Opts {
            method: method.to_string(),
            ..o.clone()
        };
        let (m, i) =
            synthesize(&asked, &ck.keys, ck.frames(), None).map_err(deeprep::Error::Invalid)?;
        info.push(format!("{}-{}: {i}", gap.start, gap.end));
        Ok(m)
    })
    .map_err(|e| format!("--fill: {e}"))?;
    let path = o
        .out
        .clone()
        .ok_or("-o OUT.bvh is required with --from-bvh")?;
    let original = std::fs::read(clip).map_err(|e| format!("{clip}: {e}"))?;
    let (out, text) =
        fill::on_user(user, &original, filled, on_model, &gaps).map_err(|e| e.to_string())?;
    std::fs::write(&path, text).map_err(|e| format!("{path}: {e}"))?;
    eprintln!(
        "wrote {path}: {} frames, {} gap(s) of {clip} filled ({} frames) with {} frames of context before and {} after by --method {}: {}",
        out.frame_count(),
        gaps.len(),
        gaps.iter().map(|g| g.len()).sum::<usize>(),
        ctx.before,
        ctx.after,
        o.method,
        info.join("; ")
    );
    Ok(())
}

fn inbetween(args: &[&str]) -> Result<(), String> {
    let o = parse_inbetween(args)?;
    if o.skeleton {
        // the joint order of keys files' "xy" lists, one name a line
        let m = deeprep::motion::pipeline::TweenModels::load_dir(std::path::Path::new(&o.models))
            .map_err(|e| e.to_string())?;
        let names: Vec<&str> = m.template.joints.iter().map(|j| j.name.as_str()).collect();
        super::args::emit(&(names.join("\n") + "\n"))?;
        return Ok(());
    }
    let kind = deeprep::motion::keys::KeyKind::parse(&o.key_kind)
        .map_err(|e| format!("--key-kind: {e}"))?;
    if o.from_bvh.is_some() {
        if let Some(k) = &o.keys_json {
            return Err(format!(
                "a keys file ({k}) and --from-bvh are two sources of keys: give one"
            ));
        }
        if o.frames.is_some() {
            return Err(
                "--frames is for a keys file; with --from-bvh the keys' span in the clip sets the length"
                    .into(),
            );
        }
        if o.out.is_none() {
            return Err("-o OUT.bvh is required with --from-bvh".into());
        }
    }
    if kind != deeprep::motion::keys::KeyKind::Pose && o.from_bvh.is_none() {
        return Err(
            "--key-kind takes keys from a --from-bvh clip; a keys file says each key's kind".into(),
        );
    }
    if let Some(clip) = &o.from_bvh {
        let user = load(clip)?;
        // on another humanoid skeleton: retargeted onto the model's, the
        // result back onto the user's (slerp and zerovel work on any skeleton)
        let on_model = if deeprep::motion::plan::runs_network(&o.method) {
            let tpl = model_skeleton(&o)?;
            Some(
                deeprep::motion::clip::OnModel::new(&user, &tpl).map_err(|e| {
                    format!("{clip}: {e}; --method slerp or zerovel work on any skeleton")
                })?,
            )
        } else {
            None
        };
        let b = on_model
            .as_ref()
            .map(|m| m.clip.clone())
            .unwrap_or_else(|| user.clone());
        if !o.fill.is_empty() {
            return fill(&o, clip, &user, &b, on_model.as_ref());
        }
        if o.context.is_some() {
            return Err("--context goes with --fill".into());
        }
        let list = o
            .keys
            .as_ref()
            .ok_or("--from-bvh needs --keys F1,F2,... or --fill START-END")?;
        let frames: Vec<usize> = list
            .split(',')
            .map(|s| {
                s.trim()
                    .parse::<usize>()
                    .map_err(|_| format!("--keys: '{s}' is not a frame index"))
            })
            .collect::<Result<_, _>>()?;
        let mut ck = deeprep::motion::clip::clip_keys(&b, &frames, false)
            .map_err(|e| format!("--keys: {e}"))?;
        ck.keys = ck
            .keys
            .iter()
            .map(|k| kind.of(k))
            .collect::<Result<_, _>>()
            .map_err(|e| e.to_string())?;
        let dna = dna_poses(&o, Some(&b), ck.frames())?;
        let (motion, info) = synthesize(&o, &ck.keys, ck.frames(), dna)?;
        let mut out = deeprep::motion::clip::splice(&b, &ck, &motion).map_err(|e| e.to_string())?;
        if let Some(m) = on_model.as_ref().filter(|m| m.retargeted()) {
            out = m.back(&user, out, &ck).map_err(|e| e.to_string())?;
            eprintln!("{clip}: not on the model's skeleton; retargeted onto it and the result back (skeleton::retarget)");
        }
        let path = o.out.ok_or("-o OUT.bvh is required with --from-bvh")?;
        std::fs::write(&path, out.write()).map_err(|e| format!("{path}: {e}"))?;
        let (first, last) = ck.span();
        eprintln!(
            "wrote {path}: {} frames, frames {first}..={last} synthesized by --method {}: {info}",
            out.frame_count(),
            o.method
        );
        return Ok(());
    }
    let keys_path = o
        .keys_json
        .clone()
        .unwrap_or_else(|| "models/examples/keys.json".into());
    let text = std::fs::read_to_string(&keys_path).map_err(|e| format!("{keys_path}: {e}"))?;
    let models = deeprep::motion::pipeline::TweenModels::load_dir(std::path::Path::new(&o.models))
        .map_err(|e| e.to_string())?;
    let tpl = &models.template;
    let file =
        deeprep::motion::keys::from_json(&text, tpl).map_err(|e| format!("{keys_path}: {e}"))?;
    let keys = file.keys;
    let frames = o
        .frames
        .or(file.frames)
        .ok_or("--frames N is required (or \"frames\" in the keys file)")?;
    let dna = dna_poses(&o, None, frames)?;
    let (motion, info) = synthesize(&o, &keys, frames, dna)?;
    let out = motion.to_bvh(tpl, 1.0 / 60.0).map_err(|e| e.to_string())?;
    let path = o.out.unwrap_or_else(|| "inbetween.bvh".into());
    std::fs::write(&path, out.write()).map_err(|e| format!("{path}: {e}"))?;
    eprintln!(
        "wrote {path}: {frames} frames at 60 fps from {} keys. {info}",
        keys.len()
    );
    Ok(())
}

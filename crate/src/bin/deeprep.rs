//! The deeprep command line.
//!
//! ```text
//! deeprep bvh info FILE            skeleton, frame count and rate
//! deeprep bvh fk FILE --frame N    one line per joint: <name> x y z (global, file units)
//! ```

use deeprep::skeleton::{fk, Bvh};
use std::fmt::Write as _;
use std::io::Write as _;
use std::process::ExitCode;

/// Prints the whole output at once; a closed pipe (e.g. `| head`) is not an error.
fn emit(s: &str) {
    let _ = std::io::stdout().lock().write_all(s.as_bytes());
}

/// The most random poses `mesh poses` writes (per clip: `mesh::rig::MAX_CLIP_SAMPLES`).
const MAX_CLIP_POSES: usize = 100_000;

const USAGE: &str = "usage:
  deeprep bvh info FILE
  deeprep bvh fk FILE --frame N
  deeprep bvh export FILE --out PREFIX
      writes PREFIX.json (skeleton, frame rate, layouts), PREFIX.positions.f32
      (frames x joints x 3 global positions) and PREFIX.rc.f32 (frames x (3 + 6 + 3K):
      root position, root 6D, range-constrained Euler angles in radians, clamped to
      Table D.1), little-endian f32; for the training pipeline
  deeprep inbetween --from-bvh CLIP.bvh --keys F1,F2,... -o OUT.bvh
          [--method model|residual|slerp|zerovel] [--models DIR] [--no-post] [--foot-lock] [--variation V]
          [--dna F1,F2,...|DNA.bvh [--seed S]]
      whole-pose keys from those frames of CLIP; OUT has CLIP's length, frame rate and
      skeleton; frames between the first and last key are synthesized, the others copied
      --method residual: the supervised residual on SLERP+LERP (models/onnx/tween_residual.onnx;
      --variation scales its correction, 1 by default)
  deeprep inbetween KEYS.json --frames N [-o OUT.bvh] [--models DIR] [--no-post] [--foot-lock] [--variation V] [--dna DNA.bvh [--seed S]]
      --no-post: keys not made exact; --foot-lock: after that, pin feet in contact by two-bone IK
      (off by default: at the default variation it raised L2P, NPSS and foot skating on training takes)
      --variation V in [0, 2]: share of the networks' departure from SLERP+LERP kept, in the pose
      and the root path (1: the networks as trained; 0: SLERP+LERP; default: the model's
      manifest value, chosen on training takes)
      --dna: Motion DNA poses (Sec. 5.2.5), frames of CLIP or every frame of a BVH on the
      model's skeleton; without it the whole-pose keys serve
      --seed S (with --dna DNA.bvh): DNA drawn as in training, the representative frames
      (largest rotation change) of a window of DNA.bvh that S places; equal seeds, equal motion
      KEYS.json: {\"keys\": [{\"frame\": F, \"channels\": [...]}, ...]} (BVH channels of the
      model's skeleton); without arguments, runs the bundled example models/examples/keys.json
  deeprep mesh topology ROBOT.glb --out TOPOLOGY.json
      the mesh autoencoder's topology: welded vertices, triangles, connected edge graph,
      sampling levels (s = 2, r = 2) with padded index/mask tables, latent seed vertices
  deeprep mesh poses ROBOT.glb --out PREFIX [--fps N] [--random N] [--seed S]
      every animation clip sampled at N fps (default 30) plus N random poses (default 0;
      each joint turned up to 30 degrees from a random clip frame), welded:
      PREFIX.f32 (poses x vertices x 3, little-endian) and PREFIX.json (clip per pose)
  deeprep hair dataset --out PREFIX [--base N] [--blends N] [--views N] [--size S] [--seed S]
      procedural hair data (ch. 3): N base styles per class (18 classes: XS..XXL x
      straight/wavy/curly), each mirrored, plus N in-class blends per base style, every
      hair rendered from N random views at S x S; split by base style (train/val/test).
      Writes PREFIX.json (hairs, classes, splits), PREFIX.strands.f32 (hairs x 1024 x 100
      x 3, root-relative metres), PREFIX.curvature.f32 (hairs x 1024 x 100, 1/m),
      PREFIX.images.u8 (renders x 3 x S x S) and PREFIX.visible.u8 (renders x 1024 x 100)
  deeprep hair preview --class M-curly [--seed S] [--yaw DEG] [--size S] --out FILE.ppm
      one procedural hair's render (orientation as red/green, segmentation as blue)";

fn robot(path: &str) -> Result<(deeprep::mesh::Rig, deeprep::mesh::Topology), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    let rig = deeprep::mesh::Rig::from_glb(&bytes).map_err(|e| format!("{path}: {e}"))?;
    let topo = deeprep::mesh::Topology::robot(&rig).map_err(|e| format!("{path}: {e}"))?;
    Ok((rig, topo))
}

fn mesh_topology(path: &str, out: &str) -> Result<(), String> {
    let (rig, t) = robot(path)?;
    let table = |n: &deeprep::mesh::NeighborTable| serde_json::json!({"rows": n.rows, "width": n.width, "indices": n.indices, "mask": n.mask});
    let levels: Vec<serde_json::Value> = t
        .levels
        .iter()
        .map(|l| {
            serde_json::json!({
                "stride": l.stride, "radius": l.radius, "selected": l.selected,
                "edges": l.graph.edges(), "down": table(&l.down), "up": table(&l.up),
            })
        })
        .collect();
    let doc = serde_json::json!({
        "source": path,
        "rig_vertices": rig.vertex_count(),
        "weld_map": t.weld_map,
        "rest": t.rest,
        "triangles": t.triangles,
        "edges": t.graph.edges(),
        "added_edges": t.added_edges,
        "seeds": t.seeds,
        "levels": levels,
        "layout": "levels[k].down: one row per vertex of level k+1 (indices into level k); levels[k].up: one row per vertex of level k (indices into level k+1); level 0 is the welded mesh",
    });
    std::fs::write(out, doc.to_string()).map_err(|e| format!("{out}: {e}"))?;
    let sizes: Vec<usize> = std::iter::once(t.rest.len())
        .chain(t.levels.iter().map(|l| l.selected.len()))
        .collect();
    eprintln!(
        "wrote {out}: {} rig vertices welded to {}, {} edges added, levels {sizes:?}",
        rig.vertex_count(),
        t.rest.len(),
        t.added_edges.len()
    );
    Ok(())
}

fn mesh_poses(path: &str, rest: &[&str]) -> Result<(), String> {
    let (mut out, mut fps, mut random, mut seed) = (None, 30.0f32, 0usize, 1u64);
    let mut i = 0;
    while i < rest.len() {
        let val = rest
            .get(i + 1)
            .ok_or_else(|| format!("{} needs a value", rest[i]))?;
        match rest[i] {
            "--out" => out = Some(val.to_string()),
            "--fps" => {
                fps = val
                    .parse()
                    .map_err(|_| format!("--fps expects a number, got '{val}'"))?
            }
            "--random" => {
                random = val
                    .parse()
                    .map_err(|_| format!("--random expects a count, got '{val}'"))?
            }
            "--seed" => {
                seed = val
                    .parse()
                    .map_err(|_| format!("--seed expects an integer, got '{val}'"))?
            }
            a => return Err(format!("unknown option '{a}'\n{USAGE}")),
        }
        i += 2;
    }
    let out = out.ok_or_else(|| format!("--out PREFIX is required\n{USAGE}"))?;
    if !(fps > 0.0 && fps <= 240.0) {
        return Err(format!("--fps must be in (0, 240], got {fps}"));
    }
    if random > MAX_CLIP_POSES {
        return Err(format!(
            "--random is at most {MAX_CLIP_POSES}, got {random}"
        ));
    }
    let (rig, t) = robot(path)?;
    let mut data: Vec<f32> = Vec::new();
    let mut labels = Vec::new();
    let mut push = |pose: Vec<[f32; 3]>,
                    label: serde_json::Value,
                    data: &mut Vec<f32>|
     -> Result<(), String> {
        for p in t.weld_pose(&pose).map_err(|e| e.to_string())? {
            data.extend_from_slice(&p);
        }
        labels.push(label);
        Ok(())
    };
    for (k, a) in rig.animations.iter().enumerate() {
        let frames = rig.clip_sample_count(k, fps).map_err(|e| e.to_string())?;
        for f in 0..frames {
            let pose = rig
                .animation_pose(k, f as f32 / fps)
                .map_err(|e| e.to_string())?;
            push(
                pose,
                serde_json::json!({"clip": a.name, "time": f as f32 / fps}),
                &mut data,
            )?;
        }
    }
    let mut rng = deeprep::rng::Rng::new(seed);
    for r in 0..random {
        let (local, k, time) = rig
            .jittered_locals(&mut rng, 30f32.to_radians())
            .map_err(|e| e.to_string())?;
        let pose = rig.pose(&local).map_err(|e| e.to_string())?;
        push(
            pose,
            serde_json::json!({"clip": "random", "index": r, "from": rig.animations[k].name, "time": time}),
            &mut data,
        )?;
    }
    let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(format!("{out}.f32"), bytes).map_err(|e| format!("{out}.f32: {e}"))?;
    let meta = serde_json::json!({"source": path, "vertices": t.rest.len(), "poses": labels.len(), "fps": fps, "seed": seed, "labels": labels});
    std::fs::write(format!("{out}.json"), meta.to_string())
        .map_err(|e| format!("{out}.json: {e}"))?;
    eprintln!(
        "wrote {out}.f32 and {out}.json: {} poses x {} vertices",
        labels.len(),
        t.rest.len()
    );
    Ok(())
}

fn load(path: &str) -> Result<Bvh, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    Bvh::parse_bytes(&bytes).map_err(|e| format!("{path}: {e}"))
}

fn info(path: &str) -> Result<(), String> {
    let b = load(path)?;
    let mut o = String::new();
    let joints = b.joints.iter().filter(|j| !j.end_site).count();
    let _ = writeln!(o, "file: {path}");
    let _ = writeln!(
        o,
        "joints: {} ({} with channels, {} end sites)",
        b.joints.len(),
        joints,
        b.joints.len() - joints
    );
    let _ = writeln!(o, "channels per frame: {}", b.channel_count());
    let _ = writeln!(
        o,
        "frames: {} at {:.3} fps (frame time {} s, {:.2} s in all)",
        b.frame_count(),
        b.fps(),
        b.frame_time,
        b.frame_count() as f64 * b.frame_time
    );
    let _ = writeln!(o, "hierarchy:");
    let mut depth = vec![0usize; b.joints.len()];
    for (i, j) in b.joints.iter().enumerate() {
        if let Some(p) = j.parent {
            depth[i] = depth[p] + 1;
        }
        let ch: Vec<&str> = j.channels.iter().map(|c| c.name()).collect();
        let _ = writeln!(
            o,
            "  {}{} offset ({}, {}, {}) {}",
            "  ".repeat(depth[i]),
            j.name,
            j.offset[0],
            j.offset[1],
            j.offset[2],
            if ch.is_empty() {
                "[end site]".to_string()
            } else {
                ch.join(" ")
            }
        );
    }
    match deeprep::rcfk::RcSkeleton::thesis(&b) {
        Ok(sk) => {
            let v = sk.violations(&b).map_err(|e| e.to_string())?;
            let _ = writeln!(
                o,
                "RC-range violations (Table D.1; frames outside / max / mean excess in degrees):"
            );
            for x in v.iter().filter(|x| x.frames > 0) {
                let _ = writeln!(
                    o,
                    "  {:<10} {:>6} frames ({:5.1}%)  max {:7.2}  mean {:6.3}",
                    x.joint,
                    x.frames,
                    100.0 * x.frames as f64 / b.frame_count().max(1) as f64,
                    x.max_deg,
                    x.mean_deg
                );
            }
            if v.iter().all(|x| x.frames == 0) {
                let _ = writeln!(o, "  none");
            }
        }
        Err(e) => {
            let _ = writeln!(o, "RC-range violations: not computed ({e})");
        }
    }
    emit(&o);
    Ok(())
}

fn fk_cmd(path: &str, frame: usize) -> Result<(), String> {
    let b = load(path)?;
    if frame >= b.frame_count() {
        return Err(format!(
            "--frame {frame} is outside the clip's {} frames",
            b.frame_count()
        ));
    }
    let p = fk::positions(&b, frame, frame + 1).map_err(|e| e.to_string())?;
    let mut o = String::new();
    for (i, j) in b.joints.iter().enumerate() {
        let _ = writeln!(
            o,
            "{} {} {} {}",
            j.name,
            p[3 * i],
            p[3 * i + 1],
            p[3 * i + 2]
        );
    }
    emit(&o);
    Ok(())
}

fn write_f32(path: &str, v: &[f32]) -> Result<(), String> {
    let mut bytes = Vec::with_capacity(v.len() * 4);
    for x in v {
        bytes.extend_from_slice(&x.to_le_bytes());
    }
    std::fs::write(path, bytes).map_err(|e| format!("{path}: {e}"))
}

fn export(path: &str, prefix: &str) -> Result<(), String> {
    let b = load(path)?;
    let sk = deeprep::rcfk::RcSkeleton::thesis(&b).map_err(|e| e.to_string())?;
    let frames = b.frame_count();
    let positions = fk::positions(&b, 0, frames).map_err(|e| e.to_string())?;
    let width = 3 + sk.output_dim();
    let mut rc = Vec::with_capacity(frames * width);
    let mut excess_sum = vec![0.0f64; sk.rotating.len()];
    for f in 0..frames {
        let r = sk.inverse(&b, f).map_err(|e| e.to_string())?;
        rc.extend(r.root_pos.iter().map(|v| *v as f32));
        rc.extend(r.root_6d.iter().map(|v| *v as f32));
        for (k, a) in r.angles.iter().enumerate() {
            rc.extend(a.iter().map(|v| *v as f32));
            excess_sum[k] += r.excess[k].iter().sum::<f64>();
        }
    }
    write_f32(&format!("{prefix}.positions.f32"), &positions)?;
    write_f32(&format!("{prefix}.rc.f32"), &rc)?;
    let meta = serde_json::json!({
        "source": path,
        "frames": frames,
        "frame_time": b.frame_time,
        "joints": b.joints.iter().map(|j| &j.name).collect::<Vec<_>>(),
        "parents": b.joints.iter().map(|j| j.parent.map_or(-1, |p| p as i64)).collect::<Vec<_>>(),
        "offsets": b.joints.iter().map(|j| j.offset).collect::<Vec<_>>(),
        "rotating": sk.rotating.iter().map(|&j| &b.joints[j].name).collect::<Vec<_>>(),
        "rc_width": width,
        "rc_layout": "root position (3), root 6D (6), then [ux, uy, uz] radians per rotating joint",
        "mean_excess_deg_per_frame": excess_sum.iter().map(|e| e.to_degrees() / frames.max(1) as f64).collect::<Vec<_>>(),
    });
    let mp = format!("{prefix}.json");
    std::fs::write(&mp, serde_json::to_string_pretty(&meta).unwrap_or_default())
        .map_err(|e| format!("{mp}: {e}"))?;
    Ok(())
}

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
    };
    let mut i = 0;
    while i < args.len() {
        let next = |i: usize| {
            args.get(i + 1)
                .map(|s| s.to_string())
                .ok_or_else(|| format!("{} needs a value", args[i]))
        };
        match args[i] {
            "--from-bvh" => o.from_bvh = Some(next(i)?),
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

fn synthesize(
    o: &Opts,
    keys: &[deeprep::motion::Keyframe],
    frames: usize,
    dna: Option<Vec<Vec<f32>>>,
) -> Result<(deeprep::motion::Motion, String), String> {
    use deeprep::motion::{baseline, pipeline};
    match o.method.as_str() {
        "slerp" => Ok((
            baseline::slerp_lerp(keys, frames).map_err(|e| e.to_string())?,
            String::new(),
        )),
        "zerovel" => Ok((
            baseline::zero_velocity(keys, frames).map_err(|e| e.to_string())?,
            String::new(),
        )),
        "residual" => {
            if o.foot_lock || dna.is_some() || !o.post {
                return Err("--method residual takes no --foot-lock, --dna or --no-post (its keys are exact by construction)".into());
            }
            let m =
                deeprep::motion::residual::ResidualModel::load_dir(std::path::Path::new(&o.models))
                    .map_err(|e| e.to_string())?;
            let start = std::time::Instant::now();
            let motion = m
                .synthesize(keys, frames, o.variation.unwrap_or(1.0))
                .map_err(|e| e.to_string())?;
            let info = format!("{:.1} ms", start.elapsed().as_secs_f64() * 1000.0);
            Ok((motion, info))
        }
        "model" => {
            let m = pipeline::TweenModels::load_dir(std::path::Path::new(&o.models))
                .map_err(|e| e.to_string())?;
            let start = std::time::Instant::now();
            let clock = move || start.elapsed().as_secs_f64() * 1000.0;
            let req = pipeline::Request {
                keys: keys.to_vec(),
                frames,
                dna,
                post_process: o.post,
                foot_lock: o.foot_lock.then(deeprep::motion::feet::FootLock::default),
                variation: o.variation,
            };
            let out = m.synthesize(&req, &clock).map_err(|e| e.to_string())?;
            let info = format!(
                "key error before post-processing: root {:.3}, joints {:.3}; after: root {:.3}, joints {:.3}; feet: {} contacts pinned over {} frames; stages ms: generator {:.1}, rc-fk {:.1}, path {:.1}, post {:.1}",
                out.key_error_raw.root,
                out.key_error_raw.local,
                out.key_error.root,
                out.key_error.local,
                out.foot_lock.contacts,
                out.foot_lock.frames,
                out.times.generator_ms,
                out.times.rcfk_ms,
                out.times.path_ms,
                out.times.post_ms
            );
            Ok((out.motion, info))
        }
        other => Err(format!(
            "unknown --method '{other}' (model, residual, slerp, zerovel)"
        )),
    }
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
            Some(_) => Err("--seed draws Motion DNA from a clip: give --dna DNA.bvh (without DNA the motion is deterministic)".into()),
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
            let all: Vec<usize> = (0..file.frame_count()).collect();
            let picked = match o.seed {
                Some(seed) => {
                    let poses = all
                        .iter()
                        .map(|&f| Keyframe::from_bvh(&file, f, f))
                        .collect::<Result<Vec<_>, _>>()
                        .map_err(|e| format!("--dna {spec}: {e}"))?;
                    deeprep::motion::dna::pick_dna_frames(&poses, out_frames, seed)
                        .map_err(|e| format!("--dna {spec}: {e}"))?
                }
                None => all,
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

fn inbetween(args: &[&str]) -> Result<(), String> {
    let o = parse_inbetween(args)?;
    if let Some(clip) = &o.from_bvh {
        let b = load(clip)?;
        let list = o.keys.as_ref().ok_or("--from-bvh needs --keys F1,F2,...")?;
        let frames: Vec<usize> = list
            .split(',')
            .map(|s| {
                s.trim()
                    .parse::<usize>()
                    .map_err(|_| format!("--keys: '{s}' is not a frame index"))
            })
            .collect::<Result<_, _>>()?;
        let ck = deeprep::motion::clip::clip_keys(&b, &frames, false)
            .map_err(|e| format!("--keys: {e}"))?;
        let dna = dna_poses(&o, Some(&b), ck.frames())?;
        let (motion, info) = synthesize(&o, &ck.keys, ck.frames(), dna)?;
        let out = deeprep::motion::clip::splice(&b, &ck, &motion).map_err(|e| e.to_string())?;
        let path = o.out.ok_or("-o OUT.bvh is required")?;
        std::fs::write(&path, out.write()).map_err(|e| format!("{path}: {e}"))?;
        let (first, last) = ck.span();
        eprintln!(
            "wrote {path}: {} frames, frames {first}..={last} synthesized by {}. {info}",
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

fn run(args: &[String]) -> Result<(), String> {
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    match a.as_slice() {
        ["bvh", "info", file] => info(file),
        ["bvh", "fk", file, "--frame", n] | ["bvh", "fk", "--frame", n, file] => {
            let frame = n
                .parse::<usize>()
                .map_err(|_| format!("--frame expects a frame index, got '{n}'"))?;
            fk_cmd(file, frame)
        }
        ["bvh", "export", file, "--out", prefix] => export(file, prefix),
        ["inbetween", rest @ ..] => inbetween(rest),
        ["mesh", "topology", file, "--out", out] => mesh_topology(file, out),
        ["mesh", "poses", file, rest @ ..] => mesh_poses(file, rest),
        ["hair", "dataset", rest @ ..] => hair_dataset(rest),
        ["hair", "preview", rest @ ..] => hair_preview(rest),
        _ => Err(help(args)),
    }
}

/// The usage entries of the command named by the leading words of `args`
/// (`inbetween`, `bvh fk`, ...), or all of them when none matches.
fn help(args: &[String]) -> String {
    let words: Vec<&str> = args
        .iter()
        .map(String::as_str)
        .take_while(|a| !a.starts_with('-'))
        .take(2)
        .collect();
    // entries: a "  deeprep ..." line and the more-indented lines after it
    let mut entries: Vec<Vec<&str>> = Vec::new();
    for line in USAGE.lines().skip(1) {
        if line.starts_with("  deeprep ") {
            entries.push(vec![line]);
        } else if let Some(e) = entries.last_mut() {
            e.push(line);
        }
    }
    for n in (1..=words.len()).rev() {
        let prefix = format!("  deeprep {}", words[..n].join(" "));
        let hits: Vec<String> = entries
            .iter()
            .filter(|e| e[0] == prefix || e[0].starts_with(&format!("{prefix} ")))
            .map(|e| e.join("\n"))
            .collect();
        if !hits.is_empty() {
            return format!("usage:\n{}", hits.join("\n"));
        }
    }
    USAGE.to_string()
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{}", help(&args));
        return ExitCode::SUCCESS;
    }
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("deeprep: {e}");
            ExitCode::from(2)
        }
    }
}

fn hair_class(name: &str) -> Result<deeprep::hair::HairClass, String> {
    deeprep::hair::HairClass::all()
        .into_iter()
        .find(|c| c.name().eq_ignore_ascii_case(name))
        .ok_or_else(|| {
            let all: Vec<String> = deeprep::hair::HairClass::all()
                .iter()
                .map(|c| c.name())
                .collect();
            format!("unknown hair class '{name}'; classes: {}", all.join(", "))
        })
}

/// Parses `--key value` pairs against the allowed keys.
fn options<'a>(
    rest: &[&'a str],
    allowed: &[&str],
) -> Result<std::collections::HashMap<String, &'a str>, String> {
    let mut out = std::collections::HashMap::new();
    let mut i = 0;
    while i < rest.len() {
        let key = rest[i].trim_start_matches("--");
        if !rest[i].starts_with("--") || !allowed.contains(&key) {
            return Err(format!("unknown option '{}'\n{USAGE}", rest[i]));
        }
        let val = rest
            .get(i + 1)
            .ok_or_else(|| format!("{} needs a value", rest[i]))?;
        out.insert(key.to_string(), *val);
        i += 2;
    }
    Ok(out)
}

fn parse_opt<T: std::str::FromStr>(
    o: &std::collections::HashMap<String, &str>,
    key: &str,
    default: T,
) -> Result<T, String> {
    match o.get(key) {
        None => Ok(default),
        Some(v) => v.parse().map_err(|_| format!("--{key}: cannot read '{v}'")),
    }
}

fn hair_preview(rest: &[&str]) -> Result<(), String> {
    use deeprep::hair::*;
    let o = options(rest, &["class", "seed", "yaw", "size", "out"])?;
    let class = hair_class(o.get("class").copied().unwrap_or("M-wavy"))?;
    let seed: u64 = parse_opt(&o, "seed", 1)?;
    let yaw: f32 = parse_opt(&o, "yaw", 0.0)?;
    let size: usize = parse_opt(&o, "size", 256)?;
    let out = o
        .get("out")
        .ok_or_else(|| format!("--out FILE.ppm is required\n{USAGE}"))?;
    let mut rng = deeprep::rng::Rng::new(seed);
    let style = Style::random(class, &mut rng);
    let (body, scalp) = (Body::default(), Scalp::default());
    let hair = Hair::generate(&style, &scalp, &body, GRID, &mut rng).map_err(|e| e.to_string())?;
    let view = View {
        yaw: yaw.to_radians(),
        noise: 0.0,
        ..Default::default()
    };
    let r = render(&hair.points, &body, &view, size, &mut rng).map_err(|e| e.to_string())?;
    let plane = size * size;
    let mut ppm = format!("P6\n{size} {size}\n255\n").into_bytes();
    for i in 0..plane {
        for c in 0..3 {
            ppm.push((r.image[c * plane + i] * 255.0).round() as u8);
        }
    }
    std::fs::write(out, ppm).map_err(|e| format!("{out}: {e}"))?;
    let vis = r.visible.iter().filter(|&&v| v).count();
    eprintln!(
        "{}: {:?}; {} of {} samples visible; wrote {out}",
        class.name(),
        style,
        vis,
        r.visible.len()
    );
    Ok(())
}

fn hair_dataset(rest: &[&str]) -> Result<(), String> {
    use deeprep::hair::*;
    use std::io::Write;
    let o = options(rest, &["out", "base", "blends", "views", "size", "seed"])?;
    let out = o
        .get("out")
        .ok_or_else(|| format!("--out PREFIX is required\n{USAGE}"))?
        .to_string();
    let base: usize = parse_opt(&o, "base", 10)?;
    let blends: usize = parse_opt(&o, "blends", 2)?;
    let views: usize = parse_opt(&o, "views", 4)?;
    let size: usize = parse_opt(&o, "size", 256)?;
    let seed: u64 = parse_opt(&o, "seed", 1)?;
    if base == 0 || views == 0 || size < 8 {
        return Err("--base and --views must be at least 1, --size at least 8".into());
    }
    if base > 10_000 || blends > 100 || views > 100 || size > MAX_IMAGE_SIZE {
        return Err(format!(
            "--base is at most 10000, --blends and --views at most 100, --size at most {MAX_IMAGE_SIZE}"
        ));
    }
    let (body, scalp) = (Body::default(), Scalp::default());
    let mut rng = deeprep::rng::Rng::new(seed);
    let file = |ext: &str| -> Result<std::io::BufWriter<std::fs::File>, String> {
        let p = format!("{out}.{ext}");
        std::fs::File::create(&p)
            .map(std::io::BufWriter::new)
            .map_err(|e| format!("{p}: {e}"))
    };
    let (mut f_strands, mut f_curv, mut f_img, mut f_vis) = (
        file("strands.f32")?,
        file("curvature.f32")?,
        file("images.u8")?,
        file("visible.u8")?,
    );
    let mut hairs_meta = Vec::new();
    let mut renders_meta = Vec::new();
    let t0 = std::time::Instant::now();
    let mut write_hair = |h: &Hair,
                          meta: serde_json::Value,
                          rng: &mut deeprep::rng::Rng|
     -> Result<(), String> {
        let idx = hairs_meta.len();
        let bytes: Vec<u8> = h
            .local()
            .iter()
            .flat_map(|p| p.iter().flat_map(|v| v.to_le_bytes()))
            .collect();
        f_strands.write_all(&bytes).map_err(|e| e.to_string())?;
        let bytes: Vec<u8> = h
            .curvatures()
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        f_curv.write_all(&bytes).map_err(|e| e.to_string())?;
        for _ in 0..views {
            let view = View::random(rng);
            let r = render(&h.points, &body, &view, size, rng).map_err(|e| e.to_string())?;
            let img: Vec<u8> = r
                .image
                .iter()
                .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
                .collect();
            f_img.write_all(&img).map_err(|e| e.to_string())?;
            let vis: Vec<u8> = r.visible.iter().map(|&v| v as u8).collect();
            f_vis.write_all(&vis).map_err(|e| e.to_string())?;
            renders_meta.push(serde_json::json!({"hair": idx, "yaw": view.yaw, "pitch": view.pitch, "roll": view.roll}));
        }
        hairs_meta.push(meta);
        Ok(())
    };
    let classes = HairClass::all();
    for class in &classes {
        // base styles of this class, split by style: 1 in 10 test, 1 in 10 validation
        let mut by_split: std::collections::BTreeMap<&str, Vec<Hair>> = Default::default();
        for b in 0..base {
            let split = match b % 10 {
                0 => "test",
                1 => "val",
                _ => "train",
            };
            let style = Style::random(*class, &mut rng);
            let h =
                Hair::generate(&style, &scalp, &body, GRID, &mut rng).map_err(|e| e.to_string())?;
            let m = h.mirrored();
            let style_id = format!("{}/{b}", class.name());
            write_hair(
                &h,
                serde_json::json!({"class": class.name(), "split": split, "style": style_id, "kind": "base"}),
                &mut rng,
            )?;
            write_hair(
                &m,
                serde_json::json!({"class": class.name(), "split": split, "style": style_id, "kind": "mirror"}),
                &mut rng,
            )?;
            let list = by_split.entry(split).or_default();
            list.push(h);
            list.push(m);
        }
        // in-class blends (Sec. 3.2.2), never across splits
        for (split, list) in &by_split {
            if list.len() < 3 {
                continue;
            }
            for k in 0..blends * list.len() / 2 {
                let a = rng.below(list.len());
                let mut b = rng.below(list.len() - 1);
                if b >= a {
                    b += 1;
                }
                let mask = 1 + rng.below(30) as u8; // 1..=30: never all or none of 5 regions
                let h = Hair::blend(&list[a], &list[b], mask, &body).map_err(|e| e.to_string())?;
                write_hair(
                    &h,
                    serde_json::json!({"class": class.name(), "split": split, "style": format!("{}/blend{k}", class.name()), "kind": "blend", "mask": mask}),
                    &mut rng,
                )?;
            }
        }
        eprintln!(
            "{} done ({:.0} s)",
            class.name(),
            t0.elapsed().as_secs_f32()
        );
    }
    for f in [&mut f_strands, &mut f_curv, &mut f_img, &mut f_vis] {
        f.flush().map_err(|e| e.to_string())?;
    }
    let counts = |key: &str| {
        let mut m: std::collections::BTreeMap<String, usize> = Default::default();
        for h in &hairs_meta {
            *m.entry(h[key].as_str().unwrap_or("").to_string())
                .or_default() += 1;
        }
        m
    };
    let meta = serde_json::json!({
        "hairs": hairs_meta.len(), "views": views, "renders": renders_meta.len(), "size": size, "grid": GRID,
        "points": POINTS, "seed": seed, "base_per_class": base, "blends_per_base": blends,
        "split_counts": counts("split"), "class_counts": counts("class"),
        "hair": hairs_meta, "render": renders_meta,
        "roots": scalp.grid_roots(GRID).iter().map(|r| r.0).collect::<Vec<_>>(),
        "body": Body::default().parts.iter().map(|e| serde_json::json!({"center": e.center, "radii": e.radii})).collect::<Vec<_>>(),
        "units": "metres; strands root-relative; curvature 1/m; image values /255",
    });
    std::fs::write(format!("{out}.json"), meta.to_string())
        .map_err(|e| format!("{out}.json: {e}"))?;
    eprintln!(
        "wrote {out}.*: {} hairs, {} renders in {:.0} s",
        hairs_meta.len(),
        renders_meta.len(),
        t0.elapsed().as_secs_f32()
    );
    Ok(())
}

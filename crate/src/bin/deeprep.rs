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

const USAGE: &str = "usage:
  deeprep bvh info FILE
  deeprep bvh fk FILE --frame N
  deeprep bvh export FILE --out PREFIX
      writes PREFIX.json (skeleton, frame rate, layouts), PREFIX.positions.f32
      (frames x joints x 3 global positions) and PREFIX.rc.f32 (frames x (3 + 6 + 3K):
      root position, root 6D, range-constrained Euler angles in radians, clamped to
      Table D.1), little-endian f32; for the training pipeline
  deeprep inbetween --from-bvh CLIP.bvh --keys F1,F2,... -o OUT.bvh
          [--method model|slerp|zerovel] [--models DIR] [--no-post]
      whole-pose keys from those frames of CLIP; OUT has CLIP's length, frame rate and
      skeleton; frames between the first and last key are synthesized, the others copied
  deeprep inbetween KEYS.json --frames N [-o OUT.bvh] [--models DIR] [--no-post]
      KEYS.json: {\"keys\": [{\"frame\": F, \"channels\": [...]}, ...]} (BVH channels of the
      model's skeleton); without arguments, runs the bundled example models/examples/keys.json
  deeprep mesh topology ROBOT.glb --out TOPOLOGY.json
      the mesh autoencoder's topology: welded vertices, triangles, connected edge graph,
      sampling levels (s = 2, r = 2) with padded index/mask tables, latent seed vertices
  deeprep mesh poses ROBOT.glb --out PREFIX [--fps N] [--random N] [--seed S]
      every animation clip sampled at N fps (default 30) plus N random poses (default 0;
      each joint turned up to 30 degrees from a random clip frame), welded:
      PREFIX.f32 (poses x vertices x 3, little-endian) and PREFIX.json (clip per pose)";

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
        let frames = (a.duration * fps).floor() as usize + 1;
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
            "--models" => o.models = next(i)?,
            "--no-post" => {
                o.post = false;
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
    method: &str,
    models: &str,
    keys: &[deeprep::motion::Keyframe],
    frames: usize,
    post: bool,
) -> Result<(deeprep::motion::Motion, String), String> {
    use deeprep::motion::{baseline, pipeline};
    match method {
        "slerp" => Ok((
            baseline::slerp_lerp(keys, frames).map_err(|e| e.to_string())?,
            String::new(),
        )),
        "zerovel" => Ok((
            baseline::zero_velocity(keys, frames).map_err(|e| e.to_string())?,
            String::new(),
        )),
        "model" => {
            let m = pipeline::TweenModels::load_dir(std::path::Path::new(models))
                .map_err(|e| e.to_string())?;
            let start = std::time::Instant::now();
            let clock = move || start.elapsed().as_secs_f64() * 1000.0;
            let req = pipeline::Request {
                keys: keys.to_vec(),
                frames,
                dna: None,
                post_process: post,
            };
            let out = m.synthesize(&req, &clock).map_err(|e| e.to_string())?;
            let info = format!(
                "key error before post-processing: root {:.3}, joints {:.3}; after: root {:.3}, joints {:.3}; stages ms: generator {:.1}, rc-fk {:.1}, path {:.1}, post {:.1}",
                out.key_error_raw.root,
                out.key_error_raw.local,
                out.key_error.root,
                out.key_error.local,
                out.times.generator_ms,
                out.times.rcfk_ms,
                out.times.path_ms,
                out.times.post_ms
            );
            Ok((out.motion, info))
        }
        other => Err(format!(
            "unknown --method '{other}' (model, slerp, zerovel)"
        )),
    }
}

fn inbetween(args: &[&str]) -> Result<(), String> {
    use deeprep::motion::Keyframe;
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
        let (first, last) = (
            *frames.first().ok_or("--keys is empty")?,
            *frames.last().unwrap_or(&0),
        );
        if last < first {
            return Err("--keys must be sorted".into());
        }
        let keys: Vec<Keyframe> = frames
            .iter()
            .map(|&f| Keyframe::from_bvh(&b, f, f.saturating_sub(first)))
            .collect::<Result<_, _>>()
            .map_err(|e| e.to_string())?;
        let (motion, info) = synthesize(&o.method, &o.models, &keys, last - first + 1, o.post)?;
        let synth = motion.to_bvh(&b, b.frame_time).map_err(|e| e.to_string())?;
        let mut out = b.clone();
        let c = b.channel_count();
        out.motion[first * c..(last + 1) * c].copy_from_slice(&synth.motion);
        let path = o.out.ok_or("-o OUT.bvh is required")?;
        std::fs::write(&path, out.write()).map_err(|e| format!("{path}: {e}"))?;
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
    let v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{keys_path}: {e}"))?;
    let models = deeprep::motion::pipeline::TweenModels::load_dir(std::path::Path::new(&o.models))
        .map_err(|e| e.to_string())?;
    let tpl = &models.template;
    let mut keys = Vec::new();
    for (i, k) in v["keys"]
        .as_array()
        .ok_or(format!("{keys_path}: expected a \"keys\" array"))?
        .iter()
        .enumerate()
    {
        let frame = k["frame"]
            .as_u64()
            .ok_or(format!("{keys_path}: key {i} lacks \"frame\""))? as usize;
        let ch: Vec<f32> = k["channels"]
            .as_array()
            .ok_or(format!("{keys_path}: key {i} lacks \"channels\""))?
            .iter()
            .map(|x| {
                x.as_f64()
                    .map(|x| x as f32)
                    .ok_or(format!("{keys_path}: key {i}: channels must be numbers"))
            })
            .collect::<Result<_, _>>()?;
        if ch.len() != tpl.channel_count() {
            return Err(format!(
                "{keys_path}: key {i} has {} channels; the skeleton has {}",
                ch.len(),
                tpl.channel_count()
            ));
        }
        let mut one = tpl.clone();
        one.motion = ch;
        keys.push(Keyframe::from_bvh(&one, 0, frame).map_err(|e| e.to_string())?);
    }
    let frames = o
        .frames
        .or(v["frames"].as_u64().map(|f| f as usize))
        .ok_or("--frames N is required (or \"frames\" in the keys file)")?;
    let (motion, info) = synthesize(&o.method, &o.models, &keys, frames, o.post)?;
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
        _ => Err(USAGE.to_string()),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("deeprep: {e}");
            ExitCode::from(2)
        }
    }
}

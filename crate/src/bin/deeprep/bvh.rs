//! `deeprep bvh info / fk / export`.

use super::args::{emit, CliError};
use deeprep::skeleton::{fk, Bvh};
use std::fmt::Write as _;

/// `deeprep bvh info FILE`.
pub fn info(rest: &[&str]) -> Result<(), CliError> {
    match rest {
        [file] => Ok(print_info(file)?),
        _ => Err(CliError::Usage),
    }
}

/// `deeprep bvh fk FILE --frame N` (or `--frame N FILE`).
pub fn positions(rest: &[&str]) -> Result<(), CliError> {
    match rest {
        [file, "--frame", n] | ["--frame", n, file] => {
            let frame = n
                .parse::<usize>()
                .map_err(|_| format!("--frame expects a frame index, got '{n}'"))?;
            Ok(print_positions(file, frame)?)
        }
        _ => Err(CliError::Usage),
    }
}

/// `deeprep bvh export FILE --out PREFIX`.
pub fn export(rest: &[&str]) -> Result<(), CliError> {
    match rest {
        [file, "--out", prefix] => Ok(export_clip(file, prefix)?),
        _ => Err(CliError::Usage),
    }
}

/// Reads and parses a BVH file, naming it in the error.
pub fn load(path: &str) -> Result<Bvh, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    Bvh::parse_bytes(&bytes).map_err(|e| format!("{path}: {e}"))
}

fn print_info(path: &str) -> Result<(), String> {
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
    emit(&o)
}

fn print_positions(path: &str, frame: usize) -> Result<(), String> {
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
    emit(&o)
}

fn write_f32(path: &str, v: &[f32]) -> Result<(), String> {
    let mut bytes = Vec::with_capacity(v.len() * 4);
    for x in v {
        bytes.extend_from_slice(&x.to_le_bytes());
    }
    std::fs::write(path, bytes).map_err(|e| format!("{path}: {e}"))
}

fn export_clip(path: &str, prefix: &str) -> Result<(), String> {
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

/// The model's skeleton: the template in `DIR/tween_generator.manifest.json`.
pub fn model_skeleton(models: &str) -> Result<Bvh, String> {
    let p = std::path::Path::new(models).join("tween_generator.manifest.json");
    let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
    deeprep::motion::manifest::parse(&text)
        .map(|m| m.template)
        .map_err(|e| format!("{}: {e}", p.display()))
}

/// A `--map MAP.json` file (role name -> joint name).
fn load_map(
    path: Option<&str>,
) -> Result<std::collections::BTreeMap<String, Option<String>>, String> {
    match path {
        None => Ok(Default::default()),
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| format!("{p}: {e}"))?;
            deeprep::skeleton::retarget::parse_map(&text).map_err(|e| format!("{p}: {e}"))
        }
    }
}

/// `deeprep bvh roles FILE [--map MAP.json]`: the humanoid roles found,
/// as a JSON map file (role -> joint name).
pub fn roles(rest: &[&str]) -> Result<(), CliError> {
    let (file, map) = match rest {
        [file] => (*file, None),
        [file, "--map", m] | ["--map", m, file] => (*file, Some(*m)),
        _ => return Err(CliError::Usage),
    };
    let b = load(file)?;
    let overrides = load_map(map)?;
    let rm = deeprep::skeleton::retarget::RoleMap::with_overrides(&b, &overrides)
        .map_err(|e| format!("{file}: {e}"))?;
    let json = serde_json::to_string_pretty(&rm.names(&b)).map_err(|e| e.to_string())?;
    emit(&(json + "\n"))?;
    Ok(())
}

/// `deeprep bvh retarget SRC.bvh --to model|TARGET.bvh [--map MAP.json]
/// [--models DIR] -o OUT.bvh`.
pub fn retarget(rest: &[&str]) -> Result<(), CliError> {
    let mut it = rest.iter();
    let (mut src, mut to, mut map, mut out, mut models) = (None, None, None, None, "models/onnx");
    while let Some(&a) = it.next() {
        let mut value = |flag: &str| {
            it.next()
                .copied()
                .ok_or_else(|| CliError::from(format!("{flag} needs a value")))
        };
        match a {
            "--to" => to = Some(value("--to")?),
            "--map" => map = Some(value("--map")?),
            "-o" | "--out" => out = Some(value("-o")?),
            "--models" => models = value("--models")?,
            f if f.starts_with('-') => return Err(format!("unknown option '{f}'").into()),
            f if src.is_none() => src = Some(f),
            _ => return Err(CliError::Usage),
        }
    }
    let (Some(src), Some(to), Some(out)) = (src, to, out) else {
        return Err(CliError::Usage);
    };
    let s = load(src)?;
    let target = if to == "model" {
        model_skeleton(models)?
    } else {
        load(to)?
    };
    let overrides = load_map(map)?;
    let model = model_skeleton(models).ok();
    let (b, r) = deeprep::motion::clip::retarget(&s, &target, model.as_ref(), &overrides)
        .map_err(|e| format!("{src} -> {to}: {e}"))?;
    std::fs::write(out, b.write()).map_err(|e| format!("{out}: {e}"))?;
    eprintln!(
        "wrote {out}: {} frames at {:.3} fps on {to}'s skeleton ({} joints); {} roles followed, root translation scaled by {:.4} (leg length)",
        b.frame_count(),
        b.fps(),
        b.joints.len(),
        r.pairs.len(),
        r.scale
    );
    Ok(())
}

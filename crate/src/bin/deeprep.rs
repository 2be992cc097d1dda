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
      Table D.1), little-endian f32; for the training pipeline";

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
    std::fs::write(&mp, serde_json::to_string_pretty(&meta).unwrap_or_default()).map_err(|e| format!("{mp}: {e}"))?;
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

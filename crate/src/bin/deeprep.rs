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
  deeprep bvh fk FILE --frame N";

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

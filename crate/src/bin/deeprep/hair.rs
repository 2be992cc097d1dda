//! `deeprep hair dataset`, `deeprep hair preview` and `deeprep hair
//! reconstruct`: HairNet's procedural training data and its reconstruction
//! (ch. 3), over `deeprep::hair` (the reconstruction is a `hair::HairJob`,
//! as in the wasm `HairLab` and the hair page).

use super::args::{options, parse_opt, CliError};
use super::USAGE;

/// `deeprep hair preview ...`.
pub fn preview(rest: &[&str]) -> Result<(), CliError> {
    Ok(hair_preview(rest)?)
}

/// `deeprep hair reconstruct ...`.
pub fn reconstruct(rest: &[&str]) -> Result<(), CliError> {
    Ok(hair_reconstruct(rest)?)
}

/// `deeprep hair dataset ...`.
pub fn dataset(rest: &[&str]) -> Result<(), CliError> {
    Ok(hair_dataset(rest)?)
}

fn hair_preview(rest: &[&str]) -> Result<(), String> {
    use deeprep::hair::*;
    let o = options(rest, &["class", "seed", "yaw", "size", "out"])?;
    let hair = TestHair::named(
        o.get("class").copied().unwrap_or("M-wavy"),
        parse_opt(&o, "seed", 1)?,
    )
    .map_err(|e| e.to_string())?;
    let yaw: f32 = parse_opt(&o, "yaw", 0.0)?;
    let size: usize = parse_opt(&o, "size", 256)?;
    let out = o
        .get("out")
        .ok_or_else(|| format!("--out FILE.ppm is required\n{USAGE}"))?;
    let body = Body::default();
    let r = hair
        .render(&body, yaw, 0.0, size)
        .map_err(|e| e.to_string())?;
    let ppm = deeprep::hair::ppm::write(&r.image, size).map_err(|e| e.to_string())?;
    std::fs::write(out, ppm).map_err(|e| format!("{out}: {e}"))?;
    let vis = r.visible.iter().filter(|&&v| v).count();
    eprintln!(
        "{} (seed {}): {} of {} samples visible; wrote {out}",
        hair.class.name(),
        hair.seed,
        vis,
        r.visible.len()
    );
    Ok(())
}

/// The network input from a 256 × 256 binary PPM such as `hair preview`
/// writes (`hair::ppm`).
fn image_of_ppm(path: &str) -> Result<Vec<f32>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    deeprep::hair::ppm::read_network_input(&bytes).map_err(|e| format!("{path}: {e}"))
}

fn hair_reconstruct(rest: &[&str]) -> Result<(), String> {
    use deeprep::hair::*;
    let o = options(
        rest,
        &[
            "class", "seed", "yaw", "image", "strands", "smooth", "curl", "models", "out",
        ],
    )?;
    let out = o
        .get("out")
        .ok_or_else(|| format!("--out FILE.obj|FILE.f32 is required\n{USAGE}"))?;
    let format_obj = if out.ends_with(".obj") {
        true
    } else if out.ends_with(".f32") {
        false
    } else {
        return Err(format!(
            "--out {out}: write .obj (polylines) or .f32 (strands x 100 x 3 float32)"
        ));
    };
    let input = match (o.get("image"), o.get("class")) {
        (Some(_), Some(_)) => return Err("give --image or --class, not both".into()),
        (Some(path), None) => {
            for k in ["seed", "yaw"] {
                if o.contains_key(k) {
                    return Err(format!("--{k} is for --class test hairs, not --image"));
                }
            }
            HairInput::Image(image_of_ppm(path)?)
        }
        (None, class) => HairInput::Test {
            hair: TestHair::named(
                class.copied().unwrap_or("M-wavy"),
                parse_opt(&o, "seed", 1)?,
            )
            .map_err(|e| e.to_string())?,
            yaw_deg: parse_opt(&o, "yaw", 0.0)?,
        },
    };
    let d = Reconstruct::default();
    let job = HairJob {
        input,
        reconstruct: Reconstruct {
            strands: parse_opt(&o, "strands", d.strands)?,
            smooth_sigma: parse_opt(&o, "smooth", d.smooth_sigma)?,
            curl_threshold: parse_opt(&o, "curl", d.curl_threshold)?,
        },
    };
    let dir = std::path::PathBuf::from(o.get("models").copied().unwrap_or("models/onnx"));
    let model = HairModel::load_dir(&dir).map_err(|e| e.to_string())?;
    let t0 = std::time::Instant::now();
    let r = job
        .run(&model, &Body::default())
        .map_err(|e| e.to_string())?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let bytes = if format_obj {
        let mut s = String::with_capacity(r.strands.points.len() * 28);
        s.push_str("# deeprep hair reconstruct: one polyline per strand, metres\n");
        for p in &r.strands.points {
            s.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
        }
        for k in 0..r.strands.points.len() / POINTS {
            s.push('l');
            for i in 0..POINTS {
                s.push_str(&format!(" {}", k * POINTS + i + 1));
            }
            s.push('\n');
        }
        s.into_bytes()
    } else {
        r.strands
            .points
            .iter()
            .flat_map(|p| p.iter().flat_map(|v| v.to_le_bytes()))
            .collect()
    };
    std::fs::write(out, bytes).map_err(|e| format!("{out}: {e}"))?;
    let summary = serde_json::json!({
        "strands": r.strands.points.len() / POINTS,
        "points_per_strand": POINTS,
        "curled": r.strands.curled,
        "collision_error": r.collision_error,
        "ms": ms,
        "out": out,
    });
    super::args::emit(&format!("{summary}\n"))?;
    Ok(())
}

fn hair_dataset(rest: &[&str]) -> Result<(), String> {
    use deeprep::hair::dataset::{write, Options, Sinks};
    let o = options(rest, &["out", "base", "blends", "views", "size", "seed"])?;
    let out = o
        .get("out")
        .ok_or_else(|| format!("--out PREFIX is required\n{USAGE}"))?
        .to_string();
    let d = Options::default();
    let opts = Options {
        base: parse_opt(&o, "base", d.base)?,
        blends: parse_opt(&o, "blends", d.blends)?,
        views: parse_opt(&o, "views", d.views)?,
        size: parse_opt(&o, "size", d.size)?,
        seed: parse_opt(&o, "seed", d.seed)?,
    };
    opts.check().map_err(|e| e.to_string())?;
    let file = |ext: &str| -> Result<std::io::BufWriter<std::fs::File>, String> {
        let p = format!("{out}.{ext}");
        std::fs::File::create(&p)
            .map(std::io::BufWriter::new)
            .map_err(|e| format!("{p}: {e}"))
    };
    let (mut strands, mut curvature, mut images, mut visible) = (
        file("strands.f32")?,
        file("curvature.f32")?,
        file("images.u8")?,
        file("visible.u8")?,
    );
    let t0 = std::time::Instant::now();
    let sinks = Sinks {
        strands: &mut strands,
        curvature: &mut curvature,
        images: &mut images,
        visible: &mut visible,
    };
    let meta = write(&opts, sinks, |class| {
        eprintln!(
            "{} done ({:.0} s)",
            class.name(),
            t0.elapsed().as_secs_f32()
        )
    })
    // the library names the files by their suffix after "PREFIX"
    .map_err(|e| e.to_string().replace("PREFIX.", &format!("{out}.")))?;
    std::fs::write(format!("{out}.json"), meta.to_string())
        .map_err(|e| format!("{out}.json: {e}"))?;
    eprintln!(
        "wrote {out}.*: {} hairs, {} renders in {:.0} s",
        meta["hairs"],
        meta["renders"],
        t0.elapsed().as_secs_f32()
    );
    Ok(())
}

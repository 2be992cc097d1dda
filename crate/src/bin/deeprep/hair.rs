//! `deeprep hair dataset` and `deeprep hair preview`: HairNet's procedural
//! training data (ch. 3).

use super::args::{options, parse_opt, CliError};
use super::USAGE;

/// `deeprep hair preview ...`.
pub fn preview(rest: &[&str]) -> Result<(), CliError> {
    Ok(hair_preview(rest)?)
}

/// `deeprep hair dataset ...`.
pub fn dataset(rest: &[&str]) -> Result<(), CliError> {
    Ok(hair_dataset(rest)?)
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
    .map_err(|e| e.to_string())?;
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

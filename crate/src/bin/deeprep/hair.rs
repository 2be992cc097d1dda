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

//! The procedural hair dataset `train/deeprep_train/hair/train.py` trains on
//! (`deeprep hair dataset --out PREFIX`): styles of every class of Table
//! 3.1, their mirror images and in-class blends (Sec. 3.2.2), each rendered
//! from random views. Written as five files:
//!
//! - `PREFIX.strands.f32`: per hair, `32 × 32 × 100 × 3` root-relative
//!   points (little-endian `f32`, metres);
//! - `PREFIX.curvature.f32`: per hair, `32 × 32 × 100` curvatures (1/m);
//! - `PREFIX.images.u8`: per render, `3 × size × size` network input
//!   values × 255;
//! - `PREFIX.visible.u8`: per render, `32 × 32 × 100` visibility flags;
//! - `PREFIX.json`: counts, a record per hair (class, split, style, kind)
//!   and per render (hair, view), the scalp roots and the body.
//!
//! [`write`] generates and writes them; [`Dataset::read`] reads them back
//! with every size checked against the description.

use super::{render, Body, Hair, HairClass, Scalp, Style, View, GRID, MAX_IMAGE_SIZE, POINTS};
use crate::error::{Error, Result};
use crate::rng::Rng;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::io::Write;

/// What to generate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Base styles per class (1 in 10 goes to the test split, 1 in 10 to validation).
    pub base: usize,
    /// In-class blends per base style and its mirror.
    pub blends: usize,
    /// Random views rendered per hair.
    pub views: usize,
    /// Rendered image size in pixels.
    pub size: usize,
    /// Seed of every random choice.
    pub seed: u64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            base: 10,
            blends: 2,
            views: 4,
            size: 256,
            seed: 1,
        }
    }
}

impl Options {
    /// Checks the limits: `base` in 1..=10,000, `blends` and `views` at most
    /// 100 (`views` at least 1), `size` in 8..=[`MAX_IMAGE_SIZE`].
    pub fn check(&self) -> Result<()> {
        if self.base == 0 || self.views == 0 || self.size < 8 {
            return Err(Error::Invalid(
                "--base and --views must be at least 1, --size at least 8".into(),
            ));
        }
        if self.base > 10_000 || self.blends > 100 || self.views > 100 || self.size > MAX_IMAGE_SIZE
        {
            return Err(Error::Invalid(format!(
                "--base is at most 10000, --blends and --views at most 100, --size at most {MAX_IMAGE_SIZE}"
            )));
        }
        let bytes = self.max_bytes();
        if bytes > MAX_DATASET_BYTES as u128 {
            return Err(Error::Invalid(format!(
                "these options write up to {:.1} GB ({} hairs, {} renders of {}x{}); the limit is {} GB: \
                 lower --base, --blends, --views or --size",
                bytes as f64 / 1e9,
                self.max_hairs(),
                self.max_hairs() * self.views as u128,
                self.size,
                self.size,
                MAX_DATASET_BYTES / 1_000_000_000
            )));
        }
        Ok(())
    }

    /// At most how many hairs: per class each base style, its mirror and
    /// `blends` blends per base style.
    pub fn max_hairs(&self) -> u128 {
        HairClass::all().len() as u128 * self.base as u128 * (2 + self.blends as u128)
    }

    /// At most how many bytes the four binary files take (known before any
    /// is written): per hair its strands and curvatures, per render its
    /// image and visibility flags.
    pub fn max_bytes(&self) -> u128 {
        let samples = (GRID * GRID * POINTS) as u128;
        let per_hair = samples * 4 * 4;
        let per_render = 3 * (self.size as u128).pow(2) + samples;
        self.max_hairs() * (per_hair + self.views as u128 * per_render)
    }
}

/// The most a dataset may write (bytes): 64 GB, far above the default's
/// (about 0.6 GB) and below what a disk of the machines this runs on holds.
pub const MAX_DATASET_BYTES: u64 = 64_000_000_000;

/// Where the four binary files go.
pub struct Sinks<'a> {
    /// `PREFIX.strands.f32`.
    pub strands: &'a mut dyn Write,
    /// `PREFIX.curvature.f32`.
    pub curvature: &'a mut dyn Write,
    /// `PREFIX.images.u8`.
    pub images: &'a mut dyn Write,
    /// `PREFIX.visible.u8`.
    pub visible: &'a mut dyn Write,
}

fn io(file: &str) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::Invalid(format!("hair dataset: {file}: {e}"))
}

/// Generates the dataset into `sinks` and returns the `PREFIX.json`
/// description. `progress(class)` is called after each class.
pub fn write(o: &Options, sinks: Sinks, mut progress: impl FnMut(HairClass)) -> Result<Value> {
    o.check()?;
    let (body, scalp) = (Body::default(), Scalp::default());
    let mut rng = Rng::new(o.seed);
    let mut hairs_meta = Vec::new();
    let mut renders_meta = Vec::new();
    let mut write_hair = |h: &Hair, meta: Value, rng: &mut Rng| -> Result<()> {
        let idx = hairs_meta.len();
        let bytes: Vec<u8> = h
            .local()
            .iter()
            .flat_map(|p| p.iter().flat_map(|v| v.to_le_bytes()))
            .collect();
        sinks
            .strands
            .write_all(&bytes)
            .map_err(io("PREFIX.strands.f32"))?;
        let bytes: Vec<u8> = h
            .curvatures()
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        sinks
            .curvature
            .write_all(&bytes)
            .map_err(io("PREFIX.curvature.f32"))?;
        for _ in 0..o.views {
            let view = View::random(rng);
            let r = render(&h.points, &body, &view, o.size, rng)?;
            let img: Vec<u8> = r
                .image
                .iter()
                .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
                .collect();
            sinks
                .images
                .write_all(&img)
                .map_err(io("PREFIX.images.u8"))?;
            let vis: Vec<u8> = r.visible.iter().map(|&v| v as u8).collect();
            sinks
                .visible
                .write_all(&vis)
                .map_err(io("PREFIX.visible.u8"))?;
            renders_meta.push(
                json!({"hair": idx, "yaw": view.yaw, "pitch": view.pitch, "roll": view.roll}),
            );
        }
        hairs_meta.push(meta);
        Ok(())
    };
    for class in HairClass::all() {
        // base styles of this class, split by style: 1 in 10 test, 1 in 10 validation
        let mut by_split: BTreeMap<&str, Vec<Hair>> = Default::default();
        for b in 0..o.base {
            let split = match b % 10 {
                0 => "test",
                1 => "val",
                _ => "train",
            };
            let style = Style::random(class, &mut rng);
            let h = Hair::generate(&style, &scalp, &body, GRID, &mut rng)?;
            let m = h.mirrored();
            let style_id = format!("{}/{b}", class.name());
            let meta = |kind: &str| json!({"class": class.name(), "split": split, "style": style_id, "kind": kind});
            write_hair(&h, meta("base"), &mut rng)?;
            write_hair(&m, meta("mirror"), &mut rng)?;
            let list = by_split.entry(split).or_default();
            list.push(h);
            list.push(m);
        }
        // in-class blends (Sec. 3.2.2), never across splits
        for (split, list) in &by_split {
            if list.len() < 3 {
                continue;
            }
            for k in 0..o.blends * list.len() / 2 {
                let a = rng.below(list.len());
                let mut b = rng.below(list.len() - 1);
                if b >= a {
                    b += 1;
                }
                let mask = 1 + rng.below(30) as u8; // 1..=30: never all or none of 5 regions
                let h = Hair::blend(&list[a], &list[b], mask, &body)?;
                write_hair(
                    &h,
                    json!({"class": class.name(), "split": split, "style": format!("{}/blend{k}", class.name()), "kind": "blend", "mask": mask}),
                    &mut rng,
                )?;
            }
        }
        progress(class);
    }
    for (f, name) in [
        (sinks.strands, "PREFIX.strands.f32"),
        (sinks.curvature, "PREFIX.curvature.f32"),
        (sinks.images, "PREFIX.images.u8"),
        (sinks.visible, "PREFIX.visible.u8"),
    ] {
        f.flush().map_err(io(name))?;
    }
    let counts = |key: &str| {
        let mut m: BTreeMap<String, usize> = Default::default();
        for h in &hairs_meta {
            *m.entry(h[key].as_str().unwrap_or("").to_string())
                .or_default() += 1;
        }
        m
    };
    Ok(json!({
        "hairs": hairs_meta.len(), "views": o.views, "renders": renders_meta.len(), "size": o.size, "grid": GRID,
        "points": POINTS, "seed": o.seed, "base_per_class": o.base, "blends_per_base": o.blends,
        "split_counts": counts("split"), "class_counts": counts("class"),
        "hair": hairs_meta, "render": renders_meta,
        "roots": scalp.grid_roots(GRID).iter().map(|r| r.0).collect::<Vec<_>>(),
        "body": body.parts.iter().map(|e| json!({"center": e.center, "radii": e.radii})).collect::<Vec<_>>(),
        "units": "metres; strands root-relative; curvature 1/m; image values /255",
    }))
}

/// A dataset read back: the description and the four arrays, flat.
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    /// The `PREFIX.json` description.
    pub meta: Value,
    /// `hairs × grid² × points × 3`.
    pub strands: Vec<f32>,
    /// `hairs × grid² × points`.
    pub curvature: Vec<f32>,
    /// `renders × 3 × size × size`.
    pub images: Vec<u8>,
    /// `renders × grid² × points`.
    pub visible: Vec<u8>,
}

impl Dataset {
    /// Reads the files' contents, checking each size against the counts of
    /// the description and every float for finiteness.
    pub fn read(
        meta_json: &str,
        strands: &[u8],
        curvature: &[u8],
        images: &[u8],
        visible: &[u8],
    ) -> Result<Self> {
        let bad = |w: String| Error::Invalid(format!("hair dataset: {w}"));
        let meta: Value = serde_json::from_str(meta_json)
            .map_err(|e| bad(format!("the description is not JSON: {e}")))?;
        let count = |k: &str| -> Result<u128> {
            meta[k]
                .as_u64()
                .map(u128::from)
                .ok_or_else(|| bad(format!("the description has no count '{k}'")))
        };
        let (hairs, renders, size) = (count("hairs")?, count("renders")?, count("size")?);
        let (grid, points) = (count("grid")?, count("points")?);
        let per_hair = grid * grid * points;
        for (what, len, want) in [
            ("strands", strands.len(), hairs * per_hair * 12),
            ("curvature", curvature.len(), hairs * per_hair * 4),
            ("images", images.len(), renders * 3 * size * size),
            ("visible", visible.len(), renders * per_hair),
        ] {
            if len as u128 != want {
                return Err(bad(format!(
                    "{what}: {len} bytes, the description needs {want}"
                )));
            }
        }
        let listed = |k: &str, n: u128| match meta[k].as_array() {
            Some(a) if a.len() as u128 == n => Ok(()),
            _ => Err(bad(format!("the description needs {n} '{k}' records"))),
        };
        listed("hair", hairs)?;
        listed("render", renders)?;
        let floats = |b: &[u8], what: &str| -> Result<Vec<f32>> {
            let v: Vec<f32> = b
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect();
            match v.iter().position(|x| !x.is_finite()) {
                Some(i) => Err(bad(format!("{what}: value {i} is not finite"))),
                None => Ok(v),
            }
        };
        Ok(Dataset {
            strands: floats(strands, "strands")?,
            curvature: floats(curvature, "curvature")?,
            images: images.to_vec(),
            visible: visible.to_vec(),
            meta,
        })
    }
}

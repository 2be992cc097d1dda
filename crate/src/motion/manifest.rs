//! The in-betweening networks' manifest (`tween_generator.manifest.json`):
//! what they need besides their weights (skeleton, Table D.1 ranges,
//! normalization, base, default variation), parsed and checked without the
//! model runtime, so hostile manifests are fuzzed in the pure core.

use super::dense::{Base, Norm};
use crate::error::{Error, Result};
use crate::rcfk::{RcSkeleton, TableRow};
use crate::skeleton::Bvh;
use serde::Deserialize;

#[derive(Deserialize)]
struct Manifest {
    skeleton_bvh: String,
    range_table: Vec<TableRow>,
    normalization: NormJson,
    #[serde(default)]
    base: Base,
    /// The default variation chosen for this model (absent: 1).
    #[serde(default = "default_variation")]
    variation: f32,
}

fn default_variation() -> f32 {
    1.0
}

#[derive(Deserialize)]
struct NormJson {
    scale: f32,
    dt_norm: f32,
    dt_clip: f32,
}

/// A checked manifest.
pub struct TweenManifest {
    /// The skeleton as a BVH with no frames.
    pub template: Bvh,
    /// RC-FK on it.
    pub rc: RcSkeleton,
    /// Normalization constants.
    pub norm: Norm,
    /// The interpolation the generator corrects.
    pub base: Base,
    /// The default variation, in [0, 2].
    pub variation: f32,
}

/// Parses and checks a manifest's text.
pub fn parse(json: &str) -> Result<TweenManifest> {
    let m: Manifest =
        serde_json::from_str(json).map_err(|e| Error::Invalid(format!("tween manifest: {e}")))?;
    let n = &m.normalization;
    if ![n.scale, n.dt_norm, n.dt_clip]
        .iter()
        .all(|x| x.is_finite() && *x > 0.0)
    {
        return Err(Error::Invalid(
            "tween manifest: normalization constants must be finite and positive".into(),
        ));
    }
    if !(0.0..=2.0).contains(&m.variation) {
        return Err(Error::Invalid(format!(
            "tween manifest: variation {} is outside [0, 2]",
            m.variation
        )));
    }
    let template = Bvh::parse(&m.skeleton_bvh)?;
    let rc = RcSkeleton::new(&template, &m.range_table)?;
    Ok(TweenManifest {
        template,
        rc,
        norm: Norm {
            scale: n.scale,
            dt_norm: n.dt_norm,
            dt_clip: n.dt_clip,
        },
        base: m.base,
        variation: m.variation,
    })
}

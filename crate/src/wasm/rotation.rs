//! Rotations (ch. 4): batch conversions, geodesic distances, Figure C.1's curves.

use super::js_err;
use crate::rotation::batch::{self, Repr};
use crate::rotation::curves;
use crate::rotation::euler::Axis;
use wasm_bindgen::prelude::*;

fn parse_axis(axis: &str) -> Result<Axis, JsError> {
    match axis {
        "x" | "X" => Ok(Axis::X),
        "y" | "Y" => Ok(Axis::Y),
        "z" | "Z" => Ok(Axis::Z),
        _ => Err(JsError::new(&format!(
            "unknown axis '{axis}'; accepted: x, y, z"
        ))),
    }
}

/// Numbers per rotation in a representation (`"6d"` → 6).
#[wasm_bindgen(js_name = rotationDim)]
pub fn rotation_dim(repr: &str) -> Result<usize, JsError> {
    Ok(Repr::parse(repr).map_err(js_err)?.dim())
}

/// Converts a batch of rotations, e.g. `convertRotations("quat", "6d", q)`.
/// Names: matrix, 6d, 5d, quat, quat_gq, quat_gu, axis_angle, rodrigues,
/// euler:XYZ (upper case intrinsic, lower case extrinsic).
#[wasm_bindgen(js_name = convertRotations)]
pub fn convert_rotations(from: &str, to: &str, input: &[f32]) -> Result<Vec<f32>, JsError> {
    let f = Repr::parse(from).map_err(js_err)?;
    let t = Repr::parse(to).map_err(js_err)?;
    batch::convert(f, t, input).map_err(js_err)
}

/// Geodesic distances (radians, eq. 4.12) between two batches.
#[wasm_bindgen(js_name = geodesicDistances)]
pub fn geodesic_distances(repr: &str, a: &[f32], b: &[f32]) -> Result<Vec<f32>, JsError> {
    let r = Repr::parse(repr).map_err(js_err)?;
    batch::geodesic(r, a, b).map_err(js_err)
}

/// The rotation circle about `axis` ("x", "y", "z") in `repr`, `steps`
/// samples (Figure C.1's input).
#[wasm_bindgen(js_name = rotationCircle)]
pub fn rotation_circle(repr: &str, axis: &str, steps: usize) -> Result<Vec<f32>, JsError> {
    let r = Repr::parse(repr).map_err(js_err)?;
    curves::rotation_circle(r, parse_axis(axis)?, steps).map_err(js_err)
}

/// PCA to 2-D of `points` with `dim` numbers per row.
#[wasm_bindgen(js_name = pca2d)]
pub fn pca_2d(points: &[f32], dim: usize) -> Result<Vec<f32>, JsError> {
    curves::pca_2d(points, dim).map_err(js_err)
}

//! Wavefront OBJ meshes: `v x y z` vertices and `f` faces (`i`, `i/t`,
//! `i//n`, `i/t/n`, negative indices counting back), polygons fan
//! triangulated; every other statement is ignored. Reading is strict: a bad
//! number, an index out of range or a face of fewer than three corners is
//! an error naming the line, and nothing is allocated from a count in the
//! file (OBJ has none; the sizes are the lines actually there, bounded by
//! [`MAX_VERTICES`] and [`MAX_TRIANGLES`]).

use crate::error::{Error, Result};

/// The most vertices a mesh may have.
pub const MAX_VERTICES: usize = 2_000_000;
/// The most triangles (after triangulation) a mesh may have.
pub const MAX_TRIANGLES: usize = 4_000_000;

/// A triangle mesh: positions and triangles over them.
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Triangles (vertex indices); degenerate ones are kept as read.
    pub triangles: Vec<[usize; 3]>,
}

fn err(line: usize, msg: impl std::fmt::Display) -> Error {
    Error::Parse {
        line,
        message: msg.to_string(),
    }
}

/// Parses OBJ text.
pub fn parse(text: &str) -> Result<TriMesh> {
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut triangles: Vec<[usize; 3]> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let mut it = raw.split_whitespace();
        match it.next() {
            Some("v") => {
                let mut p = [0.0f32; 3];
                for c in &mut p {
                    let s = it.next().ok_or_else(|| err(line, "a vertex needs x y z"))?;
                    *c = s
                        .parse::<f32>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| err(line, format!("'{s}' is not a finite number")))?;
                }
                if positions.len() == MAX_VERTICES {
                    return Err(err(line, format!("more than {MAX_VERTICES} vertices")));
                }
                positions.push(p);
            }
            Some("f") => {
                let corners = it
                    .map(|tok| {
                        let s = tok.split('/').next().unwrap_or("");
                        let v: i64 = s
                            .parse()
                            .map_err(|_| err(line, format!("'{tok}' is not a vertex index")))?;
                        let n = positions.len() as i64;
                        let idx = if v > 0 { v - 1 } else { n + v };
                        if v == 0 || idx < 0 || idx >= n {
                            return Err(err(
                                line,
                                format!("vertex index {v} is outside the {n} vertices read so far"),
                            ));
                        }
                        Ok(idx as usize)
                    })
                    .collect::<Result<Vec<usize>>>()?;
                if corners.len() < 3 {
                    return Err(err(line, "a face needs at least three corners"));
                }
                if triangles.len() + corners.len() - 2 > MAX_TRIANGLES {
                    return Err(err(line, format!("more than {MAX_TRIANGLES} triangles")));
                }
                for k in 1..corners.len() - 1 {
                    triangles.push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if positions.is_empty() {
        return Err(Error::Invalid("OBJ: no vertices ('v' lines)".into()));
    }
    if triangles.is_empty() {
        return Err(Error::Invalid("OBJ: no faces ('f' lines)".into()));
    }
    Ok(TriMesh {
        positions,
        triangles,
    })
}

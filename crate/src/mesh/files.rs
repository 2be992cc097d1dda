//! The files the mesh training code reads (`train/deeprep_train/mesh/train.py`), written
//! and read here so their layout is defined once and round-trip tested:
//!
//! - [`TopologyFile`]: a mesh's welded graph and sampling levels as JSON
//!   (`deeprep mesh topology FILE --out T.json`).
//! - [`PoseSet`]: posed meshes of one template as raw little-endian `f32`
//!   (`PREFIX.f32`, poses × vertices × 3) with a JSON description
//!   (`PREFIX.json`: `vertices`, `poses`, a label per pose and the options
//!   that made them) (`deeprep mesh poses`).
//!
//! Readers check every size and index against the file's own counts, so a
//! hostile file is an error, never a panic or an allocation it sized.

use super::{NeighborTable, Topology};
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

/// One padded neighbour table (Appendix A.1.1): `rows × width` indices
/// with a 0/1 mask.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TableFile {
    /// Row-major `rows × width` indices.
    pub indices: Vec<u32>,
    /// 1 where the index is a neighbour, 0 where it is padding.
    pub mask: Vec<u8>,
    /// Number of rows.
    pub rows: usize,
    /// Entries per row.
    pub width: usize,
}

/// One sampling level of a [`TopologyFile`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LevelFile {
    /// One row per vertex of the next level: indices into this level.
    pub down: TableFile,
    /// Edges of the next level's graph.
    pub edges: Vec<(usize, usize)>,
    /// The sampling radius (graph distance).
    pub radius: usize,
    /// The vertices of the previous level kept for this one.
    pub selected: Vec<usize>,
    /// The sampling stride.
    pub stride: usize,
    /// One row per vertex of the previous level: indices into this level.
    pub up: TableFile,
}

/// `deeprep mesh topology`'s output. Fields are in the JSON's key order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TopologyFile {
    /// Edges added to join the mesh's components.
    pub added_edges: Vec<(usize, usize)>,
    /// The welded mesh's edges.
    pub edges: Vec<(usize, usize)>,
    /// A sentence describing the tables' layout.
    pub layout: String,
    /// The sampling levels.
    pub levels: Vec<LevelFile>,
    /// Welded rest positions.
    pub rest: Vec<[f32; 3]>,
    /// Vertices of the source before welding.
    pub rig_vertices: usize,
    /// Named seed vertices of the sampling.
    pub seeds: Vec<(String, usize)>,
    /// The file the topology was made from.
    pub source: String,
    /// Welded triangles.
    pub triangles: Vec<[usize; 3]>,
    /// For each source vertex, its welded vertex.
    pub weld_map: Vec<usize>,
}

const LAYOUT: &str = "levels[k].down: one row per vertex of level k+1 (indices into level k); levels[k].up: one row per vertex of level k (indices into level k+1); level 0 is the welded mesh";

fn table(n: &NeighborTable) -> TableFile {
    TableFile {
        indices: n.indices.clone(),
        mask: n.mask.clone(),
        rows: n.rows,
        width: n.width,
    }
}

fn bad(what: String) -> Error {
    Error::Invalid(format!("topology file: {what}"))
}

fn check_edges(edges: &[(usize, usize)], n: usize, what: &str) -> Result<()> {
    match edges.iter().find(|&&(a, b)| a >= n || b >= n || a == b) {
        Some(e) => Err(bad(format!(
            "{what}: edge {e:?} is not between two of its {n} vertices"
        ))),
        None => Ok(()),
    }
}

impl TableFile {
    fn check(&self, rows: usize, targets: usize, what: &str) -> Result<()> {
        let cells = self.rows.checked_mul(self.width);
        if self.rows != rows
            || cells != Some(self.indices.len())
            || self.mask.len() != self.indices.len()
        {
            return Err(bad(format!(
                "{what}: {} rows × {} with {} indices and {} mask values (expected {rows} rows)",
                self.rows,
                self.width,
                self.indices.len(),
                self.mask.len()
            )));
        }
        if let Some(i) = self.mask.iter().position(|&m| m > 1) {
            return Err(bad(format!("{what}: mask value {i} is not 0 or 1")));
        }
        let hit = self.indices.iter().zip(&self.mask);
        if let Some(i) = hit
            .clone()
            .position(|(&x, &m)| m == 1 && x as usize >= targets)
        {
            return Err(bad(format!(
                "{what}: index {i} ({}) is outside the {targets} vertices it points into",
                self.indices[i]
            )));
        }
        Ok(())
    }
}

impl TopologyFile {
    /// The file for `t`, made from `source` (a path, for the record) whose
    /// `rig_vertices` vertices were welded into `t.rest`.
    pub fn from_topology(t: &Topology, source: &str, rig_vertices: usize) -> Self {
        TopologyFile {
            added_edges: t.added_edges.clone(),
            edges: t.graph.edges(),
            layout: LAYOUT.into(),
            levels: t
                .levels
                .iter()
                .map(|l| LevelFile {
                    down: table(&l.down),
                    edges: l.graph.edges(),
                    radius: l.radius,
                    selected: l.selected.clone(),
                    stride: l.stride,
                    up: table(&l.up),
                })
                .collect(),
            rest: t.rest.clone(),
            rig_vertices,
            seeds: t.seeds.clone(),
            source: source.into(),
            triangles: t.triangles.clone(),
            weld_map: t.weld_map.clone(),
        }
    }

    /// The JSON text (one line, keys in alphabetical order, numbers as
    /// `serde_json` writes them).
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_value(self)
            .map(|v| v.to_string())
            .map_err(|e| Error::Invalid(format!("topology file: {e}")))
    }

    /// Parses and checks a topology file: every index in range of the
    /// level it points into, tables of their declared shape.
    pub fn parse(text: &str) -> Result<Self> {
        let f: TopologyFile =
            serde_json::from_str(text).map_err(|e| bad(format!("not a topology file: {e}")))?;
        f.check()?;
        Ok(f)
    }

    /// Vertex counts per level, the welded mesh first.
    pub fn sizes(&self) -> Vec<usize> {
        std::iter::once(self.rest.len())
            .chain(self.levels.iter().map(|l| l.selected.len()))
            .collect()
    }

    fn check(&self) -> Result<()> {
        let n = self.rest.len();
        if let Some(i) = self.rest.iter().flatten().position(|v| !v.is_finite()) {
            return Err(bad(format!("rest vertex {} is not finite", i / 3)));
        }
        if self.weld_map.len() != self.rig_vertices {
            return Err(bad(format!(
                "weld_map has {} entries for {} source vertices",
                self.weld_map.len(),
                self.rig_vertices
            )));
        }
        if let Some(i) = self.weld_map.iter().position(|&w| w >= n) {
            return Err(bad(format!(
                "weld_map[{i}] is outside the {n} welded vertices"
            )));
        }
        if let Some(t) = self.triangles.iter().find(|t| t.iter().any(|&v| v >= n)) {
            return Err(bad(format!(
                "triangle {t:?} is outside the {n} welded vertices"
            )));
        }
        check_edges(&self.edges, n, "edges")?;
        check_edges(&self.added_edges, n, "added_edges")?;
        if let Some((name, v)) = self.seeds.iter().find(|(_, v)| *v >= n) {
            return Err(bad(format!("seed {name} ({v}) is outside the mesh")));
        }
        let sizes = self.sizes();
        for (k, l) in self.levels.iter().enumerate() {
            let (prev, next) = (sizes[k], sizes[k + 1]);
            let what = format!("levels[{k}]");
            if let Some(s) = l.selected.iter().find(|&&s| s >= prev) {
                return Err(bad(format!(
                    "{what}.selected: {s} is outside the previous level's {prev} vertices"
                )));
            }
            check_edges(&l.edges, next, &format!("{what}.edges"))?;
            l.down.check(next, prev, &format!("{what}.down"))?;
            l.up.check(prev, next, &format!("{what}.up"))?;
        }
        Ok(())
    }
}

/// Posed meshes of one template (`deeprep mesh poses`): `data` holds
/// `poses × vertices × 3` positions, `meta` the JSON description, whose
/// `vertices`, `poses` and `labels` (one per pose) this type keeps in step
/// with `data`.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseSet {
    /// Vertices per pose.
    pub vertices: usize,
    /// `poses × vertices × 3` positions.
    pub data: Vec<f32>,
    /// One label per pose (for example `{"clip": "Run", "time": 0.5}`).
    pub labels: Vec<Value>,
    /// Further fields of the description (source, fps, seed, ...).
    pub extra: Map<String, Value>,
}

/// The most position values (poses × vertices × 3) a [`PoseSet`] holds:
/// 2^28, 1 GiB of float32, checked before a set grows past it.
pub const MAX_POSE_SET_VALUES: usize = 1 << 28;

impl PoseSet {
    /// Checks up front that `poses` meshes of `vertices` vertices fit in a
    /// set ([`MAX_POSE_SET_VALUES`]), with an error that names both.
    pub fn check_size(poses: usize, vertices: usize) -> Result<()> {
        let values = (poses as u128) * (vertices as u128) * 3;
        if values > MAX_POSE_SET_VALUES as u128 {
            return Err(Error::Invalid(format!(
                "{poses} poses x {vertices} vertices is {:.2} GB of positions; a pose set holds at most {MAX_POSE_SET_VALUES} values ({} GB): ask for fewer poses or a smaller mesh",
                values as f64 * 4.0 / 1e9,
                MAX_POSE_SET_VALUES * 4 / 1_000_000_000
            )));
        }
        Ok(())
    }

    /// An empty set of meshes with `vertices` vertices.
    pub fn new(vertices: usize) -> Self {
        PoseSet {
            vertices,
            data: Vec::new(),
            labels: Vec::new(),
            extra: Map::new(),
        }
    }

    /// Number of poses.
    pub fn len(&self) -> usize {
        self.labels.len()
    }

    /// Whether the set holds no pose.
    pub fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }

    /// Appends a pose of `vertices` positions with its label.
    pub fn push(&mut self, pose: &[[f32; 3]], label: Value) -> Result<()> {
        if pose.len() != self.vertices {
            return Err(Error::Invalid(format!(
                "a pose of {} vertices in a set of {}-vertex meshes",
                pose.len(),
                self.vertices
            )));
        }
        Self::check_size(self.len() + 1, self.vertices)?;
        self.data.extend(pose.iter().flatten());
        self.labels.push(label);
        Ok(())
    }

    /// The `.f32` file's bytes (little-endian).
    pub fn data_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.data.len() * 4);
        // a Vec's writes do not fail
        let _ = self.write_data(&mut out);
        out
    }

    /// Writes the `.f32` file's bytes (little-endian) to `w` in chunks,
    /// without a second copy of the set.
    pub fn write_data(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        let mut buf = Vec::with_capacity(1 << 16);
        for chunk in self.data.chunks(1 << 14) {
            buf.clear();
            buf.extend(chunk.iter().flat_map(|v| v.to_le_bytes()));
            w.write_all(&buf)?;
        }
        w.flush()
    }

    /// The `.json` description's text.
    pub fn meta_json(&self) -> String {
        let mut m = self.extra.clone();
        m.insert("vertices".into(), self.vertices.into());
        m.insert("poses".into(), self.len().into());
        m.insert("labels".into(), Value::Array(self.labels.clone()));
        Value::Object(m).to_string()
    }

    /// Reads a set from its two files, checking that the data has exactly
    /// the poses and vertices the description gives.
    pub fn read(data: &[u8], meta_json: &str) -> Result<Self> {
        let bad = |w: String| Error::Invalid(format!("pose set: {w}"));
        let Value::Object(mut m) = serde_json::from_str(meta_json)
            .map_err(|e| bad(format!("the description is not JSON: {e}")))?
        else {
            return Err(bad("the description is not a JSON object".into()));
        };
        let count = |m: &mut Map<String, Value>, k: &str| {
            m.remove(k)
                .and_then(|v| v.as_u64())
                .ok_or_else(|| bad(format!("the description has no count '{k}'")))
        };
        let vertices = count(&mut m, "vertices")? as usize;
        let poses = count(&mut m, "poses")?;
        let labels = match m.remove("labels") {
            Some(Value::Array(a)) if a.len() as u64 == poses => a,
            _ => return Err(bad(format!("the description needs {poses} labels"))),
        };
        let expected = (poses as u128) * (vertices as u128) * 12;
        if data.len() as u128 != expected {
            return Err(bad(format!(
                "{} data bytes for {poses} poses × {vertices} vertices (expected {expected})",
                data.len()
            )));
        }
        let data: Vec<f32> = data
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        if let Some(i) = data.iter().position(|v| !v.is_finite()) {
            return Err(bad(format!(
                "pose {} has a non-finite coordinate",
                i / (3 * vertices.max(1))
            )));
        }
        Ok(PoseSet {
            vertices,
            data,
            labels,
            extra: m,
        })
    }
}

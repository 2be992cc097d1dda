//! Graph sampling that depends on topology alone (thesis Sec. 2.2.1,
//! Appendix A.1.2).
//!
//! Down-sampling with stride `s` keeps a set of vertices that are pairwise
//! at least `s` edges apart and maximal (every other vertex lies within
//! `s − 1` of a kept one). The traversal is breadth-first, as in A.1.2, but
//! deterministic: it starts from the manual seeds, then from each
//! component's lowest vertex, and keeps every vertex that is not yet within
//! `s − 1` of a kept one. The sampled graph connects two kept vertices when
//! they are at most `2s − 1` apart in the input graph, so it stays connected
//! wherever the input is. With kernel radius `r`:
//! - down-sampling: output vertex i (kept vertex x_i) reads the `r`-ring of
//!   x_i in the input graph;
//! - up-sampling: output vertex k (every input vertex) reads the kept
//!   vertices in its `r`-ring, as indices into the sampled graph; `r` must
//!   be at least `s − 1` so that no output vertex reads nothing.
//!
//! The neighbourhoods are emitted as Appendix A.1.1's padded `N × max E_i`
//! index table with a mask.

use super::graph::Graph;
use crate::error::{Error, Result};

/// A padded neighbourhood table: row i lists the input vertices that output
/// vertex i reads (nearest first), padded with 0 and masked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NeighborTable {
    /// Output vertices.
    pub rows: usize,
    /// max E_i: entries per row.
    pub width: usize,
    /// `rows × width` input vertex indices (0 where masked).
    pub indices: Vec<u32>,
    /// `rows × width`: 1 for a real entry, 0 for padding.
    pub mask: Vec<u8>,
}

impl NeighborTable {
    fn from_lists(lists: &[Vec<usize>]) -> Self {
        let width = lists.iter().map(Vec::len).max().unwrap_or(0);
        let mut indices = vec![0u32; lists.len() * width];
        let mut mask = vec![0u8; lists.len() * width];
        for (i, l) in lists.iter().enumerate() {
            for (j, &v) in l.iter().enumerate() {
                indices[i * width + j] = v as u32;
                mask[i * width + j] = 1;
            }
        }
        NeighborTable {
            rows: lists.len(),
            width,
            indices,
            mask,
        }
    }

    /// The real entries of row `i`.
    pub fn row(&self, i: usize) -> Vec<usize> {
        (0..self.width)
            .filter(|&j| self.mask[i * self.width + j] == 1)
            .map(|j| self.indices[i * self.width + j] as usize)
            .collect()
    }
}

/// One sampling level.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampling {
    /// Stride.
    pub stride: usize,
    /// Kernel radius.
    pub radius: usize,
    /// Kept input vertices, ascending; sampled vertex i is input vertex `selected[i]`.
    pub selected: Vec<usize>,
    /// The sampled graph (vertices `0..selected.len()`).
    pub graph: Graph,
    /// Down-sampling neighbourhoods: one row per sampled vertex, input indices.
    pub down: NeighborTable,
    /// Up-sampling neighbourhoods: one row per input vertex, sampled indices.
    pub up: NeighborTable,
}

/// The most vertices one neighbourhood that sampling lists may hold (an
/// `r`-ring, or the `2s − 1`-ring that connects the sampled graph). A mesh
/// vertex has 5-7 neighbours and its 2-ring about 19 vertices; a fan of
/// thousands of triangles around one vertex (a big polygon fan-triangulated)
/// would make every table grow with the square of its valence.
pub const MAX_RING: usize = 4096;

/// The most cells (rows × width) one padded table may have: 2^25, about
/// 170 MB of indices and mask.
pub const MAX_TABLE_CELLS: usize = 1 << 25;

/// Checks, before anything is allocated for them, that the neighbourhoods
/// `sample` lists stay within [`MAX_RING`] and its tables within
/// [`MAX_TABLE_CELLS`]; the errors name the vertex and the table size.
fn check_work(graph: &Graph, s: usize, r: usize) -> Result<()> {
    let n = graph.len();
    let mut widest = (0, 0);
    for v in 0..n {
        for radius in [r, 2 * s - 1] {
            let size = graph.ring_size_capped(v, radius, MAX_RING).ok_or_else(|| {
                Error::Invalid(format!(
                    "graph sampling: vertex {v} (valence {}) has more than {MAX_RING} vertices within {radius} edges; \
                     the padded neighbourhood tables (Appendix A.1.1) would grow with the square of its valence: \
                     split the fan around it (for example triangulate a large polygon into strips)",
                    graph.degree(v)
                ))
            })?;
            if radius == r && size > widest.1 {
                widest = (v, size);
            }
        }
    }
    let cells = n as u128 * widest.1 as u128;
    if cells > MAX_TABLE_CELLS as u128 {
        return Err(Error::Invalid(format!(
            "graph sampling: an up-sampling table of {n} rows x {} entries ({cells} cells, at most {MAX_TABLE_CELLS}); \
             vertex {} has the widest neighbourhood (valence {})",
            widest.1,
            widest.0,
            graph.degree(widest.0)
        )));
    }
    Ok(())
}

/// Samples `graph` with stride `s ≥ 1` and kernel radius `r`, keeping the
/// manual `seeds` (which must be pairwise at least `s` apart). Errors
/// before allocating when a neighbourhood or table would exceed
/// [`MAX_RING`] or [`MAX_TABLE_CELLS`].
pub fn sample(graph: &Graph, s: usize, r: usize, seeds: &[usize]) -> Result<Sampling> {
    let n = graph.len();
    if s == 0 {
        return Err(Error::Invalid(
            "graph sampling: stride must be at least 1".into(),
        ));
    }
    if r + 1 < s {
        return Err(Error::Invalid(format!(
            "graph sampling: kernel radius {r} is below stride − 1 = {}; some up-sampled vertices would read nothing",
            s - 1
        )));
    }
    if let Some(&bad) = seeds.iter().find(|&&v| v >= n) {
        return Err(Error::Invalid(format!(
            "graph sampling: seed {bad} is not a vertex (0..{n})"
        )));
    }
    check_work(graph, s, r)?;
    // covered[v]: v lies within s − 1 of a kept vertex.
    let mut covered = vec![false; n];
    let mut keep = vec![false; n];
    let mut selected = Vec::new();
    let mut take = |v: usize, covered: &mut Vec<bool>, keep: &mut Vec<bool>| {
        keep[v] = true;
        selected.push(v);
        for (w, _) in graph.ring(v, s - 1) {
            covered[w] = true;
        }
    };
    for &v in seeds {
        if keep[v] {
            continue;
        }
        if covered[v] {
            return Err(Error::Invalid(format!(
                "graph sampling: seed {v} is closer than the stride {s} to another seed"
            )));
        }
        take(v, &mut covered, &mut keep);
    }
    for v in graph.bfs_order(seeds) {
        if !covered[v] {
            take(v, &mut covered, &mut keep);
        }
    }
    // Sampled vertices in input order (stride 1 is then the identity).
    selected.sort_unstable();
    let mut index = vec![usize::MAX; n];
    for (i, &v) in selected.iter().enumerate() {
        index[v] = i;
    }
    // Sampled graph: kept vertices at most 2s − 1 apart.
    let mut edges = Vec::new();
    for (i, &v) in selected.iter().enumerate() {
        for (w, _) in graph.ring(v, 2 * s - 1) {
            if keep[w] && index[w] > i {
                edges.push((i, index[w]));
            }
        }
    }
    let sampled = Graph::from_edges(selected.len(), &edges)?;
    let down: Vec<Vec<usize>> = selected
        .iter()
        .map(|&v| graph.ring(v, r).into_iter().map(|(w, _)| w).collect())
        .collect();
    let up: Vec<Vec<usize>> = (0..n)
        .map(|v| {
            graph
                .ring(v, r)
                .into_iter()
                .filter(|&(w, _)| keep[w])
                .map(|(w, _)| index[w])
                .collect()
        })
        .collect();
    Ok(Sampling {
        stride: s,
        radius: r,
        selected,
        graph: sampled,
        down: NeighborTable::from_lists(&down),
        up: NeighborTable::from_lists(&up),
    })
}

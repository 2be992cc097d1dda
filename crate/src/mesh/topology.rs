//! The autoencoder's fixed topology for a rig: welded vertices, triangles,
//! the edge graph with its components connected, and the sampling levels
//! (stride s, radius r) down to a few latent vertices placed at chosen
//! nodes (hands, feet, head, torso). Computed once from the rest pose; the
//! training code reads it (`deeprep mesh topology`), so Rust and Python use
//! one sampler.

use super::graph::{connect_components, weld, Graph};
use super::rig::Rig;
use super::sampling::{sample, Sampling};
use crate::error::{Error, Result};

/// A rig's autoencoder topology.
#[derive(Clone, Debug)]
pub struct Topology {
    /// Welded index of every rig vertex.
    pub weld_map: Vec<usize>,
    /// Rest positions of the welded vertices.
    pub rest: Vec<[f32; 3]>,
    /// Triangles over welded vertices (degenerate ones dropped).
    pub triangles: Vec<[usize; 3]>,
    /// The edge graph, components connected.
    pub graph: Graph,
    /// Edges added to connect components.
    pub added_edges: Vec<(usize, usize)>,
    /// Down-sampling levels, first from the full graph.
    pub levels: Vec<Sampling>,
    /// Latent seed vertices (welded indices) and the nodes they stand for.
    pub seeds: Vec<(String, usize)>,
}

/// The nodes of RobotExpressive.glb whose nearest vertices become latent
/// vertices (thesis Sec. 2.4: hands, feet, head, torso).
pub const ROBOT_SEED_NODES: [&str; 6] = [
    "Palm2.L",
    "Palm2.R",
    "Foot.L_end",
    "Foot.R_end",
    "Head_end",
    "Abdomen",
];

impl Topology {
    /// The topology the bundled mesh autoencoder was trained on: weld at
    /// 1e-5, join components closer than 0.05, s = 2, r = 2, down to at most
    /// 12 vertices, seeds at [`ROBOT_SEED_NODES`]. `deeprep mesh topology`
    /// writes the same thing for the training code.
    pub fn robot(rig: &Rig) -> Result<Topology> {
        Topology::new(rig, 1e-5, 0.05, 2, 2, 12, &ROBOT_SEED_NODES)
    }

    /// Welded indices of the last level's vertices (the latent vertices),
    /// found by following each level's selection back to the full mesh.
    pub fn latent_vertices(&self) -> Vec<usize> {
        let Some(last) = self.levels.last() else {
            return (0..self.rest.len()).collect();
        };
        (0..last.selected.len())
            .map(|mut v| {
                for level in self.levels.iter().rev() {
                    v = level.selected[v];
                }
                v
            })
            .collect()
    }

    /// Builds the topology of `rig`: welds at `eps`, joins components closer
    /// than `near`, and samples with `stride`/`radius` until at most
    /// `min_vertices` remain, keeping the vertices nearest `seed_nodes`.
    pub fn new(
        rig: &Rig,
        eps: f32,
        near: f32,
        stride: usize,
        radius: usize,
        min_vertices: usize,
        seed_nodes: &[&str],
    ) -> Result<Topology> {
        let rest_all = rig.rest_pose()?;
        let (weld_map, n) = weld(&rest_all, eps);
        let mut rest = vec![[0.0f32; 3]; n];
        for (v, &w) in weld_map.iter().enumerate() {
            rest[w] = rest_all[v];
        }
        let triangles: Vec<[usize; 3]> = rig
            .triangles
            .iter()
            .map(|t| t.map(|i| weld_map[i as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        let g = Graph::from_triangles(n, &triangles)?;
        let (graph, added_edges) = connect_components(&g, &rest, near)?;
        // Seeds: the welded vertex nearest each named node's rest position.
        let globals = rig.globals(&rig.rest);
        let mut seeds = Vec::new();
        for name in seed_nodes {
            let node = rig
                .node_names
                .iter()
                .position(|n| n == name)
                .ok_or_else(|| Error::Invalid(format!("mesh topology: no node named '{name}'")))?;
            let p = globals[node].w_axis.truncate();
            let v = (0..n)
                .min_by(|&a, &b| {
                    let da = glam::Vec3::from(rest[a]).distance_squared(p);
                    let db = glam::Vec3::from(rest[b]).distance_squared(p);
                    da.total_cmp(&db)
                })
                .ok_or_else(|| Error::Invalid("mesh topology: no vertices".into()))?;
            seeds.push((name.to_string(), v));
        }
        let mut levels = Vec::new();
        let mut current = graph.clone();
        let mut seed_idx: Vec<usize> = seeds.iter().map(|s| s.1).collect();
        while current.len() > min_vertices {
            // Keep the seeds that are still pairwise at least the stride apart.
            let mut keep: Vec<usize> = Vec::new();
            for &s in &seed_idx {
                let close = current
                    .ring(s, stride - 1)
                    .iter()
                    .any(|(w, _)| keep.contains(w));
                if !close && !keep.contains(&s) {
                    keep.push(s);
                }
            }
            let level = sample(&current, stride, radius, &keep)?;
            if level.selected.len() == current.len() {
                break; // no reduction left (e.g. isolated vertices)
            }
            seed_idx = seed_idx
                .iter()
                .filter_map(|s| level.selected.binary_search(s).ok())
                .collect();
            current = level.graph.clone();
            levels.push(level);
        }
        Ok(Topology {
            weld_map,
            rest,
            triangles,
            graph,
            added_edges,
            levels,
            seeds,
        })
    }

    /// The region of each welded vertex: the index of its nearest latent
    /// vertex (in [`Topology::latent_vertices`] order) by graph distance.
    pub fn latent_regions(&self) -> Vec<usize> {
        self.graph.nearest_source(&self.latent_vertices())
    }

    /// Welded positions of a rig pose.
    pub fn weld_pose(&self, pose: &[[f32; 3]]) -> Result<Vec<[f32; 3]>> {
        if pose.len() != self.weld_map.len() {
            return Err(Error::Invalid(format!(
                "weld_pose: {} vertices for a rig of {}",
                pose.len(),
                self.weld_map.len()
            )));
        }
        let mut out = vec![[0.0f32; 3]; self.rest.len()];
        for (v, &w) in self.weld_map.iter().enumerate().rev() {
            out[w] = pose[v];
        }
        Ok(out)
    }
}

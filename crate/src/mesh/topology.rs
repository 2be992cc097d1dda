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

/// How a mesh is welded, joined and sampled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Vertices closer than this are one (seams).
    pub eps: f32,
    /// Components whose closest vertices are this close get an edge.
    pub near: f32,
    /// Sampling stride s.
    pub stride: usize,
    /// Kernel radius r.
    pub radius: usize,
    /// Levels are added until at most this many vertices remain.
    pub min_vertices: usize,
}

impl Params {
    /// Settings for a mesh of any size: weld at 1e-6 and join pieces within
    /// 1% of the bounding-box diagonal; s = 2, r = 2 (the robot's, Sec. 2.2.1)
    /// down to at most 12 latent vertices, so the number of levels follows
    /// the vertex count (about log2 of it over 2: each level keeps roughly a
    /// quarter of a surface's vertices).
    ///
    /// The diagonal is computed in double precision: in float32 its square
    /// overflows for coordinates near 1e20 and underflows near 1e-20.
    pub fn for_mesh(positions: &[[f32; 3]]) -> Params {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in positions {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a] as f64);
                hi[a] = hi[a].max(p[a] as f64);
            }
        }
        let diag = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt();
        let diag = if diag.is_finite() && diag > 0.0 {
            diag
        } else {
            1.0
        };
        Params {
            eps: (1e-6 * diag) as f32,
            near: (0.01 * diag) as f32,
            stride: 2,
            radius: 2,
            min_vertices: 12,
        }
    }
}

/// A mesh's autoencoder topology.
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
        let triangles: Vec<[usize; 3]> = rig
            .triangles
            .iter()
            .map(|t| t.map(|i| i as usize))
            .collect();
        let globals = rig.globals(&rig.rest);
        let seeds = seed_nodes
            .iter()
            .map(|name| {
                let node = rig
                    .node_names
                    .iter()
                    .position(|n| n == name)
                    .ok_or_else(|| {
                        Error::Invalid(format!("mesh topology: no node named '{name}'"))
                    })?;
                Ok((name.to_string(), globals[node].w_axis.truncate().to_array()))
            })
            .collect::<Result<Vec<_>>>()?;
        let params = Params {
            eps,
            near,
            stride,
            radius,
            min_vertices,
        };
        Topology::from_mesh(&rest_all, &triangles, &params, &seeds)
    }

    /// [`Topology::from_mesh`] with the levels chosen from the vertex count
    /// ([`Params::for_mesh`]) and no latent seeds: any mesh's default.
    pub fn of_mesh(positions: &[[f32; 3]], triangles: &[[usize; 3]]) -> Result<Topology> {
        Topology::from_mesh(positions, triangles, &Params::for_mesh(positions), &[])
    }

    /// The topology of any triangle mesh (Sec. 2.3: sampling depends on
    /// topology alone): several components, non-manifold edges and
    /// vertices, isolated vertices and degenerate triangles are all taken.
    /// `seeds` name points whose nearest vertices become latent vertices.
    pub fn from_mesh(
        positions: &[[f32; 3]],
        triangles: &[[usize; 3]],
        p: &Params,
        seeds: &[(String, [f32; 3])],
    ) -> Result<Topology> {
        let Params {
            eps,
            near,
            stride,
            radius,
            min_vertices,
        } = *p;
        if positions.is_empty() {
            return Err(Error::Invalid("mesh topology: no vertices".into()));
        }
        crate::error::check_finite("mesh positions", positions.as_flattened())?;
        if let Some(t) = triangles
            .iter()
            .find(|t| t.iter().any(|&i| i >= positions.len()))
        {
            return Err(Error::Invalid(format!(
                "mesh topology: triangle {t:?} names a vertex outside 0..{}",
                positions.len()
            )));
        }
        let (weld_map, n) = weld(positions, eps);
        let mut rest = vec![[0.0f32; 3]; n];
        for (v, &w) in weld_map.iter().enumerate() {
            rest[w] = positions[v];
        }
        let triangles: Vec<[usize; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| weld_map[i]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        let g = Graph::from_triangles(n, &triangles)?;
        let (graph, added_edges) = connect_components(&g, &rest, near)?;
        // Seeds: the welded vertex nearest each named point.
        let seeds = seeds
            .iter()
            .map(|(name, p)| {
                let p = glam::Vec3::from(*p);
                let v = (0..n)
                    .min_by(|&a, &b| {
                        let da = glam::Vec3::from(rest[a]).distance_squared(p);
                        let db = glam::Vec3::from(rest[b]).distance_squared(p);
                        da.total_cmp(&db)
                    })
                    .unwrap_or(0);
                (name.clone(), v)
            })
            .collect::<Vec<_>>();
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

    /// Welded positions of a pose whose vertices welded together in the
    /// template must still coincide: an error names the first two that a
    /// pose puts more than `tol` apart (a user's posed OBJ that splits a
    /// seam the template welds), instead of keeping one of them.
    pub fn weld_pose_strict(&self, pose: &[[f32; 3]], tol: f32) -> Result<Vec<[f32; 3]>> {
        let out = self.weld_pose(pose)?;
        let mut first = vec![usize::MAX; self.rest.len()];
        for (v, &w) in self.weld_map.iter().enumerate() {
            if first[w] == usize::MAX {
                first[w] = v;
                continue;
            }
            let (a, b) = (pose[first[w]], pose[v]);
            let d = ((0..3).map(|i| ((a[i] - b[i]) as f64).powi(2)).sum::<f64>()).sqrt();
            if d > tol as f64 {
                return Err(Error::Invalid(format!(
                    "vertices {} and {} (1-based, as in an OBJ) are one vertex in the template, but this pose puts them {d:.3e} apart (more than {tol:.1e})",
                    first[w] + 1,
                    v + 1
                )));
            }
        }
        Ok(out)
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

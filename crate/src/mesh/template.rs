//! A mesh template: the welded mesh an autoencoder is trained on, its
//! sampling levels, and, for a rigged glTF, the rig that poses it. Read from
//! any OBJ or glTF (issue 25), so the CLI, the page and `MeshLab` take any
//! topology the same way.

use super::{shapes, Rig, Topology, ROBOT_SEED_NODES};
use crate::error::{Error, Result};
use crate::rng::Rng;

/// A welded mesh with its sampling, and its rig when it has one.
#[derive(Clone, Debug)]
pub struct Template {
    /// The rig of a skinned glTF (poses from its clips); `None` for an OBJ
    /// or an unrigged glTF.
    pub rig: Option<Rig>,
    /// Welded mesh, graph and sampling levels.
    pub topology: Topology,
    /// The file's vertex count before welding.
    pub source_vertices: usize,
}

impl Template {
    /// An OBJ's template: welded by position, levels from its vertex count
    /// ([`Params::for_mesh`]), no latent seeds.
    pub fn from_obj(text: &str) -> Result<Template> {
        let m = super::obj::parse(text)?;
        let topology = Topology::of_mesh(&m.positions, &m.triangles)?;
        Ok(Template {
            rig: None,
            source_vertices: m.positions.len(),
            topology,
        })
    }

    /// A glTF's template: the bundled robot's own settings and latent seeds
    /// when it has the robot's nodes, otherwise [`Params::for_mesh`] with no
    /// seeds. The rig is kept when the file has animation clips.
    pub fn from_glb(bytes: &[u8]) -> Result<Template> {
        let rig = Rig::from_glb(bytes)?;
        let source_vertices = rig.vertex_count();
        let robot = ROBOT_SEED_NODES
            .iter()
            .all(|n| rig.node_names.iter().any(|m| m == n));
        let topology = if robot {
            Topology::robot(&rig)?
        } else {
            let rest = rig.rest_pose()?;
            let tris: Vec<[usize; 3]> = rig
                .triangles
                .iter()
                .map(|t| t.map(|i| i as usize))
                .collect();
            Topology::of_mesh(&rest, &tris)?
        };
        Ok(Template {
            rig: (!rig.animations.is_empty()).then_some(rig),
            topology,
            source_vertices,
        })
    }

    /// Checks that a model trained on `vertices` welded vertices in
    /// `levels` levels (level 0 included) fits this template.
    pub fn check_model(&self, vertices: usize, levels: usize, model: &str) -> Result<()> {
        let (v, l) = (self.topology.rest.len(), self.topology.levels.len() + 1);
        if v != vertices || l != levels {
            return Err(Error::Invalid(format!(
                "this mesh welds to {v} vertices in {l} levels; the mesh model was trained on {model} \
                 ({vertices} vertices, {levels} levels): load the mesh it was trained on, or a model trained on this one"
            )));
        }
        Ok(())
    }

    /// Clip `clip` at `time` seconds, welded.
    pub fn clip_pose(&self, clip: usize, time: f32) -> Result<Vec<[f32; 3]>> {
        crate::error::check_option("time (seconds)", time as f64, 0.0, 86_400.0)?;
        let rig = self
            .rig
            .as_ref()
            .ok_or_else(|| Error::Invalid("this mesh has no animation clips".into()))?;
        self.topology.weld_pose(&rig.animation_pose(clip, time)?)
    }

    /// A random pose like the training set's, welded: for a rig, a random
    /// clip frame with every joint turned up to `max_degrees`; without one,
    /// a random smooth deformation ([`shapes::deform`], what `deeprep mesh
    /// deform` trains on), `max_degrees` unused.
    pub fn random_pose(&self, seed: u64, max_degrees: f32) -> Result<Vec<[f32; 3]>> {
        crate::error::check_option("max degrees", max_degrees as f64, 0.0, 180.0)?;
        let mut rng = Rng::new(seed);
        match &self.rig {
            Some(rig) => {
                let (local, _, _) = rig.jittered_locals(&mut rng, max_degrees.to_radians())?;
                self.topology.weld_pose(&rig.pose(&local)?)
            }
            None => Ok(shapes::deform(&self.topology.rest, &mut rng)),
        }
    }
}

//! A rigged glTF character posed on the CPU: node hierarchies with rigid
//! parts (meshes attached to nodes) and skinned parts (linear blend
//! skinning), animations sampled at any time. All primitives are merged
//! into one vertex list of fixed topology, so every pose is a same-topology
//! mesh for the autoencoder (ch. 2).

use crate::error::{Error, Result};
use glam::{Mat4, Quat, Vec3};

/// A node's local transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    /// Translation.
    pub t: Vec3,
    /// Rotation.
    pub r: Quat,
    /// Scale.
    pub s: Vec3,
}

impl Trs {
    fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.s, self.r, self.t)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Path {
    T,
    R,
    S,
}

#[derive(Clone, Debug)]
struct Channel {
    node: usize,
    path: Path,
    step: bool,
    times: Vec<f32>,
    values: Vec<[f32; 4]>,
}

/// One animation clip.
#[derive(Clone, Debug)]
pub struct Animation {
    /// Clip name.
    pub name: String,
    /// Last keyframe time, seconds.
    pub duration: f32,
    channels: Vec<Channel>,
}

#[derive(Clone, Debug)]
struct Part {
    node: usize,
    skin: Option<usize>,
    positions: Vec<Vec3>,
    joints: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
}

#[derive(Clone, Debug)]
struct Skin {
    joints: Vec<usize>,
    inverse_bind: Vec<Mat4>,
}

/// A posable character.
#[derive(Clone, Debug)]
pub struct Rig {
    /// Node names (empty string when unnamed).
    pub node_names: Vec<String>,
    /// Parent per node.
    pub parents: Vec<Option<usize>>,
    /// Rest (bind) local transforms.
    pub rest: Vec<Trs>,
    /// Triangles of the merged mesh.
    pub triangles: Vec<[u32; 3]>,
    /// Which part (primitive) each merged vertex comes from.
    pub vertex_part: Vec<u32>,
    /// Animation clips.
    pub animations: Vec<Animation>,
    parts: Vec<Part>,
    skins: Vec<Skin>,
}

fn gltf_err(e: impl std::fmt::Display) -> Error {
    Error::Invalid(format!("glTF: {e}"))
}

impl Rig {
    /// Reads a binary glTF (.glb) with its embedded buffer.
    pub fn from_glb(bytes: &[u8]) -> Result<Rig> {
        let g = gltf::Gltf::from_slice(bytes).map_err(gltf_err)?;
        let blob = g.blob.as_deref();
        let data = |b: gltf::Buffer| -> Option<&[u8]> {
            match b.source() {
                gltf::buffer::Source::Bin => blob,
                gltf::buffer::Source::Uri(_) => None,
            }
        };
        let doc = &g.document;
        let n = doc.nodes().len();
        let mut parents = vec![None; n];
        for node in doc.nodes() {
            for c in node.children() {
                parents[c.index()] = Some(node.index());
            }
        }
        let rest: Vec<Trs> = doc
            .nodes()
            .map(|node| {
                let (t, r, s) = node.transform().decomposed();
                Trs {
                    t: Vec3::from(t),
                    r: Quat::from_array(r),
                    s: Vec3::from(s),
                }
            })
            .collect();
        let mut skins = Vec::new();
        for skin in doc.skins() {
            let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
            let inverse_bind: Vec<Mat4> = match skin.reader(data).read_inverse_bind_matrices() {
                Some(it) => it.map(|m| Mat4::from_cols_array_2d(&m)).collect(),
                None => vec![Mat4::IDENTITY; joints.len()],
            };
            skins.push(Skin {
                joints,
                inverse_bind,
            });
        }
        let mut parts = Vec::new();
        let mut triangles = Vec::new();
        let mut vertex_part = Vec::new();
        for node in doc.nodes() {
            let Some(mesh) = node.mesh() else { continue };
            for prim in mesh.primitives() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    continue;
                }
                let r = prim.reader(data);
                let positions: Vec<Vec3> = r
                    .read_positions()
                    .ok_or_else(|| gltf_err("a primitive has no positions"))?
                    .map(Vec3::from)
                    .collect();
                let base = vertex_part.len() as u32;
                let idx: Vec<u32> = match r.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..positions.len() as u32).collect(),
                };
                for t in idx.chunks_exact(3) {
                    if t.iter().any(|&i| i as usize >= positions.len()) {
                        return Err(gltf_err("a triangle index is out of range"));
                    }
                    triangles.push([base + t[0], base + t[1], base + t[2]]);
                }
                let skin = node.skin().map(|s| s.index());
                let (joints, weights) = if skin.is_some() {
                    let j: Vec<[u16; 4]> = r
                        .read_joints(0)
                        .ok_or_else(|| gltf_err("a skinned primitive has no JOINTS_0"))?
                        .into_u16()
                        .collect();
                    let w: Vec<[f32; 4]> = r
                        .read_weights(0)
                        .ok_or_else(|| gltf_err("a skinned primitive has no WEIGHTS_0"))?
                        .into_f32()
                        .collect();
                    (j, w)
                } else {
                    (Vec::new(), Vec::new())
                };
                vertex_part.extend(std::iter::repeat_n(parts.len() as u32, positions.len()));
                parts.push(Part {
                    node: node.index(),
                    skin,
                    positions,
                    joints,
                    weights,
                });
            }
        }
        if parts.is_empty() {
            return Err(gltf_err("no triangle meshes"));
        }
        let mut animations = Vec::new();
        for a in doc.animations() {
            let mut channels = Vec::new();
            let mut duration = 0.0f32;
            for ch in a.channels() {
                let r = ch.reader(data);
                let times: Vec<f32> = match r.read_inputs() {
                    Some(t) => t.collect(),
                    None => continue,
                };
                let (path, values): (Path, Vec<[f32; 4]>) = match r.read_outputs() {
                    Some(gltf::animation::util::ReadOutputs::Translations(it)) => {
                        (Path::T, it.map(|v| [v[0], v[1], v[2], 0.0]).collect())
                    }
                    Some(gltf::animation::util::ReadOutputs::Rotations(it)) => {
                        (Path::R, it.into_f32().collect())
                    }
                    Some(gltf::animation::util::ReadOutputs::Scales(it)) => {
                        (Path::S, it.map(|v| [v[0], v[1], v[2], 0.0]).collect())
                    }
                    _ => continue, // morph target weights do not move vertices here
                };
                let interp = ch.sampler().interpolation();
                let values = if interp == gltf::animation::Interpolation::CubicSpline {
                    // (in-tangent, value, out-tangent) triples: keep the values.
                    values.chunks_exact(3).map(|c| c[1]).collect()
                } else {
                    values
                };
                if times.is_empty() || values.len() != times.len() {
                    return Err(gltf_err(format!(
                        "animation '{}': times and values differ",
                        a.name().unwrap_or("")
                    )));
                }
                duration = duration.max(*times.last().unwrap_or(&0.0));
                channels.push(Channel {
                    node: ch.target().node().index(),
                    path,
                    step: interp == gltf::animation::Interpolation::Step,
                    times,
                    values,
                });
            }
            animations.push(Animation {
                name: a.name().unwrap_or("").to_string(),
                duration,
                channels,
            });
        }
        Ok(Rig {
            node_names: doc
                .nodes()
                .map(|n| n.name().unwrap_or("").to_string())
                .collect(),
            parents,
            rest,
            triangles,
            vertex_part,
            animations,
            parts,
            skins,
        })
    }

    /// Vertices of the merged mesh.
    pub fn vertex_count(&self) -> usize {
        self.vertex_part.len()
    }

    /// Local transforms of animation `anim` at time `t` (seconds, clamped
    /// to the clip); nodes the clip does not animate keep their rest pose.
    pub fn animation_locals(&self, anim: usize, t: f32) -> Result<Vec<Trs>> {
        let a = self.animations.get(anim).ok_or_else(|| {
            Error::Invalid(format!(
                "animation {anim} does not exist ({} clips)",
                self.animations.len()
            ))
        })?;
        if !t.is_finite() {
            return Err(Error::Invalid(format!("animation time {t} is not finite")));
        }
        let mut local = self.rest.clone();
        for ch in &a.channels {
            let k = ch.times.partition_point(|&x| x <= t);
            let v = if k == 0 {
                ch.values[0]
            } else if k == ch.times.len() || ch.step {
                ch.values[k - 1]
            } else {
                let (t0, t1) = (ch.times[k - 1], ch.times[k]);
                let u = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
                let (a, b) = (ch.values[k - 1], ch.values[k]);
                if ch.path == Path::R {
                    Quat::from_array(a)
                        .normalize()
                        .slerp(Quat::from_array(b).normalize(), u)
                        .to_array()
                } else {
                    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * u)
                }
            };
            let l = &mut local[ch.node];
            match ch.path {
                Path::T => l.t = Vec3::new(v[0], v[1], v[2]),
                Path::R => l.r = Quat::from_array(v).normalize(),
                Path::S => l.s = Vec3::new(v[0], v[1], v[2]),
            }
        }
        Ok(local)
    }

    /// A random pose near the clips (the training set's random poses): a
    /// random clip at a random time, every node turned about a random axis
    /// by up to `max_angle` radians. Returns the local transforms with the
    /// clip and time it started from.
    pub fn jittered_locals(
        &self,
        rng: &mut crate::rng::Rng,
        max_angle: f32,
    ) -> Result<(Vec<Trs>, usize, f32)> {
        if self.animations.is_empty() {
            return Err(Error::Invalid(
                "random pose: the rig has no animation clips".into(),
            ));
        }
        if !(max_angle.is_finite() && max_angle >= 0.0) {
            return Err(Error::Invalid(format!(
                "random pose: angle {max_angle} must be finite and ≥ 0"
            )));
        }
        let k = rng.below(self.animations.len());
        let time = rng.uniform() as f32 * self.animations[k].duration;
        let mut local = self.animation_locals(k, time)?;
        for l in local.iter_mut() {
            let axis = Vec3::new(
                rng.normal() as f32,
                rng.normal() as f32,
                rng.normal() as f32,
            )
            .normalize_or_zero();
            let angle = (rng.uniform() as f32) * max_angle;
            if axis != Vec3::ZERO {
                l.r = (l.r * Quat::from_axis_angle(axis, angle)).normalize();
            }
        }
        Ok((local, k, time))
    }

    /// Global node transforms for local transforms `local`.
    pub fn globals(&self, local: &[Trs]) -> Vec<Mat4> {
        let n = self.parents.len();
        let mut g: Vec<Option<Mat4>> = vec![None; n];
        fn resolve(
            i: usize,
            parents: &[Option<usize>],
            local: &[Trs],
            g: &mut [Option<Mat4>],
        ) -> Mat4 {
            if let Some(m) = g[i] {
                return m;
            }
            let m = match parents[i] {
                Some(p) => resolve(p, parents, local, g) * local[i].matrix(),
                None => local[i].matrix(),
            };
            g[i] = Some(m);
            m
        }
        (0..n)
            .map(|i| resolve(i, &self.parents, local, &mut g))
            .collect()
    }

    /// Vertex positions of the merged mesh for local transforms `local`:
    /// rigid parts follow their node, skinned parts blend their joints.
    pub fn pose(&self, local: &[Trs]) -> Result<Vec<[f32; 3]>> {
        if local.len() != self.parents.len() {
            return Err(Error::Invalid(format!(
                "pose: {} node transforms for {} nodes",
                local.len(),
                self.parents.len()
            )));
        }
        let g = self.globals(local);
        let mut out = Vec::with_capacity(self.vertex_count());
        for p in &self.parts {
            match p.skin {
                None => out.extend(
                    p.positions
                        .iter()
                        .map(|v| g[p.node].transform_point3(*v).to_array()),
                ),
                Some(s) => {
                    let skin = &self.skins[s];
                    let mats: Vec<Mat4> = skin
                        .joints
                        .iter()
                        .zip(&skin.inverse_bind)
                        .map(|(&j, ib)| g[j] * *ib)
                        .collect();
                    for (i, v) in p.positions.iter().enumerate() {
                        let mut acc = Vec3::ZERO;
                        let mut wsum = 0.0;
                        for k in 0..4 {
                            let w = p.weights[i][k];
                            if w > 0.0 {
                                let m = mats.get(p.joints[i][k] as usize).ok_or_else(|| {
                                    gltf_err("a vertex names a joint outside its skin")
                                })?;
                                acc += w * m.transform_point3(*v);
                                wsum += w;
                            }
                        }
                        out.push(if wsum > 0.0 {
                            (acc / wsum).to_array()
                        } else {
                            v.to_array()
                        });
                    }
                }
            }
        }
        Ok(out)
    }

    /// The rest (bind) pose.
    pub fn rest_pose(&self) -> Result<Vec<[f32; 3]>> {
        self.pose(&self.rest)
    }

    /// Animation `anim` at time `t`.
    pub fn animation_pose(&self, anim: usize, t: f32) -> Result<Vec<[f32; 3]>> {
        self.pose(&self.animation_locals(anim, t)?)
    }
}

//! A rigged glTF character posed on the CPU: node hierarchies with rigid
//! parts (meshes attached to nodes) and skinned parts (linear blend
//! skinning), animations sampled at any time. All primitives are merged
//! into one vertex list of fixed topology, so every pose is a same-topology
//! mesh for the autoencoder (ch. 2).

use crate::error::{Error, Result};
use glam::{Mat4, Quat, Vec3};
use gltf::accessor::DataType::{F32, I16, I8, U16, U32, U8};
use gltf::accessor::Dimensions::{Mat4 as Mat4x4, Scalar, Vec3 as Vec3x, Vec4 as Vec4x};

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
    /// Every node once, each after its parent.
    order: Vec<usize>,
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

/// The most poses [`Rig::clip_sample_count`] allows for one clip.
pub const MAX_CLIP_SAMPLES: usize = 100_000;

fn gltf_err(e: impl std::fmt::Display) -> Error {
    Error::Invalid(format!("glTF: {e}"))
}

/// Checks that the gltf crates (1.4.1) would panic on, before they see the
/// bytes (both found by `scripts/fuzz.sh`, target gltf_rig):
/// - a GLB header whose length is under the header's 12 bytes (gltf's
///   binary.rs:252 subtracts without checking);
/// - a primitive whose POSITION names an accessor that does not exist
///   (gltf-json's mesh.rs:151 indexes it during validation);
/// - an animation channel whose target node does not exist or whose path
///   is unknown (gltf-json does not validate channels; gltf's
///   animation/mod.rs:211 unwraps them).
///
/// Other problems are left to the gltf crate's own errors.
fn check_position_accessors(bytes: &[u8]) -> Result<()> {
    if bytes.len() >= 12 && &bytes[..4] == b"glTF" {
        let length = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
        if length < 12 {
            return Err(gltf_err(format!(
                "the GLB header gives a length of {length} bytes, less than the header itself"
            )));
        }
    }
    let json = match gltf::Glb::from_slice(bytes) {
        Ok(glb) => glb.json,
        Err(_) => std::borrow::Cow::Borrowed(bytes),
    };
    // gltf-json skips unknown keys without checking their UTF-8, so read the
    // text the same way (a stray byte in an unknown key must not hide the rest).
    let Ok(v) = serde_json::from_str::<serde_json::Value>(&String::from_utf8_lossy(&json)) else {
        return Ok(());
    };
    let accessors = v["accessors"].as_array().map_or(0, |a| a.len());
    for (m, mesh) in v["meshes"].as_array().into_iter().flatten().enumerate() {
        for prim in mesh["primitives"].as_array().into_iter().flatten() {
            if let Some(i) = prim["attributes"]["POSITION"].as_u64() {
                if i >= accessors as u64 {
                    return Err(gltf_err(format!(
                        "mesh {m}: POSITION names accessor {i}, but there are {accessors}"
                    )));
                }
            }
        }
    }
    let nodes = v["nodes"].as_array().map_or(0, |a| a.len());
    for (a, anim) in v["animations"].as_array().into_iter().flatten().enumerate() {
        for ch in anim["channels"].as_array().into_iter().flatten() {
            let t = &ch["target"];
            if let Some(n) = t["node"].as_u64() {
                if n >= nodes as u64 {
                    return Err(gltf_err(format!(
                        "animation {a} targets node {n}, but there are {nodes}"
                    )));
                }
            }
            if let Some(p) = t["path"].as_str() {
                if !["translation", "rotation", "scale", "weights"].contains(&p) {
                    return Err(gltf_err(format!(
                        "animation {a} targets an unknown property '{p}'"
                    )));
                }
            }
        }
    }
    Ok(())
}

/// Checks an accessor before the gltf crate reads it: its element type and
/// component type are among those expected, it has at least one element,
/// it is not sparse (not needed here), and its buffer view's stride holds
/// an element. gltf 1.4.1's readers assume all of this (debug assertions
/// and an unchecked `count - 1` in accessor/util.rs; found by
/// `scripts/fuzz.sh`, target gltf_rig).
fn check_accessor(
    a: &gltf::Accessor,
    what: &str,
    dims: &[gltf::accessor::Dimensions],
    types: &[gltf::accessor::DataType],
) -> Result<()> {
    if !dims.contains(&a.dimensions()) || !types.contains(&a.data_type()) {
        return Err(gltf_err(format!(
            "{what}: accessor {} is {:?} of {:?}, expected one of {dims:?} of {types:?}",
            a.index(),
            a.dimensions(),
            a.data_type()
        )));
    }
    if a.count() == 0 || a.sparse().is_some() {
        return Err(gltf_err(format!(
            "{what}: accessor {} is empty or sparse",
            a.index()
        )));
    }
    if let Some(stride) = a.view().and_then(|v| v.stride()) {
        if stride < a.size() {
            return Err(gltf_err(format!(
                "{what}: accessor {} has elements of {} bytes but a stride of {stride}",
                a.index(),
                a.size()
            )));
        }
    }
    Ok(())
}

/// Every node once, each after its parent (breadth-first from the roots);
/// an error when the parent links form a cycle, which glTF forbids.
fn parents_first(parents: &[Option<usize>]) -> Result<Vec<usize>> {
    let mut children = vec![Vec::new(); parents.len()];
    let mut order = Vec::with_capacity(parents.len());
    for (i, p) in parents.iter().enumerate() {
        match p {
            Some(p) => children[*p].push(i),
            None => order.push(i),
        }
    }
    let mut k = 0;
    while k < order.len() {
        order.extend_from_slice(&children[order[k]]);
        k += 1;
    }
    if order.len() < parents.len() {
        return Err(gltf_err(format!(
            "{} nodes form a cycle of parent links",
            parents.len() - order.len()
        )));
    }
    Ok(order)
}

impl Rig {
    /// Reads a binary glTF (.glb) with its embedded buffer.
    pub fn from_glb(bytes: &[u8]) -> Result<Rig> {
        check_position_accessors(bytes)?;
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
                let ci = c.index();
                if ci == node.index() {
                    return Err(gltf_err(format!("node {ci} is its own child")));
                }
                if parents[ci].is_some() {
                    return Err(gltf_err(format!("node {ci} has two parents")));
                }
                parents[ci] = Some(node.index());
            }
        }
        let order = parents_first(&parents)?;
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
            if let Some(a) = skin.inverse_bind_matrices() {
                check_accessor(&a, "inverse bind matrices", &[Mat4x4], &[F32])?;
            }
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
                use gltf::mesh::Semantic;
                if let Some(a) = prim.get(&Semantic::Positions) {
                    check_accessor(&a, "POSITION", &[Vec3x], &[F32])?;
                }
                if let Some(a) = prim.indices() {
                    check_accessor(&a, "indices", &[Scalar], &[U8, U16, U32])?;
                }
                if let Some(a) = prim.get(&Semantic::Joints(0)) {
                    check_accessor(&a, "JOINTS_0", &[Vec4x], &[U8, U16])?;
                }
                if let Some(a) = prim.get(&Semantic::Weights(0)) {
                    check_accessor(&a, "WEIGHTS_0", &[Vec4x], &[F32, U8, U16])?;
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
                    if j.len() != positions.len() || w.len() != positions.len() {
                        return Err(gltf_err(format!(
                            "a skinned primitive has {} positions but {} joint and {} weight entries",
                            positions.len(),
                            j.len(),
                            w.len()
                        )));
                    }
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
                let sampler = ch.sampler();
                check_accessor(&sampler.input(), "animation times", &[Scalar], &[F32])?;
                {
                    use gltf::animation::Property;
                    let (dims, types): (&[_], &[_]) = match ch.target().property() {
                        Property::Translation | Property::Scale => (&[Vec3x], &[F32]),
                        Property::Rotation => (&[Vec4x], &[F32, I8, U8, I16, U16]),
                        Property::MorphTargetWeights => (&[Scalar], &[F32, I8, U8, I16, U16]),
                    };
                    check_accessor(&sampler.output(), "animation values", dims, types)?;
                }
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
            order,
            rest,
            triangles,
            vertex_part,
            animations,
            parts,
            skins,
        })
    }

    /// Poses a clip gives when sampled at `fps` from 0 to its duration
    /// (both ends included); an error past [`MAX_CLIP_SAMPLES`], so a clip
    /// whose last key time is, say, 3·10³⁸ s is refused, not looped over.
    pub fn clip_sample_count(&self, anim: usize, fps: f32) -> Result<usize> {
        let a = self.animations.get(anim).ok_or_else(|| {
            Error::Invalid(format!(
                "animation {anim} does not exist ({} clips)",
                self.animations.len()
            ))
        })?;
        let n = (a.duration as f64 * fps as f64).floor() + 1.0;
        if !(fps > 0.0 && n >= 1.0 && n <= MAX_CLIP_SAMPLES as f64) {
            return Err(Error::Invalid(format!(
                "clip '{}' lasts {} s: at {fps} poses per second that is more than {MAX_CLIP_SAMPLES} poses",
                a.name, a.duration
            )));
        }
        Ok(n as usize)
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

    /// Global node transforms for local transforms `local` (one per node),
    /// parents first, without recursion.
    pub fn globals(&self, local: &[Trs]) -> Vec<Mat4> {
        let mut g = vec![Mat4::IDENTITY; self.parents.len()];
        for &i in &self.order {
            g[i] = match self.parents[i] {
                Some(p) => g[p] * local[i].matrix(),
                None => local[i].matrix(),
            };
        }
        g
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

//! What the viewer draws, as plain data: skeletons, a ground grid, the root
//! trajectory, and (for the hair and mesh systems) line strips and triangle
//! meshes. The renderer reads a [`Scene`]; it never owns app state.

use super::camera::OrbitCamera;

/// One skeleton pose: global joint positions and parents.
#[derive(Clone, Debug, PartialEq)]
pub struct SkeletonPose {
    /// Global joint positions.
    pub positions: Vec<[f32; 3]>,
    /// Parent per joint (`None` for roots).
    pub parents: Vec<Option<usize>>,
    /// RGBA, linear.
    pub color: [f32; 4],
    /// Joint sphere radius (world units).
    pub joint_radius: f32,
    /// Bone radius (world units).
    pub bone_radius: f32,
}

impl SkeletonPose {
    /// A pose with default radii for the CMU skeleton's units.
    pub fn new(positions: Vec<[f32; 3]>, parents: Vec<Option<usize>>, color: [f32; 4]) -> Self {
        SkeletonPose {
            positions,
            parents,
            color,
            joint_radius: 2.2,
            bone_radius: 1.6,
        }
    }
}

/// Line strips (hair strands: `strip_len` points each), drawn unlit.
/// The renderer keeps their vertex buffer across frames while `revision`
/// and the sizes stay the same: bump `revision` when the points change.
#[derive(Clone, Debug, PartialEq)]
pub struct LineStrips {
    /// Points, strip after strip.
    pub points: Vec<[f32; 3]>,
    /// Points per strip.
    pub strip_len: usize,
    /// RGBA, linear.
    pub color: [f32; 4],
    /// Content revision (see above).
    pub revision: u64,
}

/// A triangle mesh, drawn lit with flat normals: in one color, or with a
/// color per vertex (e.g. reconstruction error) multiplied by `color`.
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Triangles, three vertex indices each.
    pub indices: Vec<u32>,
    /// RGBA, linear.
    pub color: [f32; 4],
    /// One RGBA per vertex, or empty for `color` alone.
    pub vertex_colors: Vec<[f32; 4]>,
}

impl TriMesh {
    /// A mesh in one color.
    pub fn new(positions: Vec<[f32; 3]>, indices: Vec<u32>, color: [f32; 4]) -> Self {
        TriMesh {
            positions,
            indices,
            color,
            vertex_colors: Vec::new(),
        }
    }
}

/// The ground grid at y = `height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Half the grid's width.
    pub extent: f32,
    /// Spacing between lines.
    pub step: f32,
    /// Height of the ground.
    pub height: f32,
}

impl Default for Grid {
    fn default() -> Self {
        Grid {
            extent: 600.0,
            step: 50.0,
            height: 0.0,
        }
    }
}

/// Everything drawn in one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Skeletons: the current pose and, in a second color, keyframe poses.
    pub skeletons: Vec<SkeletonPose>,
    /// Root trajectory, drawn as dots on the ground (Fig. 1.2's style).
    pub trajectory: Vec<[f32; 3]>,
    /// Color of the trajectory dots.
    pub trajectory_color: [f32; 4],
    /// The ground grid, if any.
    pub grid: Option<Grid>,
    /// Line strips (hair).
    pub strips: Vec<LineStrips>,
    /// Triangle meshes.
    pub meshes: Vec<TriMesh>,
    /// Background color.
    pub background: [f32; 4],
}

impl Scene {
    /// The sketch page's skeletons: the current pose (global joint
    /// positions, flat `joints × 3`, may be empty), key poses in the key
    /// color, a little smaller (flat `keys × joints × 3`), and the selected
    /// joint of the current pose as a larger marker. Replaces the scene's
    /// skeletons; an error when the lengths do not fit `parents`.
    pub fn set_sketch_poses(
        &mut self,
        pose: &[f32],
        keys: &[f32],
        parents: &[Option<usize>],
        selected: Option<usize>,
    ) -> crate::error::Result<()> {
        let j = parents.len();
        if j == 0 || !keys.len().is_multiple_of(3 * j) || (!pose.is_empty() && pose.len() != 3 * j)
        {
            return Err(crate::error::Error::Shape {
                what: "viewer poses".into(),
                expected: format!("{j} joints × 3 numbers per pose (and a skeleton)"),
                found: format!("pose {}, keys {}", pose.len(), keys.len()),
            });
        }
        crate::error::check_finite("viewer pose", pose)?;
        crate::error::check_finite("viewer keys", keys)?;
        let points = |v: &[f32]| v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        self.skeletons.clear();
        if !pose.is_empty() {
            self.skeletons.push(SkeletonPose::new(
                points(pose),
                parents.to_vec(),
                colors::POSE,
            ));
        }
        for k in keys.chunks_exact(3 * j) {
            let mut s = SkeletonPose::new(points(k), parents.to_vec(), colors::KEY);
            s.joint_radius *= 0.8;
            s.bone_radius *= 0.8;
            self.skeletons.push(s);
        }
        if let (Some(sel), false) = (selected.filter(|&s| s < j), pose.is_empty()) {
            let p = [pose[3 * sel], pose[3 * sel + 1], pose[3 * sel + 2]];
            let mut s = SkeletonPose::new(vec![p], vec![None], colors::SELECTED);
            s.joint_radius *= 1.8;
            self.skeletons.push(s);
        }
        Ok(())
    }
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            skeletons: Vec::new(),
            trajectory: Vec::new(),
            trajectory_color: [0.35, 0.55, 0.95, 1.0],
            grid: Some(Grid::default()),
            strips: Vec::new(),
            meshes: Vec::new(),
            background: [0.08, 0.09, 0.11, 1.0],
        }
    }
}

/// Colors used by the sketching page.
pub mod colors {
    /// The synthesized pose.
    pub const POSE: [f32; 4] = [0.85, 0.87, 0.92, 1.0];
    /// Keyframe poses (the thesis' pink).
    pub const KEY: [f32; 4] = [0.95, 0.45, 0.65, 1.0];
    /// The selected joint.
    pub const SELECTED: [f32; 4] = [1.0, 0.8, 0.2, 1.0];
    /// Latent vertices of the mesh autoencoder.
    pub const LATENT: [f32; 4] = [0.2, 0.85, 0.95, 1.0];

    /// A perceptual-ish ramp for a value in [0, 1] (clamped; NaN counts as
    /// 1): blue-grey at 0, through yellow, to red at 1. Used for per-vertex
    /// error.
    pub fn ramp(t: f32) -> [f32; 4] {
        let t = if t.is_nan() { 1.0 } else { t.clamp(0.0, 1.0) };
        const STOPS: [[f32; 3]; 4] = [
            [0.55, 0.62, 0.75],
            [0.45, 0.80, 0.55],
            [0.98, 0.85, 0.25],
            [0.92, 0.22, 0.18],
        ];
        let x = t * (STOPS.len() - 1) as f32;
        let i = (x.floor() as usize).min(STOPS.len() - 2);
        let f = x - i as f32;
        let (a, b) = (STOPS[i], STOPS[i + 1]);
        [
            a[0] + f * (b[0] - a[0]),
            a[1] + f * (b[1] - a[1]),
            a[2] + f * (b[2] - a[2]),
            1.0,
        ]
    }
}

/// The joint under a pixel: `(skeleton, joint)` of the joint whose sphere
/// (radius × `slack`) the pixel's ray passes closest to its centre,
/// relative to the radius; nearer joints win ties. `None` when no sphere is hit.
pub fn pick_joint(
    scene: &Scene,
    camera: &OrbitCamera,
    x: f32,
    y: f32,
    width: f32,
    height: f32,
    slack: f32,
) -> Option<(usize, usize)> {
    let (o, d) = camera.ray(x, y, width, height);
    let mut best: Option<(f32, f32, usize, usize)> = None;
    for (s, sk) in scene.skeletons.iter().enumerate() {
        let r = sk.joint_radius * slack;
        for (j, p) in sk.positions.iter().enumerate() {
            let c = glam::Vec3::from(*p);
            let t = (c - o).dot(d);
            if t <= 0.0 {
                continue;
            }
            let miss = (o + d * t - c).length() / r;
            if miss <= 1.0
                && best.is_none_or(|b| miss < b.0 - 1e-3 || ((miss - b.0).abs() <= 1e-3 && t < b.1))
            {
                best = Some((miss, t, s, j));
            }
        }
    }
    best.map(|b| (b.2, b.3))
}

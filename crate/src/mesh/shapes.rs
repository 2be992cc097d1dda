//! Meshes the project makes itself for the thesis' other mesh experiments
//! (Sec. 2.3.3-2.3.5), and random smooth deformations to train on them:
//!
//! - [`tet_block`]: a tetrahedralized solid block (Fig. 2.8): surface and
//!   interior vertices, every tetrahedron's faces as triangles;
//! - [`crossing_planes`]: a non-manifold "tree" of quads crossing at a
//!   shared axis (Fig. 2.9), whose axis edges belong to many faces;
//! - [`subdivide`]: midpoint subdivision, which turns the robot into a
//!   high-resolution mesh (Fig. 2.6) and its poses with it;
//! - [`deform`]: a smooth random deformation (a bend, a twist and a few
//!   Gaussian bumps) standing in for the thesis' captured shapes.

use crate::error::{Error, Result};
use crate::rng::Rng;

/// A generated mesh: positions, triangles, and which vertices are interior
/// (not on the solid's surface; empty for surfaces).
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Triangles (vertex indices).
    pub triangles: Vec<[usize; 3]>,
    /// Indices of interior vertices.
    pub interior: Vec<usize>,
}

/// Largest grid [`tet_block`] and [`crossing_planes`] accept per side.
pub const MAX_CELLS: usize = 64;

/// A block of `nx × ny × nz` cubes, each split into six tetrahedra around
/// its main diagonal (Kuhn's triangulation, so neighbours' faces match);
/// cubes of side 1/`n` for the largest side `n`, the block standing on y =
/// 0. The triangles are all four faces of every tetrahedron, so the graph
/// has every tetrahedron edge.
pub fn tet_block(nx: usize, ny: usize, nz: usize) -> Result<Shape> {
    if [nx, ny, nz].iter().any(|&n| n == 0 || n > MAX_CELLS) {
        return Err(Error::Invalid(format!(
            "tet_block: {nx} x {ny} x {nz} cells; each side must be 1..={MAX_CELLS}"
        )));
    }
    let s = 1.0 / nx.max(ny).max(nz) as f32;
    let id = |x: usize, y: usize, z: usize| (x * (ny + 1) + y) * (nz + 1) + z;
    let mut positions = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    let mut interior = Vec::new();
    for x in 0..=nx {
        for y in 0..=ny {
            for z in 0..=nz {
                if x > 0 && x < nx && y > 0 && y < ny && z > 0 && z < nz {
                    interior.push(positions.len());
                }
                positions.push([
                    x as f32 * s - 0.5 * nx as f32 * s,
                    y as f32 * s,
                    z as f32 * s - 0.5 * nz as f32 * s,
                ]);
            }
        }
    }
    // the six paths from corner 000 to 111 along the cube's edges
    const PATHS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut triangles = Vec::new();
    for x in 0..nx {
        for y in 0..ny {
            for z in 0..nz {
                for path in PATHS {
                    let mut c = [x, y, z];
                    let mut tet = [id(x, y, z); 4];
                    for (i, axis) in path.iter().enumerate() {
                        c[*axis] += 1;
                        tet[i + 1] = id(c[0], c[1], c[2]);
                    }
                    let [a, b, cc, d] = tet;
                    triangles.extend([[a, b, cc], [a, b, d], [a, cc, d], [b, cc, d]]);
                }
            }
        }
    }
    Ok(Shape {
        positions,
        triangles,
        interior,
    })
}

/// A non-manifold "tree": `planes` vertical quad grids (`w × h` quads,
/// each split into two triangles) through the y axis at equal angles, all
/// sharing the axis column of vertices, so every axis edge belongs to
/// 2·`planes` triangles; 1 unit wide and `h/w` units tall.
pub fn crossing_planes(planes: usize, w: usize, h: usize) -> Result<Shape> {
    if !(2..=8).contains(&planes)
        || w < 2
        || !w.is_multiple_of(2)
        || w > MAX_CELLS
        || h == 0
        || h > MAX_CELLS
    {
        return Err(Error::Invalid(format!(
            "crossing_planes: {planes} planes of {w} x {h} quads; planes 2..=8, width even in 2..={MAX_CELLS}, height 1..={MAX_CELLS}"
        )));
    }
    let s = 1.0 / w as f32;
    let mut positions = Vec::new();
    // the shared axis column first
    for y in 0..=h {
        positions.push([0.0, y as f32 * s, 0.0]);
    }
    let mut triangles = Vec::new();
    for p in 0..planes {
        let a = std::f32::consts::PI * p as f32 / planes as f32;
        let (dx, dz) = (a.cos(), a.sin());
        // grid columns -w/2..=w/2, the middle one being the axis
        let mut col = vec![vec![0usize; h + 1]; w + 1];
        for (i, c) in col.iter_mut().enumerate() {
            let u = (i as f32 - (w / 2) as f32) * s;
            for (y, v) in c.iter_mut().enumerate() {
                if i == w / 2 {
                    *v = y;
                } else {
                    *v = positions.len();
                    positions.push([u * dx, y as f32 * s, u * dz]);
                }
            }
        }
        for i in 0..w {
            for y in 0..h {
                let (a, b, c, d) = (col[i][y], col[i + 1][y], col[i + 1][y + 1], col[i][y + 1]);
                triangles.extend([[a, b, c], [a, c, d]]);
            }
        }
    }
    Ok(Shape {
        positions,
        triangles,
        interior: Vec::new(),
    })
}

/// A subdivided mesh: positions, triangles, and for each new vertex (after
/// the old ones) the two vertices it is the middle of.
pub type Subdivided = (Vec<[f32; 3]>, Vec<[usize; 3]>, Vec<[usize; 2]>);

/// Midpoint subdivision: every triangle into four, a new vertex at the
/// middle of every edge. Returns the new mesh and, for each new vertex
/// (after the old ones), the two vertices it is the middle of: a pose of
/// the old mesh becomes one of the new with [`subdivide_pose`].
pub fn subdivide(positions: &[[f32; 3]], triangles: &[[usize; 3]]) -> Result<Subdivided> {
    let n = positions.len();
    if let Some(t) = triangles.iter().find(|t| t.iter().any(|&v| v >= n)) {
        return Err(Error::Invalid(format!(
            "subdivide: triangle {t:?} is outside the {n} vertices"
        )));
    }
    let mut mids: std::collections::HashMap<(usize, usize), usize> = Default::default();
    let mut parents: Vec<[usize; 2]> = Vec::new();
    let mut out_tris = Vec::with_capacity(4 * triangles.len());
    let mut mid = |a: usize, b: usize, parents: &mut Vec<[usize; 2]>| {
        let key = (a.min(b), a.max(b));
        *mids.entry(key).or_insert_with(|| {
            parents.push([key.0, key.1]);
            n + parents.len() - 1
        })
    };
    for &[a, b, c] in triangles {
        let (ab, bc, ca) = (
            mid(a, b, &mut parents),
            mid(b, c, &mut parents),
            mid(c, a, &mut parents),
        );
        out_tris.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    let out_pos = subdivide_pose(positions, &parents)?;
    Ok((out_pos, out_tris, parents))
}

/// A pose of a mesh extended to its subdivision: the old vertices, then
/// each new vertex at the middle of its two `parents`.
pub fn subdivide_pose(pose: &[[f32; 3]], parents: &[[usize; 2]]) -> Result<Vec<[f32; 3]>> {
    if let Some(p) = parents.iter().find(|p| p.iter().any(|&v| v >= pose.len())) {
        return Err(Error::Invalid(format!(
            "subdivide_pose: parents {p:?} outside the pose's {} vertices",
            pose.len()
        )));
    }
    let mut out = pose.to_vec();
    out.extend(parents.iter().map(|&[a, b]| {
        let (p, q) = (pose[a], pose[b]);
        [
            (p[0] + q[0]) / 2.0,
            (p[1] + q[1]) / 2.0,
            (p[2] + q[2]) / 2.0,
        ]
    }));
    Ok(out)
}

/// A smooth random deformation of `rest`: a bend about z and a twist about
/// y that grow with height, then three Gaussian bumps (radius 30% of the
/// mesh's size, displacement up to 15%) at random vertices. Deterministic
/// for a generator state.
pub fn deform(rest: &[[f32; 3]], rng: &mut Rng) -> Vec<[f32; 3]> {
    if rest.is_empty() {
        return Vec::new();
    }
    // in double precision: squared distances of meshes at 1e20 overflow
    // float32, and at 1e-30 they underflow
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for p in rest {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c] as f64);
            hi[c] = hi[c].max(p[c] as f64);
        }
    }
    let size = (0..3)
        .map(|c| hi[c] - lo[c])
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let height = (hi[1] - lo[1]).max(size * 1e-6);
    let center = [(lo[0] + hi[0]) / 2.0, lo[1], (lo[2] + hi[2]) / 2.0];
    let bend = rng.range(-0.7, 0.7);
    let twist = rng.range(-1.0, 1.0);
    let bumps: Vec<([f64; 3], [f64; 3])> = (0..3)
        .map(|_| {
            let at = rest[rng.below(rest.len())].map(|v| v as f64);
            let d = [0, 1, 2].map(|_| rng.range(-0.15, 0.15) * size);
            (at, d)
        })
        .collect();
    let r = 0.3 * size;
    rest.iter()
        .map(|p| {
            let p = p.map(|v| v as f64);
            let mut q = [p[0] - center[0], p[1] - center[1], p[2] - center[2]];
            let s = q[1] / height;
            // twist about y
            let (st, ct) = (twist * s).sin_cos();
            q = [ct * q[0] + st * q[2], q[1], -st * q[0] + ct * q[2]];
            // bend about z: the part above height y turns by bend·s
            let (sb, cb) = (bend * s).sin_cos();
            q = [cb * q[0] - sb * q[1], sb * q[0] + cb * q[1], q[2]];
            let mut out = [q[0] + center[0], q[1] + center[1], q[2] + center[2]];
            for (at, d) in &bumps {
                // distances over the bump radius first: no square overflows
                let dist2: f64 = (0..3).map(|c| ((p[c] - at[c]) / r).powi(2)).sum();
                let w = (-dist2).exp();
                for c in 0..3 {
                    out[c] += w * d[c];
                }
            }
            out.map(|v| v as f32)
        })
        .collect()
}

/// OBJ text of a mesh (`v` lines, then 1-based `f` lines).
pub fn to_obj(positions: &[[f32; 3]], triangles: &[[usize; 3]]) -> String {
    let mut s = String::with_capacity(32 * (positions.len() + triangles.len()));
    for p in positions {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in triangles {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

/// Vertices of a solid's interior: those on no boundary face, a boundary
/// face being a triangle that appears once among the triangles (a
/// tetrahedral mesh given as all its tetrahedra's faces lists an interior
/// face twice). Empty for a surface mesh, whose faces all appear once.
pub fn interior_vertices(vertices: usize, triangles: &[[usize; 3]]) -> Vec<usize> {
    let mut count: std::collections::HashMap<[usize; 3], u32> = Default::default();
    for t in triangles {
        let mut k = *t;
        k.sort_unstable();
        *count.entry(k).or_default() += 1;
    }
    if count.values().all(|&c| c == 1) {
        return Vec::new();
    }
    let mut surface = vec![false; vertices];
    for (t, &c) in &count {
        if c == 1 {
            for &v in t {
                if v < vertices {
                    surface[v] = true;
                }
            }
        }
    }
    let used: std::collections::HashSet<usize> = triangles.iter().flatten().copied().collect();
    (0..vertices)
        .filter(|v| !surface[*v] && used.contains(v))
        .collect()
}

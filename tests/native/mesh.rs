#![allow(clippy::needless_range_loop)]
//! Topology-only graph sampling (Sec. 2.2.1, App. A.1.2): small graphs
//! whose answers are worked out by hand, a non-manifold mesh, and the
//! sampler's invariants on random graphs.

use deeprep::mesh::{sample, Graph};
use deeprep::rng::Rng;

mod common;

fn path(n: usize) -> Graph {
    let e: Vec<_> = (1..n).map(|i| (i - 1, i)).collect();
    Graph::from_edges(n, &e).unwrap()
}

fn grid(w: usize, h: usize) -> Graph {
    let mut e = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let v = y * w + x;
            if x + 1 < w {
                e.push((v, v + 1));
            }
            if y + 1 < h {
                e.push((v, v + w));
            }
        }
    }
    Graph::from_edges(w * h, &e).unwrap()
}

/// All-pairs distances by BFS (test helper, independent of `ring` order).
fn dist(g: &Graph) -> Vec<Vec<usize>> {
    (0..g.len())
        .map(|s| {
            let mut d = vec![usize::MAX; g.len()];
            d[s] = 0;
            let mut q = std::collections::VecDeque::from([s]);
            while let Some(u) = q.pop_front() {
                for &w in g.neighbors(u) {
                    if d[w] == usize::MAX {
                        d[w] = d[u] + 1;
                        q.push_back(w);
                    }
                }
            }
            d
        })
        .collect()
}

#[test]
fn a_path_by_hand() {
    // 0-1-2-3-4-5-6, stride 2: keep 0, 2, 4, 6; kept vertices 2 apart are
    // within 2s-1 = 3, so the sampled graph is the path 0-1-2-3.
    let g = path(7);
    let s = sample(&g, 2, 1, &[]).unwrap();
    assert_eq!(s.selected, vec![0, 2, 4, 6]);
    assert_eq!(s.graph.edges(), vec![(0, 1), (1, 2), (2, 3)]);
    // Down, r = 1: each kept vertex reads itself, then its neighbours.
    assert_eq!(s.down.width, 3);
    assert_eq!(s.down.row(0), vec![0, 1]);
    assert_eq!(s.down.row(1), vec![2, 1, 3]);
    assert_eq!(s.down.row(3), vec![6, 5]);
    assert_eq!(s.down.mask[0..3], [1, 1, 0]);
    // Up, r = 1: vertex 1 reads kept vertices 0 and 2 (sampled 0 and 1).
    assert_eq!(s.up.rows, 7);
    assert_eq!(s.up.row(0), vec![0]);
    assert_eq!(s.up.row(1), vec![0, 1]);
    assert_eq!(s.up.row(5), vec![2, 3]);
}

#[test]
fn a_grid_and_a_cycle_by_hand() {
    // 3x3 grid (0..8 row by row), stride 2, BFS from 0: 0 is kept and covers
    // 1 and 3; 2 is kept (covers 5); 4 is 2 from 0 and 2, kept; 6 and 8 too.
    let s = sample(&grid(3, 3), 2, 1, &[]).unwrap();
    assert_eq!(s.selected, vec![0, 2, 4, 6, 8]);
    // Corners along a side are 2 apart (linked), diagonal corners 4 (> 3, not
    // linked: 0-8 and 2-6); the centre is 2 from every corner.
    assert_eq!(
        s.graph.edges(),
        vec![
            (0, 1),
            (0, 2),
            (0, 3),
            (1, 2),
            (1, 4),
            (2, 3),
            (2, 4),
            (3, 4)
        ]
    );
    // A 6-cycle with stride 2 keeps 0, 2, 4, which become a triangle.
    let c = Graph::from_edges(6, &[(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 0)]).unwrap();
    let s = sample(&c, 2, 1, &[]).unwrap();
    assert_eq!(s.selected, vec![0, 2, 4]);
    assert_eq!(s.graph.edges(), vec![(0, 1), (0, 2), (1, 2)]);
    // Stride 1 keeps everything with the same edges.
    let s = sample(&c, 1, 1, &[]).unwrap();
    assert_eq!(s.selected, (0..6).collect::<Vec<_>>());
    assert_eq!(s.graph, c);
}

#[test]
fn seeds_are_kept_and_bad_requests_are_errors() {
    let g = path(7);
    let s = sample(&g, 2, 1, &[3]).unwrap();
    // From 3 outwards: 3, then 1 and 5 (2 away); 0 is within 1 of 1, 6 of 5.
    assert_eq!(s.selected, vec![1, 3, 5]);
    assert!(sample(&g, 2, 1, &[3, 4])
        .unwrap_err()
        .to_string()
        .contains("closer than the stride"));
    assert!(sample(&g, 0, 1, &[]).is_err());
    assert!(sample(&g, 3, 1, &[])
        .unwrap_err()
        .to_string()
        .contains("radius"));
    assert!(sample(&g, 2, 1, &[9]).is_err());
    assert!(Graph::from_edges(3, &[(0, 5)]).is_err());
}

#[test]
fn a_non_manifold_mesh() {
    // Two triangles meeting at one vertex (a bowtie), a third triangle
    // sharing an edge with three faces (non-manifold edge 0-1), and an
    // isolated vertex 7.
    let tris = [[0, 1, 2], [0, 1, 3], [0, 1, 4], [2, 5, 6]];
    let g = Graph::from_triangles(8, &tris).unwrap();
    assert_eq!(g.neighbors(0), &[1, 2, 3, 4]);
    assert_eq!(g.neighbors(7), &[] as &[usize]);
    let s = sample(&g, 2, 1, &[]).unwrap();
    // BFS from 0 covers 1..4; 5 and 6 are 2 from 0 (via 2): 5 is kept and covers 6; 7 alone.
    assert_eq!(s.selected, vec![0, 5, 7]);
    assert_eq!(s.graph.edges(), vec![(0, 1)]);
    assert_eq!(s.up.row(7), vec![2]);
    let again = sample(&g, 2, 1, &[]).unwrap();
    assert_eq!(s, again, "deterministic");
}

#[test]
fn invariants_on_random_graphs() {
    let mut rng = Rng::new(21);
    for case in 0..40 {
        let n = 20 + (rng.uniform() * 60.0) as usize;
        // A random spanning tree plus extra edges: connected.
        let mut e = Vec::new();
        for v in 1..n {
            e.push(((rng.uniform() * v as f64) as usize, v));
        }
        for _ in 0..n / 2 {
            e.push((
                (rng.uniform() * n as f64) as usize,
                (rng.uniform() * n as f64) as usize,
            ));
        }
        let g = Graph::from_edges(n, &e).unwrap();
        let d = dist(&g);
        for stride in 1..=3 {
            let r = stride.max(1);
            let s = sample(&g, stride, r, &[]).unwrap();
            let kept = &s.selected;
            for (i, &a) in kept.iter().enumerate() {
                for (j, &b) in kept.iter().enumerate() {
                    if i < j {
                        assert!(
                            d[a][b] >= stride,
                            "case {case}: kept {a}, {b} only {} apart",
                            d[a][b]
                        );
                        let linked = s.graph.neighbors(i).contains(&j);
                        assert_eq!(
                            linked,
                            d[a][b] < 2 * stride,
                            "case {case}: edge rule for {a}, {b}"
                        );
                    }
                }
            }
            for v in 0..n {
                let near = kept.iter().map(|&k| d[v][k]).min().unwrap();
                assert!(
                    near < stride,
                    "case {case}: vertex {v} is {near} from every kept vertex (not maximal)"
                );
                let up = s.up.row(v);
                assert!(!up.is_empty());
                assert!(up.iter().all(|&i| d[v][kept[i]] <= r));
            }
            for (i, &k) in kept.iter().enumerate() {
                let row = s.down.row(i);
                assert_eq!(row[0], k, "a kept vertex reads itself first");
                assert_eq!(row.len(), (0..n).filter(|&v| d[k][v] <= r).count());
            }
            // Connected input, connected output.
            let comps = s.graph.components();
            assert!(
                comps.iter().all(|&c| c == 0),
                "case {case} stride {stride}: sampled graph split"
            );
        }
    }
}

/// The CC0 robot of ../shared/data/gltf: merged topology, rest pose,
/// animations and skinned hands.
#[test]
fn the_robot_poses_with_one_topology() {
    let p = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/gltf/RobotExpressive.glb");
    let Ok(bytes) = std::fs::read(&p) else {
        eprintln!("SKIP: ../shared/data/gltf/RobotExpressive.glb is absent");
        return;
    };
    let rig = deeprep::mesh::Rig::from_glb(&bytes).unwrap();
    let n = rig.vertex_count();
    assert_eq!(rig.animations.len(), 14);
    assert!((6000..9000).contains(&n), "{n} vertices");
    assert_eq!(
        rig.vertex_part.iter().max().map(|&m| m + 1),
        Some(19),
        "19 primitives"
    );
    assert!(rig.triangles.iter().flatten().all(|&i| (i as usize) < n));
    let rest = rig.rest_pose().unwrap();
    let (lo, hi) = rest
        .iter()
        .fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| {
            (
                std::array::from_fn(|i| lo[i].min(p[i])),
                std::array::from_fn(|i| hi[i].max(p[i])),
            )
        });
    let size: Vec<f32> = (0..3).map(|i| hi[i] - lo[i]).collect();
    eprintln!(
        "rest pose bounding box {size:?}, {n} vertices, {} triangles",
        rig.triangles.len()
    );
    assert!(size[1] > size[0] * 0.5 && size.iter().all(|s| s.is_finite() && *s > 0.0));
    let walk = rig
        .animations
        .iter()
        .position(|a| a.name == "Walking")
        .unwrap();
    let d = rig.animations[walk].duration;
    let a = rig.animation_pose(walk, 0.0).unwrap();
    let b = rig.animation_pose(walk, d / 2.0).unwrap();
    assert_eq!(a.len(), n);
    let moved = a
        .iter()
        .zip(&b)
        .filter(|(p, q)| (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f32>().sqrt() > 0.01 * size[1])
        .count();
    assert!(
        moved > n / 10,
        "walking moves the body: {moved} of {n} vertices"
    );
    // The skinned hands (parts 15-16 right, 17-18 left; each hand has two
    // primitives) must be assembled and placed: in the rest pose the hands
    // mirror each other across x = 0, and in every clip the two primitives
    // of a hand stay together. (Skinning without the inverse bind matrices
    // fails both: it puts the left hand at x < 0 and splits each hand.)
    let centroid = |pose: &[[f32; 3]], part: u32| -> [f32; 3] {
        let v: Vec<&[f32; 3]> = pose
            .iter()
            .zip(&rig.vertex_part)
            .filter(|(_, p)| **p == part)
            .map(|(v, _)| v)
            .collect();
        std::array::from_fn(|i| v.iter().map(|p| p[i]).sum::<f32>() / v.len() as f32)
    };
    let dist = |a: [f32; 3], b: [f32; 3]| (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f32>().sqrt();
    let (r, l) = (centroid(&rest, 15), centroid(&rest, 17));
    assert!(
        (r[0] + l[0]).abs() < 0.05 * size[1] && (r[1] - l[1]).abs() < 0.05 * size[1],
        "hands not mirrored: {r:?} {l:?}"
    );
    assert!(r[0].signum() != l[0].signum());
    for (k, anim) in rig.animations.iter().enumerate() {
        for f in [0.0, 0.3, 0.7] {
            let pose = rig.animation_pose(k, anim.duration * f).unwrap();
            assert!(
                pose.iter().flatten().all(|v| v.is_finite()),
                "{}",
                anim.name
            );
            for (a, b) in [(15, 16), (17, 18)] {
                let d = dist(centroid(&pose, a), centroid(&pose, b));
                assert!(
                    d < 0.1 * size[1],
                    "{} at {f}: hand parts {a} and {b} are {d} apart",
                    anim.name
                );
            }
        }
    }
    assert!(rig.animation_pose(99, 0.0).is_err());
    assert!(rig.animation_pose(walk, f32::NAN).is_err());
    assert!(deeprep::mesh::Rig::from_glb(b"not a glb").is_err());
}

#[test]
fn welding_and_connecting_components() {
    use deeprep::mesh::graph::{connect_components, weld};
    // Two triangles sharing an edge, stored with split vertices (4 and 5
    // duplicate 1 and 2), plus a third triangle far away and a fourth close
    // to the first pair.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0], // 0 1 2
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0], // 3 4 5 (4 = 1, 5 = 2)
        [10.0, 0.0, 0.0],
        [11.0, 0.0, 0.0],
        [10.0, 1.0, 0.0], // far
        [1.2, 1.0, 0.0],
        [2.2, 1.0, 0.0],
        [1.2, 2.0, 0.0], // near vertex 3
    ];
    let (map, n) = weld(&p, 1e-4);
    assert_eq!(n, 10);
    assert_eq!((map[4], map[5]), (map[1], map[2]));
    let tris: Vec<[usize; 3]> = [[0, 1, 2], [3, 5, 4], [6, 7, 8], [9, 10, 11]]
        .iter()
        .map(|t| [map[t[0]], map[t[1]], map[t[2]]])
        .collect();
    let g = Graph::from_triangles(n, &tris).unwrap();
    let mut wp = vec![[0.0f32; 3]; n];
    for (v, &w) in map.iter().enumerate() {
        wp[w] = p[v];
    }
    assert_eq!(
        g.components().iter().max(),
        Some(&2),
        "three components after welding"
    );
    let (c, added) = connect_components(&g, &wp, 0.5).unwrap();
    // The close pair (3 and 9, 0.2 apart) is joined by the "close" rule; the
    // far triangle by the spanning rule, at the closest pair left: 10 (2.2, 1)
    // to 8 (10, 1), 7.8 apart (the first pair's 1 to 6 is 9 apart).
    let mut want = vec![(map[3], map[9]), (map[8].min(map[10]), map[8].max(map[10]))];
    want.sort();
    let mut got = added.clone();
    got.sort();
    assert_eq!(got, want);
    assert!(c.components().iter().all(|&l| l == 0));
    assert!(connect_components(&g, &wp[1..], 0.5).is_err());
}

/// The robot's autoencoder topology: welded, one component, levels that
/// shrink to a handful of latent vertices at the hands, feet, head, torso.
#[test]
fn the_robot_topology_samples_down_to_latent_vertices() {
    let p = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/gltf/RobotExpressive.glb");
    let Ok(bytes) = std::fs::read(&p) else {
        eprintln!("SKIP: ../shared/data/gltf/RobotExpressive.glb is absent");
        return;
    };
    let rig = deeprep::mesh::Rig::from_glb(&bytes).unwrap();
    let seeds = [
        "Palm2.L",
        "Palm2.R",
        "Foot.L_end",
        "Foot.R_end",
        "Head_end",
        "Abdomen",
    ];
    let t = deeprep::mesh::Topology::new(&rig, 1e-5, 0.05, 2, 2, 12, &seeds).unwrap();
    let sizes: Vec<usize> = std::iter::once(t.rest.len())
        .chain(t.levels.iter().map(|l| l.selected.len()))
        .collect();
    eprintln!(
        "welded {} -> {} vertices, {} added edges, levels {sizes:?}",
        rig.vertex_count(),
        t.rest.len(),
        t.added_edges.len()
    );
    assert!(
        t.rest.len() < rig.vertex_count(),
        "welding merges split vertices"
    );
    assert!(t.graph.components().iter().all(|&c| c == 0));
    assert!(sizes.windows(2).all(|w| w[1] < w[0]));
    assert!(*sizes.last().unwrap() <= 12);
    for l in &t.levels {
        assert!(
            l.graph.components().iter().all(|&c| c == 0),
            "every level stays connected"
        );
    }
    let pose = rig.animation_pose(0, 0.5).unwrap();
    assert_eq!(t.weld_pose(&pose).unwrap().len(), t.rest.len());
    assert!(t.weld_pose(&pose[1..]).is_err());
    assert!(deeprep::mesh::Topology::new(&rig, 1e-5, 0.05, 2, 2, 12, &["Nope"]).is_err());
}

/// The bundled mesh autoencoder: tract matches onnxruntime on both graphs,
/// and the codec's round trip and local edits keep their contracts.
#[test]
fn mesh_codec_matches_onnxruntime() {
    let codec = deeprep::mesh::MeshCodec::load_dir(&common::root().join("models/onnx"))
        .expect("bundled mesh models");
    for name in ["mesh_encoder", "mesh_decoder"] {
        common::fixture_parity(name, 1e-4);
        // Multiplying the factored kernels out at load changes nothing but speed.
        let bytes = std::fs::read(common::root().join(format!("models/onnx/{name}.onnx"))).unwrap();
        let plain = deeprep::runtime::Model::from_onnx_bytes(&bytes).unwrap();
        let (folded, n) = deeprep::runtime::Model::from_onnx_bytes_folding_factors(&bytes).unwrap();
        assert_eq!(n, 4, "{name}: one kernel product per vcConv layer");
        let shape = if name == "mesh_encoder" {
            vec![2, codec.vertices(), 3]
        } else {
            vec![2, 8, 16]
        };
        let len: usize = shape.iter().product();
        let x = deeprep::runtime::TensorF32::new(
            (0..len)
                .map(|i| ((i * 37 % 101) as f32 / 101.0) - 0.5)
                .collect(),
            shape,
        )
        .unwrap();
        let (a, b) = (
            plain.run(std::slice::from_ref(&x)).unwrap(),
            folded.run(&[x]).unwrap(),
        );
        let diff = a[0]
            .data
            .iter()
            .zip(&b[0].data)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0f32, f32::max);
        assert!(diff < 1e-4, "{name}: folded kernels differ by {diff}");
    }
    let (l, c) = codec.latent_shape();
    let rest = vec![[0.0f32, 1.0, 0.0]; codec.vertices()];
    let z = codec.encode(&rest).unwrap();
    assert_eq!(z.len(), l * c);
    assert_eq!(codec.decode(&z).unwrap().len(), codec.vertices());
    let z2: Vec<f32> = z.iter().map(|v| v + 1.0).collect();
    let e = codec.blend_one(&z, &z2, 1, 0.5).unwrap();
    for (i, (a, b)) in z.iter().zip(&e).enumerate() {
        if i / c == 1 {
            assert!((b - a - 0.5).abs() < 1e-6)
        } else {
            assert_eq!(a, b)
        }
    }
    assert!(codec.encode(&rest[1..]).is_err());
    assert!(codec.decode(&z[1..]).is_err());
    assert!(codec.blend_one(&z, &z2, l, 0.5).is_err());
}

/// The bundled autoencoder on the robot: a held-out clip pose comes back
/// close, and Fig. 2.7's edit (one latent vertex's code moved towards
/// another pose) moves that latent vertex's region more than the rest.
#[test]
fn the_robot_reconstructs_and_one_latent_vertex_edits_locally() {
    let p = common::root().join("../shared/data/gltf/RobotExpressive.glb");
    let Ok(bytes) = std::fs::read(&p) else {
        eprintln!("SKIP: ../shared/data/gltf/RobotExpressive.glb is absent");
        return;
    };
    let rig = deeprep::mesh::Rig::from_glb(&bytes).unwrap();
    let topo = deeprep::mesh::Topology::robot(&rig).unwrap();
    let codec = deeprep::mesh::MeshCodec::load_dir(&common::root().join("models/onnx")).unwrap();
    assert_eq!(topo.rest.len(), codec.vertices());
    let latent = topo.latent_vertices();
    assert_eq!(latent.len(), codec.latent_shape().0);
    let kept: Vec<&str> = topo
        .seeds
        .iter()
        .filter(|(_, v)| latent.contains(v))
        .map(|(n, _)| n.as_str())
        .collect();
    eprintln!("latent vertices {latent:?}; seeds kept to the last level: {kept:?}");
    for name in ["Palm2.L", "Palm2.R", "Foot.L_end", "Foot.R_end", "Head_end"] {
        assert!(kept.contains(&name), "seed {name} is a latent vertex");
    }
    let regions = topo.latent_regions();
    assert!(regions.iter().all(|&r| r < latent.len()));
    for (k, &v) in latent.iter().enumerate() {
        assert_eq!(regions[v], k);
    }

    let clip = |name: &str| rig.animations.iter().position(|a| a.name == name).unwrap();
    // Wave and Punch are held out of training.
    let a = topo
        .weld_pose(&rig.animation_pose(clip("Wave"), 0.8).unwrap())
        .unwrap();
    let b = topo
        .weld_pose(&rig.animation_pose(clip("Punch"), 0.4).unwrap())
        .unwrap();
    let (za, zb) = (codec.encode(&a).unwrap(), codec.encode(&b).unwrap());
    let ra = codec.decode(&za).unwrap();
    let dist = |p: &[f32; 3], q: &[f32; 3]| {
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    };
    let err: f32 = a.iter().zip(&ra).map(|(p, q)| dist(p, q)).sum::<f32>() / a.len() as f32;
    eprintln!("held-out Wave pose: mean reconstruction error {err:.4} units");
    assert!(err < 0.3, "reconstruction error {err}");

    for (name, v) in topo
        .seeds
        .iter()
        .filter(|(n, _)| kept.contains(&n.as_str()))
    {
        let k = latent.iter().position(|x| x == v).unwrap();
        let e = codec
            .decode(&codec.blend_one(&za, &zb, k, 1.0).unwrap())
            .unwrap();
        let (mut inside, mut n_in, mut outside, mut n_out) = (0.0f32, 0, 0.0f32, 0);
        for (i, (p, q)) in ra.iter().zip(&e).enumerate() {
            if regions[i] == k {
                inside += dist(p, q);
                n_in += 1;
            } else {
                outside += dist(p, q);
                n_out += 1;
            }
        }
        let (mi, mo) = (inside / n_in as f32, outside / n_out as f32);
        eprintln!("edit of latent {k} ({name}): mean displacement {mi:.4} in its region ({n_in} vertices), {mo:.4} elsewhere");
        assert!(
            mi > 1.5 * mo,
            "the edit of {name}'s latent vertex is not local: {mi} in its region, {mo} elsewhere"
        );
    }
}

/// An OBJ of a `w × h` vertex grid of quads (z = 0), shifted by `dx`.
fn grid_obj(w: usize, h: usize, dx: f32, first: usize) -> String {
    let mut s = String::new();
    for y in 0..h {
        for x in 0..w {
            s += &format!("v {} {} 0\n", x as f32 + dx, y as f32);
        }
    }
    for y in 0..h - 1 {
        for x in 0..w - 1 {
            let v = |x: usize, y: usize| first + y * w + x + 1;
            s += &format!(
                "f {} {} {} {}\n",
                v(x, y),
                v(x + 1, y),
                v(x + 1, y + 1),
                v(x, y + 1)
            );
        }
    }
    s
}

#[test]
fn obj_files_read_strictly() {
    use deeprep::mesh::obj::parse;
    // a pentagon fan, corners with texture/normal indices, a negative index
    let m = parse("# a comment\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\nvn 0 0 1\nf 1/1/1 2//1 3 4 -1\n").unwrap();
    assert_eq!(m.positions.len(), 5);
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    for (bad, says) in [
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "index 0"),
        ("v 0 0 nan\n", "line 1"),
        ("v 0 0\n", "line 1"),
        ("v 0 0 0\nv 1 0 0\nf 1 2\n", "three corners"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
        ("f 1 2 3\n", "outside the 0 vertices"),
        ("", "no vertices"),
    ] {
        let e = parse(bad).unwrap_err().to_string();
        assert!(e.contains(says), "{bad:?}: {e}");
    }
}

#[test]
fn any_mesh_gets_a_topology() {
    use deeprep::mesh::{obj::parse, Params, Topology};
    let topo = |obj: &str| {
        let m = parse(obj).unwrap();
        Topology::of_mesh(&m.positions, &m.triangles)
    };
    let levels = |t: &Topology| -> Vec<usize> {
        std::iter::once(t.rest.len())
            .chain(t.levels.iter().map(|l| l.selected.len()))
            .collect()
    };
    // two separate sheets: joined by added edges into one graph, sampled down
    let two = format!(
        "{}{}",
        grid_obj(12, 12, 0.0, 0),
        grid_obj(12, 12, 11.5, 144)
    );
    let t = topo(&two).unwrap();
    assert_eq!(t.rest.len(), 288);
    assert!(!t.added_edges.is_empty());
    assert_eq!(
        t.graph.components().iter().max(),
        Some(&0),
        "one piece after joining"
    );
    assert!(*levels(&t).last().unwrap() <= 12, "{:?}", levels(&t));
    // non-manifold: three quads sharing one edge (Fig. 2.9's kind), plus an
    // isolated vertex and a degenerate triangle
    let fan = "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 1 0\nv 0 0 1\nv 0 1 1\nv 5 5 5\n\
               f 1 2 4 3\nf 1 2 6 5\nf 1 2 8 7\nf 3 3 4\n";
    let t = topo(fan).unwrap();
    assert_eq!(t.rest.len(), 9);
    let on_edge = t
        .triangles
        .iter()
        .filter(|t| t.contains(&0) && t.contains(&1))
        .count();
    assert_eq!(on_edge, 3, "one edge in three triangles (non-manifold)");
    assert!(t
        .triangles
        .iter()
        .all(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]));
    assert!(
        !t.graph.neighbors(8).is_empty(),
        "the isolated vertex is joined"
    );
    // a large mesh: 230 × 230 = 52,900 vertices
    let big = grid_obj(230, 230, 0.0, 0);
    let t0 = std::time::Instant::now();
    let t = topo(&big).unwrap();
    eprintln!(
        "52,900-vertex grid: levels {:?} in {:.2} s (debug build)",
        levels(&t),
        t0.elapsed().as_secs_f64()
    );
    assert_eq!(t.rest.len(), 52_900);
    assert!(*levels(&t).last().unwrap() <= 12, "{:?}", levels(&t));
    // bad meshes are errors
    assert!(Topology::from_mesh(&[], &[], &Params::for_mesh(&[]), &[]).is_err());
    assert!(Topology::from_mesh(
        &[[0.0; 3]; 3],
        &[[0, 1, 3]],
        &Params::for_mesh(&[[0.0; 3]; 3]),
        &[]
    )
    .is_err());
    assert!(Topology::from_mesh(
        &[[f32::NAN, 0.0, 0.0]; 3],
        &[[0, 1, 2]],
        &Params::for_mesh(&[[0.0; 3]; 3]),
        &[]
    )
    .is_err());
}

#[test]
fn the_cli_writes_the_topology_of_an_obj_file() {
    let dir = std::env::temp_dir().join(format!("deeprep-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let obj = dir.join("sheet.obj");
    std::fs::write(&obj, grid_obj(20, 20, 0.0, 0)).unwrap();
    let out = dir.join("sheet.json");
    let topology = || {
        std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
            .args([
                "mesh",
                "topology",
                obj.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap()
    };
    let r = topology();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(doc["rest"].as_array().unwrap().len(), 400);
    assert!(doc["levels"].as_array().unwrap().len() >= 3);
    std::fs::write(&obj, "v 0 0 0\nf 1 2 3\n").unwrap();
    let r = topology();
    assert!(!r.status.success());
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("line 2"),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn training_files_round_trip_and_reject_hostile_contents() {
    use deeprep::mesh::files::{PoseSet, TopologyFile};
    use deeprep::mesh::{obj::parse, Topology};
    let obj = format!("{}{}", grid_obj(9, 9, 0.0, 0), grid_obj(5, 5, 20.0, 81));
    let m = parse(&obj).unwrap();
    let t = Topology::of_mesh(&m.positions, &m.triangles).unwrap();
    let f = TopologyFile::from_topology(&t, "two.obj", m.positions.len());
    let text = f.to_json().unwrap();
    let back = TopologyFile::parse(&text).unwrap();
    assert_eq!(back, f);
    assert_eq!(back.to_json().unwrap(), text, "written again byte for byte");
    assert_eq!(back.sizes()[0], t.rest.len());
    assert!(!back.added_edges.is_empty(), "two sheets are joined");
    // hostile edits: each an error naming what is wrong
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let edit = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut w = v.clone();
        f(&mut w);
        TopologyFile::parse(&w.to_string()).unwrap_err().to_string()
    };
    let n = t.rest.len();
    for (e, says) in [
        (edit(&|w| w["weld_map"][0] = n.into()), "weld_map[0]"),
        (
            edit(&|w| w["triangles"][0][1] = 1_000_000.into()),
            "triangle",
        ),
        (
            edit(&|w| w["edges"][0] = serde_json::json!([0, 0])),
            "edges",
        ),
        (
            edit(&|w| w["levels"][0]["down"]["indices"][0] = n.into()),
            "levels[0].down",
        ),
        (
            edit(&|w| w["levels"][1]["up"]["rows"] = 3.into()),
            "levels[1].up",
        ),
        (
            edit(&|w| w["levels"][0]["up"]["mask"][0] = 2.into()),
            "mask value",
        ),
        (
            edit(&|w| w["levels"][0]["selected"][0] = n.into()),
            "levels[0].selected",
        ),
        (
            edit(&|w| w["rig_vertices"] = 1_000_000_000_000u64.into()),
            "weld_map has",
        ),
        (
            edit(&|w| w["rest"] = serde_json::json!("x")),
            "not a topology file",
        ),
    ] {
        assert!(e.contains(says), "expected '{says}' in: {e}");
    }
    assert!(TopologyFile::parse("[]").is_err());

    // pose sets: two poses, written and read back exactly
    let mut set = PoseSet::new(3);
    let pose = [[0.5f32, 1.0, -2.0], [3.0, 4.0, 5.0], [1e-7, -0.0, 7.25]];
    set.push(&pose, serde_json::json!({"clip": "a", "time": 0.0}))
        .unwrap();
    set.push(
        &pose.map(|p| p.map(|x| x * 2.0)),
        serde_json::json!({"clip": "random", "index": 0}),
    )
    .unwrap();
    set.extra.insert("fps".into(), 30.0f32.into());
    assert!(set.push(&pose[..2], serde_json::Value::Null).is_err());
    let back = PoseSet::read(&set.data_bytes(), &set.meta_json()).unwrap();
    assert_eq!(back, set);
    assert_eq!(back.meta_json(), set.meta_json());
    let bytes = set.data_bytes();
    for (data, meta, says) in [
        (&bytes[..bytes.len() - 4], set.meta_json(), "data bytes"),
        (
            &bytes[..],
            set.meta_json().replace("\"poses\":2", "\"poses\":3"),
            "3 labels",
        ),
        (
            &bytes[..],
            set.meta_json()
                .replace("\"vertices\":3", "\"vertices\":4611686018427387904"),
            "data bytes",
        ),
        (&bytes[..], "{\"poses\":2}".to_string(), "'vertices'"),
        (&bytes[..], "[1]".to_string(), "not a JSON object"),
    ] {
        let e = PoseSet::read(data, &meta).unwrap_err().to_string();
        assert!(e.contains(says), "expected '{says}' in: {e}");
    }
    let mut nan = bytes.clone();
    nan[12..16].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = PoseSet::read(&nan, &set.meta_json())
        .unwrap_err()
        .to_string();
    assert!(e.contains("pose 0"), "{e}");
}

#[test]
fn generated_shapes_have_the_structure_their_experiments_need() {
    use deeprep::mesh::shapes::*;
    use deeprep::mesh::Topology;
    let edge_faces = |tris: &[[usize; 3]]| {
        let mut m: std::collections::HashMap<(usize, usize), usize> = Default::default();
        for t in tris {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *m.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        m
    };
    // a tetrahedral block: (n+1)^3 grid vertices, the inner ones interior,
    // found again from the faces alone
    let tet = tet_block(3, 4, 2).unwrap();
    assert_eq!(tet.positions.len(), 4 * 5 * 3);
    assert_eq!(tet.interior.len(), 2 * 3);
    assert_eq!(tet.triangles.len(), 3 * 4 * 2 * 6 * 4);
    assert_eq!(
        interior_vertices(tet.positions.len(), &tet.triangles),
        tet.interior
    );
    let t = Topology::of_mesh(&tet.positions, &tet.triangles).unwrap();
    assert_eq!(t.rest.len(), tet.positions.len(), "nothing welded");
    assert!(t.added_edges.is_empty(), "one connected solid");
    // crossing planes: the axis edges belong to 2 x planes triangles (non-manifold)
    let tree = crossing_planes(3, 4, 5).unwrap();
    assert_eq!(tree.positions.len(), 6 + 3 * 4 * 6);
    assert!(interior_vertices(tree.positions.len(), &tree.triangles).is_empty());
    let most = edge_faces(&tree.triangles).into_values().max().unwrap();
    assert_eq!(most, 6, "an axis edge in six triangles");
    let t = Topology::of_mesh(&tree.positions, &tree.triangles).unwrap();
    assert!(t.levels.len() >= 2);
    // subdivision: V + E vertices, 4 F triangles; poses follow by midpoints
    let (p, tr, parents) = subdivide(&tet.positions, &tet.triangles[..8]).unwrap();
    let edges = edge_faces(&tet.triangles[..8]).len();
    assert_eq!(p.len(), tet.positions.len() + edges);
    assert_eq!(tr.len(), 32);
    let moved: Vec<[f32; 3]> = tet
        .positions
        .iter()
        .map(|q| [q[0] + 1.0, 2.0 * q[1], q[2]])
        .collect();
    let sub = subdivide_pose(&moved, &parents).unwrap();
    let [a, b] = parents[0];
    let mid = sub[tet.positions.len()];
    assert!((0..3).all(|c| (mid[c] - (moved[a][c] + moved[b][c]) / 2.0).abs() < 1e-6));
    assert!(subdivide_pose(&moved[..3], &parents).is_err());
    // deformations: repeatable per seed, finite, smooth (neighbours move alike)
    let mut r1 = deeprep::rng::Rng::new(5);
    let mut r2 = deeprep::rng::Rng::new(5);
    let d = deform(&tet.positions, &mut r1);
    assert_eq!(d, deform(&tet.positions, &mut r2));
    assert!(d.iter().flatten().all(|v| v.is_finite()));
    assert!(d
        .iter()
        .zip(&tet.positions)
        .any(|(a, b)| (a[0] - b[0]).abs() > 1e-3));
    for &[a, b] in parents.iter().take(20) {
        let before: f32 = (0..3)
            .map(|c| (tet.positions[a][c] - tet.positions[b][c]).powi(2))
            .sum::<f32>()
            .sqrt();
        let after: f32 = (0..3)
            .map(|c| (d[a][c] - d[b][c]).powi(2))
            .sum::<f32>()
            .sqrt();
        assert!(
            after < 3.0 * before + 1e-4,
            "an edge stretched from {before} to {after}"
        );
    }
    // OBJ text reads back to the same mesh
    let back = deeprep::mesh::obj::parse(&to_obj(&tree.positions, &tree.triangles)).unwrap();
    assert_eq!(back.positions, tree.positions);
    assert_eq!(back.triangles, tree.triangles);
    // bad sizes are errors
    assert!(tet_block(0, 1, 1).is_err() && tet_block(1, 1, 65).is_err());
    assert!(crossing_planes(1, 4, 4).is_err() && crossing_planes(3, 3, 4).is_err());
    assert!(subdivide(&tet.positions[..2], &tet.triangles).is_err());
}

#[test]
fn the_cli_makes_shapes_and_deformations_for_training() {
    let dir = std::env::temp_dir().join(format!("deeprep-shapes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = |f: &str| dir.join(f).to_str().unwrap().to_string();
    let run = |args: &[&str]| {
        let r = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
            .args(args)
            .output()
            .unwrap();
        (
            r.status.success(),
            String::from_utf8_lossy(&r.stderr).to_string(),
        )
    };
    let (ok, err) = run(&[
        "mesh",
        "shape",
        "tet",
        "--out",
        &p("tet.obj"),
        "--size",
        "2",
    ]);
    assert!(ok, "{err}");
    let (ok, err) = run(&[
        "mesh",
        "deform",
        &p("tet.obj"),
        "--out",
        &p("d"),
        "--count",
        "3",
        "--seed",
        "4",
    ]);
    assert!(ok, "{err}");
    let set = deeprep::mesh::files::PoseSet::read(
        &std::fs::read(p("d.f32")).unwrap(),
        &std::fs::read_to_string(p("d.json")).unwrap(),
    )
    .unwrap();
    assert_eq!((set.len(), set.vertices), (3, 3 * 5 * 3));
    assert_eq!(
        set.extra["interior"].as_array().unwrap().len(),
        3,
        "1 x 3 x 1 inner grid vertices"
    );
    // a user's own poses of the template (an OBJ sequence) packed as a pose set
    let tet = std::fs::read_to_string(p("tet.obj")).unwrap();
    let moved = |dx: f32| {
        tet.lines()
            .map(|l| match l.strip_prefix("v ") {
                Some(v) => {
                    let c: Vec<f32> = v.split_whitespace().map(|x| x.parse().unwrap()).collect();
                    format!("v {} {} {}", c[0] + dx, c[1], c[2])
                }
                None => l.to_string(),
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    std::fs::write(p("a.obj"), moved(0.5)).unwrap();
    std::fs::write(p("b.obj"), moved(-0.25)).unwrap();
    let (ok, err) = run(&[
        "mesh",
        "pack",
        &p("tet.obj"),
        &p("a.obj"),
        &p("b.obj"),
        "--out",
        &p("mine"),
    ]);
    assert!(ok, "{err}");
    let mine = deeprep::mesh::files::PoseSet::read(
        &std::fs::read(p("mine.f32")).unwrap(),
        &std::fs::read_to_string(p("mine.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(mine.len(), 2);
    let rest = deeprep::mesh::Template::from_obj(&tet)
        .unwrap()
        .topology
        .rest;
    assert!(
        (mine.data[0] - (rest[0][0] + 0.5)).abs() < 1e-6
            && (mine.data[3 * rest.len()] - (rest[0][0] - 0.25)).abs() < 1e-6
    );
    std::fs::write(p("c.obj"), tet.replace("f 1 ", "f 2 ")).unwrap();
    let (ok, err) = run(&[
        "mesh",
        "pack",
        &p("tet.obj"),
        &p("c.obj"),
        "--out",
        &p("bad"),
    ]);
    assert!(!ok && err.contains("faces"), "{err}");
    let (ok, err) = run(&["mesh", "shape", "cube", "--out", &p("x.obj")]);
    assert!(!ok && err.contains("mesh shape"), "{err}");
    let (ok, err) = run(&[
        "mesh",
        "deform",
        &p("tet.obj"),
        "--out",
        &p("d"),
        "--count",
        "0",
    ]);
    assert!(!ok && err.contains("--count"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_model_trained_on_another_template_runs_on_it_and_only_on_it() {
    use deeprep::mesh::{MeshCodec, Template};
    // tests/fixtures/mesh_tet: `deeprep mesh shape tet --size 3` and a small
    // autoencoder trained 2 minutes on its deformations (mesh/train.py,
    // mesh/export.py --out)
    let dir = common::root().join("tests/fixtures/mesh_tet");
    let obj = std::fs::read_to_string(dir.join("tet.obj")).unwrap();
    let tet = Template::from_obj(&obj).unwrap();
    assert!(tet.rig.is_none());
    let codec = MeshCodec::load_dir(&dir).unwrap();
    tet.check_model(codec.vertices(), codec.levels(), codec.trained_on())
        .unwrap();
    // a deformation like the training set's reconstructs to a few % of the size
    let pose = tet.random_pose(9, 30.0).unwrap();
    let rec = codec.decode(&codec.encode(&pose).unwrap()).unwrap();
    let err = pose
        .iter()
        .zip(&rec)
        .map(|(a, b)| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f32>().sqrt())
        .sum::<f32>()
        / pose.len() as f32;
    assert!(
        err < 0.1,
        "mean reconstruction error {err} (the block is 1 unit tall)"
    );
    assert!(tet.clip_pose(0, 0.0).is_err(), "no clips without a rig");
    // the bundled robot model on the tet, and the tet model on a grid: errors naming both
    let robot = MeshCodec::load_dir(&common::root().join("models/onnx")).unwrap();
    let e = tet
        .check_model(robot.vertices(), robot.levels(), robot.trained_on())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("112 vertices") && e.contains("RobotExpressive.glb"),
        "{e}"
    );
    let grid = Template::from_obj(&grid_obj(6, 6, 0.0, 0)).unwrap();
    let e = grid
        .check_model(codec.vertices(), codec.levels(), codec.trained_on())
        .unwrap_err()
        .to_string();
    assert!(e.contains("36 vertices") && e.contains("tet.obj"), "{e}");
}

/// Issue 49: the mesh template's numeric arguments (what `MeshLab`'s
/// `clipPose` and `randomPose` pass) follow `error::check_option`'s rule.
#[test]
fn mesh_template_numbers_are_checked() {
    let mut s = String::new();
    for y in 0..4 {
        for x in 0..4 {
            s += &format!("v {x} {y} 0\n");
        }
    }
    for y in 0..3 {
        for x in 0..3 {
            let a = y * 4 + x + 1;
            s += &format!(
                "f {a} {} {}\nf {} {} {}\n",
                a + 1,
                a + 4,
                a + 1,
                a + 5,
                a + 4
            );
        }
    }
    let t = deeprep::mesh::Template::from_obj(&s).unwrap();
    for v in [f32::NAN, f32::INFINITY, -1.0, 1e30] {
        let e = t.random_pose(1, v).unwrap_err().to_string();
        assert!(
            e.contains("max degrees must be a number in [0, 180]"),
            "{v}: {e}"
        );
        let e = t.clip_pose(0, v).unwrap_err().to_string();
        assert!(
            e.contains("time (seconds) must be a number in [0, 86400]"),
            "{v}: {e}"
        );
    }
    assert_eq!(t.random_pose(1, 30.0).unwrap().len(), 16);
}

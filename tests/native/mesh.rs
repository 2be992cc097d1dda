#![allow(clippy::needless_range_loop)]
//! Topology-only graph sampling (Sec. 2.2.1, App. A.1.2): small graphs
//! whose answers are worked out by hand, a non-manifold mesh, and the
//! sampler's invariants on random graphs.

use deeprep::mesh::{sample, Graph};
use deeprep::rng::Rng;

use crate::common;

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

mod files;

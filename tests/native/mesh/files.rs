//! OBJ files, any mesh's topology, the CLI, training files, generated shapes and other templates.

use super::*;

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

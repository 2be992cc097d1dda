//! `deeprep mesh topology` and `deeprep mesh poses`: the mesh autoencoder's
//! topology tables (any OBJ or glTF mesh) and training poses from a rigged glTF.

use super::args::CliError;
use super::USAGE;

/// The most random poses `mesh poses` writes (per clip: `mesh::rig::MAX_CLIP_SAMPLES`).
const MAX_CLIP_POSES: usize = 100_000;

/// `deeprep mesh topology MESH.obj|MESH.glb --out TOPOLOGY.json`.
pub fn topology(rest: &[&str]) -> Result<(), CliError> {
    match rest {
        [file, "--out", out] => Ok(mesh_topology(file, out)?),
        _ => Err(CliError::Usage),
    }
}

/// `deeprep mesh poses RIGGED.glb --out PREFIX [...]`.
pub fn poses(rest: &[&str]) -> Result<(), CliError> {
    match rest {
        [file, options @ ..] => Ok(mesh_poses(file, options)?),
        _ => Err(CliError::Usage),
    }
}

/// `deeprep mesh shape tet|tree --out MESH.obj [--size N]`.
pub fn shape(rest: &[&str]) -> Result<(), CliError> {
    use deeprep::mesh::shapes;
    let [kind, options @ ..] = rest else {
        return Err(CliError::Usage);
    };
    let o = super::args::options(options, &["out", "size"])?;
    let out = o.get("out").ok_or(CliError::Usage)?;
    let size: usize = super::args::parse_opt(&o, "size", 6)?;
    let s = match *kind {
        "tet" => shapes::tet_block(size, 2 * size, size),
        "tree" => shapes::crossing_planes(3, 2 * size.div_ceil(2), 4 * size),
        _ => return Err(CliError::Usage),
    }
    .map_err(|e| e.to_string())?;
    std::fs::write(out, shapes::to_obj(&s.positions, &s.triangles))
        .map_err(|e| format!("{out}: {e}"))?;
    eprintln!(
        "wrote {out}: {} vertices ({} interior), {} triangles",
        s.positions.len(),
        s.interior.len(),
        s.triangles.len()
    );
    Ok(())
}

/// `deeprep mesh deform MESH.obj --out PREFIX [--count N] [--seed S]`.
pub fn deform(rest: &[&str]) -> Result<(), CliError> {
    use deeprep::mesh::{files::PoseSet, shapes};
    let [file, options @ ..] = rest else {
        return Err(CliError::Usage);
    };
    let o = super::args::options(options, &["out", "count", "seed"])?;
    let out = o.get("out").ok_or(CliError::Usage)?;
    let count: usize = super::args::parse_opt(&o, "count", 100)?;
    let seed: u64 = super::args::parse_opt(&o, "seed", 1)?;
    if count == 0 || count > MAX_CLIP_POSES {
        return Err(format!("--count must be 1..={MAX_CLIP_POSES}, got {count}").into());
    }
    let (_, t) = any_topology(file)?;
    PoseSet::check_size(count, t.rest.len()).map_err(|e| format!("--count {count}: {e}"))?;
    let mut set = PoseSet::new(t.rest.len());
    let mut rng = deeprep::rng::Rng::new(seed);
    for i in 0..count {
        set.push(
            &shapes::deform(&t.rest, &mut rng),
            serde_json::json!({"clip": "deform", "index": i}),
        )
        .map_err(|e| e.to_string())?;
    }
    let interior = shapes::interior_vertices(t.rest.len(), &t.triangles);
    set.extra.insert("source".into(), (*file).into());
    set.extra.insert("seed".into(), seed.into());
    if !interior.is_empty() {
        set.extra.insert("interior".into(), interior.clone().into());
    }
    write_set(&set, out)?;
    eprintln!(
        "wrote {out}.f32 and {out}.json: {count} deformations x {} vertices ({} interior)",
        t.rest.len(),
        interior.len()
    );
    Ok(())
}

/// `deeprep mesh pack TEMPLATE.obj POSE.obj... --out PREFIX`: a user's own
/// posed meshes (an OBJ sequence with the template's vertices in the
/// template's order) as a pose set, welded as the template is.
pub fn pack(rest: &[&str]) -> Result<(), CliError> {
    use deeprep::mesh::files::PoseSet;
    let Some(at) = rest.iter().position(|a| *a == "--out") else {
        return Err(CliError::Usage);
    };
    let (files, out) = (&rest[..at], rest.get(at + 1).ok_or(CliError::Usage)?);
    if files.len() < 2 || rest.len() != at + 2 {
        return Err(CliError::Usage);
    }
    let read = |p: &str| -> Result<deeprep::mesh::obj::TriMesh, String> {
        let text = std::fs::read_to_string(p).map_err(|e| format!("{p}: {e}"))?;
        deeprep::mesh::obj::parse(&text).map_err(|e| format!("{p}: {e}"))
    };
    let template = files[0];
    let t = deeprep::mesh::Template::from_obj(
        &std::fs::read_to_string(template).map_err(|e| format!("{template}: {e}"))?,
    )
    .map_err(|e| format!("{template}: {e}"))?;
    let faces = read(template)?.triangles;
    PoseSet::check_size(files.len() - 1, t.topology.rest.len()).map_err(|e| e.to_string())?;
    // welded template vertices must stay together in every pose: within the
    // template's own weld distance (Params::for_mesh, 1e-6 of its diagonal),
    // widened to 1e-4 for rounding in the user's exporter
    let tol = 100.0 * deeprep::mesh::Params::for_mesh(&t.topology.rest).eps;
    let mut set = PoseSet::new(t.topology.rest.len());
    for (i, p) in files[1..].iter().enumerate() {
        let m = read(p)?;
        if m.triangles != faces {
            return Err(format!("{p}: its faces are not {template}'s (a pose must keep the template's vertices and faces)").into());
        }
        let welded = t
            .topology
            .weld_pose_strict(&m.positions, tol)
            .map_err(|e| format!("{p}: {e}"))?;
        set.push(
            &welded,
            serde_json::json!({"clip": "pose", "index": i, "file": p}),
        )
        .map_err(|e| format!("{p}: {e}"))?;
    }
    set.extra.insert("source".into(), template.into());
    write_set(&set, out)?;
    eprintln!(
        "wrote {out}.f32 and {out}.json: {} poses x {} vertices",
        set.len(),
        set.vertices
    );
    Ok(())
}

fn write_set(set: &deeprep::mesh::files::PoseSet, out: &str) -> Result<(), String> {
    let path = format!("{out}.f32");
    std::fs::File::create(&path)
        .and_then(|f| set.write_data(&mut std::io::BufWriter::new(f)))
        .map_err(|e| format!("{path}: {e}"))?;
    std::fs::write(format!("{out}.json"), set.meta_json()).map_err(|e| format!("{out}.json: {e}"))
}

/// A rigged glTF's rig and welded topology (`mesh::Template`: the robot's
/// own settings and seeds for the robot, `Params::for_mesh` otherwise).
fn rigged(path: &str) -> Result<(deeprep::mesh::Rig, deeprep::mesh::Topology), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    let t = deeprep::mesh::Template::from_glb(&bytes).map_err(|e| format!("{path}: {e}"))?;
    let rig = t.rig.ok_or_else(|| {
        format!("{path}: no animation clips to pose (deeprep mesh deform makes poses of any mesh)")
    })?;
    Ok((rig, t.topology))
}

/// The topology of any mesh file (`mesh::Template`: an OBJ, or a glTF with
/// the robot's own settings and latent seeds when it has the robot's
/// nodes). Returns the file's vertex count too.
fn any_topology(path: &str) -> Result<(usize, deeprep::mesh::Topology), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    let at = |e: deeprep::Error| format!("{path}: {e}");
    let t = if path.to_ascii_lowercase().ends_with(".obj") {
        let text = String::from_utf8(bytes).map_err(|e| format!("{path}: {e}"))?;
        deeprep::mesh::Template::from_obj(&text).map_err(at)?
    } else {
        deeprep::mesh::Template::from_glb(&bytes).map_err(at)?
    };
    Ok((t.source_vertices, t.topology))
}

fn mesh_topology(path: &str, out: &str) -> Result<(), String> {
    let (vertices, t) = any_topology(path)?;
    let doc = deeprep::mesh::files::TopologyFile::from_topology(&t, path, vertices)
        .to_json()
        .map_err(|e| e.to_string())?;
    std::fs::write(out, doc).map_err(|e| format!("{out}: {e}"))?;
    let sizes: Vec<usize> = std::iter::once(t.rest.len())
        .chain(t.levels.iter().map(|l| l.selected.len()))
        .collect();
    eprintln!(
        "wrote {out}: {} rig vertices welded to {}, {} edges added, levels {sizes:?}",
        vertices,
        t.rest.len(),
        t.added_edges.len()
    );
    Ok(())
}

fn mesh_poses(path: &str, rest: &[&str]) -> Result<(), String> {
    let (mut out, mut fps, mut random, mut seed, mut subdiv) =
        (None, 30.0f32, 0usize, 1u64, 0usize);
    let mut i = 0;
    while i < rest.len() {
        let val = &super::args::value_of(rest, i)?;
        match rest[i] {
            "--out" => out = Some(val.to_string()),
            "--fps" => {
                fps = val
                    .parse()
                    .map_err(|_| format!("--fps must be a number in [1, 240], found '{val}'"))?
            }
            "--random" => {
                random = val
                    .parse()
                    .map_err(|_| format!("--random expects a count, got '{val}'"))?
            }
            "--seed" => {
                seed = val
                    .parse()
                    .map_err(|_| format!("--seed expects an integer, got '{val}'"))?
            }
            "--subdivide" => {
                subdiv = val
                    .parse()
                    .ok()
                    .filter(|k| *k <= 3)
                    .ok_or_else(|| format!("--subdivide expects 0 to 3, got '{val}'"))?
            }
            a => return Err(format!("unknown option '{a}'\n{USAGE}")),
        }
        i += 2;
    }
    let out = out.ok_or_else(|| format!("--out PREFIX is required\n{USAGE}"))?;
    // the one rule of numeric options (error::check_option)
    deeprep::error::check_option("--fps", fps as f64, 1.0, 240.0).map_err(|e| e.to_string())?;
    if random > MAX_CLIP_POSES {
        return Err(format!(
            "--random is at most {MAX_CLIP_POSES}, got {random}"
        ));
    }
    let (rig, t) = rigged(path)?;
    // --subdivide K: the welded mesh subdivided K times (midpoints), each
    // pose with it; the subdivided rest mesh is written as PREFIX.obj
    let (mut positions, mut triangles, mut steps) =
        (t.rest.clone(), t.triangles.clone(), Vec::new());
    // every pose the set will hold, counted before any is made
    let mut poses = random;
    for k in 0..rig.animations.len() {
        poses += rig.clip_sample_count(k, fps).map_err(|e| e.to_string())?;
    }
    for _ in 0..subdiv {
        let (p, tr, parents) =
            deeprep::mesh::shapes::subdivide(&positions, &triangles).map_err(|e| e.to_string())?;
        (positions, triangles) = (p, tr);
        steps.push(parents);
    }
    deeprep::mesh::files::PoseSet::check_size(poses, positions.len()).map_err(|e| {
        format!("--fps {fps}, --random {random} and --subdivide {subdiv} give {poses} poses: {e}")
    })?;
    if subdiv > 0 {
        // the OBJ's own topology must keep this vertex order (no two vertices welded)
        let check = deeprep::mesh::Topology::of_mesh(&positions, &triangles).map_err(|e| {
            format!(
                "--subdivide {subdiv}: the subdivided mesh ({} vertices) has no topology for the autoencoder ({e}); use a smaller --subdivide",
                positions.len()
            )
        })?;
        if check.weld_map.iter().enumerate().any(|(i, &w)| i != w) {
            return Err("--subdivide: the subdivided mesh welds some vertices together".into());
        }
        let obj = format!("{out}.obj");
        std::fs::write(&obj, deeprep::mesh::shapes::to_obj(&positions, &triangles))
            .map_err(|e| format!("{obj}: {e}"))?;
    }
    let mut set = deeprep::mesh::files::PoseSet::new(positions.len());
    let mut push = |pose: Vec<[f32; 3]>, label: serde_json::Value| -> Result<(), String> {
        let mut welded = t.weld_pose(&pose).map_err(|e| e.to_string())?;
        for parents in &steps {
            welded = deeprep::mesh::shapes::subdivide_pose(&welded, parents)
                .map_err(|e| e.to_string())?;
        }
        set.push(&welded, label).map_err(|e| e.to_string())
    };
    for (k, a) in rig.animations.iter().enumerate() {
        let frames = rig.clip_sample_count(k, fps).map_err(|e| e.to_string())?;
        for f in 0..frames {
            let pose = rig
                .animation_pose(k, f as f32 / fps)
                .map_err(|e| e.to_string())?;
            push(
                pose,
                serde_json::json!({"clip": a.name, "time": f as f32 / fps}),
            )?;
        }
    }
    let mut rng = deeprep::rng::Rng::new(seed);
    for r in 0..random {
        let (local, k, time) = rig
            .jittered_locals(&mut rng, 30f32.to_radians())
            .map_err(|e| e.to_string())?;
        let pose = rig.pose(&local).map_err(|e| e.to_string())?;
        push(
            pose,
            serde_json::json!({"clip": "random", "index": r, "from": rig.animations[k].name, "time": time}),
        )?;
    }
    set.extra.insert("source".into(), path.into());
    set.extra.insert("fps".into(), fps.into());
    set.extra.insert("seed".into(), seed.into());
    if subdiv > 0 {
        set.extra.insert("subdivide".into(), subdiv.into());
    }
    write_set(&set, &out)?;
    eprintln!(
        "wrote {out}.f32 and {out}.json: {} poses x {} vertices",
        set.len(),
        set.vertices
    );
    Ok(())
}

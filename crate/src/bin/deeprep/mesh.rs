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

/// `deeprep mesh poses ROBOT.glb --out PREFIX [...]`.
pub fn poses(rest: &[&str]) -> Result<(), CliError> {
    match rest {
        [file, options @ ..] => Ok(mesh_poses(file, options)?),
        _ => Err(CliError::Usage),
    }
}

fn robot(path: &str) -> Result<(deeprep::mesh::Rig, deeprep::mesh::Topology), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    let rig = deeprep::mesh::Rig::from_glb(&bytes).map_err(|e| format!("{path}: {e}"))?;
    let topo = deeprep::mesh::Topology::robot(&rig).map_err(|e| format!("{path}: {e}"))?;
    Ok((rig, topo))
}

/// The topology of any mesh file: an OBJ, or a glTF (the bundled robot's
/// own settings and latent seeds when it has the robot's nodes, otherwise
/// `Params::for_mesh` with no seeds). Returns the file's vertex count too.
fn any_topology(path: &str) -> Result<(usize, deeprep::mesh::Topology), String> {
    use deeprep::mesh::{Params, Topology, ROBOT_SEED_NODES};
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    let at = |e: deeprep::Error| format!("{path}: {e}");
    let (positions, triangles) = if path.to_ascii_lowercase().ends_with(".obj") {
        let text = String::from_utf8(bytes).map_err(|e| format!("{path}: {e}"))?;
        let m = deeprep::mesh::obj::parse(&text).map_err(at)?;
        (m.positions, m.triangles)
    } else {
        let rig = deeprep::mesh::Rig::from_glb(&bytes).map_err(at)?;
        if ROBOT_SEED_NODES
            .iter()
            .all(|n| rig.node_names.iter().any(|m| m == n))
        {
            return Ok((rig.vertex_count(), Topology::robot(&rig).map_err(at)?));
        }
        let tris = rig
            .triangles
            .iter()
            .map(|t| t.map(|i| i as usize))
            .collect();
        (rig.rest_pose().map_err(at)?, tris)
    };
    let t = Topology::from_mesh(&positions, &triangles, &Params::for_mesh(&positions), &[])
        .map_err(at)?;
    Ok((positions.len(), t))
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
    let (mut out, mut fps, mut random, mut seed) = (None, 30.0f32, 0usize, 1u64);
    let mut i = 0;
    while i < rest.len() {
        let val = rest
            .get(i + 1)
            .ok_or_else(|| format!("{} needs a value", rest[i]))?;
        match rest[i] {
            "--out" => out = Some(val.to_string()),
            "--fps" => {
                fps = val
                    .parse()
                    .map_err(|_| format!("--fps expects a number, got '{val}'"))?
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
            a => return Err(format!("unknown option '{a}'\n{USAGE}")),
        }
        i += 2;
    }
    let out = out.ok_or_else(|| format!("--out PREFIX is required\n{USAGE}"))?;
    if !(fps > 0.0 && fps <= 240.0) {
        return Err(format!("--fps must be in (0, 240], got {fps}"));
    }
    if random > MAX_CLIP_POSES {
        return Err(format!(
            "--random is at most {MAX_CLIP_POSES}, got {random}"
        ));
    }
    let (rig, t) = robot(path)?;
    let mut set = deeprep::mesh::files::PoseSet::new(t.rest.len());
    let mut push = |pose: Vec<[f32; 3]>, label: serde_json::Value| -> Result<(), String> {
        let welded = t.weld_pose(&pose).map_err(|e| e.to_string())?;
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
    std::fs::write(format!("{out}.f32"), set.data_bytes())
        .map_err(|e| format!("{out}.f32: {e}"))?;
    std::fs::write(format!("{out}.json"), set.meta_json())
        .map_err(|e| format!("{out}.json: {e}"))?;
    let labels = &set.labels;
    eprintln!(
        "wrote {out}.f32 and {out}.json: {} poses x {} vertices",
        labels.len(),
        t.rest.len()
    );
    Ok(())
}

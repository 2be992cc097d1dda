//! Mesh autoencoder in tract: load + plan time and encode/decode time per
//! mesh for each exported op form (JSON on stdout). The committed model
//! (`models/onnx/mesh_{encoder,decoder}.onnx`, form "factored") always runs;
//! `MESH_FORMS_DIR` may hold `mesh_{encoder,decoder}_{factored,matmul,einsum}.onnx`
//! from `train/deeprep_train/mesh/export.py --form F --suffix _F` for the comparison.
//! The committed graphs run twice: as exported, and with their factored
//! kernels multiplied out at load (`Model::from_onnx_bytes_folding_factors`,
//! what `MeshCodec` does). `DEEPREP_BENCH_SMOKE=1` runs each graph once.

use deeprep::runtime::{Model, TensorF32};
use std::time::Instant;

fn time(
    path: &std::path::Path,
    shape: Vec<usize>,
    reps: usize,
    fold: bool,
) -> Option<serde_json::Value> {
    let bytes = std::fs::read(path).ok()?;
    let t0 = Instant::now();
    let (m, folded) = if fold {
        Model::from_onnx_bytes_folding_factors(&bytes).expect("model loads")
    } else {
        (Model::from_onnx_bytes(&bytes).expect("model loads"), 0)
    };
    let n: usize = shape.iter().product();
    let x = TensorF32::new(
        (0..n).map(|i| ((i % 97) as f32 / 97.0) - 0.5).collect(),
        shape,
    )
    .unwrap();
    m.run(std::slice::from_ref(&x)).expect("first run");
    let load_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t1 = Instant::now();
    for _ in 0..reps {
        m.run(std::slice::from_ref(&x)).unwrap();
    }
    Some(serde_json::json!({
        "file": path.file_name()?.to_str()?,
        "bytes": bytes.len(),
        "factors_folded_at_load": folded,
        "load_and_first_run_ms": load_ms,
        "run_ms": t1.elapsed().as_secs_f64() * 1e3 / reps as f64,
    }))
}

fn main() {
    let smoke = std::env::var("DEEPREP_BENCH_SMOKE").is_ok();
    let reps = if smoke { 1 } else { 20 };
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join("models/onnx/mesh_autoencoder.manifest.json"))
            .expect("models/onnx/mesh_autoencoder.manifest.json"),
    )
    .unwrap();
    let v = manifest["levels"][0].as_u64().unwrap() as usize;
    let latent: Vec<usize> = manifest["inputs"]["decoder"]
        .as_array()
        .unwrap()
        .iter()
        .skip(1)
        .map(|x| x.as_u64().unwrap() as usize)
        .collect();
    let mut rows = Vec::new();
    let onnx = root.join("models/onnx");
    for fold in [false, true] {
        rows.push(time(
            &onnx.join("mesh_encoder.onnx"),
            vec![1, v, 3],
            reps,
            fold,
        ));
        rows.push(time(
            &onnx.join("mesh_decoder.onnx"),
            [vec![1], latent.clone()].concat(),
            reps,
            fold,
        ));
    }
    if let Ok(dir) = std::env::var("MESH_FORMS_DIR") {
        let dir = std::path::PathBuf::from(dir);
        for form in ["factored", "matmul", "einsum"] {
            rows.push(time(
                &dir.join(format!("mesh_encoder_{form}.onnx")),
                vec![1, v, 3],
                reps,
                false,
            ));
            rows.push(time(
                &dir.join(format!("mesh_decoder_{form}.onnx")),
                [vec![1], latent.clone()].concat(),
                reps,
                false,
            ));
        }
    }
    let rows: Vec<_> = rows.into_iter().flatten().collect();
    // Graph sampling of a mesh of any topology (issue 25): a 230 × 230 grid
    // of quads (52,900 vertices), welded, joined and sampled down to at
    // most 12 vertices, as `deeprep mesh topology` does for an OBJ file.
    let n = if smoke { 40 } else { 230 };
    let positions: Vec<[f32; 3]> = (0..n * n)
        .map(|i| [(i % n) as f32, (i / n) as f32, 0.0])
        .collect();
    let mut triangles = Vec::new();
    for y in 0..n - 1 {
        for x in 0..n - 1 {
            let v = |x: usize, y: usize| y * n + x;
            triangles.push([v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
            triangles.push([v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
        }
    }
    let t0 = std::time::Instant::now();
    let params = deeprep::mesh::Params::for_mesh(&positions);
    let topo = deeprep::mesh::Topology::from_mesh(&positions, &triangles, &params, &[])
        .expect("grid topology");
    let topology = serde_json::json!({
        "vertices": positions.len(),
        "levels": std::iter::once(topo.rest.len())
            .chain(topo.levels.iter().map(|l| l.selected.len()))
            .collect::<Vec<_>>(),
        "ms": t0.elapsed().as_secs_f64() * 1e3,
    });
    println!(
        "{}",
        serde_json::to_string_pretty(&serde_json::json!({
            "tract_mesh_autoencoder": rows,
            "threads": 1,
            "mesh_topology_of_a_grid": topology
        }))
        .unwrap()
    );
}

//! Runs in headless Chromium (wasm-bindgen-test): the rotation library and
//! tract inside the browser, checked against native results.
#![cfg(target_arch = "wasm32")]

use deeprep::rotation::batch::{self, Repr};
use deeprep::runtime::{Model, TensorF32};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

const ROT_FIXTURE: &str = include_str!("../fixtures/rotations_native.json");
const MODEL: &[u8] = include_bytes!("../../models/onnx/rot6d_autoencoder.onnx");
const MODEL_FIXTURE: &str = include_str!("../../models/onnx/fixtures/rot6d_autoencoder.json");

/// The largest absolute difference between two equally long slices.
fn max_abs_diff(a: &[f32], b: &[f32]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0f32, f32::max)
}

fn floats(v: &serde_json::Value) -> Vec<f32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect()
}

#[wasm_bindgen_test]
fn rotation_batches_match_native_outputs() {
    let f: serde_json::Value = serde_json::from_str(ROT_FIXTURE).unwrap();
    let input = floats(&f["input_matrices"]);
    let outputs = f["outputs"].as_object().unwrap();
    assert!(outputs.len() >= 10);
    for (name, expected) in outputs {
        let got = batch::convert(Repr::Matrix, Repr::parse(name).unwrap(), &input).unwrap();
        let expected = floats(expected);
        assert_eq!(got.len(), expected.len(), "{name}");
        let diff = max_abs_diff(&got, &expected);
        // Rounding of sin/cos/atan2 may differ by an ulp between wasm's libm
        // and the native C library.
        assert!(diff < 1e-5, "{name}: wasm vs native max abs diff {diff}");
    }
}

#[wasm_bindgen_test]
fn rotation_errors_surface_in_wasm() {
    let e = batch::convert(Repr::SixD, Repr::Quat, &[0.0; 6]).unwrap_err();
    assert!(e.to_string().contains("degenerate"), "{e}");
    let e = deeprep::wasm::convert_rotations("6d", "nope", &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    assert!(e.is_err());
}

/// The rot6d fixture's input and its shape.
fn model_fixture_input() -> (serde_json::Value, Vec<f32>, Vec<usize>) {
    let f: serde_json::Value = serde_json::from_str(MODEL_FIXTURE).unwrap();
    let input = floats(&f["input"]);
    let shape = f["input_shape"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect();
    (f, input, shape)
}

#[wasm_bindgen_test]
fn tract_runs_the_tiny_network_in_the_browser() {
    let (f, input, shape) = model_fixture_input();
    let expected = floats(&f["output_onnxruntime"]);
    let model = Model::from_onnx_bytes(MODEL).unwrap();
    let out = model.run(&[TensorF32::new(input, shape).unwrap()]).unwrap();
    let diff = max_abs_diff(&out[0].data, &expected);
    assert!(diff <= 1e-5, "tract in Chromium vs onnxruntime: {diff}");
}

/// Issue 23: tract's own profile in the browser, per operator, from the
/// same inputs `runInputs` takes; bad inputs are errors naming the method.
#[wasm_bindgen_test]
fn onnx_models_profile_per_operator_in_the_browser() {
    let (_, input, shape) = model_fixture_input();
    let shape: Vec<u32> = shape.iter().map(|&d| d as u32).collect();
    let ranks = [shape.len() as u32];
    let m = deeprep::wasm::OnnxModel::new(MODEL).unwrap();
    let ops: Vec<serde_json::Value> =
        serde_json::from_str(&m.profile_inputs(&input, &shape, &ranks, 3).unwrap()).unwrap();
    assert!(!ops.is_empty());
    let share: f64 = ops.iter().map(|o| o["share"].as_f64().unwrap()).sum();
    assert!(
        (share - 1.0).abs() < 1e-6 || share == 0.0,
        "shares sum to {share}"
    );
    assert!(ops
        .iter()
        .any(|o| o["op"].as_str().unwrap().contains("MatMul")));
    // the products' kernels are named, and only theirs
    for o in &ops {
        let kernel = o.get("kernel").and_then(|k| k.as_str());
        assert_eq!(kernel.is_some(), o["op"] == "OptMatMul", "{o}");
        assert!(kernel.is_none_or(|k| k.contains("f32")), "{o}");
    }
    assert!(ops.iter().any(|o| o.get("kernel").is_some()), "{ops:?}");
    let ms: Vec<f64> = ops.iter().map(|o| o["ms"].as_f64().unwrap()).collect();
    assert!(ms.windows(2).all(|w| w[0] >= w[1]), "slowest first: {ms:?}");
    assert!(m.profile_inputs(&input, &shape, &[9], 1).is_err());
    assert!(m.profile_inputs(&input[1..], &shape, &ranks, 1).is_err());
}

/// `OnnxModel.prepareAnyShape`: one plan for every frame count, which
/// gives the outputs of each length's own plan.
#[wasm_bindgen_test]
fn onnx_models_prepare_one_plan_for_any_length() {
    let own = deeprep::wasm::OnnxModel::new(TWEEN_PATH).unwrap();
    let any = deeprep::wasm::OnnxModel::new(TWEEN_PATH).unwrap();
    assert!(any.prepare_any_shape().unwrap());
    assert!(!any.prepare_any_shape().unwrap(), "built once");
    for frames in [40u32, 97] {
        let x: Vec<f32> = (0..171 * frames).map(|i| (i as f32 * 0.37).sin()).collect();
        let shape = [1, 171, frames];
        let (a, b) = (own.run(&x, &shape).unwrap(), any.run(&x, &shape).unwrap());
        assert_eq!(a.len(), b.len());
        let diff = max_abs_diff(&a, &b);
        assert!(
            diff < 1e-4,
            "{frames} frames: any-length plan differs by {diff}"
        );
    }
    assert!(
        any.run(&[0.0; 170], &[1, 170, 1]).is_err(),
        "fixed axis still checked"
    );
}

const IK_MODEL: &[u8] = include_bytes!("../../models/onnx/ik.onnx");
const IK_MANIFEST: &str = include_str!("../../models/onnx/ik.manifest.json");
const IK_FIXTURE: &str = include_str!("../../models/onnx/fixtures/ik.json");

#[wasm_bindgen_test]
fn ik_from_joint_positions_runs_in_the_browser() {
    let f: serde_json::Value = serde_json::from_str(IK_FIXTURE).unwrap();
    let x = floats(&f["input"]);
    let frames = f["input_shape"][0].as_u64().unwrap() as usize;
    let solver = deeprep::wasm::IkSolver::new(IK_MODEL, IK_MANIFEST).unwrap();
    let r = solver.solve(&x, frames).unwrap();
    let expected = floats(&f["reconstructed_positions_torch"]);
    let diff = max_abs_diff(&r.positions(), &expected);
    assert!(diff <= 2e-3, "wasm IK reconstruction vs PyTorch: {diff}");
    assert!(r.bvh().contains("MOTION"));
    assert!(solver.solve(&x[1..], frames).is_err());
}

/// The viewer's renderer on the browser's WebGPU (SwiftShader here): a
/// skeleton drawn into an offscreen texture and read back. (Headless
/// Chromium cannot present a WebGPU canvas; the page falls back to WebGL2
/// there, which tests/web/sketch.test.mjs checks from screenshots.)
#[wasm_bindgen_test]
async fn the_renderer_draws_on_webgpu() {
    use deeprep::viewer::{scene::colors, OrbitCamera, Renderer, Scene, SkeletonPose};
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::BROWSER_WEBGPU;
    let instance = wgpu::Instance::new(desc);
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions::default())
        .await
        .expect("a WebGPU adapter (crate/webdriver.json enables SwiftShader WebGPU)");
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor::default())
        .await
        .unwrap();
    let (w, h) = (256u32, 192u32);
    let mut scene = Scene::default();
    let pose = vec![
        [0.0, 90.0, 0.0],
        [0.0, 130.0, 0.0],
        [0.0, 165.0, 0.0],
        [-30.0, 120.0, 0.0],
        [30.0, 120.0, 0.0],
    ];
    let parents = vec![None, Some(0), Some(1), Some(1), Some(1)];
    scene.skeletons.push(SkeletonPose::new(
        pose.clone(),
        parents.clone(),
        colors::POSE,
    ));
    let key: Vec<[f32; 3]> = pose.iter().map(|p| [p[0] + 80.0, p[1], p[2]]).collect();
    scene
        .skeletons
        .push(SkeletonPose::new(key, parents, colors::KEY));
    let mut cam = OrbitCamera::default();
    let pts: Vec<[f32; 3]> = scene
        .skeletons
        .iter()
        .flat_map(|s| s.positions.clone())
        .collect();
    cam.frame(&pts);
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let tex = device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
    let mut renderer = Renderer::new(&device, format);
    renderer.render(&device, &queue, &view, w, h, &scene, &cam);
    let buf = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: (w * 4 * h) as u64, // 1024 bytes per row: already 256-aligned
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: &tex,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buf,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * 4),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([enc.finish()]);
    let done = js_sys::Promise::new(&mut |resolve, reject| {
        buf.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            let _ = match r {
                Ok(()) => resolve.call0(&wasm_bindgen::JsValue::NULL),
                Err(e) => reject.call1(&wasm_bindgen::JsValue::NULL, &e.to_string().into()),
            };
        });
    });
    wasm_bindgen_futures::JsFuture::from(done)
        .await
        .expect("buffer mapping");
    let data = buf.slice(..).get_mapped_range().unwrap().to_vec();
    let (mut key, mut light) = (0, 0);
    for px in data.chunks_exact(4) {
        let (r, g, b) = (px[0] as i32, px[1] as i32, px[2] as i32);
        if r > 120 && r > g + 50 && b > g {
            key += 1;
        }
        if r > 120 && g > 120 && b > 120 && (r - g).abs() < 30 {
            light += 1;
        }
    }
    assert!(
        key > 100 && light > 100,
        "key-colored {key}, pose-colored {light} of {} pixels",
        w * h
    );
}

const TWEEN_GENERATOR: &[u8] = include_bytes!("../../models/onnx/tween_generator.onnx");
const TWEEN_PATH: &[u8] = include_bytes!("../../models/onnx/tween_path.onnx");
const TWEEN_MANIFEST: &str = include_str!("../../models/onnx/tween_generator.manifest.json");

macro_rules! corpus {
    ($($name:literal),* $(,)?) => {
        &[$(($name, include_bytes!(concat!("../corpus/bvh/", $name)) as &[u8])),*]
    };
}
const BVH_CORPUS: &[(&str, &[u8])] = corpus!(
    "bad-channels-overflow.bvh",
    "bad-four-rotations.bvh",
    "bad-frame-time.bvh",
    "bad-frames-huge.bvh",
    "bad-frames-overflow.bvh",
    "bad-nan.bvh",
    "bad-truncated.bvh",
    "bad-unknown-channel.bvh",
    "ok-interleaved-channels.bvh",
    "ok-root-positions-only.bvh",
    "ok-small.bvh",
    "ok-two-rotations.bvh",
    "ok-zero-frames.bvh",
);

fn wasm_memory_bytes() -> u32 {
    use wasm_bindgen::JsCast;
    let m: js_sys::WebAssembly::Memory = wasm_bindgen::memory().unchecked_into();
    m.buffer()
        .unchecked_into::<js_sys::ArrayBuffer>()
        .byte_length()
}

/// Issue 22: every exported class given the reported hostile inputs
/// returns an `Error`, memory does not grow by a header's claim, and the
/// instance keeps working afterwards (a trap would make every later call,
/// even `version()`, fail).
#[wasm_bindgen_test]
fn hostile_inputs_reject_and_the_instance_keeps_working() {
    use deeprep::wasm::{convert_rotations, version, BvhClip, HairLab, Inbetweener, OnnxModel};
    for (name, bytes) in BVH_CORPUS {
        let r = BvhClip::from_bytes(bytes);
        assert_eq!(r.is_ok(), name.starts_with("ok-"), "{name}");
        if let Ok(c) = r {
            let again = BvhClip::parse(&c.to_bvh()).expect("write → parse");
            assert_eq!(again.frame_count(), c.frame_count(), "{name}");
            assert!(c.fk_positions(0, c.frame_count()).is_ok(), "{name}");
        }
    }
    // nesting deeper than the recursive parser survived in wasm (5,468)
    let mut deep = String::from(
        "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\n",
    );
    for i in 0..6000 {
        deep.push_str(&format!(
            "JOINT j{i}\n{{\nOFFSET 0 1 0\nCHANNELS 1 Zrotation\n"
        ));
    }
    deep.push_str(&"}\n".repeat(6001));
    deep.push_str("MOTION\nFrames: 0\nFrame Time: 0.01\n");
    assert!(BvhClip::parse(&deep).is_err(), "over MAX_JOINTS");
    // `Frames: 3000000` used to grow memory to 2 GB for good
    let before = wasm_memory_bytes();
    let text = String::from_utf8(BVH_CORPUS[9].1.to_vec())
        .unwrap()
        .replace("Frames: 2", "Frames: 3000000");
    assert!(BvhClip::parse(&text).is_err());
    let grown = wasm_memory_bytes() - before;
    assert!(grown < 16 << 20, "memory grew by {grown} bytes");
    // rotations, ONNX bytes
    assert!(convert_rotations("quat", "6d", &[1.0, 2.0, 3.0]).is_err());
    assert!(convert_rotations("quat", "nope", &[0.0, 0.0, 0.0, 1.0]).is_err());
    // sizes that reached an allocation unchecked (an abort in wasm: a trap)
    assert!(deeprep::wasm::rotation_circle("6d", "x", usize::MAX).is_err());
    assert!(deeprep::wasm::pca_2d(&[0.5; 4096], 4096).is_err());
    assert!(OnnxModel::new(b"not an onnx file").is_err());
    assert!(OnnxModel::new(&TWEEN_PATH[..TWEEN_PATH.len() / 2]).is_err());
    // the in-betweener: bad models, bad keys, impossible lengths
    assert!(Inbetweener::new(b"x", TWEEN_PATH, TWEEN_MANIFEST).is_err());
    assert!(Inbetweener::new(TWEEN_GENERATOR, TWEEN_PATH, "{").is_err());
    let m = Inbetweener::new(TWEEN_GENERATOR, TWEEN_PATH, TWEEN_MANIFEST).unwrap();
    let tpl = BvhClip::parse(&m.skeleton_bvh()).unwrap();
    let row = vec![0.0f32; tpl.channel_count()];
    let two: Vec<f32> = row.iter().chain(&row).copied().collect();
    assert!(m.interpolate(&[0, 10], &row, 20).is_err(), "short channels");
    assert!(m.interpolate(&[0, 10], &two, usize::MAX).is_err(), "frames");
    assert!(m.interpolate(&[10, 0], &two, 20).is_err(), "unsorted");
    let mut nan = two.clone();
    nan[5] = f32::NAN;
    assert!(m.interpolate(&[0, 10], &nan, 20).is_err(), "NaN");
    let none = synth_options(&[]);
    assert!(m
        .synthesize(&[0, 10], &two, usize::MAX, Some(synth_options(&[])))
        .is_err());
    let nan_variation = synth_options(&[("variation", JsValue::from_f64(f64::NAN))]);
    assert!(m
        .synthesize(&[0, 10], &two, 20, Some(nan_variation))
        .is_err());
    // the options object: defaults, every option, and mistakes named
    assert!(m.synthesize(&[0, 10], &two, 20, Some(none)).is_ok());
    // the BVH text is written on the first read of `bvh` and the same on the next
    let r = m.synthesize(&[0, 10], &two, 20, None).unwrap();
    let text = r.bvh().unwrap();
    assert!(
        text.starts_with("HIERARCHY") && text.contains("Frames: 20"),
        "{text}"
    );
    assert_eq!(r.bvh().unwrap(), text);
    let all = synth_options(&[
        ("post", JsValue::TRUE),
        ("footLock", JsValue::TRUE),
        ("variation", JsValue::from_f64(0.5)),
        ("dna", js_sys::Float32Array::from(&two[..]).into()),
    ]);
    assert!(m.synthesize(&[0, 10], &two, 20, Some(all)).is_ok());
    for (opts, says) in [
        (
            synth_options(&[("footlock", JsValue::TRUE)]),
            "unknown option 'footlock'",
        ),
        (
            synth_options(&[("post", JsValue::from_f64(1.0))]),
            "'post' must be a boolean",
        ),
        (
            synth_options(&[("variation", JsValue::from_str("1"))]),
            "'variation' must be a number",
        ),
        (
            synth_options(&[("dna", JsValue::from_str("x"))]),
            "'dna' must be a Float32Array",
        ),
        (
            js_sys::Array::new().unchecked_into(),
            "options must be an object",
        ),
    ] {
        let e = m
            .synthesize(&[0, 10], &two, 20, Some(opts))
            .err()
            .expect(says);
        let msg = JsValue::from(e);
        let msg = js_sys::Reflect::get(&msg, &"message".into())
            .unwrap()
            .as_string()
            .unwrap();
        assert!(msg.contains(says), "{msg}");
    }
    // requests as JSON with keys of any kind (issue 20): bad ones are errors
    for bad in [
        "{",
        r#"{"keys": [{"frame": 0, "root": [0, 56, 0]}]}"#,
        r#"{"frames": 60, "keys": [{"frame": 0, "root": [0, 56]}]}"#,
        r#"{"frames": 60, "keys": [{"frame": 0, "root": [0, 56, 0]}], "method": "fast"}"#,
        r#"{"frames": 60, "keys": [{"frame": 0, "root": [0, 56, 0]}, {"frame": 59, "root": [1, 56, 0]}], "method": "slerp"}"#,
        r#"{"frames": 60, "keys": [{"frame": 70, "root": [0, 56, 0]}]}"#,
    ] {
        assert!(m.synthesize_request(bad).is_err(), "{bad}");
    }
    // root-only keys run, and the root passes through them
    let r = m
        .synthesize_request(
            r#"{"frames": 61, "keys": [{"frame": 0, "root": [0, 56, 0]}, {"frame": 60, "root": [50, 56, 40]}]}"#,
        )
        .unwrap();
    let (p, j) = (r.positions(), tpl.joint_names().len());
    assert!((p[60 * 3 * j] - 50.0).abs() < 1e-3 && (p[60 * 3 * j + 2] - 40.0).abs() < 1e-3);
    // a 2-D key (every joint's x and y, and the root) between two whole
    // poses: met in x and y after post-processing (Sec. 5.4.2)
    let mut stand = row.clone();
    stand[1] = 56.0;
    let mut bent = stand.clone();
    for c in [10, 14, 20] {
        bent[c] = 30.0;
    }
    let fk = tpl.pose_fk(&bent).unwrap();
    let xy: Vec<[f32; 2]> = fk.chunks(3).map(|p| [p[0], p[1]]).collect();
    let req = serde_json::json!({"frames": 121, "keys": [
        {"frame": 0, "channels": stand},
        {"frame": 60, "xy": xy, "root": [fk[0], fk[1], fk[2]]},
        {"frame": 120, "channels": stand},
    ]});
    let r = m.synthesize_request(&req.to_string()).unwrap();
    let p = r.positions();
    let worst = (0..j)
        .map(|k| {
            let q = &p[(60 * j + k) * 3..];
            (q[0] - xy[k][0]).hypot(q[1] - xy[k][1])
        })
        .fold(0.0f32, f32::max);
    assert!(worst < 0.05, "a joint misses its keyed x/y by {worst}");
    // a 1,500-frame gap runs hierarchically (Sec. 5.4.3) and says so
    let req = serde_json::json!({"frames": 1501, "keys": [
        {"frame": 0, "channels": stand}, {"frame": 1500, "channels": stand},
    ]});
    let r = m.synthesize_request(&req.to_string()).unwrap();
    assert_eq!(r.frames(), 1501);
    assert!(!r.critical_frames().is_empty());
    assert!(m.rc_angles(&row, 0).is_err(), "the root is not an RC joint");
    assert!(m.set_rc_angles(&row, 5, &[f64::NAN, 0.0, 0.0]).is_err());
    // hair photo sizes whose product wraps on 32-bit
    let hair = HairLab::new(HAIR_FEATURES, HAIR_STRANDS, HAIR_MANIFEST).unwrap();
    assert!(hair.photo_input(&[], &[], &[], 65536, 65536).is_err());
    assert!(hair.photo_input(&[], &[], &[], usize::MAX, 2).is_err());
    // and the instance still works
    assert_eq!(version(), env!("CARGO_PKG_VERSION"));
    let r = m.interpolate(&[0, 10], &two, 20).unwrap();
    assert_eq!(r.frames(), 20);
}

const HAIR_FEATURES: &[u8] = include_bytes!("../../models/onnx/hair_features.onnx");
const HAIR_STRANDS: &[u8] = include_bytes!("../../models/onnx/hair_strands.onnx");
const HAIR_MANIFEST: &str = include_str!("../../models/onnx/hair_features.manifest.json");

const TWEEN_RESIDUAL: &[u8] = include_bytes!("../../models/onnx/tween_residual.onnx");
const TWEEN_RESIDUAL_MANIFEST: &str =
    include_str!("../../models/onnx/tween_residual.manifest.json");

/// Issue 23: `warmUp` (what the npm worker runs before it reports ready and
/// when idle) and `prepareLength` (a length's own plan, built and run once)
/// leave no trace in results: the same keys give the same motion, to the
/// bit, by the residual network and by the generator, as in an Inbetweener
/// that ran neither.
#[wasm_bindgen_test]
fn warming_up_and_preparing_a_length_leave_results_unchanged() {
    use deeprep::wasm::{BvhClip, Inbetweener};
    let make = || {
        let mut m = Inbetweener::new(TWEEN_GENERATOR, TWEEN_PATH, TWEEN_MANIFEST).unwrap();
        m.set_residual(TWEEN_RESIDUAL, TWEEN_RESIDUAL_MANIFEST)
            .unwrap();
        m
    };
    let tpl = BvhClip::parse(&make().skeleton_bvh()).unwrap();
    let c = tpl.channel_count();
    // three made-up whole poses 50 frames apart, walking forward
    let keys: Vec<f32> = (0..3)
        .flat_map(|k| {
            (0..c).map(move |i| match i {
                1 => 90.0,
                2 => 60.0 * k as f32,
                0 => 0.0,
                i => 20.0 * (0.3 * i as f32 + k as f32).sin(),
            })
        })
        .collect();
    let run = |m: &Inbetweener, dna: bool| {
        let opts =
            dna.then(|| synth_options(&[("dna", js_sys::Float32Array::from(&keys[..c]).into())]));
        let r = m.synthesize(&[0, 50, 100], &keys, 120, opts).unwrap();
        (r.method(), r.positions())
    };
    let cold = make();
    let (cold_res, cold_gen) = (run(&cold, false), run(&cold, true));
    assert_eq!(cold_res.0, "residual");
    assert_eq!(cold_gen.0, "generator", "Motion DNA runs the generator");
    let warm = make();
    warm.warm_up(2, true).unwrap();
    assert_eq!(run(&warm, false), cold_res, "residual network after warmUp");
    assert_eq!(run(&warm, true), cold_gen, "generator after warmUp");
    assert!(warm.prepare_length(120).unwrap(), "a new plan");
    assert!(!warm.prepare_length(120).unwrap(), "kept");
    let own = run(&warm, false);
    assert_eq!(own.0, "residual");
    let gap = own
        .1
        .iter()
        .zip(&cold_res.1)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    // the own plan's kernels may sum in another order than the any-length plan's
    assert!(gap < 1e-3, "the length's own plan moved a joint by {gap}");
}

/// An `Inbetweener.synthesize` options object with these fields.
fn synth_options(fields: &[(&str, JsValue)]) -> deeprep::wasm::SynthesizeOptions {
    let o = js_sys::Object::new();
    for (k, v) in fields {
        js_sys::Reflect::set(&o, &JsValue::from_str(k), v).unwrap();
    }
    o.unchecked_into()
}

#[path = "browser/matmul.rs"]
mod matmul;
#[path = "browser/numbers.rs"]
mod numbers;

//! Runs in headless Chromium (wasm-bindgen-test): the rotation library and
//! tract inside the browser, checked against native results.
#![cfg(target_arch = "wasm32")]

use deeprep::rotation::batch::{self, Repr};
use deeprep::runtime::{Model, TensorF32};
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

const ROT_FIXTURE: &str = include_str!("../fixtures/rotations_native.json");
const MODEL: &[u8] = include_bytes!("../../models/onnx/rot6d_autoencoder.onnx");
const MODEL_FIXTURE: &str = include_str!("../../models/onnx/fixtures/rot6d_autoencoder.json");

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
        let diff = got
            .iter()
            .zip(&expected)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
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

#[wasm_bindgen_test]
fn tract_runs_the_tiny_network_in_the_browser() {
    let f: serde_json::Value = serde_json::from_str(MODEL_FIXTURE).unwrap();
    let input = floats(&f["input"]);
    let shape: Vec<usize> = f["input_shape"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect();
    let expected = floats(&f["output_onnxruntime"]);
    let model = Model::from_onnx_bytes(MODEL).unwrap();
    let out = model.run(&[TensorF32::new(input, shape).unwrap()]).unwrap();
    let diff = out[0]
        .data
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(diff <= 1e-5, "tract in Chromium vs onnxruntime: {diff}");
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
    let diff = r
        .positions()
        .iter()
        .zip(&expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
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

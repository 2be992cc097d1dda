//! The wgpu viewer on a canvas (WebGPU, else WebGL2).

use super::{install_panic_hook, points3};
use crate::viewer::gpu;
use wasm_bindgen::prelude::*;

/// The wgpu viewer on a canvas: WebGPU when the browser offers it, WebGL2
/// otherwise (or when forced). It draws the current pose, keyframe poses in
/// a second color, the root trajectory as dots on the ground, and a grid.
#[wasm_bindgen]
pub struct Viewer {
    _instance: wgpu::Instance,
    _adapter: wgpu::Adapter,
    lost: std::sync::Arc<std::sync::atomic::AtomicBool>,
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    renderer: crate::viewer::Renderer,
    scene: crate::viewer::Scene,
    camera: crate::viewer::OrbitCamera,
    parents: Vec<Option<usize>>,
    selected: Option<usize>,
    backend: String,
    strands_revision: u64,
}

/// Per-vertex values in [0, max] as ramp colors (empty: none).
fn value_colors(values: &[f32], max: f32, n: usize) -> Result<Vec<[f32; 4]>, JsError> {
    if values.is_empty() {
        return Ok(Vec::new());
    }
    if values.len() != n {
        return Err(JsError::new(&format!(
            "viewer: {} values for {n} vertices",
            values.len()
        )));
    }
    if !(max.is_finite() && max > 0.0) {
        return Err(JsError::new(&format!(
            "viewer: the color scale's maximum must be positive, got {max}"
        )));
    }
    Ok(values
        .iter()
        .map(|v| crate::viewer::scene::colors::ramp(v / max))
        .collect())
}

fn parents_from(parents: &[i32]) -> Vec<Option<usize>> {
    parents
        .iter()
        .map(|&p| if p < 0 { None } else { Some(p as usize) })
        .collect()
}

#[wasm_bindgen]
impl Viewer {
    /// Opens the viewer on `canvas`. `forceWebgl2` skips WebGPU.
    pub async fn create(
        canvas: web_sys::HtmlCanvasElement,
        force_webgl2: bool,
    ) -> Result<Viewer, JsError> {
        install_panic_hook();
        // WebGPU first: ask for an adapter before touching the canvas, so that
        // the canvas is still free for WebGL2 when WebGPU is unavailable.
        // (wgpu's detection helper requests and drops a second adapter; in
        // Chromium that lost the device once the dropped one was collected.)
        let (w, h) = (canvas.width().max(1), canvas.height().max(1));
        let mut found = None;
        if !force_webgl2 {
            let instance = gpu::instance(wgpu::Backends::BROWSER_WEBGPU);
            if let Ok(adapter) = instance
                .request_adapter(&wgpu::RequestAdapterOptions::default())
                .await
            {
                found = Some((instance, adapter));
            }
        }
        let (instance, surface, adapter) = match found {
            Some((instance, adapter)) => {
                let surface = instance
                    .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
                    .map_err(|e| JsError::new(&format!("viewer: cannot use the canvas: {e}")))?;
                (instance, surface, adapter)
            }
            None => {
                let instance = gpu::instance(wgpu::Backends::GL);
                let surface = instance
                    .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
                    .map_err(|e| JsError::new(&format!("viewer: cannot use the canvas: {e}")))?;
                let adapter = instance
                    .request_adapter(&wgpu::RequestAdapterOptions {
                        compatible_surface: Some(&surface),
                        ..Default::default()
                    })
                    .await
                    .map_err(|e| {
                        JsError::new(&format!("viewer: no WebGPU or WebGL2 adapter: {e}"))
                    })?;
                (instance, surface, adapter)
            }
        };
        let info = adapter.get_info();
        let lost = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = lost.clone();
        let (device, queue) = gpu::open_device(
            &adapter,
            wgpu::Limits::downlevel_webgl2_defaults(),
            "deeprep viewer",
            move |m| {
                flag.store(true, std::sync::atomic::Ordering::SeqCst);
                web_sys::console::warn_1(&m.into());
            },
        )
        .await
        .map_err(|e| JsError::new(&e.to_string()))?;
        let mut config = surface
            .get_default_config(&adapter, w, h)
            .ok_or_else(|| JsError::new("viewer: the canvas surface is not supported"))?;
        // The renderer's colors are display values: prefer a non-sRGB target
        // so that WebGPU and WebGL2 show the same picture.
        if let Some(f) = surface
            .get_capabilities(&adapter)
            .formats
            .iter()
            .find(|f| !f.is_srgb())
        {
            config.format = *f;
        }
        surface.configure(&device, &config);
        let renderer = crate::viewer::Renderer::new(&device, config.format);
        let backend = match info.backend {
            wgpu::Backend::BrowserWebGpu => "webgpu".to_string(),
            wgpu::Backend::Gl => "webgl2".to_string(),
            other => format!("{other:?}").to_lowercase(),
        };
        Ok(Viewer {
            _instance: instance,
            _adapter: adapter,
            lost,
            surface,
            device,
            queue,
            config,
            renderer,
            scene: crate::viewer::Scene::default(),
            camera: crate::viewer::OrbitCamera::default(),
            parents: Vec::new(),
            selected: None,
            backend,
            strands_revision: 0,
        })
    }

    /// "webgpu" or "webgl2".
    #[wasm_bindgen(getter)]
    pub fn backend(&self) -> String {
        self.backend.clone()
    }

    /// True once the GPU device is lost (the browser reset the GPU, or a
    /// headless browser could not present a WebGPU canvas): draw nothing
    /// more and open a new viewer, e.g. with WebGL2 on a fresh canvas.
    #[wasm_bindgen(getter, js_name = deviceLost)]
    pub fn device_lost(&self) -> bool {
        self.lost.load(std::sync::atomic::Ordering::SeqCst)
    }

    /// Sets the skeleton's parents (−1 for the root); call before poses.
    #[wasm_bindgen(js_name = setParents)]
    pub fn set_parents(&mut self, parents: &[i32]) {
        self.parents = parents_from(parents);
    }

    /// Sets the drawn poses: `pose` (global positions, joints × 3; may be
    /// empty) and `keys` (key poses, k × joints × 3, in the key color).
    #[wasm_bindgen(js_name = setPoses)]
    pub fn set_poses(&mut self, pose: &[f32], keys: &[f32]) -> Result<(), JsError> {
        if self.parents.is_empty() {
            return Err(JsError::new("viewer: call setParents first"));
        }
        self.scene
            .set_sketch_poses(pose, keys, &self.parents, self.selected)
            .map_err(|e| JsError::new(&format!("viewer: {e}")))
    }

    /// The root trajectory (points × 3), drawn as dots on the ground.
    #[wasm_bindgen(js_name = setTrajectory)]
    pub fn set_trajectory(&mut self, points: &[f32]) -> Result<(), JsError> {
        self.scene.trajectory = points3(points, "trajectory")?;
        Ok(())
    }

    /// Highlights a joint of the current pose (−1: none); takes effect at the next `setPoses`.
    #[wasm_bindgen(js_name = setSelected)]
    pub fn set_selected(&mut self, joint: i32) {
        self.selected = (joint >= 0).then_some(joint as usize);
    }

    /// Orbits by pixel deltas. Non-finite values are ignored.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.camera.orbit(-dx * 0.008, dy * 0.008);
    }

    /// Looks from `yaw`, `pitch` (radians): `(0, 0)` is the front view (x
    /// right, y up), in which 2-D keys are sketched. Non-finite values are ignored.
    #[wasm_bindgen(js_name = setView)]
    pub fn set_view(&mut self, yaw: f32, pitch: f32) {
        self.camera.set_angles(yaw, pitch);
    }

    /// Pans by pixel deltas. Non-finite values are ignored.
    pub fn pan(&mut self, dx: f32, dy: f32) {
        self.camera.pan(dx, dy, self.config.height as f32);
    }

    /// Zooms: the distance is multiplied by `factor`. Non-finite or
    /// non-positive factors are ignored.
    pub fn zoom(&mut self, factor: f32) {
        self.camera.zoom(factor);
    }

    /// Draws one triangle mesh (replacing any other): `positions` (vertices
    /// × 3), `triangles` (vertex indices, 3 per triangle), and optionally a
    /// value per vertex shown as colors from blue-grey (0) to red (`max` and
    /// above); empty `values` draw the mesh in one color.
    #[wasm_bindgen(js_name = setMesh)]
    pub fn set_mesh(
        &mut self,
        positions: &[f32],
        triangles: &[u32],
        values: &[f32],
        max: f32,
    ) -> Result<(), JsError> {
        let pts = points3(positions, "mesh")?;
        if !triangles.len().is_multiple_of(3) {
            return Err(JsError::new("viewer: triangles need 3 indices each"));
        }
        if let Some(&bad) = triangles.iter().find(|&&i| i as usize >= pts.len()) {
            return Err(JsError::new(&format!(
                "viewer: triangle index {bad} is out of range ({} vertices)",
                pts.len()
            )));
        }
        let mut m = crate::viewer::TriMesh::new(pts, triangles.to_vec(), [0.78, 0.8, 0.86, 1.0]);
        m.vertex_colors = value_colors(values, max, m.positions.len())?;
        if !m.vertex_colors.is_empty() {
            m.color = [1.0; 4];
        }
        self.scene.meshes = vec![m];
        Ok(())
    }

    /// Draws strands (`strandLength` points each, × 3) as lines in `color`
    /// (RGBA, 0..1), replacing any others; empty `points` clears them. The
    /// GPU buffer is rebuilt only when this is called.
    #[wasm_bindgen(js_name = setStrands)]
    pub fn set_strands(
        &mut self,
        points: &[f32],
        strand_length: usize,
        color: &[f32],
    ) -> Result<(), JsError> {
        let pts = points3(points, "strands")?;
        if strand_length < 2 || pts.len() % strand_length != 0 {
            return Err(JsError::new(&format!(
                "viewer: {} strand points are not whole strands of {strand_length}",
                pts.len()
            )));
        }
        let c: [f32; 4] = match color {
            [r, g, b, a] => [*r, *g, *b, *a],
            [r, g, b] => [*r, *g, *b, 1.0],
            _ => return Err(JsError::new("viewer: strand color must be RGB or RGBA")),
        };
        self.strands_revision += 1;
        self.scene.strips = if pts.is_empty() {
            Vec::new()
        } else {
            vec![crate::viewer::LineStrips {
                points: pts,
                strip_len: strand_length,
                color: c,
                revision: self.strands_revision,
            }]
        };
        Ok(())
    }

    /// Removes the mesh.
    #[wasm_bindgen(js_name = clearMesh)]
    pub fn clear_mesh(&mut self) {
        self.scene.meshes.clear();
    }

    /// Draws marker spheres of `radius` at `points` (× 3) in place of any
    /// skeleton poses, e.g. a mesh's latent vertices; `highlight` (−1: none)
    /// is drawn larger in the selection color. `pickJoint` then picks markers.
    #[wasm_bindgen(js_name = setMarkers)]
    pub fn set_markers(
        &mut self,
        points: &[f32],
        radius: f32,
        highlight: i32,
    ) -> Result<(), JsError> {
        use crate::viewer::scene::colors;
        if !(radius.is_finite() && radius > 0.0) {
            return Err(JsError::new(&format!(
                "viewer: marker radius must be positive, got {radius}"
            )));
        }
        let pts = points3(points, "markers")?;
        let mut s =
            crate::viewer::SkeletonPose::new(pts.clone(), vec![None; pts.len()], colors::LATENT);
        s.joint_radius = radius;
        self.scene.skeletons = vec![s];
        if let Some(p) = usize::try_from(highlight).ok().and_then(|h| pts.get(h)) {
            let mut h = crate::viewer::SkeletonPose::new(vec![*p], vec![None], colors::SELECTED);
            h.joint_radius = radius * 1.5;
            self.scene.skeletons.push(h);
        }
        Ok(())
    }

    /// Sets the ground grid: half-width `extent` and line spacing `step`
    /// (world units) at height `height`; `extent` 0 hides it.
    #[wasm_bindgen(js_name = setGrid)]
    pub fn set_grid(&mut self, extent: f32, step: f32, height: f32) -> Result<(), JsError> {
        if extent == 0.0 {
            self.scene.grid = None;
            return Ok(());
        }
        if !(extent > 0.0
            && step > 0.0
            && extent.is_finite()
            && height.is_finite()
            && extent / step <= 1000.0)
        {
            return Err(JsError::new(&format!(
                "viewer: grid extent {extent} and step {step} must be positive (at most 1000 lines a side)"
            )));
        }
        self.scene.grid = Some(crate::viewer::Grid {
            extent,
            step,
            height,
        });
        Ok(())
    }

    /// Aims the camera at everything drawn: poses, markers, the trajectory and the mesh.
    pub fn frame(&mut self) {
        let mut pts: Vec<[f32; 3]> = self
            .scene
            .skeletons
            .iter()
            .flat_map(|s| s.positions.iter().copied())
            .collect();
        pts.extend(self.scene.trajectory.iter().copied());
        pts.extend(
            self.scene
                .meshes
                .iter()
                .flat_map(|m| m.positions.iter().copied()),
        );
        self.camera.frame(&pts);
    }

    /// The joint of the current pose under canvas pixel (x, y), or −1.
    #[wasm_bindgen(js_name = pickJoint)]
    pub fn pick_joint(&self, x: f32, y: f32) -> i32 {
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        match crate::viewer::pick_joint(&self.scene, &self.camera, x, y, w, h, 2.5) {
            Some((0, j)) if !self.scene.skeletons.is_empty() => j as i32,
            _ => -1,
        }
    }

    /// Where the ray through canvas pixel (x, y) meets the ground (y = 0):
    /// [x, 0, z], or an empty array when it does not.
    #[wasm_bindgen(js_name = groundPoint)]
    pub fn ground_point(&self, x: f32, y: f32) -> Vec<f32> {
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        self.camera
            .ground_point(x, y, w, h)
            .map_or(Vec::new(), |p| p.to_array().to_vec())
    }

    /// Where the ray through canvas pixel (x, y) meets the plane through
    /// (px, py, pz) that faces the camera: for dragging a joint in the view
    /// plane. Empty when the ray runs parallel to it.
    #[wasm_bindgen(js_name = planePoint)]
    pub fn plane_point(&self, x: f32, y: f32, px: f32, py: f32, pz: f32) -> Vec<f32> {
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        self.camera
            .plane_point(x, y, w, h, glam::Vec3::new(px, py, pz))
            .map_or(Vec::new(), |p| p.to_array().to_vec())
    }

    /// Canvas pixel (x, y) of a world point, or an empty array behind the camera.
    #[wasm_bindgen(js_name = projectPoint)]
    pub fn project_point(&self, px: f32, py: f32, pz: f32) -> Vec<f32> {
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        self.camera
            .project([px, py, pz], w, h)
            .map_or(Vec::new(), |p| vec![p[0], p[1]])
    }

    /// Matches the canvas size (pixels).
    pub fn resize(&mut self, width: u32, height: u32) {
        let (w, h) = (width.max(1), height.max(1));
        if (w, h) != (self.config.width, self.config.height) {
            self.config.width = w;
            self.config.height = h;
            self.surface.configure(&self.device, &self.config);
        }
    }

    /// Draws one frame.
    pub fn render(&mut self) -> Result<(), JsError> {
        if self.device_lost() {
            return Err(JsError::new(
                "viewer: the GPU device was lost; open a new viewer",
            ));
        }
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.device, &self.config);
                return Ok(());
            }
            _ => return Ok(()),
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        self.renderer.render(
            &self.device,
            &self.queue,
            &view,
            self.config.width,
            self.config.height,
            &self.scene,
            &self.camera,
        );
        self.queue.present(frame);
        Ok(())
    }
}

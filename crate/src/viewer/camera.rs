//! An orbit camera: yaw and pitch around a target, distance for zoom, and a
//! target that pans in the view plane. Pure math (glam), no GPU types.

use glam::camera::rh::{proj::directx, view::look_at_mat4};
use glam::{Mat4, Vec3, Vec4};

/// Orbit/pan/zoom camera (right-handed, y up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point the camera looks at and orbits around.
    pub target: Vec3,
    /// Rotation about world y, radians (0: the camera looks along −z).
    pub yaw: f32,
    /// Elevation, radians, kept inside (−89°, 89°).
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        OrbitCamera {
            target: Vec3::new(0.0, 90.0, 0.0),
            yaw: 0.5,
            pitch: 0.25,
            distance: 450.0,
            fov_y: 45f32.to_radians(),
        }
    }
}

const PITCH_LIMIT: f32 = 89.0 * std::f32::consts::PI / 180.0;

impl OrbitCamera {
    /// The camera position.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(sy * cp, sp, cy * cp)
    }

    /// Near and far planes, scaled with the distance.
    pub fn clip(&self) -> (f32, f32) {
        (self.distance * 0.01, self.distance * 20.0 + 1000.0)
    }

    /// View matrix.
    pub fn view(&self) -> Mat4 {
        look_at_mat4(self.eye(), self.target, Vec3::Y)
    }

    /// Projection × view for a viewport of aspect ratio `aspect` (depth 0..1).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let (near, far) = self.clip();
        // WebGPU's clip space: y up, depth 0..1 (Direct3D's convention).
        directx::perspective(self.fov_y, aspect.max(1e-3), near, far) * self.view()
    }

    /// Orbits by `dx`, `dy` radians (yaw, pitch).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        if !(dx.is_finite() && dy.is_finite()) {
            return; // a NaN here would stay in the camera for good
        }
        self.yaw += dx;
        self.pitch = (self.pitch + dy).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Looks from the direction `yaw`, `pitch` (radians; pitch clamped like
    /// [`orbit`](Self::orbit)'s): `(0, 0)` is the front view, along −z, in
    /// which x and y are the screen's axes.
    pub fn set_angles(&mut self, yaw: f32, pitch: f32) {
        if yaw.is_finite() && pitch.is_finite() {
            self.yaw = yaw;
            self.pitch = pitch.clamp(-PITCH_LIMIT, PITCH_LIMIT);
        }
    }

    /// Pans by a screen drag of `dx`, `dy` pixels in a viewport `height`
    /// pixels tall: the point under the cursor at the target's depth follows it.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        if !(dx.is_finite() && dy.is_finite() && height.is_finite()) {
            return;
        }
        let per_pixel = 2.0 * self.distance * (self.fov_y / 2.0).tan() / height.max(1.0);
        let fwd = (self.target - self.eye()).normalize();
        let right = fwd.cross(Vec3::Y).normalize();
        let up = right.cross(fwd);
        self.target += (-dx * right + dy * up) * per_pixel;
    }

    /// Zooms: the distance is multiplied by `factor` (> 1 moves away).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(1e-2, 1e6);
        }
    }

    /// Aims at the centre of `points` from far enough to see all of them.
    pub fn frame(&mut self, points: &[[f32; 3]]) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in points
            .iter()
            .map(|p| Vec3::from(*p))
            .filter(|p| p.is_finite())
        {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        if !lo.is_finite() || !hi.is_finite() {
            return;
        }
        self.target = (lo + hi) / 2.0;
        // A lone point (or a tiny cluster) is seen from a few units away.
        let radius = ((hi - lo).length() / 2.0).max(1e-3);
        let radius = if radius < 1e-2 { 10.0 } else { radius };
        self.distance = radius / (self.fov_y / 2.0).sin() * 1.1;
    }

    /// Screen position (pixels, y down) and depth of a world point, or `None`
    /// behind the camera.
    pub fn project(&self, p: [f32; 3], width: f32, height: f32) -> Option<[f32; 3]> {
        let c = self.view_proj(width / height) * Vec4::new(p[0], p[1], p[2], 1.0);
        if c.w <= 1e-6 {
            return None;
        }
        let n = c / c.w;
        Some([(n.x + 1.0) / 2.0 * width, (1.0 - n.y) / 2.0 * height, n.z])
    }

    /// The world-space ray (origin, unit direction) through a pixel.
    pub fn ray(&self, x: f32, y: f32, width: f32, height: f32) -> (Vec3, Vec3) {
        let inv = self.view_proj(width / height).inverse();
        let nx = 2.0 * x / width - 1.0;
        let ny = 1.0 - 2.0 * y / height;
        let a = inv * Vec4::new(nx, ny, 0.0, 1.0);
        let b = inv * Vec4::new(nx, ny, 1.0, 1.0);
        let (a, b) = (a.truncate() / a.w, b.truncate() / b.w);
        (a, (b - a).normalize())
    }

    /// Where the ray through pixel (x, y) meets the ground (y = 0), or
    /// `None` when it runs parallel to it or meets it behind the camera.
    pub fn ground_point(&self, x: f32, y: f32, width: f32, height: f32) -> Option<Vec3> {
        let (o, d) = self.ray(x, y, width, height);
        if d.y.abs() < 1e-6 {
            return None;
        }
        let t = -o.y / d.y;
        (t > 0.0).then(|| {
            let p = o + d * t;
            Vec3::new(p.x, 0.0, p.z)
        })
    }

    /// Where the ray through pixel (x, y) meets the plane through `p` that
    /// faces the camera (for dragging a point in the view plane), or `None`
    /// when the ray runs parallel to it.
    pub fn plane_point(&self, x: f32, y: f32, width: f32, height: f32, p: Vec3) -> Option<Vec3> {
        let (o, d) = self.ray(x, y, width, height);
        let n = (self.target - self.eye()).normalize();
        let denom = d.dot(n);
        if denom.abs() < 1e-6 {
            return None;
        }
        Some(o + d * ((p - o).dot(n) / denom))
    }
}

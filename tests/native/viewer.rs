//! The viewer: camera math and picking (pure), and a headless render of a
//! skeleton scene through wgpu (lavapipe or any adapter the machine has).

use deeprep::viewer::headless::Headless;
use deeprep::viewer::scene::colors;
use deeprep::viewer::{pick_joint, OrbitCamera, Scene, SkeletonPose};

/// A stick figure of the project's own: hip, spine, head, two arms, two legs.
fn figure(dx: f32) -> (Vec<[f32; 3]>, Vec<Option<usize>>) {
    let p = vec![
        [dx, 95.0, 0.0],         // 0 hip
        [dx, 130.0, 0.0],        // 1 chest
        [dx, 160.0, 0.0],        // 2 head
        [dx - 20.0, 140.0, 0.0], // 3 l shoulder
        [dx - 45.0, 115.0, 5.0], // 4 l hand
        [dx + 20.0, 140.0, 0.0], // 5 r shoulder
        [dx + 45.0, 115.0, 5.0], // 6 r hand
        [dx - 10.0, 50.0, 0.0],  // 7 l knee
        [dx - 12.0, 5.0, 0.0],   // 8 l foot
        [dx + 10.0, 50.0, 0.0],  // 9 r knee
        [dx + 12.0, 5.0, 0.0],   // 10 r foot
    ];
    let parents = vec![
        None,
        Some(0),
        Some(1),
        Some(1),
        Some(3),
        Some(1),
        Some(5),
        Some(0),
        Some(7),
        Some(0),
        Some(9),
    ];
    (p, parents)
}

fn scene() -> Scene {
    let (p, par) = figure(0.0);
    let (k, kpar) = figure(-120.0);
    let mut s = Scene::default();
    s.skeletons.push(SkeletonPose::new(p, par, colors::POSE));
    s.skeletons.push(SkeletonPose::new(k, kpar, colors::KEY));
    s.trajectory = (0..40)
        .map(|i| [-120.0 + 3.0 * i as f32, 0.0, 0.0])
        .collect();
    s
}

#[test]
fn projection_and_rays_agree() {
    let mut cam = OrbitCamera::default();
    cam.orbit(0.3, -0.1);
    for p in [[0.0, 90.0, 0.0], [40.0, 10.0, -30.0], [-100.0, 150.0, 60.0]] {
        let s = cam.project(p, 800.0, 600.0).unwrap();
        let (o, d) = cam.ray(s[0], s[1], 800.0, 600.0);
        let t = (glam::Vec3::from(p) - o).dot(d);
        let miss = (o + d * t - glam::Vec3::from(p)).length();
        assert!(miss < 1e-2, "ray through the projection misses by {miss}");
    }
    cam.orbit(0.0, 10.0);
    assert!(cam.pitch < 1.56, "pitch is clamped below 90 degrees");
    let d = cam.distance;
    cam.zoom(2.0);
    assert!((cam.distance - 2.0 * d).abs() < 1e-3);
    cam.zoom(f32::NAN);
    assert!((cam.distance - 2.0 * d).abs() < 1e-3, "NaN zoom is ignored");
    let before = cam.target;
    cam.pan(100.0, 0.0, 600.0);
    assert!((cam.target - before).length() > 1.0);
}

#[test]
fn framing_keeps_every_point_on_screen() {
    let mut cam = OrbitCamera::default();
    let (p, _) = figure(300.0);
    cam.frame(&p);
    for q in &p {
        let s = cam.project(*q, 640.0, 480.0).unwrap();
        assert!(
            s[0] > 0.0 && s[0] < 640.0 && s[1] > 0.0 && s[1] < 480.0,
            "{q:?} -> {s:?}"
        );
    }
}

/// The mesh tab frames a robot 4.5 units tall as tightly as a 170-unit
/// skeleton: framing does not assume the skeleton's scale.
#[test]
fn framing_works_at_any_scale() {
    for scale in [0.01f32, 1.0, 100.0] {
        let mut cam = OrbitCamera::default();
        let (p, _) = figure(300.0);
        let p: Vec<[f32; 3]> = p.iter().map(|q| q.map(|v| v * scale)).collect();
        cam.frame(&p);
        let xs: Vec<[f32; 3]> = p
            .iter()
            .map(|q| cam.project(*q, 640.0, 480.0).unwrap())
            .collect();
        let h = xs.iter().map(|s| s[1]).fold(f32::MIN, f32::max)
            - xs.iter().map(|s| s[1]).fold(f32::MAX, f32::min);
        assert!(xs
            .iter()
            .all(|s| s[0] > 0.0 && s[0] < 640.0 && s[1] > 0.0 && s[1] < 480.0));
        assert!(h > 120.0, "at scale {scale} the figure is only {h} px tall");
    }
}

#[test]
fn picking_finds_the_joint_under_the_cursor() {
    let s = scene();
    let cam = OrbitCamera::default();
    for (sk, j) in [(0, 2), (0, 6), (1, 8)] {
        let q = cam
            .project(s.skeletons[sk].positions[j], 800.0, 600.0)
            .unwrap();
        assert_eq!(
            pick_joint(&s, &cam, q[0], q[1], 800.0, 600.0, 1.5),
            Some((sk, j))
        );
    }
    assert_eq!(pick_joint(&s, &cam, 2.0, 2.0, 800.0, 600.0, 1.5), None);
}

#[test]
fn headless_render_draws_the_scene() {
    let mut h = Headless::new().expect("a wgpu adapter (setup.sh installs Mesa's lavapipe)");
    eprintln!("adapter: {}", h.adapter);
    let s = scene();
    let mut cam = OrbitCamera::default();
    let mut pts: Vec<[f32; 3]> = s
        .skeletons
        .iter()
        .flat_map(|k| k.positions.clone())
        .collect();
    pts.extend(&s.trajectory);
    cam.frame(&pts);
    let (w, h_px) = (320u32, 240u32);
    let img = h.render(&s, &cam, w, h_px).unwrap();
    assert_eq!(img.len(), (w * h_px * 4) as usize);
    let bg = s.background.map(|c| (c * 255.0).round() as i32);
    let px = |i: usize| [img[i] as i32, img[i + 1] as i32, img[i + 2] as i32];
    let mut drawn = 0;
    let mut pink = 0;
    let mut light = 0;
    for i in (0..img.len()).step_by(4) {
        let [r, g, b] = px(i);
        if (r - bg[0]).abs() + (g - bg[1]).abs() + (b - bg[2]).abs() > 30 {
            drawn += 1;
        }
        if r > 120 && r > g + 50 && b > g {
            pink += 1;
        }
        if r > 120 && g > 120 && b > 120 && (r - g).abs() < 30 {
            light += 1;
        }
    }
    let n = (w * h_px) as usize;
    eprintln!("drawn {drawn}, key-colored {pink}, pose-colored {light} of {n} pixels");
    assert!(drawn > n / 50, "too little drawn: {drawn}");
    assert!(pink > 100, "the key pose (second color) is missing: {pink}");
    assert!(light > 100, "the current pose is missing: {light}");
    // The same scene without skeletons draws far less.
    let mut empty = s.clone();
    empty.skeletons.clear();
    let img2 = h.render(&empty, &cam, w, h_px).unwrap();
    let drawn2 = (0..img2.len())
        .step_by(4)
        .filter(|&i| {
            (img2[i] as i32 - bg[0]).abs()
                + (img2[i + 1] as i32 - bg[1]).abs()
                + (img2[i + 2] as i32 - bg[2]).abs()
                > 30
        })
        .count();
    assert!(drawn2 < drawn, "{drawn2} vs {drawn}");
    // A PPM beside the build output, for eyes.
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("viewer_headless.ppm");
    let mut ppm = format!("P6\n{w} {h_px}\n255\n").into_bytes();
    for i in (0..img.len()).step_by(4) {
        ppm.extend_from_slice(&img[i..i + 3]);
    }
    std::fs::write(&out, ppm).unwrap();
    eprintln!("wrote {}", out.display());
    assert!(h.render(&s, &cam, 0, 10).is_err());
}

/// Per-vertex colors: a quad whose left vertices are at the ramp's low end
/// and right vertices at its high end draws both ends' hues; the same quad
/// without vertex colors draws neither.
#[test]
fn headless_render_shows_vertex_colors() {
    use deeprep::viewer::scene::colors::ramp;
    let mut h = Headless::new().expect("a wgpu adapter (setup.sh installs Mesa's lavapipe)");
    let quad = vec![
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 2.0, 0.0],
        [-1.0, 2.0, 0.0],
    ];
    let mut m = deeprep::viewer::TriMesh::new(quad.clone(), vec![0, 1, 2, 0, 2, 3], [1.0; 4]);
    m.vertex_colors = vec![ramp(0.0), ramp(1.0), ramp(1.0), ramp(0.0)];
    let mut s = deeprep::viewer::Scene {
        grid: None,
        meshes: vec![m.clone()],
        ..Default::default()
    };
    let mut cam = OrbitCamera {
        yaw: 0.0,
        pitch: 0.0,
        ..Default::default()
    };
    cam.frame(&quad);
    let count = |img: &[u8]| {
        let (mut red, mut blue) = (0, 0);
        for p in img.chunks_exact(4) {
            let [r, g, b] = [p[0] as i32, p[1] as i32, p[2] as i32];
            if r > 120 && r > g + 60 && r > b + 60 {
                red += 1;
            }
            if b > 100 && b > r + 20 && b > g {
                blue += 1;
            }
        }
        (red, blue)
    };
    let (red, blue) = count(&h.render(&s, &cam, 160, 120).unwrap());
    eprintln!("vertex colors: {red} red, {blue} blue-grey pixels");
    assert!(red > 200 && blue > 200, "{red} red, {blue} blue-grey");
    m.vertex_colors.clear();
    m.color = [0.5, 0.5, 0.5, 1.0];
    s.meshes = vec![m];
    let (red, blue) = count(&h.render(&s, &cam, 160, 120).unwrap());
    assert!(
        red < 10 && blue < 10,
        "{red} red, {blue} blue-grey without vertex colors"
    );
}

#[test]
fn ground_and_view_plane_points_project_back_to_their_pixel() {
    let mut cam = OrbitCamera::default();
    cam.orbit(0.4, -0.2);
    let (w, h) = (800.0, 600.0);
    // a ground point seen below the horizon: on y = 0, and under the pixel
    for g in [[10.0f32, 0.0, -20.0], [-60.0, 0.0, 35.0]] {
        let px = cam.project(g, w, h).unwrap();
        let p = cam.ground_point(px[0], px[1], w, h).unwrap();
        assert!(
            p.y == 0.0 && (p - glam::Vec3::from(g)).length() < 1e-2,
            "{p:?} vs {g:?}"
        );
    }
    // the top row looks above the horizon: no ground point
    assert!(cam.ground_point(w / 2.0, 0.0, w, h).is_none());
    // dragging a joint: the point on the plane through it facing the camera,
    // under the cursor, at the joint's depth
    let joint = glam::Vec3::new(5.0, 120.0, 3.0);
    let px = cam.project(joint.to_array(), w, h).unwrap();
    let same = cam.plane_point(px[0], px[1], w, h, joint).unwrap();
    assert!((same - joint).length() < 1e-2, "{same:?}");
    let moved = cam.plane_point(px[0] + 40.0, px[1], w, h, joint).unwrap();
    let n = (cam.target - cam.eye()).normalize();
    assert!(((moved - joint).dot(n)).abs() < 1e-2, "off the view plane");
    let back = cam.project(moved.to_array(), w, h).unwrap();
    assert!((back[0] - px[0] - 40.0).abs() < 0.05 && (back[1] - px[1]).abs() < 0.05);
}

#[test]
fn the_front_view_drags_joints_in_x_and_y_only() {
    let mut cam = OrbitCamera::default();
    cam.set_angles(0.0, 0.0);
    let (w, h) = (800.0, 600.0);
    let joint = glam::Vec3::new(5.0, 120.0, 3.0);
    let px = cam.project(joint.to_array(), w, h).unwrap();
    let moved = cam
        .plane_point(px[0] + 30.0, px[1] - 20.0, w, h, joint)
        .unwrap();
    assert!((moved.z - joint.z).abs() < 1e-3, "depth kept: {moved:?}");
    assert!(
        moved.x > joint.x && moved.y > joint.y,
        "right and up: {moved:?}"
    );
    // pitch is clamped as by orbit; non-finite angles are ignored
    cam.set_angles(1.0, 10.0);
    assert!(cam.pitch < 1.56 && cam.yaw == 1.0);
    cam.set_angles(f32::NAN, 0.0);
    assert_eq!(cam.yaw, 1.0);
}

#[test]
fn sketch_poses_become_skeletons_with_a_selection_marker() {
    let (p, par) = figure(0.0);
    let flat: Vec<f32> = p.iter().flatten().copied().collect();
    let keys: Vec<f32> = flat.iter().chain(&flat).map(|v| v + 1.0).collect();
    let mut s = Scene::default();
    s.set_sketch_poses(&flat, &keys, &par, Some(4)).unwrap();
    assert_eq!(s.skeletons.len(), 4, "pose, two keys, the selected joint");
    assert_eq!(s.skeletons[0].color, colors::POSE);
    assert_eq!(s.skeletons[1].color, colors::KEY);
    assert!(s.skeletons[1].joint_radius < s.skeletons[0].joint_radius);
    assert_eq!(s.skeletons[3].positions, vec![p[4]]);
    // no current pose: keys only, no marker
    s.set_sketch_poses(&[], &keys, &par, Some(4)).unwrap();
    assert_eq!(s.skeletons.len(), 2);
    // lengths that do not fit the skeleton, or NaN: errors
    assert!(s.set_sketch_poses(&flat[1..], &[], &par, None).is_err());
    assert!(s.set_sketch_poses(&flat, &keys[1..], &par, None).is_err());
    assert!(s.set_sketch_poses(&flat, &[], &[], None).is_err());
    let mut nan = flat.clone();
    nan[7] = f32::NAN;
    assert!(s.set_sketch_poses(&nan, &[], &par, None).is_err());
}

//! Hair (ch. 3): scalp, procedural generator invariants, strand geometry,
//! rendering, upsampling and the collision metric.

use deeprep::hair::{self, generator::*, render::*, strand, upsample, Body, Scalp, GRID, POINTS};
use deeprep::rng::Rng;

use crate::common;

fn style(length: Length, curl: Curl, seed: u64) -> (Style, Rng) {
    let mut rng = Rng::new(seed);
    let s = Style::random(HairClass { length, curl }, &mut rng);
    (s, rng)
}

#[test]
fn the_scalp_is_a_symmetric_cap_on_the_head() {
    let scalp = Scalp::default();
    let roots = scalp.grid_roots(GRID);
    assert_eq!(roots.len(), GRID * GRID);
    for (p, n) in &roots {
        assert!(scalp.head.dist(*p).abs() < 1e-4, "root off the head: {p:?}");
        assert!((n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0).abs() < 1e-4);
    }
    // mirror symmetry: cell (i, j) and (n-1-i, j)
    for j in 0..GRID {
        for i in 0..GRID {
            let a = roots[j * GRID + i].0;
            let b = roots[j * GRID + GRID - 1 - i].0;
            assert!(
                (a[0] + b[0]).abs() < 1e-5
                    && (a[1] - b[1]).abs() < 1e-5
                    && (a[2] - b[2]).abs() < 1e-5
            );
        }
    }
    // the front row (v small) is above the forehead, the back row reaches the nape
    let front = scalp.root(0.5, 0.0).0;
    let back = scalp.root(0.5, 1.0).0;
    let top = scalp.root(0.5, 0.5).0;
    assert!(front[2] > 0.0 && front[1] > 0.0, "front {front:?}");
    assert!(back[2] < 0.0 && back[1] < top[1], "back {back:?}");
    // distinct roots
    let d = (roots[0].0[0] - roots[1].0[0]).abs() + (roots[0].0[2] - roots[1].0[2]).abs();
    assert!(d > 1e-4);
}

#[test]
fn generated_hair_keeps_its_invariants() {
    let body = Body::default();
    let scalp = Scalp::default();
    for (k, class) in HairClass::all().into_iter().enumerate() {
        let mut rng = Rng::new(k as u64 + 10);
        let st = Style::random(class, &mut rng);
        let h = Hair::generate(&st, &scalp, &body, GRID, &mut rng).unwrap();
        assert_eq!(h.strands(), GRID * GRID);
        assert_eq!(h.points.len(), GRID * GRID * POINTS);
        let roots = scalp.grid_roots(GRID);
        for (i, root) in roots.iter().enumerate() {
            assert_eq!(h.strand(i)[0], root.0, "strand {i} starts at its root");
        }
        assert!(h.points.iter().all(|p| p.iter().all(|v| v.is_finite())));
        // collision-free targets: every non-root sample outside every ellipsoid
        for (idx, p) in h.points.iter().enumerate() {
            if idx % POINTS != 0 {
                assert!(
                    body.is_outside(*p),
                    "{}: sample {idx} inside the body at {p:?}",
                    class.name()
                );
            }
        }
        assert_eq!(body.collision_sum(&h.points, POINTS), 0.0);
        // lengths near the class' typical length (curls add arc length)
        let mean_len: f32 = (0..h.strands())
            .map(|i| strand::length(h.strand(i)))
            .sum::<f32>()
            / h.strands() as f32;
        let typ = class.typical_length();
        assert!(
            mean_len > 0.5 * typ && mean_len < 3.0 * typ,
            "{}: mean length {mean_len}",
            class.name()
        );
    }
}

#[test]
fn curly_hair_is_curlier_than_straight_hair() {
    let (body, scalp) = (Body::default(), Scalp::default());
    let mean_curv = |curl| {
        let (st, mut rng) = style(Length::M, curl, 3);
        let h = Hair::generate(&st, &scalp, &body, 16, &mut rng).unwrap();
        let c = h.curvatures();
        c.iter().sum::<f32>() / c.len() as f32
    };
    let (s, w, c) = (
        mean_curv(Curl::Straight),
        mean_curv(Curl::Wavy),
        mean_curv(Curl::Curly),
    );
    eprintln!("mean curvature (1/m): straight {s:.1}, wavy {w:.1}, curly {c:.1}");
    assert!(s < w && w < c, "{s} {w} {c}");
}

#[test]
fn mirroring_and_blending_keep_roots_and_stay_outside_the_body() {
    let (body, scalp) = (Body::default(), Scalp::default());
    let (sa, mut ra) = style(Length::L, Curl::Wavy, 5);
    let (sb, mut rb) = style(Length::L, Curl::Wavy, 6);
    let a = Hair::generate(&sa, &scalp, &body, 16, &mut ra).unwrap();
    let b = Hair::generate(&sb, &scalp, &body, 16, &mut rb).unwrap();
    let m = a.mirrored();
    for i in 0..m.strands() {
        let r = scalp.grid_roots(16)[i].0;
        let d: f32 = (0..3).map(|k| (m.roots[i][k] - r[k]).abs()).sum();
        assert!(d < 1e-5, "mirrored root {i} is not the grid's root");
    }
    assert_eq!(m.mirrored().points.len(), a.points.len());
    let mm = m.mirrored();
    let err = mm
        .points
        .iter()
        .zip(&a.points)
        .map(|(p, q)| (0..3).map(|k| (p[k] - q[k]).abs()).sum::<f32>())
        .fold(0.0, f32::max);
    assert!(err < 1e-5, "mirroring twice is the identity ({err})");
    for mask in [0b00001u8, 0b10110, 0b01010] {
        let c = Hair::blend(&a, &b, mask, &body).unwrap();
        assert_eq!(c.roots, a.roots);
        assert_eq!(body.collision_sum(&c.points, POINTS), 0.0);
        // differs from both parents
        let da: f32 = c
            .points
            .iter()
            .zip(&a.points)
            .map(|(p, q)| (p[1] - q[1]).abs())
            .sum();
        let db: f32 = c
            .points
            .iter()
            .zip(&b.points)
            .map(|(p, q)| (p[1] - q[1]).abs())
            .sum();
        assert!(da > 0.0 && db > 0.0);
    }
    assert!(Hair::blend(
        &a,
        &Hair::generate(&sb, &scalp, &body, 8, &mut rb).unwrap(),
        1,
        &body
    )
    .is_err());
}

#[test]
fn curvature_smoothing_and_curl_restoration() {
    // a circle of radius 5 cm has curvature 20 / m
    let circle: Vec<[f32; 3]> = (0..100)
        .map(|k| {
            let t = k as f32 * 0.02;
            [0.05 * t.cos(), 0.05 * t.sin(), 0.0]
        })
        .collect();
    let c = strand::curvature(&circle);
    assert!(c.iter().all(|k| (k - 20.0).abs() < 0.2), "{:?}", &c[..3]);
    let line: Vec<[f32; 3]> = (0..100).map(|k| [0.0, -0.003 * k as f32, 0.0]).collect();
    assert!(strand::curvature(&line).iter().all(|k| k.abs() < 1e-3));
    assert_eq!(strand::smooth(&line, 2.0)[0], line[0]);
    // smoothing removes noise
    let mut rng = Rng::new(1);
    let noisy: Vec<[f32; 3]> = line
        .iter()
        .map(|p| {
            [
                p[0] + 0.001 * rng.normal() as f32,
                p[1],
                p[2] + 0.001 * rng.normal() as f32,
            ]
        })
        .collect();
    let sm = strand::smooth(&noisy, 2.0);
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    assert!(mean(&strand::curvature(&sm)) < 0.3 * mean(&strand::curvature(&noisy)));
    // a helix built for curvature κ measures about κ
    let (r, w) = strand::helix_for_curvature(60.0);
    let helix = strand::add_helix(&line, &vec![r; 100], &vec![w; 100], 0.0, 0);
    let hk = mean(&strand::curvature(&helix)[5..95]);
    assert!((hk - 60.0).abs() < 6.0, "helix curvature {hk}");
    // restoration adds curls only where the prediction asks for them
    let (out, curled) = strand::restore(&line, &vec![60.0; 100], 1.0, 5.0);
    assert!(curled);
    let got = mean(&strand::curvature(&out)[20..95]);
    assert!(got > 40.0, "restored curvature {got}");
    assert_eq!(out[0], line[0]);
    let (out2, curled2) = strand::restore(&line, &vec![0.0; 100], 1.0, 5.0);
    assert!(!curled2);
    assert!(out2
        .iter()
        .zip(&line)
        .all(|(p, q)| (p[1] - q[1]).abs() < 1e-6));
}

#[test]
fn renders_show_orientation_segmentation_and_visibility() {
    let body = Body::default();
    // one vertical strand in front of the face, one behind the head
    let front: Vec<[f32; 3]> = (0..POINTS)
        .map(|k| [0.0, 0.02 - 0.002 * k as f32, 0.15])
        .collect();
    let back: Vec<[f32; 3]> = (0..POINTS)
        .map(|k| [0.0, 0.02 - 0.002 * k as f32, -0.15])
        .collect();
    let pts = [front, back].concat();
    let mut rng = Rng::new(0);
    let r = render(&pts, &body, &View::default(), 128, &mut rng).unwrap();
    let plane = 128 * 128;
    let hair: Vec<usize> = (0..plane)
        .filter(|&i| r.image[2 * plane + i] == 1.0)
        .collect();
    let bodyp = (0..plane)
        .filter(|&i| r.image[2 * plane + i] == 0.5)
        .count();
    assert!(
        hair.len() > 20 && bodyp > 1000,
        "hair {} body {bodyp}",
        hair.len()
    );
    // vertical: θ = π/2, so cos 2θ = −1 and sin 2θ = 0
    for &i in &hair {
        assert!(r.image[i] < 0.05 && (r.image[plane + i] - 0.5).abs() < 0.05);
    }
    assert!(
        r.visible[..POINTS].iter().all(|&v| v),
        "the front strand is visible"
    );
    assert!(
        r.visible[POINTS..].iter().filter(|&&v| v).count() < 10,
        "the strand behind the head is hidden"
    );
    // turned 180°, it is the other way round
    let turned = View {
        yaw: std::f32::consts::PI,
        ..Default::default()
    };
    let r2 = render(&pts, &body, &turned, 128, &mut rng).unwrap();
    assert!(r2.visible[POINTS..].iter().all(|&v| v));
    assert!(render(&pts[1..], &body, &View::default(), 128, &mut rng).is_err());
}

#[test]
fn bilinear_upsampling_reproduces_the_grid_and_linear_fields() {
    let n = 4;
    let c = 2;
    let mut f = vec![0.0f32; c * n * n];
    for j in 0..n {
        for i in 0..n {
            f[j * n + i] = i as f32 + 10.0 * j as f32;
            f[n * n + j * n + i] = 1.0;
        }
    }
    for j in 0..n {
        for i in 0..n {
            let (u, v) = Scalp::cell_uv(i, j, n);
            let x = upsample::bilinear(&f, c, n, u, v).unwrap();
            assert!((x[0] - f[j * n + i]).abs() < 1e-5 && (x[1] - 1.0).abs() < 1e-6);
        }
    }
    // between centres the linear field is exact
    let x = upsample::bilinear(&f, c, n, 0.5, 0.5).unwrap();
    assert!((x[0] - (1.5 + 15.0)).abs() < 1e-4, "{x:?}");
    let uv = upsample::dense_uv(30_000);
    assert_eq!(uv.len(), 30_000);
    assert_eq!(upsample::upsample(&f, c, n, &uv[..10]).unwrap().len(), 20);
    assert!(upsample::bilinear(&f[1..], c, n, 0.5, 0.5).is_err());
    assert!(upsample::bilinear(&f, c, n, f32::NAN, 0.5).is_err());
}

#[test]
fn the_collision_error_follows_eq_3_3() {
    let body = Body::default();
    // a strand straight through the head's centre along x: segments inside count
    let through: Vec<[f32; 3]> = (0..POINTS)
        .map(|k| [-0.2 + 0.004 * k as f32, 0.0, 0.0])
        .collect();
    let outside: Vec<[f32; 3]> = (0..POINTS)
        .map(|k| [-0.2 + 0.004 * k as f32, 0.3, 0.0])
        .collect();
    assert_eq!(body.collision_sum(&outside, POINTS), 0.0);
    let c = body.collision_sum(&through, POINTS);
    // analytic: Σ 0.004 · (1 − (x/0.078)²) over the samples inside ≈ ∫ (1 − x²/a²) dx = 4a/3
    let expect = 4.0 * 0.078 / 3.0;
    assert!((c - expect).abs() < 0.01, "{c} vs {expect}");
    assert!((body.collision_error(&through, POINTS) - c / POINTS as f32).abs() < 1e-7);
    let _ = hair::GRID;
}

mod model;

/// The photo path's filter bank recovers known orientations: straight
/// stripes at several angles, and the tangents of concentric rings.
#[test]
fn the_gabor_bank_recovers_synthetic_orientations() {
    use deeprep::hair::orientation::{network_input, Gabor};
    let bank = Gabor::default();
    let (w, h) = (64usize, 64usize);
    let ang = |a: f32, b: f32| {
        let d = (a - b).rem_euclid(std::f32::consts::PI);
        d.min(std::f32::consts::PI - d)
    };
    for deg in [0.0f32, 20.0, 45.0, 90.0, 133.0, 170.0] {
        let t = deg.to_radians();
        // bright lines along direction t (y down): intensity varies across them
        let img: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                let across = -x * t.sin() + y * t.cos();
                0.5 + 0.5 * (std::f32::consts::TAU * across / 4.0).cos()
            })
            .collect();
        let mask = vec![true; w * h];
        let (theta, _) = bank.orientations(&img, &mask, w, h).unwrap();
        let inner: Vec<f32> = (0..w * h)
            .filter(|i| (8..56).contains(&(i % w)) && (8..56).contains(&(i / w)))
            .map(|i| ang(theta[i], t))
            .collect();
        let mean = inner.iter().sum::<f32>() / inner.len() as f32;
        assert!(
            mean.to_degrees() < 3.0,
            "stripes at {deg}°: mean error {:.1}°",
            mean.to_degrees()
        );
    }
    // rings around the centre: strands run tangentially
    let (w, h) = (96usize, 96usize);
    let img: Vec<f32> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 - 48.0, (i / w) as f32 - 48.0);
            0.5 + 0.5 * (std::f32::consts::TAU * (x * x + y * y).sqrt() / 4.0).cos()
        })
        .collect();
    let mask: Vec<bool> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 - 48.0, (i / w) as f32 - 48.0);
            (x * x + y * y).sqrt() > 14.0 && (x * x + y * y).sqrt() < 40.0
        })
        .collect();
    let (theta, _) = bank.orientations(&img, &mask, w, h).unwrap();
    let mut errs = Vec::new();
    for i in 0..w * h {
        if mask[i] {
            let (x, y) = ((i % w) as f32 - 48.0, (i / w) as f32 - 48.0);
            let tangent = y.atan2(x) + std::f32::consts::FRAC_PI_2;
            errs.push(ang(theta[i], tangent).to_degrees());
        }
    }
    errs.sort_by(f32::total_cmp);
    let median = errs[errs.len() / 2];
    let mean = errs.iter().sum::<f32>() / errs.len() as f32;
    eprintln!("rings: median orientation error {median:.1}°, mean {mean:.1}°");
    assert!(median < 5.0 && mean < 10.0);
    // the network input: orientation channels on hair pixels, segmentation
    let hair: Vec<f32> = mask.iter().map(|&m| m as u8 as f32).collect();
    let body: Vec<f32> = (0..w * h).map(|i| ((i / w) > 80) as u8 as f32).collect();
    let x = network_input(&img, &hair, Some(&body), w, h, &bank).unwrap();
    assert_eq!(x.len(), 3 * 256 * 256);
    let plane = 256 * 256;
    assert!(x[2 * plane..].contains(&1.0) && x[2 * plane..].contains(&0.5));
    assert!(network_input(&img, &vec![0.0; w * h], None, w, h, &bank).is_err());
    assert!(network_input(&img[1..], &hair, None, w, h, &bank).is_err());
    let mut nan = img.clone();
    nan[5] = f32::NAN;
    assert!(bank.orientations(&nan, &mask, w, h).is_err());
}

#[test]
fn the_dataset_files_read_back_and_wrong_sizes_are_errors() {
    use deeprep::hair::dataset::{write, Dataset, Options, Sinks};
    let o = Options {
        base: 1,
        blends: 0,
        views: 1,
        size: 16,
        seed: 3,
    };
    let (mut s, mut c, mut i, mut v) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut classes = 0;
    let sinks = Sinks {
        strands: &mut s,
        curvature: &mut c,
        images: &mut i,
        visible: &mut v,
    };
    let meta = write(&o, sinks, |_| classes += 1).unwrap();
    let text = meta.to_string();
    let d = Dataset::read(&text, &s, &c, &i, &v).unwrap();
    let hairs = meta["hairs"].as_u64().unwrap() as usize;
    assert_eq!(hairs, 2 * classes, "a base style and its mirror per class");
    assert_eq!(d.strands.len(), hairs * 32 * 32 * 100 * 3);
    assert_eq!(d.images.len(), hairs * 3 * 16 * 16);
    assert_eq!(d.meta["hair"], meta["hair"]);
    assert!(d.visible.iter().all(|&x| x <= 1));
    for (what, e) in [
        (
            "strands",
            Dataset::read(&text, &s[..s.len() - 12], &c, &i, &v),
        ),
        ("images", Dataset::read(&text, &s, &c, &i[1..], &v)),
        (
            "hairs",
            Dataset::read(
                &text.replace("\"hairs\":", "\"hair_count\":"),
                &s,
                &c,
                &i,
                &v,
            ),
        ),
    ] {
        let e = e.unwrap_err().to_string();
        assert!(e.contains(what), "expected '{what}' in: {e}");
    }
    let mut nan = c.clone();
    nan[8..12].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = Dataset::read(&text, &s, &nan, &i, &v)
        .unwrap_err()
        .to_string();
    assert!(e.contains("curvature: value 2"), "{e}");
    assert!(Options { views: 0, ..o }.check().is_err());
    assert!(Options { size: 1 << 20, ..o }.check().is_err());
}

//! Hostile input (issue 22): every reproducer found by the mutation loop,
//! the libFuzzer target and the wasm probes is a regression test here, and
//! each must give a clear error (or a bounded result), never a panic, an
//! abort, a stack overflow or an allocation sized by a header.
//!
//! The small reproducers are committed under tests/corpus/ (the fuzz
//! targets' seed corpora read the same files); the large ones (deep
//! nesting, long chains) are generated here. This binary counts the bytes
//! it has allocated, so memory bounds are checked exactly, not by timing.

use deeprep::motion::{baseline, Keyframe};
use deeprep::skeleton::{fk, Bvh};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Counts live and peak heap bytes of the whole test process.
struct Counting;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// Tests that measure the peak run one at a time.
static MEASURE: Mutex<()> = Mutex::new(());

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(l) };
        if !p.is_null() {
            let now = LIVE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) };
        LIVE.fetch_sub(l.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, l, new) };
        if !q.is_null() {
            if new >= l.size() {
                let now = LIVE.fetch_add(new - l.size(), Ordering::Relaxed) + new - l.size();
                PEAK.fetch_max(now, Ordering::Relaxed);
            } else {
                LIVE.fetch_sub(l.size() - new, Ordering::Relaxed);
            }
        }
        q
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Runs `f` and returns its result with the peak heap growth it caused.
fn peak_during<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let _g = MEASURE.lock().unwrap_or_else(|e| e.into_inner());
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let out = f();
    (out, PEAK.load(Ordering::Relaxed).saturating_sub(base))
}

fn corpus(dir: &str) -> Vec<(String, Vec<u8>)> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/corpus")
        .join(dir);
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(&p)
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    out.sort();
    out
}

const HEAD: &str = "HIERARCHY\nROOT hip\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n";

/// A chain of `depth` nested joints under a root, with one frame.
fn nested(depth: usize) -> String {
    let mut s = String::from(HEAD);
    for i in 0..depth {
        s.push_str(&format!(
            "JOINT j{i}\n{{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n"
        ));
    }
    s.push_str("End Site\n{\nOFFSET 0 1 0\n}\n");
    for _ in 0..=depth {
        s.push_str("}\n");
    }
    s.push_str("MOTION\nFrames: 1\nFrame Time: 0.01\n");
    let vals = vec!["0"; 6 + 3 * depth];
    s.push_str(&vals.join(" "));
    s.push('\n');
    s
}

/// Every committed BVH reproducer parses to an error or a valid clip, and
/// every clip that parses survives write → parse, FK and SLERP keys.
#[test]
fn bvh_corpus_gives_errors_not_panics() {
    let files = corpus("bvh");
    assert!(files.len() >= 8, "{} corpus files", files.len());
    for (name, bytes) in files {
        let r = Bvh::parse_bytes(&bytes);
        if name.starts_with("bad-") {
            let e = r.expect_err(&name);
            assert!(!e.to_string().is_empty(), "{name}");
            continue;
        }
        let b = r.unwrap_or_else(|e| panic!("{name}: {e}"));
        let again = Bvh::parse(&b.write()).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(again, b, "{name}: write → parse");
        if b.frame_count() > 0 {
            fk::positions(&b, 0, b.frame_count()).unwrap();
            let k = Keyframe::from_bvh(&b, 0, 0).unwrap();
            let m = baseline::slerp_lerp(&[k], 4).unwrap();
            m.to_bvh(&b, b.frame_time).unwrap();
        }
    }
}

/// Nesting is read with an explicit stack: 4,000 levels parse (the
/// recursive parser overflowed natively at ~15,900 and in wasm at 5,468),
/// more than MAX_JOINTS is an error, and writing stays linear in size.
#[test]
fn deep_nesting_parses_without_recursion() {
    let text = nested(4000);
    let b = Bvh::parse(&text).unwrap();
    assert_eq!(b.joints.len(), 4002);
    let out = b.write();
    // linear in the joint count: twice the depth writes about twice the text
    // (indenting by depth wrote ~depth² bytes: 500 MB from a 759 KB file)
    let half = Bvh::parse(&nested(2000)).unwrap().write();
    assert!(
        (out.len() as f64) < 2.1 * half.len() as f64,
        "written {} bytes at depth 4000, {} at depth 2000",
        out.len(),
        half.len()
    );
    assert!(out.len() < 400 * b.joints.len(), "{} bytes", out.len());
    assert_eq!(Bvh::parse(&out).unwrap(), b);
    fk::positions(&b, 0, 1).unwrap();
    let e = Bvh::parse(&nested(20_000)).unwrap_err().to_string();
    assert!(e.contains("joints"), "{e}");
}

/// `Frames:` is not trusted for memory: a 12 KB file declaring 10^9 frames
/// fails after reading what is there, and stays far under 100 MB.
#[test]
fn a_huge_frame_count_allocates_nothing_large() {
    let mut text = nested(10).replace("Frames: 1", "Frames: 1000000000");
    let row = format!("{}\n", vec!["0.5"; 36].join(" "));
    while text.len() < 12_000 {
        text.push_str(&row);
    }
    let (r, peak) = peak_during(|| Bvh::parse(&text));
    let e = r.unwrap_err().to_string();
    assert!(e.contains("the header says 1000000000"), "{e}");
    assert!(peak < 100 << 20, "peak {peak} bytes");
    assert!(
        peak < 20 * text.len(),
        "peak {peak} bytes for {} bytes",
        text.len()
    );
    for frames in ["18446744073709551615", "99999999999999999999999"] {
        let t = nested(2).replace("Frames: 1", &format!("Frames: {frames}"));
        let (r, peak) = peak_during(|| Bvh::parse(&t));
        assert!(r.is_err(), "Frames: {frames}");
        assert!(peak < 1 << 20, "Frames: {frames}: peak {peak}");
    }
}

/// Motion lengths are bounded before anything is allocated.
#[test]
fn motion_lengths_are_limited() {
    let b = Bvh::parse(&nested(3)).unwrap();
    let k = Keyframe::from_bvh(&b, 0, 0).unwrap();
    for frames in [usize::MAX, deeprep::motion::MAX_FRAMES + 1] {
        let (r, peak) = peak_during(|| baseline::slerp_lerp(std::slice::from_ref(&k), frames));
        let e = r.unwrap_err().to_string();
        assert!(e.contains("at most"), "{e}");
        assert!(peak < 1 << 20, "peak {peak}");
        assert!(baseline::zero_velocity(std::slice::from_ref(&k), frames).is_err());
    }
    assert!(baseline::slerp_lerp(&[k], deeprep::motion::MAX_FRAMES).is_ok());
}

/// A minimal GLB: one triangle on node 0, `children` per node, optionally
/// a skin on node 0 with `weights` JOINTS_0/WEIGHTS_0 entries.
fn glb(children: &[Vec<usize>], weights: Option<usize>) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
        for x in v {
            bin.extend_from_slice(&x.to_le_bytes());
        }
    }
    let nodes: Vec<String> = children
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let kids = if c.is_empty() {
                String::new()
            } else {
                format!(
                    ",\"children\":[{}]",
                    c.iter()
                        .map(|x| x.to_string())
                        .collect::<Vec<_>>()
                        .join(",")
                )
            };
            let mesh = if i == 0 {
                if weights.is_some() {
                    ",\"mesh\":0,\"skin\":0"
                } else {
                    ",\"mesh\":0"
                }
            } else {
                ""
            };
            format!("{{\"name\":\"n{i}\"{kids}{mesh}}}")
        })
        .collect();
    let mut views = vec!["{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}".to_string()];
    let mut accessors = vec![
        "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]}"
            .to_string(),
    ];
    let mut attrs = "\"POSITION\":0".to_string();
    let mut skins = String::new();
    if let Some(n) = weights {
        let j0 = bin.len();
        bin.extend(std::iter::repeat_n(0u8, 4 * n));
        let w0 = bin.len();
        for _ in 0..n {
            for x in [1f32, 0., 0., 0.] {
                bin.extend_from_slice(&x.to_le_bytes());
            }
        }
        views.push(format!(
            "{{\"buffer\":0,\"byteOffset\":{j0},\"byteLength\":{}}}",
            4 * n
        ));
        views.push(format!(
            "{{\"buffer\":0,\"byteOffset\":{w0},\"byteLength\":{}}}",
            16 * n
        ));
        accessors.push(format!(
            "{{\"bufferView\":1,\"componentType\":5121,\"count\":{n},\"type\":\"VEC4\"}}"
        ));
        accessors.push(format!(
            "{{\"bufferView\":2,\"componentType\":5126,\"count\":{n},\"type\":\"VEC4\"}}"
        ));
        attrs.push_str(",\"JOINTS_0\":1,\"WEIGHTS_0\":2");
        skins = ",\"skins\":[{\"joints\":[0]}]".into();
    }
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"buffers\":[{{\"byteLength\":{}}}],\"bufferViews\":[{}],\"accessors\":[{}],\"meshes\":[{{\"primitives\":[{{\"attributes\":{{{attrs}}}}}]}}],\"nodes\":[{}]{skins},\"scenes\":[{{\"nodes\":[0]}}]}}",
        bin.len(),
        views.join(","),
        accessors.join(","),
        nodes.join(",")
    );
    let mut j = json.into_bytes();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

#[test]
fn gltf_node_trees_are_checked_not_recursed() {
    use deeprep::mesh::Rig;
    // the builder itself makes a valid rig
    let ok = Rig::from_glb(&glb(&[vec![1], vec![]], None)).unwrap();
    assert_eq!(ok.rest_pose().unwrap().len(), 3);
    let e = |g: Vec<u8>| Rig::from_glb(&g).err().map(|e| e.to_string());
    let own = e(glb(&[vec![0]], None)).expect("own child");
    assert!(own.contains("its own child"), "{own}");
    let cycle = e(glb(&[vec![1], vec![2], vec![1]], None)).expect("cycle");
    assert!(
        cycle.contains("cycle") || cycle.contains("two parents"),
        "{cycle}"
    );
    let cycle2 = e(glb(&[vec![], vec![2], vec![1]], None)).expect("cycle");
    assert!(cycle2.contains("cycle"), "{cycle2}");
    // a 100,000-node chain: no recursion, so it loads and poses
    let chain: Vec<Vec<usize>> = (0..100_000)
        .map(|i| if i + 1 < 100_000 { vec![i + 1] } else { vec![] })
        .collect();
    let rig = Rig::from_glb(&glb(&chain, None)).unwrap();
    assert_eq!(rig.globals(&rig.rest).len(), 100_000);
    // skin weights shorter than the positions
    let short = e(glb(&[vec![]], Some(2))).expect("short weights");
    assert!(short.contains("weight"), "{short}");
    Rig::from_glb(&glb(&[vec![]], Some(3)))
        .unwrap()
        .rest_pose()
        .unwrap();
}

#[test]
fn photo_sizes_cannot_wrap() {
    use deeprep::hair::orientation::{network_input, Gabor};
    let bank = Gabor::default();
    for (w, h) in [(65536, 65536), (usize::MAX, 2), (0, 0), (1 << 20, 1)] {
        let e = network_input(&[], &[], None, w, h, &bank).unwrap_err();
        assert!(e.to_string().contains("photo"), "{w}x{h}: {e}");
    }
    assert!(bank.orientations(&[], &[], usize::MAX, 2).is_err());
}

/// Many components are joined in bounded work or refused.
#[test]
fn joining_many_pieces_is_bounded() {
    use deeprep::mesh::graph::{connect_components, Graph};
    let n = 5000;
    let g = Graph::from_edges(n, &[]).unwrap();
    let pos: Vec<[f32; 3]> = (0..n).map(|i| [i as f32, 0.0, 0.0]).collect();
    let t = std::time::Instant::now();
    let e = connect_components(&g, &pos, 0.5).unwrap_err().to_string();
    assert!(e.contains("separate pieces"), "{e}");
    assert!(t.elapsed().as_secs_f64() < 1.0);
}

/// The CLI's numeric options from the reports: each is a clear error, never
/// a panic (exit 101) or an abort.
#[test]
fn cli_sizes_from_arguments_are_errors() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let tmp = std::env::temp_dir().join(format!("deeprep-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let clip = tmp.join("clip.bvh");
    std::fs::write(&clip, nested(3)).unwrap();
    let clip = clip.to_str().unwrap();
    let out = tmp.join("out").to_str().unwrap().to_string();
    let keys = root.join("models/examples/keys.json");
    let models = root.join("models/onnx");
    let huge = "18446744073709551615";
    // PPM headers that ask for more than the file holds: errors before any
    // allocation sized by them
    let obj = tmp.join("hair.obj").to_str().unwrap().to_string();
    let huge_ppm = tmp.join("huge.ppm");
    std::fs::write(&huge_ppm, b"P6\n99999999 99999999\n255\n\x01\x02").unwrap();
    let huge_ppm = huge_ppm.to_str().unwrap().to_string();
    let short_ppm = tmp.join("short.ppm");
    std::fs::write(&short_ppm, b"P6\n256 256\n255\n\x01\x02\x03").unwrap();
    let short_ppm = short_ppm.to_str().unwrap().to_string();
    let cases: Vec<Vec<&str>> = vec![
        vec!["bvh", "fk", clip, "--frame", huge],
        vec!["bvh", "fk", clip, "--frame", "1"],
        vec![
            "inbetween",
            keys.to_str().unwrap(),
            "--models",
            models.to_str().unwrap(),
            "--frames",
            huge,
            "-o",
            &out,
        ],
        vec![
            "inbetween",
            "--from-bvh",
            clip,
            "--keys",
            "0,18446744073709551615",
            "-o",
            &out,
        ],
        vec!["hair", "dataset", "--out", &out, "--blends", huge],
        vec!["hair", "dataset", "--out", &out, "--size", "100000"],
        vec![
            "hair", "preview", "--class", "M-curly", "--size", huge, "--out", &out,
        ],
        vec!["hair", "reconstruct", "--strands", huge, "--out", &obj],
        vec!["hair", "reconstruct", "--strands", "0", "--out", &obj],
        vec!["hair", "reconstruct", "--class", "Medium", "--out", &obj],
        vec!["hair", "reconstruct", "--out", &out],
        vec!["hair", "reconstruct", "--image", &huge_ppm, "--out", &obj],
        vec!["hair", "reconstruct", "--image", &short_ppm, "--out", &obj],
        vec![
            "hair",
            "reconstruct",
            "--image",
            &short_ppm,
            "--class",
            "M-curly",
            "--out",
            &obj,
        ],
    ];
    for args in cases {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_deeprep"))
            .args(&args)
            .current_dir(&root)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(
            o.status.code().is_some_and(|c| c != 101) && !err.contains("panicked"),
            "{args:?}: {:?}\n{err}",
            o.status
        );
        assert!(!err.trim().is_empty(), "{args:?}: no message");
    }
    let _ = std::fs::remove_dir_all(&tmp);
}

/// The glTF, keys-file and photo corpora (the fuzz targets' seeds): files
/// named `bad-*` fail with an error, `ok-*` load and run.
#[test]
fn gltf_keys_and_photo_corpora() {
    for (name, bytes) in corpus("gltf") {
        let r = deeprep::mesh::Rig::from_glb(&bytes).and_then(|r| r.rest_pose());
        assert_eq!(r.is_ok(), name.starts_with("ok-"), "{name}: {r:?}");
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join("models/onnx/tween_generator.manifest.json")).unwrap(),
    )
    .unwrap();
    let tpl = Bvh::parse(m["skeleton_bvh"].as_str().unwrap()).unwrap();
    for (name, bytes) in corpus("keys") {
        let r = deeprep::motion::keys::from_json(std::str::from_utf8(&bytes).unwrap(), &tpl)
            .and_then(|f| baseline::slerp_lerp(&f.keys, f.frames.unwrap_or(64)));
        assert_eq!(r.is_ok(), name.starts_with("ok-"), "{name}: {:?}", r.err());
    }
    let bank = deeprep::hair::orientation::Gabor::default();
    for (name, bytes) in corpus("hair") {
        let w = u16::from_le_bytes([bytes[0], bytes[1]]) as usize;
        let h = u16::from_le_bytes([bytes[2], bytes[3]]) as usize;
        let px: Vec<f32> = bytes[4..].iter().map(|&b| b as f32 / 255.0).collect();
        let half = px.len() / 2;
        let r = deeprep::hair::orientation::network_input(
            &px[..half],
            &px[half..2 * half],
            None,
            w,
            h,
            &bank,
        );
        assert_eq!(r.is_ok(), name.starts_with("ok-"), "{name}: {:?}", r.err());
    }
}

/// A clip whose last key time is 3·10³⁸ s (it overflowed `mesh poses`'
/// frame count) is refused by the sample count, not looped over.
#[test]
fn an_endless_gltf_clip_is_refused() {
    let mut bytes = corpus("gltf")
        .into_iter()
        .find(|(n, _)| n == "ok-triangle-anim.glb")
        .unwrap()
        .1;
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let bin = 20 + json_len + 8;
    // the animation's times [0, 1] start at byte 36 of the BIN chunk
    assert_eq!(&bytes[bin + 40..bin + 44], &1f32.to_le_bytes());
    bytes[bin + 40..bin + 44].copy_from_slice(&3e38f32.to_le_bytes());
    let rig = deeprep::mesh::Rig::from_glb(&bytes).unwrap();
    assert_eq!(rig.animations[0].duration, 3e38);
    let e = rig.clip_sample_count(0, 30.0).unwrap_err().to_string();
    assert!(e.contains("more than"), "{e}");
    assert!(rig.clip_sample_count(0, f32::NAN).is_err());
    assert!(rig.clip_sample_count(1, 30.0).is_err());
}

/// ONNX bytes: mutated copies of a bundled model load or fail with an
/// error; a panic inside tract's import is caught natively (one mutated
/// tween_path.onnx in 2,250 panicked at tract-onnx model.rs:187).
#[test]
fn mutated_onnx_bytes_are_errors_not_panics() {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/onnx/rot6d_autoencoder.onnx");
    let good = std::fs::read(path).unwrap();
    let mut rng = deeprep::rng::Rng::new(22);
    // (a panic caught inside tract's import still prints its message here)
    let (mut ok, mut err) = (0, 0);
    for _ in 0..300 {
        let mut b = good.clone();
        for _ in 0..1 + rng.below(4) {
            let i = rng.below(b.len());
            b[i] = (rng.below(256)) as u8;
        }
        match deeprep::runtime::Model::from_onnx_bytes(&b) {
            Ok(_) => ok += 1,
            Err(_) => err += 1,
        }
    }
    assert_eq!(ok + err, 300);
    assert!(err > 0, "some mutations must fail");
}

/// Sizes that reached an allocation unchecked from the wasm API: a rotation
/// circle of 4·10⁹ steps, PCA rows of 10⁵ numbers (a 10¹⁰-entry covariance).
#[test]
fn curve_and_pca_sizes_are_limited() {
    use deeprep::rotation::batch::Repr;
    use deeprep::rotation::curves::{pca_2d, rotation_circle};
    use deeprep::rotation::euler::Axis;
    let (r, peak) = peak_during(|| rotation_circle(Repr::SixD, Axis::X, usize::MAX));
    assert!(r.is_err() && peak < 1 << 20, "peak {peak}");
    let pts = vec![0.5f32; 100_000];
    let (r, peak) = peak_during(|| pca_2d(&pts, 100_000));
    assert!(r.is_err() && peak < 1 << 20, "peak {peak}");
    assert!(pca_2d(&pts, 0).is_err() && pca_2d(&pts, 7).is_err());
    assert_eq!(pca_2d(&pts, 4).unwrap().len(), 50_000);
    assert_eq!(rotation_circle(Repr::SixD, Axis::Y, 16).unwrap().len(), 96);
}

/// The manifest and request corpora (the fuzz targets' seeds): `bad-*`
/// fail with an error, `ok-*` parse (and a valid request interpolates).
#[test]
fn manifest_and_request_corpora() {
    for (name, bytes) in corpus("manifest") {
        let r = deeprep::motion::manifest::parse(std::str::from_utf8(&bytes).unwrap());
        assert_eq!(r.is_ok(), name.starts_with("ok-"), "{name}: {:?}", r.err());
    }
    let m = deeprep::motion::manifest::parse(
        &std::fs::read_to_string(
            PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../models/onnx/tween_generator.manifest.json"),
        )
        .unwrap(),
    )
    .unwrap();
    for (name, bytes) in corpus("request") {
        let frames = u32::from_le_bytes(bytes[0..4].try_into().unwrap()) as usize;
        let variation = f32::from_le_bytes(bytes[4..8].try_into().unwrap());
        let file = deeprep::motion::keys::from_json(
            std::str::from_utf8(&bytes[8..]).unwrap(),
            &m.template,
        )
        .unwrap();
        let req = deeprep::motion::Request {
            keys: file.keys,
            frames,
            dna: None,
            post_process: true,
            foot_lock: None,
            variation: Some(variation),
        };
        let r = req.validate(m.template.joints.len(), 1.0);
        assert_eq!(r.is_ok(), name.starts_with("ok-"), "{name}: {r:?}");
    }
}

#[path = "hostile/inputs.rs"]
mod inputs;

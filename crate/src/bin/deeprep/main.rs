//! The deeprep command line: a table of commands, one module per family
//! (`bvh`, `inbetween`, `mesh`, `hair`), each a thin layer over the
//! library. `deeprep --help` lists them; `deeprep COMMAND --help` shows one.
//!
//! ```text
//! deeprep bvh info FILE            skeleton, frame count and rate
//! deeprep bvh fk FILE --frame N    one line per joint: <name> x y z (global, file units)
//! ```

mod args;
mod bvh;
mod hair;
mod inbetween;
mod mesh;

use args::CliError;
use std::process::ExitCode;

const USAGE: &str = "usage:
  deeprep bvh info FILE
  deeprep bvh fk FILE --frame N
  deeprep bvh export FILE --out PREFIX
      writes PREFIX.json (skeleton, frame rate, layouts), PREFIX.positions.f32
      (frames x joints x 3 global positions) and PREFIX.rc.f32 (frames x (3 + 6 + 3K):
      root position, root 6D, range-constrained Euler angles in radians, clamped to
      Table D.1), little-endian f32; for the training pipeline
  deeprep bvh roles FILE [--map MAP.json]
      the humanoid roles found in FILE's skeleton (hips, spine, chest, neck, head; per side
      collar, upper arm, forearm, hand, buttock, thigh, shin, foot, toe) as a JSON map file
  deeprep bvh retarget SRC.bvh --to model|TARGET.bvh [--map MAP.json] [--models DIR] -o OUT.bvh
      SRC's motion on the model's skeleton or TARGET's (its hierarchy, rest pose and channel
      orders), at SRC's frame rate: each bone aimed where SRC's bone points (rest poses
      aligned per bone: T-pose or A-pose), the root path scaled by leg length, unmapped joints
      at rest; MAP.json ({\"leftShin\": \"L_Knee\", ...}) replaces roles found in SRC by name
  deeprep inbetween --from-bvh CLIP.bvh --keys F1,F2,... -o OUT.bvh
          [--method model|generator|residual|cond|slerp|zerovel] [--models DIR] [--no-post] [--foot-lock] [--variation V]
          [--dna F1,F2,...|DNA.bvh [--seed S]] [--seed S (--method cond)] [--key-kind pose|root|xy]
      keys from those frames of CLIP (--key-kind: whole poses, the default; the root's
      position only; or every joint's global x and y with the root); OUT has CLIP's length, frame rate and
      skeleton; frames between the first and last key are synthesized, the others copied
      --method residual: the supervised residual on SLERP+LERP (models/onnx/tween_residual.onnx;
      --variation scales its correction; default: its manifest's); --method generator: the
      Generative Tweening generator and path predictor (any key kind, DNA); --method cond: the
      conditional network (models/onnx/tween_cond.onnx: whole-pose, root-only and 2-D keys; with
      --dna the DNA network models/onnx/tween_cond_dna.onnx where present); --method model (the
      default): the residual network where its manifest makes it the default and every key is a
      whole pose without --dna or --no-post, else the conditional network where its manifest
      makes it the default for partial keys and it takes them, with --dna the DNA network where
      its manifest makes it the default for DNA, the generator otherwise
  deeprep inbetween --from-bvh CLIP.bvh --fill S-E [--fill S-E ...] [--context B[,A]] -o OUT.bvh
          [--method model|fill-mlp|fill|fill-long|residual|generator|cond|hermite|slerp|zerovel] [--models DIR]
      gaps in captured motion filled: frames S to E (inclusive) of CLIP synthesized from the
      known frames around them (B before, A after; default 20,1), every other line of CLIP
      written unchanged; the default fills the gaps a gap-filling network claims with it
      (--method fill-mlp: models/onnx/tween_fill_mlp.onnx, first; --method fill: models/onnx/
      tween_fill.onnx; --method fill-long: models/onnx/tween_fill_long.onnx; each where
      present, on the lengths its manifest's
      fill_from..fill_up_to give), other gaps up to 45 frames with a cubic Hermite curve whose
      tangents are the context's velocities (--method hermite) and longer ones with the
      network; a gap reversed, outside the clip, touching its first or last frame, or
      overlapping another is an error
  deeprep inbetween KEYS.json --frames N [-o OUT.bvh] [--models DIR] [--method M] [--no-post] [--foot-lock] [--variation V] [--dna DNA.bvh [--seed S]]
      --no-post: keys not made exact; --foot-lock: after that, pin feet in contact by two-bone IK
      (off by default: at the default variation it raised L2P, NPSS and foot skating on training takes)
      --variation V in [0, 2]: share of the networks' departure from SLERP+LERP kept, in the pose
      and the root path (1: the networks as trained; 0: SLERP+LERP; default: the model's
      manifest value, chosen on training takes)
      --dna: Motion DNA poses (Sec. 5.2.5), frames of CLIP or every frame of a BVH on the
      model's skeleton; without it the whole-pose keys serve
      --seed S (with --dna DNA.bvh): a window of DNA.bvh that S places, and S's draw of its
      representative frames (largest rotation change) among twice as many as training takes;
      equal seeds, equal motion. A conditional network with DNA spreads the poses over the
      output in their order, each steering the frames around its place
      --seed S (with --method cond, no --dna): the conditional network's noise draw; another
      seed, another motion through the same keys; without it, zero noise
      KEYS.json: {\"keys\": [KEY, ...]}, each KEY one of {\"frame\": F, \"channels\": [...]} (a whole
      pose: BVH channels of the model's skeleton), {\"frame\": F, \"root\": [x, y, z]} (the root
      only), {\"frame\": F, \"xy\": [[x, y] or null per joint], \"root\": [x, y, z] or null} (2-D
      joints, front view); without arguments, runs the bundled example models/examples/keys.json
  deeprep inbetween --skeleton [--models DIR]
      the model skeleton's joint names, one a line (the order of \"xy\" lists)
  deeprep mesh topology MESH.obj|MESH.glb --out TOPOLOGY.json
      the mesh autoencoder's topology: welded vertices, triangles, connected edge graph,
      sampling levels (s = 2, r = 2) with padded index/mask tables, latent seed vertices;
      any topology (pieces, non-manifold edges, isolated vertices); the robot's glTF keeps
      its latent seeds (hands, feet, head, torso)
  deeprep mesh poses RIGGED.glb --out PREFIX [--fps N] [--random N] [--seed S] [--subdivide K]
      every animation clip sampled at N fps (default 30) plus N random poses (default 0;
      each joint turned up to 30 degrees from a random clip frame), welded:
      PREFIX.f32 (poses x vertices x 3, little-endian) and PREFIX.json (clip per pose);
      --subdivide K (0-3): the welded mesh and every pose midpoint-subdivided K times
      (high resolution, Fig. 2.6), the subdivided rest mesh written as PREFIX.obj
  deeprep mesh shape tet|tree --out MESH.obj [--size N]
      a mesh for the thesis' other experiments: tet, a tetrahedralized block of N x 2N x N
      cubes (every tetrahedron's faces; Fig. 2.8); tree, three crossing quad planes sharing
      their axis, a non-manifold surface (Fig. 2.9); default N 6
  deeprep mesh pack TEMPLATE.obj POSE.obj... --out PREFIX
      a user's posed meshes (OBJ files with the template's vertices and faces, in order) as a
      pose set for mesh/train.py (each labelled with its index and file)
  deeprep mesh deform MESH.obj --out PREFIX [--count N] [--seed S]
      N smooth random deformations (a bend, a twist, three bumps) of MESH's welded
      vertices, as mesh poses writes them; interior vertices of a solid are listed
  deeprep hair dataset --out PREFIX [--base N] [--blends N] [--views N] [--size S] [--seed S]
      procedural hair data (ch. 3): N base styles per class (18 classes: XS..XXL x
      straight/wavy/curly), each mirrored, plus N in-class blends per base style, every
      hair rendered from N random views at S x S; split by base style (train/val/test).
      Writes PREFIX.json (hairs, classes, splits), PREFIX.strands.f32 (hairs x 1024 x 100
      x 3, root-relative metres), PREFIX.curvature.f32 (hairs x 1024 x 100, 1/m),
      PREFIX.images.u8 (renders x 3 x S x S) and PREFIX.visible.u8 (renders x 1024 x 100)
  deeprep hair preview --class M-curly [--seed S] [--yaw DEG] [--size S] --out FILE.ppm
      one procedural hair's render (orientation as red/green, segmentation as blue)
  deeprep hair reconstruct [--class M-curly [--seed S] [--yaw DEG] | --image FILE.ppm]
          [--strands N] [--smooth S] [--curl T] [--models DIR] --out FILE.obj|FILE.f32
      HairNet's reconstruction (Sec. 3.2.4) of a procedural test hair (the hair page's
      class and seed) or a 256 x 256 orientation image (as `hair preview` writes): N
      strands (default 30000) upsampled from the 32 x 32 features, smoothed (S samples,
      default 1.5), curls restored above T 1/m (default 15; inf: never). Writes OBJ
      polylines or float32 strands x 100 x 3 (metres); prints a JSON summary with the
      collision error (eq. 3.3)";

/// One command: the words that name it and what runs the rest of the
/// arguments. Its usage is the entry of [`USAGE`] that starts with
/// `deeprep <words>`.
struct Command {
    words: &'static [&'static str],
    run: fn(&[&str]) -> Result<(), CliError>,
}

const COMMANDS: &[Command] = &[
    Command {
        words: &["bvh", "info"],
        run: bvh::info,
    },
    Command {
        words: &["bvh", "fk"],
        run: bvh::positions,
    },
    Command {
        words: &["bvh", "export"],
        run: bvh::export,
    },
    Command {
        words: &["bvh", "roles"],
        run: bvh::roles,
    },
    Command {
        words: &["bvh", "retarget"],
        run: bvh::retarget,
    },
    Command {
        words: &["inbetween"],
        run: inbetween::run,
    },
    Command {
        words: &["mesh", "topology"],
        run: mesh::topology,
    },
    Command {
        words: &["mesh", "poses"],
        run: mesh::poses,
    },
    Command {
        words: &["mesh", "shape"],
        run: mesh::shape,
    },
    Command {
        words: &["mesh", "pack"],
        run: mesh::pack,
    },
    Command {
        words: &["mesh", "deform"],
        run: mesh::deform,
    },
    Command {
        words: &["hair", "dataset"],
        run: hair::dataset,
    },
    Command {
        words: &["hair", "preview"],
        run: hair::preview,
    },
    Command {
        words: &["hair", "reconstruct"],
        run: hair::reconstruct,
    },
];

fn run(args: &[String]) -> Result<(), CliError> {
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    let cmd = COMMANDS
        .iter()
        .find(|c| a.len() >= c.words.len() && a[..c.words.len()] == *c.words)
        .ok_or(CliError::Usage)?;
    (cmd.run)(&a[cmd.words.len()..])
}

/// The usage entries of the command named by the leading words of `args`
/// (`inbetween`, `bvh fk`, ...), or all of them when none matches.
fn help(args: &[String]) -> String {
    let words: Vec<&str> = args
        .iter()
        .map(String::as_str)
        .take_while(|a| !a.starts_with('-'))
        .take(2)
        .collect();
    // entries: a "  deeprep ..." line and the more-indented lines after it
    let mut entries: Vec<Vec<&str>> = Vec::new();
    for line in USAGE.lines().skip(1) {
        if line.starts_with("  deeprep ") {
            entries.push(vec![line]);
        } else if let Some(e) = entries.last_mut() {
            e.push(line);
        }
    }
    for n in (1..=words.len()).rev() {
        let prefix = format!("  deeprep {}", words[..n].join(" "));
        let hits: Vec<String> = entries
            .iter()
            .filter(|e| e[0] == prefix || e[0].starts_with(&format!("{prefix} ")))
            .map(|e| e.join("\n"))
            .collect();
        if !hits.is_empty() {
            return format!("usage:\n{}", hits.join("\n"));
        }
    }
    USAGE.to_string()
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        return match args::emit(&format!("{}\n", help(&args))) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("deeprep: {e}");
                ExitCode::from(2)
            }
        };
    }
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let text = match e {
                CliError::Usage => help(&args),
                CliError::Failed(m) => m,
            };
            eprintln!("deeprep: {text}");
            ExitCode::from(2)
        }
    }
}

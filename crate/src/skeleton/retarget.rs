//! Retargeting motion between humanoid skeletons.
//!
//! A humanoid's joints are found by role ([`Role`]: hips, spine, chest,
//! neck, head, and per side collar, upper arm, forearm, hand, buttock,
//! thigh, shin, foot, toe). [`find_roles`] finds them from the names of the
//! common families (the model's Daz-style `hip/abdomen/lThigh`,
//! MotionBuilder/3ds Max-style `Hips/LeftUpLeg/LowerBack/Spine1` and
//! `LeftHip/LeftKnee/LeftAnkle`, iClone `CC_Base_*`, Mixamo's `mixamorig:`,
//! VRM humanoid names, Blender/Unreal `thigh.L`/`thigh_l` suffixes) and from
//! the tree: the chest is where the two arms meet, the spine the joint
//! below it, a collar the joint between the chest and an upper arm. An
//! explicit map ([`RoleMap::with_overrides`]) replaces any of them.
//!
//! [`Retarget`] carries motion from one skeleton to another:
//! - **rest alignment per bone**: for each pair of mapped joints, the
//!   rotation `A` that turns the target's rest bone directions into the
//!   source's (towards the nearest mapped joints below it; a best fit over
//!   several branches, Horn's quaternion method), so a T-pose and an
//!   A-pose, or bones along other axes, line up;
//! - **rotations as world-space changes from the rest pose**: a mapped
//!   target joint's global rotation is the source joint's times `A`, so
//!   every mapped bone points where the source's points;
//! - **root translation scaled by leg length** (the hips' rest distance
//!   from the ankles, [`hip_height`]);
//! - **feet placed**: each ankle where the source's is, scaled like the
//!   root, by two-bone IK on thigh and shin ([`super::two_bone`]), so that
//!   planted feet stay planted on other proportions;
//! - **unmapped joints** (fingers, eyes, twist bones) stay at rest, or keep
//!   their values from a clip on the target skeleton ([`Retarget::clip`]'s
//!   `carry`: the way back onto a user's own skeleton).
//!
//! Both skeletons are taken as Y-up with BVH's rest convention (every
//! rotation channel zero is the rest pose). The frame rate is kept;
//! [`super::resample`] changes it.

use super::bvh::Bvh;
use super::pose::{offset, Pose};
use crate::error::{Error, Result};
use crate::rotation::{from_glam_f64, to_glam_f64};
use glam::{DMat3, DQuat, DVec3};
use std::collections::BTreeMap;

/// A position (glam's double-precision vector).
pub type Vec3 = DVec3;

/// A humanoid joint's role.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Role {
    /// The pelvis: the root of the legs and the spine.
    Hips,
    /// The first joint of the spine above the hips (below the chest).
    Spine,
    /// Where the arms and the neck meet.
    Chest,
    /// The first joint between the chest and the head.
    Neck,
    /// The head.
    Head,
    /// Collar bone (clavicle, Mixamo's "Shoulder").
    Collar(Side),
    /// Upper arm (the model's "Shldr", Mixamo's "Arm").
    UpperArm(Side),
    /// Forearm (elbow).
    ForeArm(Side),
    /// Hand (wrist).
    Hand(Side),
    /// The joint between the hips and a thigh (the model's "Buttock",
    /// MotionBuilder's "HipJoint").
    Buttock(Side),
    /// Thigh (upper leg).
    Thigh(Side),
    /// Shin (lower leg, knee, calf).
    Shin(Side),
    /// Foot (ankle).
    Foot(Side),
    /// Toe (ball of the foot).
    Toe(Side),
}

/// Left or right, as the character sees it.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Side {
    /// The character's left.
    Left,
    /// The character's right.
    Right,
}

const SIDES: [Side; 2] = [Side::Left, Side::Right];

impl Role {
    /// Every role, in the order of the map files (`leftUpperArm` style).
    pub fn all() -> Vec<Role> {
        let mut v = vec![Role::Hips, Role::Spine, Role::Chest, Role::Neck, Role::Head];
        for s in SIDES {
            v.extend([
                Role::Collar(s),
                Role::UpperArm(s),
                Role::ForeArm(s),
                Role::Hand(s),
                Role::Buttock(s),
                Role::Thigh(s),
                Role::Shin(s),
                Role::Foot(s),
                Role::Toe(s),
            ]);
        }
        v
    }

    /// The role's name in map files: `hips`, `leftUpperArm`, `rightShin`.
    pub fn name(self) -> String {
        let (side, base) = match self {
            Role::Hips => return "hips".into(),
            Role::Spine => return "spine".into(),
            Role::Chest => return "chest".into(),
            Role::Neck => return "neck".into(),
            Role::Head => return "head".into(),
            Role::Collar(s) => (s, "Collar"),
            Role::UpperArm(s) => (s, "UpperArm"),
            Role::ForeArm(s) => (s, "ForeArm"),
            Role::Hand(s) => (s, "Hand"),
            Role::Buttock(s) => (s, "Buttock"),
            Role::Thigh(s) => (s, "Thigh"),
            Role::Shin(s) => (s, "Shin"),
            Role::Foot(s) => (s, "Foot"),
            Role::Toe(s) => (s, "Toe"),
        };
        let side = match side {
            Side::Left => "left",
            Side::Right => "right",
        };
        format!("{side}{base}")
    }

    /// The role named `name` (see [`Role::name`]).
    pub fn parse(name: &str) -> Option<Role> {
        Role::all().into_iter().find(|r| r.name() == name)
    }

    /// Roles every humanoid must have (the others are found when present).
    fn required(self) -> bool {
        matches!(
            self,
            Role::Hips
                | Role::Chest
                | Role::Head
                | Role::UpperArm(_)
                | Role::ForeArm(_)
                | Role::Hand(_)
                | Role::Thigh(_)
                | Role::Shin(_)
                | Role::Foot(_)
        )
    }
}

/// The joint (an index into the skeleton's joints) of each role found.
#[derive(Clone, Debug, PartialEq)]
pub struct RoleMap {
    /// Role → joint index.
    pub joints: BTreeMap<Role, usize>,
}

/// A name split into its side (prefix `l`/`left`/`L_`, suffix `_l`/`.L`)
/// and its lower-case base without separators or family prefixes.
fn split_name(name: &str) -> (Option<Side>, String) {
    let mut s = name.rsplit(':').next().unwrap_or(name).to_string();
    for prefix in ["CC_Base_", "cc_base_", "Bip01 ", "Bip001 ", "DEF-", "ORG-"] {
        if let Some(rest) = s.strip_prefix(prefix) {
            s = rest.to_string();
        }
    }
    let lower = s.to_ascii_lowercase();
    let clean = |t: &str| -> String {
        t.chars()
            .filter(|c| c.is_ascii_alphanumeric())
            .collect::<String>()
            .to_ascii_lowercase()
    };
    for (side, word) in [(Side::Left, "left"), (Side::Right, "right")] {
        if lower.starts_with(word) {
            return (Some(side), clean(&s[word.len()..]));
        }
    }
    let b = s.as_bytes();
    // `lThigh`, `LHipJoint`, `L_Thigh`, `l.thigh`: one letter then a capital or a separator
    if b.len() > 1 && matches!(b[0], b'l' | b'L' | b'r' | b'R') {
        let next = b[1];
        if next.is_ascii_uppercase() || matches!(next, b'_' | b'.' | b' ' | b'-') {
            let side = if matches!(b[0], b'l' | b'L') {
                Side::Left
            } else {
                Side::Right
            };
            return (Some(side), clean(&s[1..]));
        }
    }
    // `thigh_l`, `thigh.L`, `Thigh_Left`
    for (side, suffixes) in [
        (Side::Left, ["_l", ".l", " l", "_left", ".left"]),
        (Side::Right, ["_r", ".r", " r", "_right", ".right"]),
    ] {
        for suf in suffixes {
            if lower.ends_with(suf) {
                return (Some(side), clean(&s[..s.len() - suf.len()]));
            }
        }
    }
    (None, clean(&s))
}

/// Base names (see [`split_name`]) of the roles found by name.
const HIPS: &[&str] = &["hips", "hip", "pelvis"];
const HEAD: &[&str] = &["head"];
const FOREARM: &[&str] = &["forearm", "lowerarm", "elbow"];
const HAND: &[&str] = &["hand", "wrist"];
const SHIN: &[&str] = &["shin", "leg", "knee", "calf", "lowerleg"];
const FOOT: &[&str] = &["foot", "ankle"];
const TOE: &[&str] = &["toe", "toebase", "toes"];

/// What a role's joint is called in the families, for error messages.
fn examples(role: Role) -> &'static str {
    match role {
        Role::Hips => "hip, Hips, CC_Base_Hip, pelvis",
        Role::Head => "head, Head",
        Role::ForeArm(_) => "lForeArm, LeftForeArm, LeftElbow, L_Forearm, leftLowerArm",
        Role::Hand(_) => "lHand, LeftHand, LeftWrist",
        Role::Shin(_) => "lShin, LeftLeg, LeftKnee, L_Calf, leftLowerLeg",
        Role::Foot(_) => "lFoot, LeftFoot, LeftAnkle",
        Role::UpperArm(_) => "the parent of the forearm",
        Role::Thigh(_) => "the parent of the shin",
        Role::Chest => "the joint where both arms meet",
        _ => "",
    }
}

/// Per joint: its parent chain (the joint itself first, the root last).
fn ancestors(bvh: &Bvh, j: usize) -> Vec<usize> {
    let mut out = vec![j];
    let mut k = j;
    while let Some(p) = bvh.joints[k].parent {
        out.push(p);
        k = p;
    }
    out
}

fn is_ancestor(bvh: &Bvh, a: usize, j: usize) -> bool {
    ancestors(bvh, j).contains(&a)
}

/// The child of `top` on the path down to `j` (`None` when `j` is not
/// below `top`).
fn child_towards(bvh: &Bvh, top: usize, j: usize) -> Option<usize> {
    let chain = ancestors(bvh, j);
    let at = chain.iter().position(|&k| k == top)?;
    (at > 0).then(|| chain[at - 1])
}

/// The nearest joint below `top` (breadth-first) whose name has `side` and
/// one of `bases`, End Sites excluded.
fn find_below(bvh: &Bvh, top: usize, side: Option<Side>, bases: &[&str]) -> Option<usize> {
    let children = bvh.children();
    let mut queue = std::collections::VecDeque::from(children[top].clone());
    while let Some(j) = queue.pop_front() {
        let joint = &bvh.joints[j];
        if !joint.end_site {
            let (s, b) = split_name(&joint.name);
            if s == side && bases.contains(&b.as_str()) {
                return Some(j);
            }
        }
        queue.extend(children[j].iter().copied());
    }
    None
}

/// The first joint (file order, End Sites excluded) with `side` and one of
/// `bases`, trying the bases in order.
fn find_named(bvh: &Bvh, side: Option<Side>, bases: &[&str]) -> Option<usize> {
    bases.iter().find_map(|base| {
        bvh.joints.iter().position(|j| {
            if j.end_site {
                return false;
            }
            let (s, b) = split_name(&j.name);
            s == side && b == *base
        })
    })
}

/// Finds every role of a humanoid skeleton from its joint names and tree.
/// Errors name every required bone that could not be found.
pub fn find_roles(bvh: &Bvh) -> Result<RoleMap> {
    RoleMap::with_overrides(bvh, &BTreeMap::new())
}

impl RoleMap {
    /// [`find_roles`] with some roles given: `overrides` maps a role name
    /// (`leftShin`) to a joint name of `bvh`, or to `None` to leave the role
    /// unmapped (optional roles only). Unknown role names, absent joints
    /// and a joint given to two roles are errors.
    pub fn with_overrides(
        bvh: &Bvh,
        overrides: &BTreeMap<String, Option<String>>,
    ) -> Result<RoleMap> {
        let mut given: BTreeMap<Role, Option<usize>> = BTreeMap::new();
        for (name, joint) in overrides {
            let role = Role::parse(name).ok_or_else(|| {
                Error::Invalid(format!(
                    "the joint map names a role '{name}' that does not exist; roles are {}",
                    Role::all()
                        .iter()
                        .map(|r| r.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })?;
            let j = match joint {
                None if role.required() => {
                    return Err(Error::Invalid(format!(
                        "the joint map leaves '{name}' unmapped, but every humanoid needs one"
                    )))
                }
                None => None,
                Some(jn) => Some(bvh.joint_index(jn).filter(|&j| !bvh.joints[j].end_site).ok_or_else(
                    || {
                        Error::Invalid(format!(
                            "the joint map gives '{name}' the joint '{jn}', which the skeleton does not have"
                        ))
                    },
                )?),
            };
            given.insert(role, j);
        }
        let mut found: BTreeMap<Role, usize> = BTreeMap::new();
        let mut missing: Vec<String> = Vec::new();
        let mut get = |role: Role,
                       find: &dyn Fn(&BTreeMap<Role, usize>) -> Option<usize>,
                       found: &mut BTreeMap<Role, usize>| {
            let j = match given.get(&role) {
                Some(j) => *j,
                None => find(found),
            };
            match j {
                Some(j) => {
                    found.insert(role, j);
                }
                None if role.required() => {
                    missing.push(format!("{} ({})", role.name(), examples(role)))
                }
                None => {}
            }
        };
        get(Role::Hips, &|_| find_named(bvh, None, HIPS), &mut found);
        for s in SIDES {
            get(
                Role::ForeArm(s),
                &|f| {
                    f.get(&Role::Hips)
                        .and_then(|_| find_named(bvh, Some(s), FOREARM))
                },
                &mut found,
            );
            get(
                Role::Hand(s),
                &|f| {
                    f.get(&Role::ForeArm(s))
                        .and_then(|&fa| find_below(bvh, fa, Some(s), HAND))
                },
                &mut found,
            );
            get(
                Role::UpperArm(s),
                &|f| {
                    f.get(&Role::ForeArm(s))
                        .and_then(|&fa| bvh.joints[fa].parent)
                },
                &mut found,
            );
            get(
                Role::Shin(s),
                &|_| find_named(bvh, Some(s), SHIN),
                &mut found,
            );
            get(
                Role::Foot(s),
                &|f| {
                    f.get(&Role::Shin(s))
                        .and_then(|&sh| find_below(bvh, sh, Some(s), FOOT))
                },
                &mut found,
            );
            get(
                Role::Thigh(s),
                &|f| f.get(&Role::Shin(s)).and_then(|&sh| bvh.joints[sh].parent),
                &mut found,
            );
            get(
                Role::Toe(s),
                &|f| {
                    f.get(&Role::Foot(s))
                        .and_then(|&ft| find_below(bvh, ft, Some(s), TOE))
                },
                &mut found,
            );
        }
        get(
            Role::Chest,
            &|f| {
                let (a, b) = (
                    f.get(&Role::UpperArm(Side::Left))?,
                    f.get(&Role::UpperArm(Side::Right))?,
                );
                let chain = ancestors(bvh, *a);
                let other = ancestors(bvh, *b);
                chain.into_iter().skip(1).find(|k| other.contains(k))
            },
            &mut found,
        );
        get(
            Role::Head,
            &|f| {
                let chest = *f.get(&Role::Chest)?;
                find_below(bvh, chest, None, HEAD).or_else(|| find_named(bvh, None, HEAD))
            },
            &mut found,
        );
        // joints between two found ones, on one branch only
        get(
            Role::Spine,
            &|f| {
                let (h, c) = (*f.get(&Role::Hips)?, *f.get(&Role::Chest)?);
                child_towards(bvh, h, c).filter(|&k| k != c)
            },
            &mut found,
        );
        get(
            Role::Neck,
            &|f| {
                let (c, h) = (*f.get(&Role::Chest)?, *f.get(&Role::Head)?);
                child_towards(bvh, c, h).filter(|&k| k != h)
            },
            &mut found,
        );
        for s in SIDES {
            let other = |r: fn(Side) -> Role, f: &BTreeMap<Role, usize>| {
                let o = if s == Side::Left {
                    Side::Right
                } else {
                    Side::Left
                };
                f.get(&r(o)).copied()
            };
            get(
                Role::Collar(s),
                &|f| {
                    let (c, ua) = (*f.get(&Role::Chest)?, *f.get(&Role::UpperArm(s))?);
                    let k = child_towards(bvh, c, ua).filter(|&k| k != ua)?;
                    let o = other(Role::UpperArm, f)?;
                    (!is_ancestor(bvh, k, o)).then_some(k)
                },
                &mut found,
            );
            get(
                Role::Buttock(s),
                &|f| {
                    let (h, th) = (*f.get(&Role::Hips)?, *f.get(&Role::Thigh(s))?);
                    let k = child_towards(bvh, h, th).filter(|&k| k != th)?;
                    let o = other(Role::Thigh, f)?;
                    (!is_ancestor(bvh, k, o)).then_some(k)
                },
                &mut found,
            );
        }
        if !missing.is_empty() {
            return Err(Error::Invalid(format!(
                "the skeleton (root '{}', {} joints) cannot be mapped onto a humanoid: no {}; give a joint map (--map MAP.json: role -> joint name)",
                bvh.joints.first().map(|j| j.name.as_str()).unwrap_or(""),
                bvh.joints.len(),
                missing.join(", no ")
            )));
        }
        let map = RoleMap { joints: found };
        map.check(bvh)?;
        Ok(map)
    }

    /// Checks the map's shape: distinct joints, the legs and arms as chains
    /// below the hips and the chest.
    fn check(&self, bvh: &Bvh) -> Result<()> {
        let mut seen: BTreeMap<usize, Role> = BTreeMap::new();
        for (&r, &j) in &self.joints {
            if let Some(o) = seen.insert(j, r) {
                return Err(Error::Invalid(format!(
                    "joint '{}' is both {} and {}",
                    bvh.joints[j].name,
                    o.name(),
                    r.name()
                )));
            }
        }
        let j = |r: Role| self.joints.get(&r).copied();
        let chains: Vec<Vec<Role>> = SIDES
            .iter()
            .flat_map(|&s| {
                [
                    vec![
                        Role::Hips,
                        Role::Buttock(s),
                        Role::Thigh(s),
                        Role::Shin(s),
                        Role::Foot(s),
                        Role::Toe(s),
                    ],
                    vec![
                        Role::Hips,
                        Role::Spine,
                        Role::Chest,
                        Role::Collar(s),
                        Role::UpperArm(s),
                        Role::ForeArm(s),
                        Role::Hand(s),
                    ],
                ]
            })
            .chain([vec![
                Role::Hips,
                Role::Spine,
                Role::Chest,
                Role::Neck,
                Role::Head,
            ]])
            .collect();
        for chain in chains {
            let present: Vec<Role> = chain.into_iter().filter(|&r| j(r).is_some()).collect();
            for w in present.windows(2) {
                let (a, b) = (j(w[0]).unwrap_or(0), j(w[1]).unwrap_or(0));
                if !is_ancestor(bvh, a, b) || a == b {
                    return Err(Error::Invalid(format!(
                        "the joint map puts {} ('{}') below {} ('{}'), which is not its ancestor",
                        w[1].name(),
                        bvh.joints[b].name,
                        w[0].name(),
                        bvh.joints[a].name
                    )));
                }
            }
        }
        Ok(())
    }

    /// The map without `roles` (joints a skeleton's motion never rotates:
    /// the motion they would take goes to the next mapped joint instead).
    pub fn without(mut self, roles: &[Role]) -> RoleMap {
        self.joints.retain(|r, _| !roles.contains(r));
        self
    }

    /// The map as `role name -> joint name` (what `--map` files hold).
    pub fn names(&self, bvh: &Bvh) -> BTreeMap<String, String> {
        self.joints
            .iter()
            .map(|(r, &j)| (r.name(), bvh.joints[j].name.clone()))
            .collect()
    }
}

/// Parses a joint map file: a JSON object from role names to joint names
/// (`null` leaves an optional role unmapped).
pub fn parse_map(text: &str) -> Result<BTreeMap<String, Option<String>>> {
    serde_json::from_str(text).map_err(|e| {
        Error::Invalid(format!(
            "a joint map is a JSON object from role names to joint names ({{\"leftShin\": \"L_Knee\"}}): {e}"
        ))
    })
}

/// Every joint's position in the rest pose (all channels zero).
pub fn rest_positions(bvh: &Bvh) -> Vec<DVec3> {
    let mut p: Vec<DVec3> = Vec::with_capacity(bvh.joints.len());
    for j in &bvh.joints {
        let base = j.parent.map(|q| p[q]).unwrap_or(DVec3::ZERO);
        p.push(base + offset(j));
    }
    p
}

/// Rest-pose distances below this count as the same place.
const NEAR: f64 = 1e-6;

/// The rotation `R` that best turns each `a` into its `b` (unit vectors;
/// Horn's closed form through the largest eigenvector of a 4×4 matrix).
fn best_rotation(pairs: &[(DVec3, DVec3)]) -> DMat3 {
    let mut s = [[0.0f64; 3]; 3];
    for (a, b) in pairs {
        let (a, b) = (a.to_array(), b.to_array());
        for i in 0..3 {
            for k in 0..3 {
                s[i][k] += a[i] * b[k];
            }
        }
    }
    let (xx, xy, xz) = (s[0][0], s[0][1], s[0][2]);
    let (yx, yy, yz) = (s[1][0], s[1][1], s[1][2]);
    let (zx, zy, zz) = (s[2][0], s[2][1], s[2][2]);
    let n = [
        [xx + yy + zz, yz - zy, zx - xz, xy - yx],
        [yz - zy, xx - yy - zz, xy + yx, zx + xz],
        [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
        [xy - yx, zx + xz, yz + zy, -xx - yy + zz],
    ];
    let q = largest_eigenvector(n);
    DMat3::from_quat(DQuat::from_xyzw(q[1], q[2], q[3], q[0]).normalize())
}

/// The eigenvector of the largest eigenvalue of a symmetric 4×4 matrix
/// (cyclic Jacobi rotations).
fn largest_eigenvector(mut a: [[f64; 4]; 4]) -> [f64; 4] {
    let mut v = [[0.0f64; 4]; 4];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _ in 0..64 {
        let off: f64 = (0..4)
            .flat_map(|i| (0..4).filter(move |&k| k != i).map(move |k| (i, k)))
            .map(|(i, k)| a[i][k] * a[i][k])
            .sum();
        if off < 1e-30 {
            break;
        }
        for p in 0..3 {
            for q in p + 1..4 {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..4 {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..4 {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    let best = (0..4)
        .max_by(|&i, &k| a[i][i].total_cmp(&a[k][k]))
        .unwrap_or(0);
    [v[0][best], v[1][best], v[2][best], v[3][best]]
}

/// Motion carried from a source skeleton onto a target skeleton.
#[derive(Clone, Debug)]
pub struct Retarget {
    /// Per target joint: the source joint it follows and the rest alignment
    /// `A` (target rest directions → source rest directions).
    follow: Vec<Option<(usize, DMat3)>>,
    /// Target hips, source hips.
    hips: (usize, usize),
    /// Root translation scale: the target's [`hip_height`] over the source's.
    pub scale: f64,
    /// The mapped pairs, role → (target joint, source joint).
    pub pairs: BTreeMap<Role, (usize, usize)>,
    /// Per leg whose thigh, shin and foot are mapped with the foot a child
    /// of the shin and the shin of the thigh on the target: the three
    /// (target joint, source joint) pairs.
    legs: Vec<[(usize, usize); 3]>,
}

/// The hips' distance from the ankles in the rest pose (legs straight in
/// every family's rest pose), averaged over the legs: what the root path is
/// scaled by, so that the scaled hips leave the feet within reach. A
/// distance, not a height: some files' rest poses are Z-up under a rotated
/// root.
pub fn hip_height(map: &RoleMap, rest: &[DVec3]) -> f64 {
    let hips = rest[map.joints[&Role::Hips]];
    SIDES
        .iter()
        .map(|&s| hips.distance(rest[map.joints[&Role::Foot(s)]]))
        .sum::<f64>()
        / 2.0
}

impl Retarget {
    /// Retargeting from `src` (roles `src_map`) to `dst` (roles `dst_map`):
    /// the roles both have are followed.
    pub fn new(src: &Bvh, src_map: &RoleMap, dst: &Bvh, dst_map: &RoleMap) -> Result<Retarget> {
        let pairs: BTreeMap<Role, (usize, usize)> = dst_map
            .joints
            .iter()
            .filter_map(|(r, &t)| src_map.joints.get(r).map(|&s| (*r, (t, s))))
            .collect();
        let (rs, rd) = (rest_positions(src), rest_positions(dst));
        let (ls, ld) = (hip_height(src_map, &rs), hip_height(dst_map, &rd));
        if !(ls > NEAR && ld > NEAR && ls.is_finite() && ld.is_finite()) {
            return Err(Error::Invalid(format!(
                "the hips must stand apart from the feet in both rest poses: {ls} (source) and {ld} (target) units"
            )));
        }
        let by_target: BTreeMap<usize, usize> = pairs.values().copied().collect();
        let mut follow: Vec<Option<(usize, DMat3)>> = vec![None; dst.joints.len()];
        let dst_children = dst.children();
        let src_children = src.children();
        // parents precede children: a pair with nothing to aim at takes its
        // nearest mapped ancestor's alignment
        for t in 0..dst.joints.len() {
            let Some(&s) = by_target.get(&t) else {
                continue;
            };
            let dirs = aim_pairs(t, s, &by_target, &dst_children, src, &rd, &rs);
            let a = if dirs.len() >= 2 {
                Some(best_rotation(&dirs))
            } else if let Some((a, b)) = dirs.first() {
                Some(DMat3::from_quat(DQuat::from_rotation_arc(*a, *b)))
            } else {
                let dt = mean_below(t, &dst_children, &rd);
                let ds = mean_below(s, &src_children, &rs);
                match (dt, ds) {
                    (Some(a), Some(b)) => Some(DMat3::from_quat(DQuat::from_rotation_arc(a, b))),
                    _ => None,
                }
            };
            let a = a.unwrap_or_else(|| {
                ancestors(dst, t)
                    .into_iter()
                    .skip(1)
                    .find_map(|k| follow[k].map(|(_, a)| a))
                    .unwrap_or(DMat3::IDENTITY)
            });
            follow[t] = Some((s, a));
        }
        let legs = SIDES
            .iter()
            .filter_map(|&s| {
                let p = |r| pairs.get(&r).copied();
                let legs = [p(Role::Thigh(s))?, p(Role::Shin(s))?, p(Role::Foot(s))?];
                let chained = dst.joints[legs[2].0].parent == Some(legs[1].0)
                    && dst.joints[legs[1].0].parent == Some(legs[0].0);
                chained.then_some(legs)
            })
            .collect();
        Ok(Retarget {
            legs,
            follow,
            hips: (dst_map.joints[&Role::Hips], src_map.joints[&Role::Hips]),
            scale: ld / ls,
            pairs,
        })
    }

    /// Retargeting between two skeletons whose roles are found by name
    /// ([`find_roles`]; `src_overrides` replace the source's).
    pub fn between(
        src: &Bvh,
        dst: &Bvh,
        src_overrides: &BTreeMap<String, Option<String>>,
    ) -> Result<Retarget> {
        let sm = RoleMap::with_overrides(src, src_overrides).map_err(|e| prefix("source", e))?;
        let dm = find_roles(dst).map_err(|e| prefix("target", e))?;
        Retarget::new(src, &sm, dst, &dm)
    }

    /// One frame: the target pose whose mapped bones point where the
    /// source's do. `carry` is a pose on the target skeleton whose unmapped
    /// joints are kept (rest when `None`).
    pub fn pose(&self, src: &Bvh, src_pose: &Pose, dst: &Bvh, carry: Option<&Pose>) -> Pose {
        let g = src_pose.global(src);
        let n = dst.joints.len();
        let mut global: Vec<DMat3> = Vec::with_capacity(n);
        let mut rotations = Vec::with_capacity(n);
        let mut translations: Vec<DVec3> = dst.joints.iter().map(offset).collect();
        let hips_line = ancestors(dst, self.hips.0);
        for (t, joint) in dst.joints.iter().enumerate() {
            let parent = joint.parent.map(|p| global[p]).unwrap_or(DMat3::IDENTITY);
            let above_hips = t != self.hips.0 && hips_line.contains(&t);
            let gt = match (self.follow[t], carry) {
                (Some((s, a)), _) => g.rotations[s] * a,
                (None, Some(c)) if !above_hips => parent * c.rotations[t],
                _ => parent,
            };
            if let (None, Some(c)) = (self.follow[t], carry) {
                if !above_hips {
                    translations[t] = c.translations[t];
                }
            }
            rotations.push(parent.transpose() * gt);
            global.push(gt);
        }
        // the hips where the source's are, scaled; joints above them at rest
        let want = g.positions[self.hips.1] * self.scale;
        let rest = rest_positions(dst);
        let root = hips_line.last().copied().unwrap_or(self.hips.0);
        translations[root] = want - rest[self.hips.0] + offset(&dst.joints[root]);
        let mut pose = Pose {
            translations,
            rotations,
        };
        // each ankle where the source's is, scaled
        for &[(thigh, _), (shin, _), (foot, sf)] in &self.legs {
            let gt = pose.global(dst);
            let to = |v: DVec3| [v.x, v.y, v.z];
            let chain = super::two_bone::Chain {
                h: to(gt.positions[thigh]),
                k: to(gt.positions[shin]),
                a: to(gt.positions[foot]),
                upper: from_glam_f64(&gt.rotations[thigh]),
                lower: from_glam_f64(&gt.rotations[shin]),
            };
            let target = to(g.positions[sf] * self.scale);
            let Some((upper, lower)) = super::two_bone::solve(&chain, &target) else {
                continue;
            };
            let (upper, lower) = (to_glam_f64(&upper), to_glam_f64(&lower));
            let parent = dst.joints[thigh]
                .parent
                .map(|p| gt.rotations[p])
                .unwrap_or(DMat3::IDENTITY);
            pose.rotations[thigh] = parent.transpose() * upper;
            pose.rotations[shin] = upper.transpose() * lower;
            pose.rotations[foot] = lower.transpose() * gt.rotations[foot];
        }
        pose
    }

    /// Every frame of `src` on `dst`'s skeleton, at `src`'s frame rate.
    /// `carry`, a clip on `dst`'s skeleton with the same frame count, gives
    /// the unmapped joints their values (the way back onto a user's own
    /// skeleton); without it they stay at rest.
    pub fn clip(&self, src: &Bvh, dst: &Bvh, carry: Option<&Bvh>) -> Result<Bvh> {
        let frames = src.frame_count();
        if let Some(c) = carry {
            if c.frame_count() != frames || c.channel_count() != dst.channel_count() {
                return Err(Error::Invalid(format!(
                    "the clip whose unmapped joints are kept has {} frames of {} channels; {frames} of {} expected",
                    c.frame_count(),
                    c.channel_count(),
                    dst.channel_count()
                )));
            }
        }
        let orders = super::pose::rotation_orders(dst);
        let mut motion = Vec::with_capacity(frames * dst.channel_count());
        for f in 0..frames {
            let sp = Pose::read(src, src.frame(f));
            let cp = carry.map(|c| Pose::read(dst, c.frame(f)));
            let p = self.pose(src, &sp, dst, cp.as_ref());
            motion.extend(p.to_row_with_orders(dst, &orders)?);
        }
        if let Some(i) = motion.iter().position(|v| !v.is_finite()) {
            return Err(Error::Invalid(format!(
                "retargeting gave a non-finite value at frame {}",
                i / dst.channel_count().max(1)
            )));
        }
        Ok(Bvh {
            joints: dst.joints.clone(),
            frame_time: src.frame_time,
            motion,
        })
    }

    /// Target joints that follow a source joint.
    pub fn mapped_targets(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self.pairs.values().map(|p| p.0).collect();
        v.sort_unstable();
        v
    }
}

fn prefix(which: &str, e: Error) -> Error {
    match e {
        Error::Invalid(m) => Error::Invalid(format!("{which} skeleton: {m}")),
        other => other,
    }
}

/// The directions a pair aims at: for each nearest mapped pair below the
/// target joint (and below the source joint), the two rest directions; a
/// pair at the same rest place on either side is looked through.
fn aim_pairs(
    t: usize,
    s: usize,
    by_target: &BTreeMap<usize, usize>,
    dst_children: &[Vec<usize>],
    src: &Bvh,
    rd: &[DVec3],
    rs: &[DVec3],
) -> Vec<(DVec3, DVec3)> {
    let mut out = Vec::new();
    let mut stack: Vec<usize> = dst_children[t].clone();
    while let Some(k) = stack.pop() {
        match by_target.get(&k) {
            Some(&ks) if is_ancestor(src, s, ks) && ks != s => {
                let (a, b) = (rd[k] - rd[t], rs[ks] - rs[s]);
                if a.length() > NEAR && b.length() > NEAR {
                    out.push((a.normalize(), b.normalize()));
                } else {
                    stack.extend(dst_children[k].iter().copied());
                }
            }
            _ => stack.extend(dst_children[k].iter().copied()),
        }
    }
    out
}

/// The mean rest direction from `j` to every joint below it (`None` when
/// they all sit at `j`).
fn mean_below(j: usize, children: &[Vec<usize>], rest: &[DVec3]) -> Option<DVec3> {
    let mut stack = children[j].clone();
    let (mut sum, mut n) = (DVec3::ZERO, 0usize);
    while let Some(k) = stack.pop() {
        sum += rest[k] - rest[j];
        n += 1;
        stack.extend(children[k].iter().copied());
    }
    let d = sum / n.max(1) as f64;
    (d.length() > NEAR).then(|| d.normalize())
}

/// Mean distance between `a`'s and `b`'s global positions of the joints
/// `joints` (same skeleton, same frame count), in the skeleton's units.
pub fn mean_position_error(a: &Bvh, b: &Bvh, joints: &[usize]) -> Result<f64> {
    if a.frame_count() != b.frame_count() || a.channel_count() != b.channel_count() {
        return Err(Error::Invalid(
            "the two clips differ in frames or channels".into(),
        ));
    }
    let (mut sum, mut n) = (0.0, 0usize);
    for f in 0..a.frame_count() {
        let (pa, pb) = (
            Pose::read(a, a.frame(f)).global(a),
            Pose::read(b, b.frame(f)).global(b),
        );
        for &j in joints {
            sum += pa.positions[j].distance(pb.positions[j]);
            n += 1;
        }
    }
    Ok(sum / n.max(1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_split_into_side_and_base() {
        assert_eq!(split_name("lThigh"), (Some(Side::Left), "thigh".into()));
        assert_eq!(split_name("LeftUpLeg"), (Some(Side::Left), "upleg".into()));
        assert_eq!(
            split_name("CC_Base_R_Calf"),
            (Some(Side::Right), "calf".into())
        );
        assert_eq!(
            split_name("mixamorig:LeftForeArm"),
            (Some(Side::Left), "forearm".into())
        );
        assert_eq!(split_name("thigh.L"), (Some(Side::Left), "thigh".into()));
        assert_eq!(split_name("calf_r"), (Some(Side::Right), "calf".into()));
        assert_eq!(split_name("LowerBack"), (None, "lowerback".into()));
        assert_eq!(split_name("lowerback"), (None, "lowerback".into()));
        assert_eq!(
            split_name("RHipJoint"),
            (Some(Side::Right), "hipjoint".into())
        );
        assert_eq!(
            split_name("rightUpperArm"),
            (Some(Side::Right), "upperarm".into())
        );
    }

    #[test]
    fn best_rotation_recovers_a_rotation() {
        let r = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::ZXY, 0.7, -1.1, 2.5));
        let dirs = [
            DVec3::X,
            DVec3::new(0.2, 1.0, -0.3).normalize(),
            DVec3::new(-1.0, 0.1, 0.5).normalize(),
        ];
        let pairs: Vec<_> = dirs.iter().map(|&a| (a, r * a)).collect();
        let got = best_rotation(&pairs);
        for (a, b) in got.to_cols_array().iter().zip(r.to_cols_array()) {
            assert!((a - b).abs() < 1e-9, "{got:?} vs {r:?}");
        }
        // two directions fix it too
        let got2 = best_rotation(&pairs[..2]);
        assert!((got2 - r).to_cols_array().iter().all(|v| v.abs() < 1e-9));
    }
}

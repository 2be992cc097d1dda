//! Humanoid roles: which joint of a skeleton is the hips, a shin, a hand,
//! found by name in the common families and by the tree, or given by a map.

use crate::error::{Error, Result};
use crate::skeleton::bvh::Bvh;
use std::collections::BTreeMap;

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

pub(super) const SIDES: [Side; 2] = [Side::Left, Side::Right];

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
const HAND: &[&str] = &["hand", "wrist", "palm"];
const SHIN: &[&str] = &["shin", "leg", "knee", "calf", "lowerleg"];
const FOOT: &[&str] = &["foot", "ankle"];
const TOE: &[&str] = &["toe", "toebase", "toes"];

/// What a role's joint is called in the families, for error messages.
fn examples(role: Role) -> &'static str {
    match role {
        Role::Hips => "hip, Hips, CC_Base_Hip, pelvis",
        Role::Head => "head, Head",
        Role::ForeArm(_) => "lForeArm, LeftForeArm, LeftElbow, L_Forearm, leftLowerArm",
        Role::Hand(_) => "lHand, LeftHand, LeftWrist, Palm.L",
        Role::Shin(_) => "lShin, LeftLeg, LeftKnee, L_Calf, leftLowerLeg",
        Role::Foot(_) => "lFoot, LeftFoot, LeftAnkle",
        Role::UpperArm(_) => "the parent of the forearm",
        Role::Thigh(_) => "the parent of the shin",
        Role::Chest => "the joint where both arms meet",
        _ => "",
    }
}

/// Per joint: its parent chain (the joint itself first, the root last).
pub(super) fn ancestors(bvh: &Bvh, j: usize) -> Vec<usize> {
    let mut out = vec![j];
    let mut k = j;
    while let Some(p) = bvh.joints[k].parent {
        out.push(p);
        k = p;
    }
    out
}

pub(super) fn is_ancestor(bvh: &Bvh, a: usize, j: usize) -> bool {
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
/// one of `bases`, possibly numbered (`Palm2.L`), End Sites excluded.
fn find_below(bvh: &Bvh, top: usize, side: Option<Side>, bases: &[&str]) -> Option<usize> {
    let children = bvh.children();
    let mut queue = std::collections::VecDeque::from(children[top].clone());
    while let Some(j) = queue.pop_front() {
        let joint = &bvh.joints[j];
        if !joint.end_site {
            let (s, b) = split_name(&joint.name);
            let b = b.trim_end_matches(|c: char| c.is_ascii_digit());
            if s == side && bases.contains(&b) {
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
        // A rig whose joint named hips carries only the spine (the legs hang
        // from its parent, as in RobotExpressive's `Body`): the hips are the
        // nearest joint above it that both legs hang from.
        if !given.contains_key(&Role::Hips) {
            if let (Some(&h), Some(&l), Some(&r)) = (
                found.get(&Role::Hips),
                found.get(&Role::Shin(Side::Left)),
                found.get(&Role::Shin(Side::Right)),
            ) {
                if let Some(k) = ancestors(bvh, h)
                    .into_iter()
                    .find(|&k| is_ancestor(bvh, k, l) && is_ancestor(bvh, k, r))
                {
                    found.insert(Role::Hips, k);
                }
            }
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
}

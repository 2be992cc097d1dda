//! BVH reading and writing.
//!
//! A [`Bvh`] holds the joint tree (End Sites are joints with no channels,
//! named `<parent>_Nub` unless the file names them) and the motion as one
//! flat `f32` array, frame-major. Parsing is a single pass over the text:
//! linear in the file size. Errors name the line and what was expected.

use crate::error::{Error, Result};

// writing BVH text (whole clips, or a clip's text with some frames rewritten)
mod write;

/// One BVH channel.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Channel {
    /// Translation along X.
    Xposition,
    /// Translation along Y.
    Yposition,
    /// Translation along Z.
    Zposition,
    /// Rotation about X, degrees.
    Xrotation,
    /// Rotation about Y, degrees.
    Yrotation,
    /// Rotation about Z, degrees.
    Zrotation,
}

impl Channel {
    fn parse(s: &str) -> Option<Channel> {
        Some(match s.to_ascii_lowercase().as_str() {
            "xposition" => Channel::Xposition,
            "yposition" => Channel::Yposition,
            "zposition" => Channel::Zposition,
            "xrotation" => Channel::Xrotation,
            "yrotation" => Channel::Yrotation,
            "zrotation" => Channel::Zrotation,
            _ => return None,
        })
    }

    /// The name as written in BVH files.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Xposition => "Xposition",
            Channel::Yposition => "Yposition",
            Channel::Zposition => "Zposition",
            Channel::Xrotation => "Xrotation",
            Channel::Yrotation => "Yrotation",
            Channel::Zrotation => "Zrotation",
        }
    }

    /// True for the rotation channels.
    pub fn is_rotation(self) -> bool {
        matches!(
            self,
            Channel::Xrotation | Channel::Yrotation | Channel::Zrotation
        )
    }

    /// Axis index 0, 1, 2 for X, Y, Z.
    pub fn axis(self) -> usize {
        match self {
            Channel::Xposition | Channel::Xrotation => 0,
            Channel::Yposition | Channel::Yrotation => 1,
            Channel::Zposition | Channel::Zrotation => 2,
        }
    }
}

/// One joint (or End Site) of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Joint name.
    pub name: String,
    /// Index of the parent joint; `None` for the root.
    pub parent: Option<usize>,
    /// Rest offset from the parent.
    pub offset: [f32; 3],
    /// Channels, in file order.
    pub channels: Vec<Channel>,
    /// Index of this joint's first channel within a frame.
    pub channel_start: usize,
    /// True for an End Site.
    pub end_site: bool,
}

/// A parsed BVH file: hierarchy plus motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    /// Joints in file (depth-first) order; parents precede children.
    pub joints: Vec<Joint>,
    /// Seconds per frame.
    pub frame_time: f64,
    /// Channel values, `frames × channel_count`, frame-major.
    pub motion: Vec<f32>,
}

impl Bvh {
    /// Channels per frame.
    pub fn channel_count(&self) -> usize {
        self.joints.iter().map(|j| j.channels.len()).sum()
    }

    /// Number of frames.
    pub fn frame_count(&self) -> usize {
        self.motion
            .len()
            .checked_div(self.channel_count())
            .unwrap_or(0)
    }

    /// The channel values of one frame.
    pub fn frame(&self, f: usize) -> &[f32] {
        let c = self.channel_count();
        &self.motion[f * c..(f + 1) * c]
    }

    /// Frames per second (1 / frame time).
    pub fn fps(&self) -> f64 {
        1.0 / self.frame_time
    }

    /// Index of a joint by name.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Children of each joint.
    pub fn children(&self) -> Vec<Vec<usize>> {
        let mut c = vec![Vec::new(); self.joints.len()];
        for (i, j) in self.joints.iter().enumerate() {
            if let Some(p) = j.parent {
                c[p].push(i);
            }
        }
        c
    }

    /// Parses BVH text.
    pub fn parse(text: &str) -> Result<Bvh> {
        Parser::new(text).parse()
    }

    /// Parses BVH bytes (UTF-8, or Latin-1 fallback for stray bytes).
    pub fn parse_bytes(bytes: &[u8]) -> Result<Bvh> {
        match std::str::from_utf8(bytes) {
            Ok(s) => Self::parse(s),
            Err(_) => Self::parse(&bytes.iter().map(|&b| b as char).collect::<String>()),
        }
    }
}

struct Parser<'a> {
    lines: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'a>>>,
    line_no: usize,
    text_len: usize,
}

/// The most joints (End Sites included) a BVH file may declare. Real
/// skeletons have tens to a few hundred.
pub const MAX_JOINTS: usize = 4096;

fn err<T>(line: usize, message: impl Into<String>) -> Result<T> {
    Err(Error::Parse {
        line,
        message: message.into(),
    })
}

impl<'a> Parser<'a> {
    fn new(text: &'a str) -> Self {
        Parser {
            lines: text.lines().enumerate().peekable(),
            line_no: 0,
            text_len: text.len(),
        }
    }

    /// Next non-empty line, trimmed; `None` at end of input.
    fn next_line(&mut self) -> Option<&'a str> {
        for (i, l) in self.lines.by_ref() {
            let t = l.trim();
            if !t.is_empty() {
                self.line_no = i + 1;
                return Some(t);
            }
        }
        self.line_no += 1;
        None
    }

    fn expect_line(&mut self, what: &str) -> Result<&'a str> {
        match self.next_line() {
            Some(l) => Ok(l),
            None => err(
                self.line_no,
                format!("unexpected end of file; expected {what}"),
            ),
        }
    }

    fn parse_f32(&self, tok: &str, what: &str) -> Result<f32> {
        match tok.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => err(
                self.line_no,
                format!("expected a number for {what}, found '{tok}'"),
            ),
        }
    }

    fn parse(mut self) -> Result<Bvh> {
        let first = self.expect_line("HIERARCHY")?;
        if first != "HIERARCHY" {
            return err(self.line_no, format!("expected HIERARCHY, found '{first}'"));
        }
        let mut joints: Vec<Joint> = Vec::new();
        let mut channel_total = 0usize;
        let line = self.expect_line("ROOT <name>")?;
        let mut toks = line.split_whitespace();
        if toks.next() != Some("ROOT") {
            return err(
                self.line_no,
                format!("expected 'ROOT <name>', found '{line}'"),
            );
        }
        let name = toks.collect::<Vec<_>>().join(" ");
        if name.is_empty() {
            return err(self.line_no, "expected a joint name after ROOT");
        }
        self.parse_hierarchy(&mut joints, name, &mut channel_total)?;
        let line = self.expect_line("MOTION")?;
        if line != "MOTION" {
            return err(
                self.line_no,
                format!("expected MOTION after the hierarchy, found '{line}'"),
            );
        }
        let line = self.expect_line("'Frames: <count>'")?;
        let frames = match line
            .strip_prefix("Frames:")
            .map(str::trim)
            .map(str::parse::<usize>)
        {
            Some(Ok(n)) => n,
            _ => {
                return err(
                    self.line_no,
                    format!("expected 'Frames: <count>', found '{line}'"),
                )
            }
        };
        let line = self.expect_line("'Frame Time: <seconds>'")?;
        let frame_time = match line
            .strip_prefix("Frame Time:")
            .map(str::trim)
            .map(str::parse::<f64>)
        {
            Some(Ok(t)) if t > 0.0 && t.is_finite() => t,
            _ => {
                return err(
                    self.line_no,
                    format!("expected 'Frame Time: <positive seconds>', found '{line}'"),
                )
            }
        };
        // The header's count is not trusted for memory: reserve no more than
        // the rest of the text could hold (a value takes at least two bytes).
        let values = frames
            .checked_mul(channel_total)
            .ok_or_else(|| Error::Parse {
                line: self.line_no,
                message: format!("{frames} frames of {channel_total} channels is too large"),
            })?;
        let mut motion = Vec::with_capacity(values.min(self.text_len / 2));
        for f in 0..frames {
            let line = match self.next_line() {
                Some(l) => l,
                None => {
                    return err(
                        self.line_no,
                        format!("file ends after {f} frames; the header says {frames}"),
                    )
                }
            };
            let before = motion.len();
            for tok in line.split_whitespace() {
                let v = self.parse_f32(tok, "a channel value")?;
                motion.push(v);
            }
            let n = motion.len() - before;
            if n != channel_total {
                return err(
                    self.line_no,
                    format!("frame {f} has {n} values; expected {channel_total} (one per channel)"),
                );
            }
        }
        if let Some(extra) = self.next_line() {
            let preview: String = extra.chars().take(40).collect();
            return err(
                self.line_no,
                format!(
                    "unexpected data after the {frames} frames the header announces: '{preview}'"
                ),
            );
        }
        Ok(Bvh {
            joints,
            frame_time,
            motion,
        })
    }

    /// Reads one joint's (or End Site's) opening: `{`, `OFFSET`, and for a
    /// joint its `CHANNELS` line. Pushes the joint and returns its index.
    fn open_joint(
        &mut self,
        joints: &mut Vec<Joint>,
        name: String,
        parent: Option<usize>,
        end_site: bool,
        channel_total: &mut usize,
    ) -> Result<usize> {
        if joints.len() >= MAX_JOINTS {
            return err(
                self.line_no,
                format!("more than {MAX_JOINTS} joints; deeprep reads skeletons up to that size"),
            );
        }
        let line = self.expect_line("'{'")?;
        if line != "{" {
            return err(
                self.line_no,
                format!("expected '{{' to open joint '{name}', found '{line}'"),
            );
        }
        let line = self.expect_line("OFFSET x y z")?;
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks.len() != 4 || toks[0] != "OFFSET" {
            return err(
                self.line_no,
                format!("expected 'OFFSET x y z' for '{name}', found '{line}'"),
            );
        }
        let offset = [
            self.parse_f32(toks[1], "OFFSET x")?,
            self.parse_f32(toks[2], "OFFSET y")?,
            self.parse_f32(toks[3], "OFFSET z")?,
        ];
        let index = joints.len();
        joints.push(Joint {
            name: name.clone(),
            parent,
            offset,
            channels: Vec::new(),
            channel_start: *channel_total,
            end_site,
        });
        if end_site {
            let line = self.expect_line("'}'")?;
            if line != "}" {
                return err(
                    self.line_no,
                    format!("expected '}}' to close End Site of '{name}', found '{line}'"),
                );
            }
            return Ok(index);
        }
        let line = self.expect_line("CHANNELS")?;
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks.first() != Some(&"CHANNELS") || toks.len() < 2 {
            return err(
                self.line_no,
                format!("expected 'CHANNELS <n> ...' for '{name}', found '{line}'"),
            );
        }
        let listed = toks.len() - 2;
        match toks[1].parse::<usize>() {
            Ok(n) if n == listed => {}
            Ok(n) => {
                return err(
                    self.line_no,
                    format!("CHANNELS says {n} channels but lists {listed}"),
                )
            }
            Err(_) => {
                return err(
                    self.line_no,
                    format!("expected a channel count, found '{}'", toks[1]),
                )
            }
        }
        let mut channels: Vec<Channel> = Vec::with_capacity(listed.min(6));
        for t in &toks[2..] {
            match Channel::parse(t) {
                Some(c) if channels.contains(&c) => {
                    return err(
                        self.line_no,
                        format!("joint '{name}' lists channel {} twice", c.name()),
                    )
                }
                Some(c) => channels.push(c),
                None => {
                    return err(
                        self.line_no,
                        format!("unknown channel '{t}'; expected X/Y/Z position or rotation"),
                    )
                }
            }
        }
        // Each of the six channels at most once (checked above), so a joint
        // has at most three rotation and three position channels.
        *channel_total += channels.len();
        joints[index].channels = channels;
        Ok(index)
    }

    /// The joint tree after `ROOT <name>`, read with an explicit stack of
    /// open joints (no recursion: nesting depth is bounded only by the
    /// joint limit, never by the call stack).
    fn parse_hierarchy(
        &mut self,
        joints: &mut Vec<Joint>,
        root: String,
        channel_total: &mut usize,
    ) -> Result<()> {
        let mut open = vec![self.open_joint(joints, root, None, false, channel_total)?];
        while let Some(&top) = open.last() {
            let line = self.expect_line("JOINT, End Site or '}'")?;
            if line == "}" {
                open.pop();
            } else if let Some(rest) = line.strip_prefix("JOINT") {
                let child = rest.trim().to_string();
                if child.is_empty() {
                    return err(self.line_no, "expected a joint name after JOINT");
                }
                let j = self.open_joint(joints, child, Some(top), false, channel_total)?;
                open.push(j);
            } else if line.starts_with("End Site") || line == "End" {
                let nub = format!("{}_Nub", joints[top].name);
                self.open_joint(joints, nub, Some(top), true, channel_total)?;
            } else {
                let name = &joints[top].name;
                return err(
                    self.line_no,
                    format!("expected JOINT, End Site or '}}' inside '{name}', found '{line}'"),
                );
            }
        }
        Ok(())
    }
}

//! BVH reading and writing.
//!
//! A [`Bvh`] holds the joint tree (End Sites are joints with no channels,
//! named `<parent>_Nub` unless the file names them) and the motion as one
//! flat `f32` array, frame-major. Parsing is a single pass over the text:
//! linear in the file size. Errors name the line and what was expected.

use crate::error::{Error, Result};
use std::fmt::Write as _;

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

    /// Writes BVH text. Values are written in the shortest form that reads
    /// back to the same `f32`, so write → parse is exact.
    pub fn write(&self) -> String {
        let mut s = String::with_capacity(64 * self.joints.len() + 12 * self.motion.len());
        s.push_str("HIERARCHY\n");
        let children = self.children();
        if !self.joints.is_empty() {
            self.write_joint(&mut s, 0, &children);
        }
        let _ = writeln!(
            s,
            "MOTION\nFrames: {}\nFrame Time: {}",
            self.frame_count(),
            self.frame_time
        );
        let c = self.channel_count();
        if c > 0 {
            let mut buf = zmij::Buffer::new();
            for frame in self.motion.chunks(c) {
                for (i, v) in frame.iter().enumerate() {
                    if i > 0 {
                        s.push(' ');
                    }
                    push_display_f32(&mut s, *v, &mut buf);
                }
                s.push('\n');
            }
        }
        s
    }

    /// `original` (the text this clip was parsed from, or a clip with the
    /// same skeleton and frame count) with the frames where `replace(f)`
    /// holds written from `self`, every other byte as it was: what a
    /// partial edit (a gap fill) writes. `None` when `original`'s motion
    /// is not one line a frame (the parser also reads frames that span
    /// lines); write the whole clip then.
    pub fn rewrite_frames(
        &self,
        original: &str,
        replace: &dyn Fn(usize) -> bool,
    ) -> Option<String> {
        let at = original
            .find("\nMOTION")
            .map(|i| i + 1)
            .or_else(|| original.starts_with("MOTION").then_some(0))?;
        let (head, motion) = original.split_at(at);
        // MOTION, Frames:, Frame Time:, then the rows (blank lines skipped)
        let mut lines: Vec<&str> = motion.split_inclusive('\n').collect();
        let first_row = 3;
        let rows: Vec<usize> = (first_row..lines.len())
            .filter(|&i| !lines[i].trim().is_empty())
            .collect();
        let c = self.channel_count();
        if rows.len() != self.frame_count() || lines.len() < first_row {
            return None;
        }
        let mut written: Vec<String> = Vec::new();
        let mut buf = zmij::Buffer::new();
        for (f, &i) in rows.iter().enumerate() {
            if lines[i].split_whitespace().count() != c {
                return None;
            }
            if replace(f) {
                let mut row = String::new();
                for (k, v) in self.frame(f).iter().enumerate() {
                    if k > 0 {
                        row.push(' ');
                    }
                    push_display_f32(&mut row, *v, &mut buf);
                }
                row.push_str(if lines[i].ends_with("\r\n") {
                    "\r\n"
                } else {
                    "\n"
                });
                written.push(row);
            }
        }
        let mut it = written.iter();
        for (f, &i) in rows.iter().enumerate() {
            if replace(f) {
                lines[i] = it.next().map(|s| s.as_str()).unwrap_or(lines[i]);
            }
        }
        Some(format!("{head}{}", lines.concat()))
    }

    /// Writes the joint tree below `root` depth-first with an explicit
    /// stack (no recursion), indenting at most [`MAX_INDENT`] levels.
    fn write_joint(&self, s: &mut String, root: usize, children: &[Vec<usize>]) {
        // (joint, depth, opening): a joint is visited once to open it and
        // once, after its children, to close it.
        let mut stack = vec![(root, 0usize, true)];
        while let Some((j, depth, opening)) = stack.pop() {
            let ind = "  ".repeat(depth.min(MAX_INDENT));
            let joint = &self.joints[j];
            if !opening {
                let _ = writeln!(s, "{ind}}}");
                continue;
            }
            let o = joint.offset;
            if joint.end_site {
                let _ = writeln!(
                    s,
                    "{ind}End Site\n{ind}{{\n{ind}  OFFSET {} {} {}\n{ind}}}",
                    o[0], o[1], o[2]
                );
                continue;
            }
            let kw = if joint.parent.is_none() {
                "ROOT"
            } else {
                "JOINT"
            };
            let _ = writeln!(
                s,
                "{ind}{kw} {}\n{ind}{{\n{ind}  OFFSET {} {} {}",
                joint.name, o[0], o[1], o[2]
            );
            let names: Vec<&str> = joint.channels.iter().map(|c| c.name()).collect();
            let _ = writeln!(s, "{ind}  CHANNELS {} {}", names.len(), names.join(" "));
            stack.push((j, depth, false));
            for &c in children[j].iter().rev() {
                stack.push((c, depth + 1, true));
            }
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

/// Writing indents by depth up to this many levels; deeper joints are
/// written at this indentation (BVH ignores it), so output stays linear in
/// the joint count however deep the tree.
const MAX_INDENT: usize = 32;

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

/// Appends `v` as `{v}` lays it out (Rust's `Display`: the shortest digits
/// that read back to `v`, never an exponent, no trailing ".0"), several
/// times faster: the digits come from Żmij (`zmij`). Where two shortest
/// digit strings are equally near (an exact tie such as 1765629.25), Żmij
/// and `Display` may pick different ones; both read back to `v`. BVH files
/// of long motions are hundreds of thousands of numbers.
pub(crate) fn push_display_f32(s: &mut String, v: f32, buf: &mut zmij::Buffer) {
    if !v.is_finite() {
        let _ = write!(s, "{v}");
        return;
    }
    let text = buf.format_finite(v);
    // bytes, not a char pattern: with `contains(['e', 'E'])`, which decodes
    // every char, a 2,048-frame BVH took 34 ms to write natively, 21 without
    if !text.bytes().any(|b| b == b'e' || b == b'E') {
        // the common case: already laid out, maybe with a ".0" to drop
        s.push_str(text.strip_suffix(".0").unwrap_or(text));
        return;
    }
    let (neg, body) = match text.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, text),
    };
    let (mantissa, exp) = match body.split_once(['e', 'E']) {
        Some((m, e)) => (m, e.parse::<i32>().unwrap_or(0)),
        None => (body, 0),
    };
    // digits and the position of the decimal point among them
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let mut digits: String = String::with_capacity(int.len() + frac.len());
    digits.push_str(int);
    digits.push_str(frac);
    let mut point = int.len() as i32 + exp;
    // drop leading zeros (keeping the point where it is) and trailing zeros
    let lead = digits.len() - digits.trim_start_matches('0').len();
    if lead == digits.len() {
        s.push_str(if neg { "-0" } else { "0" });
        return;
    }
    point -= lead as i32;
    let digits = digits[lead..].trim_end_matches('0');
    if neg {
        s.push('-');
    }
    let n = digits.len() as i32;
    if point <= 0 {
        s.push_str("0.");
        for _ in 0..-point {
            s.push('0');
        }
        s.push_str(digits);
    } else if point >= n {
        s.push_str(digits);
        for _ in 0..point - n {
            s.push('0');
        }
    } else {
        s.push_str(&digits[..point as usize]);
        s.push('.');
        s.push_str(&digits[point as usize..]);
    }
}

#[cfg(test)]
mod tests {
    use super::push_display_f32;

    /// Laid out as `{v}` (no exponent), reads back to `v` exactly, and is no
    /// longer than `{v}`; on special values and a million pseudo-random bit
    /// patterns (every exponent, both signs). Counts the exact ties where
    /// the digits differ from `Display`'s.
    #[test]
    fn fast_float_text_reads_back_and_is_as_short_as_displays() {
        let mut buf = zmij::Buffer::new();
        let mut differ = 0usize;
        let mut check = |v: f32| {
            let mut s = String::new();
            push_display_f32(&mut s, v, &mut buf);
            let d = format!("{v}");
            if v.is_nan() {
                assert_eq!(s, d);
                return;
            }
            assert!(!s.contains(['e', 'E']), "{s}");
            assert_eq!(
                s.parse::<f32>().unwrap().to_bits(),
                v.to_bits(),
                "{s} vs {d}"
            );
            assert!(s.len() <= d.len(), "{s} vs {d}");
            if s != d {
                differ += 1;
            }
        };
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            10.0,
            100.0,
            1e7,
            1.5e-7,
            123.456,
            f32::MAX,
            f32::MIN,
            f32::MIN_POSITIVE,
            1e-45,
            f32::EPSILON,
            56.0,
            -180.0,
            359.99997,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ] {
            check(v);
        }
        let mut x: u64 = 0x9e3779b97f4a7c15;
        for _ in 0..1_000_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            check(f32::from_bits((x >> 32) as u32));
            // typical BVH values: degrees and centimetres with a few decimals
            check(((x & 0xffff) as f32 - 32768.0) * 0.0137);
        }
        eprintln!("{differ} of 2,000,000 differ from Display (exact ties)");
        assert!(differ < 10_000, "{differ} of 2,000,000 differ from Display");
    }
}

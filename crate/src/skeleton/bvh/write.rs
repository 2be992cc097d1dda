//! Writing BVH text: a whole clip in the shortest form that reads back
//! exactly, or a clip's own text with some frames rewritten.

use super::Bvh;
use std::fmt::Write as _;

/// Writing indents by depth up to this many levels; deeper joints are
/// written at this indentation (BVH ignores it), so output stays linear in
/// the joint count however deep the tree.
const MAX_INDENT: usize = 32;

impl Bvh {
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

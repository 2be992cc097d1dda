//! Binary PPM (P6) images as the hair network's input and the CLI's
//! preview output: `hair preview` writes one, `hair reconstruct --image`
//! reads it back (orientation in red and green, segmentation in blue).
//!
//! The reader takes untrusted bytes: each header field is at most
//! [`MAX_FIELD`] bytes of ASCII, the maxval must be followed by exactly one
//! whitespace byte (the P6 rule), and sizes are compared with the file's
//! length before anything is allocated for the pixels.

use crate::error::{Error, Result};

/// The side of the network's input image.
pub const SIDE: usize = 256;

/// The longest header field read (a size or maxval has at most 10 digits).
pub const MAX_FIELD: usize = 16;

/// A 3 × size × size image in [0, 1] as binary PPM (channels as RGB).
pub fn write(image: &[f32], size: usize) -> Result<Vec<u8>> {
    let plane = size * size;
    if image.len() != 3 * plane {
        return Err(Error::Shape {
            what: "PPM image".into(),
            expected: format!("3 x {size} x {size} values"),
            found: format!("{}", image.len()),
        });
    }
    let mut ppm = format!("P6\n{size} {size}\n255\n").into_bytes();
    ppm.reserve(3 * plane);
    for i in 0..plane {
        for c in 0..3 {
            ppm.push((image[c * plane + i].clamp(0.0, 1.0) * 255.0).round() as u8);
        }
    }
    Ok(ppm)
}

/// A header field as the user would read it: printable ASCII as it is,
/// anything else as escapes.
fn shown(field: &[u8]) -> String {
    field.escape_ascii().to_string()
}

/// The network input (3 × 256 × 256, values / 255) from the bytes of a
/// 256 × 256 binary PPM with maxval 255.
pub fn read_network_input(bytes: &[u8]) -> Result<Vec<f32>> {
    let bad = |m: String| Error::Invalid(format!("PPM: {m}"));
    // header: "P6", width, height, maxval, separated by whitespace and comments
    let mut fields: Vec<&[u8]> = Vec::new();
    let mut i = 0;
    while fields.len() < 4 {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        if i < bytes.len() && bytes[i] == b'#' {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let s = i;
        while i < bytes.len() && !bytes[i].is_ascii_whitespace() && bytes[i] != b'#' {
            i += 1;
            if i - s > MAX_FIELD {
                return Err(bad(format!(
                    "header field {} is longer than {MAX_FIELD} bytes (starts '{}'); not a binary PPM (P6) image",
                    fields.len() + 1,
                    shown(&bytes[s..s + MAX_FIELD])
                )));
            }
        }
        if s == i {
            return Err(bad(format!(
                "the header ends after {} of its 4 fields (P6, width, height, maxval); not a binary PPM (P6) image",
                fields.len()
            )));
        }
        fields.push(&bytes[s..i]);
    }
    if fields[0] != b"P6" {
        return Err(bad(format!(
            "expected a binary PPM starting 'P6', found '{}'",
            shown(fields[0])
        )));
    }
    if fields[3] != b"255" {
        return Err(bad(format!(
            "expected maxval 255, found '{}'",
            shown(fields[3])
        )));
    }
    if fields[1] != SIDE.to_string().as_bytes() || fields[2] != SIDE.to_string().as_bytes() {
        return Err(bad(format!(
            "HairNet takes a {SIDE} x {SIDE} orientation image, found '{}' x '{}'",
            shown(fields[1]),
            shown(fields[2])
        )));
    }
    // exactly one whitespace byte after the maxval, then the pixels
    if !bytes.get(i).is_some_and(|b| b.is_ascii_whitespace()) {
        return Err(bad(
            "no whitespace byte after the maxval (the pixel data must follow one)".into(),
        ));
    }
    let data = &bytes[i + 1..];
    let plane = SIDE * SIDE;
    if data.len() != 3 * plane {
        return Err(bad(format!(
            "{SIDE} x {SIDE} RGB needs {} pixel bytes, found {}",
            3 * plane,
            data.len()
        )));
    }
    let mut image = vec![0.0f32; 3 * plane];
    for (p, px) in data.chunks_exact(3).enumerate() {
        for c in 0..3 {
            image[c * plane + p] = px[c] as f32 / 255.0;
        }
    }
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_image_round_trips() {
        let image: Vec<f32> = (0..3 * SIDE * SIDE)
            .map(|i| (i % 256) as f32 / 255.0)
            .collect();
        let back = read_network_input(&write(&image, SIDE).unwrap()).unwrap();
        assert!(back.iter().zip(&image).all(|(a, b)| (a - b).abs() < 1e-6));
    }

    #[test]
    fn odd_headers_are_clear_errors() {
        let pixels = vec![0u8; 3 * SIDE * SIDE];
        let with = |header: &[u8]| [header, &pixels].concat();
        for (bytes, want) in [
            (
                b"P6\n256 256\n255".to_vec(),
                "no whitespace byte after the maxval",
            ),
            (b"P6 256".to_vec(), "ends after 2 of its 4 fields"),
            (with(b"P6\n256 256\n255\xff\xfe"), "longer than"),
            (with(b"P6\n256 256\n2550000000000000000000 "), "longer than"),
            (with(b"P5\n256 256\n255\n"), "starting 'P6'"),
            (with(b"P6\n256 256\n65535\n"), "maxval 255"),
            (with(b"P6\n128 256\n255\n"), "found '128' x '256'"),
        ] {
            let header = &bytes[..bytes.len().min(24)];
            let e = read_network_input(&bytes).unwrap_err().to_string();
            assert!(e.contains(want), "{header:?}: {e}");
            assert!(e.is_ascii() && !e.contains('\u{fffd}'), "{e}");
        }
        let e = read_network_input(b"P6 256 256 255 \x01")
            .unwrap_err()
            .to_string();
        assert!(e.contains("pixel bytes, found 1"), "{e}");
        assert!(read_network_input(b"P6 # a comment\n256 256 255\n")
            .unwrap_err()
            .to_string()
            .contains("found 0"));
    }
}

//! A C1 cubic through scalar keys, used for the generator's spline bases
//! ([`super::dense::spline_channels`]).

/// Cubic Hermite spline through `(time, value)` keys sorted by time, with
/// finite-difference tangents `(v[k+1] - v[k-1]) / (t[k+1] - t[k-1])` and
/// the secant at the first and the last key. With evenly spaced keys this
/// is uniform Catmull-Rom; a line through the keys is reproduced exactly.
/// Held constant before the first and after the last key.
#[derive(Clone, Debug)]
pub struct KeySpline {
    keys: Vec<(f64, f64)>,
    tangents: Vec<f64>,
}

impl KeySpline {
    /// A spline through `keys` (sorted by strictly increasing time; at least one).
    pub fn new(keys: Vec<(f64, f64)>) -> Self {
        let n = keys.len();
        let tangents = (0..n)
            .map(|k| {
                let (lo, hi) = (k.saturating_sub(1), (k + 1).min(n.saturating_sub(1)));
                if lo == hi {
                    0.0
                } else {
                    (keys[hi].1 - keys[lo].1) / (keys[hi].0 - keys[lo].0)
                }
            })
            .collect();
        KeySpline { keys, tangents }
    }

    /// The value at time `t`.
    pub fn at(&self, t: f64) -> f64 {
        let b = self.keys.partition_point(|k| k.0 <= t);
        if b == 0 {
            return self.keys[0].1;
        }
        if b == self.keys.len() {
            return self.keys[b - 1].1;
        }
        let ((ta, va), (tb, vb)) = (self.keys[b - 1], self.keys[b]);
        let h = tb - ta;
        let s = (t - ta) / h;
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * va
            + (s3 - 2.0 * s2 + s) * h * self.tangents[b - 1]
            + (-2.0 * s3 + 3.0 * s2) * vb
            + (s3 - s2) * h * self.tangents[b]
    }
}

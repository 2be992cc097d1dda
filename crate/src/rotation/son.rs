//! General rotations SO(n), orthogonal O(n) and similarity Sim(n) transforms
//! (thesis Sec. 4.3.2, Cases 3 and 4, Fig. 4.4).
//!
//! - Case 3: `g_GS` keeps the first n−1 columns (n²−n numbers); `f_GS` is
//!   Gram-Schmidt on them, with the last column given by the generalized
//!   cross product (eq. 4.5–4.7).
//! - Case 4: up to n−2 normalized projections (eq. 4.8, 4.9) reduce this to as
//!   few as n²−2n+2 numbers. Following Fig. 4.4, projection i (1-based,
//!   i = 1..k) takes basis vector i+1 and prepends the first basis vector's
//!   entry γ_{n+1−i}; the representation is
//!   `[γ_1..γ_{n−k}, P(proj 1), …, P(proj k), basis vectors k+2..n−1]`.
//!   For n = 3, k = 1 this is exactly eq. 4.10.
//! - O(n): any of the above plus one determinant component (positive means
//!   +1); when it is negative the last Gram-Schmidt vector is negated.
//! - Sim(n) `x ↦ αRx + u`: the Case 3 form of `αR` (its norm gives α), the
//!   determinant component, then `u` as is. (The thesis allows Case 4 here as
//!   well; this library implements Sim(n) on Case 3 only.)

use super::Real;
use crate::error::{Error, Result};
use crate::rng::Rng;

/// A square n×n matrix, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct MatN<T> {
    /// Size n.
    pub n: usize,
    /// Row-major entries, length n².
    pub data: Vec<T>,
}

impl<T: Real> MatN<T> {
    /// The n×n identity.
    pub fn identity(n: usize) -> Self {
        let mut data = vec![T::zero(); n * n];
        for i in 0..n {
            data[i * n + i] = T::one();
        }
        MatN { n, data }
    }

    /// Builds a matrix from row-major data; errors when the length is not n².
    pub fn from_rows(n: usize, data: Vec<T>) -> Result<Self> {
        if data.len() != n * n {
            return Err(Error::Shape {
                what: "SO(n) matrix".into(),
                expected: format!("{} numbers (n = {n})", n * n),
                found: format!("{}", data.len()),
            });
        }
        Ok(MatN { n, data })
    }

    /// Entry (row i, column j).
    pub fn get(&self, i: usize, j: usize) -> T {
        self.data[i * self.n + j]
    }

    /// Column j as a vector.
    pub fn column(&self, j: usize) -> Vec<T> {
        (0..self.n).map(|i| self.get(i, j)).collect()
    }

    /// Builds a matrix from columns.
    pub fn from_columns(cols: &[Vec<T>]) -> Self {
        let n = cols.len();
        let mut data = vec![T::zero(); n * n];
        for (j, c) in cols.iter().enumerate() {
            for i in 0..n {
                data[i * n + j] = c[i];
            }
        }
        MatN { n, data }
    }

    /// Transpose.
    pub fn transpose(&self) -> Self {
        let n = self.n;
        let mut data = vec![T::zero(); n * n];
        for i in 0..n {
            for j in 0..n {
                data[j * n + i] = self.data[i * n + j];
            }
        }
        MatN { n, data }
    }

    /// Product `self · other`.
    pub fn mul(&self, other: &Self) -> Self {
        let n = self.n;
        let mut data = vec![T::zero(); n * n];
        for i in 0..n {
            for k in 0..n {
                let a = self.data[i * n + k];
                for j in 0..n {
                    data[i * n + j] = data[i * n + j] + a * other.data[k * n + j];
                }
            }
        }
        MatN { n, data }
    }

    /// Determinant (LU with partial pivoting).
    pub fn det(&self) -> T {
        det_rows(self.n, self.data.clone())
    }

    /// Largest absolute element-wise difference.
    pub fn max_abs_diff(&self, other: &Self) -> T {
        self.data
            .iter()
            .zip(&other.data)
            .fold(T::zero(), |m, (a, b)| m.max((*a - *b).abs()))
    }

    /// A rotation uniform on SO(n) (Haar): Gram-Schmidt of a Gaussian matrix
    /// (Haar on O(n)), with the first column negated when the determinant is −1.
    pub fn random_rotation(n: usize, rng: &mut Rng) -> Self {
        loop {
            let cols: Vec<Vec<T>> = (0..n)
                .map(|_| (0..n).map(|_| T::c(rng.normal())).collect())
                .collect();
            // Gram-Schmidt twice ("twice is enough"): one classical pass
            // loses orthogonality in proportion to the condition number.
            if let Some(mut q) = orthonormalize(&cols).and_then(|q| orthonormalize(&q)) {
                let m = MatN::from_columns(&q);
                if m.det() < T::zero() {
                    for x in q[0].iter_mut() {
                        *x = -*x;
                    }
                    return MatN::from_columns(&q);
                }
                return m;
            }
        }
    }
}

fn det_rows<T: Real>(n: usize, mut a: Vec<T>) -> T {
    let mut det = T::one();
    for c in 0..n {
        let mut p = c;
        for r in c + 1..n {
            if a[r * n + c].abs() > a[p * n + c].abs() {
                p = r;
            }
        }
        if a[p * n + c] == T::zero() {
            return T::zero();
        }
        if p != c {
            for j in 0..n {
                a.swap(c * n + j, p * n + j);
            }
            det = -det;
        }
        let piv = a[c * n + c];
        det = det * piv;
        for r in c + 1..n {
            let f = a[r * n + c] / piv;
            for j in c..n {
                a[r * n + j] = a[r * n + j] - f * a[c * n + j];
            }
        }
    }
    det
}

fn norm<T: Real>(v: &[T]) -> T {
    v.iter().fold(T::zero(), |s, x| s + *x * *x).sqrt()
}

fn orthonormalize<T: Real>(cols: &[Vec<T>]) -> Option<Vec<Vec<T>>> {
    let mut out: Vec<Vec<T>> = Vec::with_capacity(cols.len());
    for a in cols {
        let mut u = a.clone();
        // Classical Gram-Schmidt as in eq. 4.7, with the projections taken
        // against the original a_i.
        for b in &out {
            let d = b.iter().zip(a).fold(T::zero(), |s, (x, y)| s + *x * *y);
            for (ui, bi) in u.iter_mut().zip(b) {
                *ui = *ui - d * *bi;
            }
        }
        let nu = norm(&u);
        if !(nu > T::tiny().sqrt() * (T::one() + norm(a))) {
            return None;
        }
        out.push(u.iter().map(|x| *x / nu).collect());
    }
    Some(out)
}

/// The generalized cross product of n−1 vectors in Rⁿ (the last line of
/// eq. 4.7): the vector of signed cofactors, so that `det[b_1 … b_{n−1}, b_n]`
/// is positive.
pub fn generalized_cross<T: Real>(vs: &[Vec<T>]) -> Vec<T> {
    let n = vs.len() + 1;
    (0..n)
        .map(|k| {
            // Minor: delete row k from the n×(n−1) matrix [v_1 … v_{n−1}].
            let mut m = Vec::with_capacity((n - 1) * (n - 1));
            for i in (0..n).filter(|&i| i != k) {
                for v in vs {
                    m.push(v[i]);
                }
            }
            let minor = det_rows(n - 1, m);
            if (n - 1 + k).is_multiple_of(2) {
                minor
            } else {
                -minor
            }
        })
        .collect()
}

/// g_GS (eq. 4.5): the first n−1 columns, stacked (γ(M), length n²−n).
pub fn matrix_to_gs<T: Real>(m: &MatN<T>) -> Vec<T> {
    (0..m.n - 1).flat_map(|j| m.column(j)).collect()
}

/// f_GS (eq. 4.6–4.7): Gram-Schmidt on n−1 stacked columns, plus the
/// generalized cross product. `a` has length n²−n.
pub fn gs_to_matrix<T: Real>(a: &[T], n: usize) -> Result<MatN<T>> {
    if n < 2 || a.len() != n * (n - 1) {
        return Err(Error::Shape {
            what: "SO(n) Gram-Schmidt representation".into(),
            expected: format!("n >= 2 and n²−n = {} numbers", n * n.saturating_sub(1)),
            found: format!("{}", a.len()),
        });
    }
    if let Some(index) = a.iter().position(|x| !x.is_finite()) {
        return Err(Error::NotFinite {
            what: "SO(n) Gram-Schmidt representation".into(),
            index,
        });
    }
    let cols: Vec<Vec<T>> = a.chunks(n).map(|c| c.to_vec()).collect();
    let mut b = orthonormalize(&cols).ok_or(Error::Degenerate {
        what: "SO(n) Gram-Schmidt representation: columns span fewer than n−1 dimensions".into(),
        index: 0,
    })?;
    let last = generalized_cross(&b);
    b.push(last);
    Ok(MatN::from_columns(&b))
}

/// The normalized projection P of eq. 4.8: Rᵐ → Rᵐ⁻¹, a stereographic
/// projection from (1, 0, …, 0) of `u/|u|`. `out.len()` must be `u.len() − 1`.
pub fn normalized_projection<T: Real>(u: &[T], out: &mut [T]) -> Result<()> {
    let n = norm(u);
    if !(n > T::tiny()) {
        return Err(Error::Degenerate {
            what: "normalized projection of a zero vector".into(),
            index: 0,
        });
    }
    let d = T::one() - u[0] / n;
    if !(d > T::zero()) {
        return Err(Error::Degenerate {
            what: "normalized projection at the projection point".into(),
            index: 0,
        });
    }
    for (o, x) in out.iter_mut().zip(&u[1..]) {
        *o = *x / n / d;
    }
    Ok(())
}

/// The un-projection Q of eq. 4.9: Rᵐ⁻¹ → Rᵐ,
/// `Q(u) = [(|u|² − 1)/2, u_1, …, u_{m−1}] / |u|`, so that coordinates 2..m
/// are a unit vector. `out.len()` must be `u.len() + 1`.
pub fn unprojection<T: Real>(u: &[T], out: &mut [T]) -> Result<()> {
    let n = norm(u);
    if !(n > T::tiny()) {
        return Err(Error::Degenerate {
            what: "stereographic un-projection of a zero vector".into(),
            index: 0,
        });
    }
    out[0] = (n * n - T::one()) / (T::c(2.0) * n);
    for (o, x) in out[1..].iter_mut().zip(u) {
        *o = *x / n;
    }
    Ok(())
}

/// Dimension of the Case 4 representation of SO(n) with k projections:
/// n²−n−k.
pub fn projected_dim(n: usize, k: usize) -> usize {
    n * (n - 1) - k
}

fn check_k(n: usize, k: usize) -> Result<()> {
    if n < 3 || k > n - 2 {
        return Err(Error::Invalid(format!(
            "SO(n) projections: need n >= 3 and k <= n−2 (got n = {n}, k = {k})"
        )));
    }
    Ok(())
}

/// g_P generalized (eq. 4.10 and Fig. 4.4): Case 3 with k normalized
/// projections, 0 ≤ k ≤ n−2. k = 0 is Case 3 itself.
pub fn matrix_to_projected<T: Real>(m: &MatN<T>, k: usize) -> Result<Vec<T>> {
    let n = m.n;
    if k == 0 {
        return Ok(matrix_to_gs(m));
    }
    check_k(n, k)?;
    let g = matrix_to_gs(m);
    let mut out = Vec::with_capacity(projected_dim(n, k));
    out.extend_from_slice(&g[0..n - k]);
    let mut buf = vec![T::zero(); n + 1];
    let mut p = vec![T::zero(); n];
    for i in 1..=k {
        buf[0] = g[n - i]; // γ_{n+1−i}, 1-based
        buf[1..].copy_from_slice(&g[i * n..(i + 1) * n]); // basis vector i+1
        normalized_projection(&buf, &mut p)?;
        out.extend_from_slice(&p);
    }
    out.extend_from_slice(&g[(k + 1) * n..]);
    Ok(out)
}

/// f_P generalized (eq. 4.11): un-project the k groups, then f_GS.
pub fn projected_to_matrix<T: Real>(u: &[T], n: usize, k: usize) -> Result<MatN<T>> {
    if k == 0 {
        return gs_to_matrix(u, n);
    }
    check_k(n, k)?;
    if u.len() != projected_dim(n, k) {
        return Err(Error::Shape {
            what: format!("SO({n}) representation with {k} projections"),
            expected: format!("{} numbers", projected_dim(n, k)),
            found: format!("{}", u.len()),
        });
    }
    if let Some(index) = u.iter().position(|x| !x.is_finite()) {
        return Err(Error::NotFinite {
            what: "SO(n) projected representation".into(),
            index,
        });
    }
    let mut g = vec![T::zero(); n * (n - 1)];
    g[0..n - k].copy_from_slice(&u[0..n - k]);
    let mut q = vec![T::zero(); n + 1];
    for i in 1..=k {
        let start = n - k + (i - 1) * n;
        unprojection(&u[start..start + n], &mut q)?;
        g[n - i] = q[0];
        g[i * n..(i + 1) * n].copy_from_slice(&q[1..]);
    }
    let rest = n - k + k * n;
    g[(k + 1) * n..].copy_from_slice(&u[rest..]);
    gs_to_matrix(&g, n)
}

/// O(n) representation: the Case 3/4 representation of the matrix with its
/// last column sign-corrected, plus a determinant component (±1).
pub fn orthogonal_to_rep<T: Real>(m: &MatN<T>, k: usize) -> Result<Vec<T>> {
    let d = if m.det() < T::zero() {
        -T::one()
    } else {
        T::one()
    };
    let mut r = matrix_to_projected(m, k)?;
    r.push(d);
    Ok(r)
}

/// Inverse of [`orthogonal_to_rep`]: a negative last component negates the
/// last Gram-Schmidt vector, giving determinant −1.
pub fn rep_to_orthogonal<T: Real>(u: &[T], n: usize, k: usize) -> Result<MatN<T>> {
    let Some((d, rest)) = u.split_last() else {
        return Err(Error::Invalid("O(n) representation is empty".into()));
    };
    let mut m = projected_to_matrix(rest, n, k)?;
    if *d < T::zero() {
        for i in 0..n {
            m.data[i * n + n - 1] = -m.data[i * n + n - 1];
        }
    }
    Ok(m)
}

/// A similarity transform `x ↦ α R x + u` with `α > 0` and R orthogonal.
#[derive(Clone, Debug, PartialEq)]
pub struct Similarity<T> {
    /// Scale α > 0.
    pub alpha: T,
    /// Orthogonal part R (determinant ±1).
    pub rot: MatN<T>,
    /// Translation u.
    pub trans: Vec<T>,
}

/// Sim(n) representation: `[γ(αR) (n²−n), det component, u (n)]`.
pub fn similarity_to_rep<T: Real>(s: &Similarity<T>) -> Vec<T> {
    let n = s.rot.n;
    let d = if s.rot.det() < T::zero() {
        -T::one()
    } else {
        T::one()
    };
    let mut r: Vec<T> = matrix_to_gs(&s.rot).iter().map(|x| *x * s.alpha).collect();
    r.push(d);
    r.extend_from_slice(&s.trans[..n]);
    r
}

/// Inverse of [`similarity_to_rep`]: α = |a_1|, R from f_GS (sign-corrected).
pub fn rep_to_similarity<T: Real>(u: &[T], n: usize) -> Result<Similarity<T>> {
    let m = n * (n - 1);
    if u.len() != m + 1 + n {
        return Err(Error::Shape {
            what: format!("Sim({n}) representation"),
            expected: format!("{} numbers", m + 1 + n),
            found: format!("{}", u.len()),
        });
    }
    let alpha = norm(&u[0..n]);
    let rot = rep_to_orthogonal(&u[0..m + 1], n, 0)?;
    Ok(Similarity {
        alpha,
        rot,
        trans: u[m + 1..].to_vec(),
    })
}

//! Which matrix kernel tract runs our networks' products with in wasm
//! (issue 23).
//!
//! tract-linalg 0.23.9 runs every f32 matrix product in wasm with its
//! `wasm_f32_8x8` kernel: 16 `v128` accumulators, and per step of the inner
//! dimension two vectors of each operand and a broadcast on top. That is
//! more than the 15 SIMD registers V8 allocates on x86-64 (16, one kept as
//! scratch), so V8 spills in the inner loop; tract chose the tile on ARM64,
//! where V8 has 32. [`OWN_KERNEL`], registered with tract-linalg through its
//! public registries (`mmm_routines` for the kernel, `mmm_tiers` for a
//! dispatch tier above tract's own), is a 3x12 tile: 9 accumulators, three
//! vectors of the data side and one broadcast weight, 13 registers. In
//! headless Chromium on x86-64 (relaxed SIMD, the bundled residual network,
//! tract's tile against tiles of 2x8 to 8x4 in one page, in turn) it was the
//! fastest: 0.65-0.82x tract's time at 1,024-4,096 frames, with the same
//! output bit for bit (`docs/experiments/bench_matmul_kernels.mjs`,
//! `matmul_tiles_2026-12-04.jsonl`;
//! tiles with 15 registers or more, 6x8, 4x12, 5x8, 3x16, 2x20, were no
//! faster than tract's).
//!
//! The better tile depends on the machine under the browser and on the
//! product: on our convolutional networks' products ours ran 0.75-0.83x
//! tract's time, on the IK network's 0.74x, and it lost where products are
//! narrow (the mesh autoencoder's, 8-32 columns, which tract's 8-wide tile
//! fits exactly), so it takes products of at least [`MIN_COLUMNS`] columns
//! or of a width known only when run (a frame count). A wasm module cannot
//! ask which CPU it runs on, and timing both kernels on one product when the
//! module loads proved no guide (on the residual network's blocks' shape,
//! alone, the two were within 10% of each other, while inside the network
//! ours was 25% faster). So under [`Policy::Auto`] (the default) [`choose`]
//! asks the hardware indirectly ([`host_is_x86`]): on x86-64 ours runs,
//! elsewhere tract's (tuned on ARM64, where V8 has 32 vector registers).
//! [`set_policy`] overrides it (`OnnxModel.setMatmulKernel` in JS). Natively
//! tract's assembly kernels run and nothing here applies.
//!
//! [`gemm_plan`] (one constant-times-input product as a tract plan) and
//! [`plan_kernels`] are plain tract code, for the tests.

use crate::error::{Error, Result};
use std::sync::Mutex;
use tract_onnx::prelude::*;
use tract_onnx::tract_core::ops::einsum::EinSum;
use tract_onnx::tract_core::plan::SimpleState;

/// The name tract-linalg knows [`OWN_KERNEL`]'s kernel by.
pub const OWN_KERNEL: &str = "deeprep_wasm_f32_3x12";
/// tract-linalg's own wasm f32 matrix kernel.
pub const TRACT_KERNEL: &str = "wasm_f32_8x8";

/// Which kernel plans optimized from now on use for f32 products.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Policy {
    /// [`OWN_KERNEL`] on x86-64 hosts, tract's elsewhere (the default).
    Auto,
    /// [`OWN_KERNEL`] for products of [`MIN_COLUMNS`] columns or more.
    Own,
    /// tract's own choice ([`TRACT_KERNEL`] for products).
    Tract,
}

/// What [`choose`] decided, and why.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Choice {
    /// The kernel wide f32 products use: [`OWN_KERNEL`] or [`TRACT_KERNEL`].
    pub kernel: &'static str,
    /// `"x86-64 host"` or `"other host"` ([`Policy::Auto`]), `"own"` or
    /// `"tract"` (fixed by [`set_policy`]), `"not wasm"`.
    pub by: &'static str,
}

/// The fewest columns (of a width known when the plan is optimized) a
/// product needs for [`OWN_KERNEL`]: narrower ones waste much of its
/// 12-wide tile (16 columns: a third) where tract's 8-wide fits.
pub const MIN_COLUMNS: usize = 64;

struct State {
    policy: Policy,
    choice: Option<Choice>,
}

static STATE: Mutex<State> = Mutex::new(State {
    policy: Policy::Auto,
    choice: None,
});

/// Whether the dispatch tier answers with [`OWN_KERNEL`] now (read by
/// tract while it optimizes a plan: an atomic, so that tract's dispatch
/// never waits on [`STATE`]'s lock).
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
static USE_OWN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

fn use_own(on: bool) {
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    USE_OWN.store(on, std::sync::atomic::Ordering::Relaxed);
    #[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
    let _ = on;
}

/// Whether this build has [`OWN_KERNEL`] (wasm with SIMD).
pub const AVAILABLE: bool = cfg!(all(target_arch = "wasm32", target_feature = "simd128"));

/// Fixes the kernel of plans optimized from now on (`Own`, `Tract`), or
/// (`Auto`) lets the next [`choose`] decide again. Plans already built
/// keep theirs.
pub fn set_policy(policy: Policy) {
    if let Ok(mut s) = STATE.lock() {
        s.policy = policy;
        s.choice = None;
    }
    use_own(false);
    if policy != Policy::Auto {
        // fixed now, also for plans optimized outside runtime::Model (gemm_plan)
        let _ = choose();
    }
}

/// Decides the kernel once (until [`set_policy`]); the runtime calls it
/// before it optimizes a plan. Under `Auto`: [`OWN_KERNEL`] where
/// [`host_is_x86`], tract's elsewhere.
pub fn choose() -> Result<Choice> {
    let mut s = STATE
        .lock()
        .map_err(|_| Error::Model("the matrix-kernel choice's lock".into()))?;
    if let Some(c) = &s.choice {
        return Ok(c.clone());
    }
    let (kernel, by) = match (AVAILABLE, s.policy) {
        (false, _) => (TRACT_KERNEL, "not wasm"),
        (true, Policy::Own) => (OWN_KERNEL, "own"),
        (true, Policy::Tract) => (TRACT_KERNEL, "tract"),
        (true, Policy::Auto) if host_is_x86() => (OWN_KERNEL, "x86-64 host"),
        (true, Policy::Auto) => (TRACT_KERNEL, "other host"),
    };
    let c = Choice { kernel, by };
    use_own(kernel == OWN_KERNEL);
    s.choice = Some(c.clone());
    Ok(c)
}

/// Whether the hardware under this code looks like x86-64: its 0/0 is a
/// NaN with the sign bit set (x86's "indefinite"), where ARM64 and RISC-V
/// give a positive one. wasm leaves a NaN's sign to the hardware, and V8
/// runs `f32.div` as the CPU's divide. A guess for speed, never used for
/// correctness.
pub fn host_is_x86() -> bool {
    let (zero, also_zero) = std::hint::black_box((0.0f32, 0.0f32));
    (zero / also_zero).to_bits() >> 31 == 1
}

/// A plan of one product `weights · x`: `weights` a constant `m` x `k`
/// (row-major), `x` the input, `k` x `n`; optimized as tract optimizes a
/// network's (an `OptMatMul` with the weights packed once).
pub fn gemm_plan(
    weights: &[f32],
    m: usize,
    k: usize,
    n: usize,
) -> Result<std::sync::Arc<TypedSimplePlan>> {
    let err = |e: TractError| Error::Model(e.to_string());
    let mut model = TypedModel::default();
    let w = Tensor::from_shape(&[m, k], weights).map_err(err)?;
    let w = model.add_const("weights", w).map_err(err)?;
    let x = model.add_source("x", f32::fact([k, n])).map_err(err)?;
    let y = model
        .wire_node(
            "product",
            EinSum::new("mk,kn->mn".parse().map_err(err)?, f32::datum_type()),
            &[w, x],
        )
        .map_err(err)?;
    model.select_output_outlets(&y).map_err(err)?;
    model
        .into_optimized()
        .map_err(err)?
        .into_runnable()
        .map_err(err)
}

/// Runs a [`gemm_plan`] on `x` (`k` x `n`, row-major); returns the
/// product, `m` x `n`, row-major.
pub fn run_gemm(
    plan: &std::sync::Arc<TypedSimplePlan>,
    x: &[f32],
    k: usize,
    n: usize,
) -> Result<Vec<f32>> {
    let err = |e: TractError| Error::Model(e.to_string());
    let x = Tensor::from_shape(&[k, n], x).map_err(err)?.into_tvalue();
    let y = SimpleState::new(plan)
        .and_then(|mut s| s.run(tvec!(x)))
        .map_err(err)?;
    let y = y
        .first()
        .ok_or_else(|| Error::Model("the product has no output".into()))?;
    Ok(y.to_plain_array_view::<f32>()
        .map_err(err)?
        .iter()
        .copied()
        .collect())
}

/// The names of the matrix kernels a plan's products run with.
pub fn plan_kernels(plan: &TypedSimplePlan) -> Vec<String> {
    plan.model()
        .nodes
        .iter()
        .filter_map(kernel_names)
        .flatten()
        .map(str::to_string)
        .collect()
}

/// The matrix kernel a plan node runs its product with (tract-linalg's
/// name; several joined by `+` where tract keeps one per case of a
/// symbolic size), or `None` for a node that is not a matrix product.
pub fn node_kernel(node: &TypedNode) -> Option<String> {
    kernel_names(node).map(|names| names.collect::<Vec<_>>().join("+"))
}

/// tract-linalg's names of a product node's kernels; `None` for other nodes.
fn kernel_names(node: &TypedNode) -> Option<impl Iterator<Item = &str>> {
    use tract_onnx::tract_core::ops::matmul::optimized::OptMatMul;
    node.op_as::<OptMatMul>()
        .map(|op| op.mmm.iter().map(|k| k.name()))
}

#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod wasm_kernel {
    //! [`super::OWN_KERNEL`] and the dispatch tier that picks it.
    use super::{MIN_COLUMNS, OWN_KERNEL, USE_OWN};
    use std::arch::wasm32::*;
    use std::sync::atomic::Ordering;
    use std::sync::LazyLock;
    use tract_onnx::prelude::DatumType;
    use tract_onnx::tract_core::tract_linalg::isa::{Arch, IsaSet};
    use tract_onnx::tract_core::tract_linalg::mmm::{
        DynKernel, FusedKerSpec, MatMatMul, Query, Suitable,
    };
    use tract_onnx::tract_core::tract_linalg::mmm_routines::MmmRoutine;
    use tract_onnx::tract_core::tract_linalg::mmm_tiers::MmmTier;
    use tract_onnx::tract_core::tract_linalg::pack::Packing;
    use tract_onnx::tract_core::tract_linalg::Scaler;

    /// Rows of the weights per tile.
    const MR: usize = 3;
    /// `v128` vectors of data columns per tile (12 columns).
    const NV: usize = 3;

    /// Answers f32 products of [`MIN_COLUMNS`] columns or more (or of a
    /// width unknown until run) with our kernel while [`USE_OWN`] is set;
    /// otherwise leaves them to tract's tier below (its gemv kernels for
    /// one column, its 8x8 for the rest).
    fn preferred(_: &IsaSet, dt: DatumType, q: &Query, _: &[Suitable]) -> Option<&'static str> {
        let wide = q.n.is_none_or(|n| n >= MIN_COLUMNS);
        (dt == DatumType::F32 && wide && USE_OWN.load(Ordering::Relaxed)).then_some(OWN_KERNEL)
    }

    inventory::submit! {
        MmmTier {
            arch: Some(Arch::Wasm32Simd128),
            precedence: 2,
            name: "deeprep",
            applies: |_| true,
            preferred,
        }
    }

    #[cfg(target_feature = "relaxed-simd")]
    #[inline(always)]
    fn madd(acc: v128, a: v128, b: v128) -> v128 {
        f32x4_relaxed_madd(a, b, acc)
    }

    #[cfg(not(target_feature = "relaxed-simd"))]
    #[inline(always)]
    fn madd(acc: v128, a: v128, b: v128) -> v128 {
        f32x4_add(acc, f32x4_mul(a, b))
    }

    /// `f(row, vector, accumulator)` on every accumulator.
    #[inline(always)]
    fn each(acc: &mut [[v128; NV]; MR], f: impl Fn(usize, usize, v128) -> v128) {
        for (r, row) in acc.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = f(r, j, *v);
            }
        }
    }

    /// tract's kernel contract: runs the fused operations in `spec` on an
    /// MR x 4 NV tile of accumulators. The weights (A) come packed `[k][MR]`
    /// and are broadcast one at a time (`v128.load32_splat`); the data (B)
    /// packed `[k][4 NV]`, read as NV vectors.
    ///
    /// # Safety
    /// The pointers in `spec` are tract's, valid for the tile's shape.
    unsafe fn kernel(spec: &[FusedKerSpec<f32>]) -> isize {
        let mut acc = [[f32x4_splat(0.0); NV]; MR];
        // SAFETY (every arm): tract passes pointers to tiles, rows and
        // columns of this kernel's MR x 4 NV shape (its packings below).
        unsafe {
            for s in spec {
                match *s {
                    FusedKerSpec::Done => break,
                    FusedKerSpec::Clear => acc = [[f32x4_splat(0.0); NV]; MR],
                    FusedKerSpec::LoadTile(_cols, rows) => {
                        let p = rows as *const v128;
                        each(&mut acc, |r, j, _| v128_load(p.add(r * NV + j)));
                    }
                    FusedKerSpec::ScalarMin(a) => {
                        each(&mut acc, |_, _, v| f32x4_min(f32x4_splat(a), v))
                    }
                    FusedKerSpec::ScalarMax(a) => {
                        each(&mut acc, |_, _, v| f32x4_max(f32x4_splat(a), v))
                    }
                    FusedKerSpec::ScalarAdd(a) => {
                        each(&mut acc, |_, _, v| f32x4_add(f32x4_splat(a), v))
                    }
                    FusedKerSpec::ScalarMul(a) => {
                        each(&mut acc, |_, _, v| f32x4_mul(f32x4_splat(a), v))
                    }
                    FusedKerSpec::ScalarSub(a) => {
                        each(&mut acc, |_, _, v| f32x4_sub(f32x4_splat(a), v))
                    }
                    FusedKerSpec::ScalarSubF(a) => {
                        each(&mut acc, |_, _, v| f32x4_sub(v, f32x4_splat(a)))
                    }
                    FusedKerSpec::LeakyRelu(a) => each(&mut acc, |_, _, v| {
                        v128_bitselect(
                            v,
                            f32x4_mul(f32x4_splat(a), v),
                            f32x4_gt(v, f32x4_splat(0.0)),
                        )
                    }),
                    FusedKerSpec::PerRowMin(p) => {
                        each(&mut acc, |r, _, v| f32x4_min(f32x4_splat(*p.add(r)), v))
                    }
                    FusedKerSpec::PerRowMax(p) => {
                        each(&mut acc, |r, _, v| f32x4_max(f32x4_splat(*p.add(r)), v))
                    }
                    FusedKerSpec::PerRowAdd(p) => {
                        each(&mut acc, |r, _, v| f32x4_add(f32x4_splat(*p.add(r)), v))
                    }
                    FusedKerSpec::PerRowMul(p) => {
                        each(&mut acc, |r, _, v| f32x4_mul(f32x4_splat(*p.add(r)), v))
                    }
                    FusedKerSpec::PerRowSub(p) => {
                        each(&mut acc, |r, _, v| f32x4_sub(f32x4_splat(*p.add(r)), v))
                    }
                    FusedKerSpec::PerRowSubF(p) => {
                        each(&mut acc, |r, _, v| f32x4_sub(v, f32x4_splat(*p.add(r))))
                    }
                    FusedKerSpec::PerColMin(p) => each(&mut acc, |_, j, v| {
                        f32x4_min(v128_load((p as *const v128).add(j)), v)
                    }),
                    FusedKerSpec::PerColMax(p) => each(&mut acc, |_, j, v| {
                        f32x4_max(v128_load((p as *const v128).add(j)), v)
                    }),
                    FusedKerSpec::PerColAdd(p) => each(&mut acc, |_, j, v| {
                        f32x4_add(v128_load((p as *const v128).add(j)), v)
                    }),
                    FusedKerSpec::PerColMul(p) => each(&mut acc, |_, j, v| {
                        f32x4_mul(v128_load((p as *const v128).add(j)), v)
                    }),
                    FusedKerSpec::PerColSub(p) => each(&mut acc, |_, j, v| {
                        f32x4_sub(v128_load((p as *const v128).add(j)), v)
                    }),
                    FusedKerSpec::PerColSubF(p) => each(&mut acc, |_, j, v| {
                        f32x4_sub(v, v128_load((p as *const v128).add(j)))
                    }),
                    FusedKerSpec::QScale(shift, rp, mult) => {
                        let s = Scaler::from_fuse_params(shift, rp, mult).scale;
                        each(&mut acc, |_, _, v| f32x4_mul(f32x4_splat(s), v))
                    }
                    FusedKerSpec::RoundingShiftRight(shift, _) => {
                        let s = 2f32.powi(-(shift as i32));
                        each(&mut acc, |_, _, v| f32x4_mul(f32x4_splat(s), v))
                    }
                    FusedKerSpec::ShiftLeft(shift) => {
                        let s = 2f32.powi(shift as i32);
                        each(&mut acc, |_, _, v| f32x4_mul(f32x4_splat(s), v))
                    }
                    FusedKerSpec::AddRowColProducts(rows, cols) => each(&mut acc, |r, j, v| {
                        madd(
                            v,
                            f32x4_splat(*rows.add(r)),
                            v128_load((cols as *const v128).add(j)),
                        )
                    }),
                    FusedKerSpec::AddUnicast(tile) => each(&mut acc, |r, j, v| {
                        let at = |c: usize| {
                            *(tile.ptr.offset(
                                tile.row_byte_stride * r as isize
                                    + tile.col_byte_stride * c as isize,
                            ) as *const f32)
                        };
                        f32x4_add(
                            f32x4(at(4 * j), at(4 * j + 1), at(4 * j + 2), at(4 * j + 3)),
                            v,
                        )
                    }),
                    FusedKerSpec::Store(tile) => {
                        for (r, row) in acc.iter().enumerate() {
                            let p = tile.ptr.offset(tile.row_byte_stride * r as isize);
                            for (j, v) in row.iter().enumerate() {
                                if tile.col_byte_stride == 4 {
                                    v128_store(p.add(16 * j) as *mut v128, *v);
                                } else {
                                    let c = |l: usize| {
                                        p.offset(tile.col_byte_stride * (4 * j + l) as isize)
                                            as *mut f32
                                    };
                                    *c(0) = f32x4_extract_lane::<0>(*v);
                                    *c(1) = f32x4_extract_lane::<1>(*v);
                                    *c(2) = f32x4_extract_lane::<2>(*v);
                                    *c(3) = f32x4_extract_lane::<3>(*v);
                                }
                            }
                        }
                    }
                    FusedKerSpec::AddMatMul { k, pa, pb, .. } => {
                        let a = pa as *const u32;
                        let b = pb as *const v128;
                        for i in 0..k {
                            let mut bv = [f32x4_splat(0.0); NV];
                            for (j, v) in bv.iter_mut().enumerate() {
                                *v = v128_load(b.add(i * NV + j));
                            }
                            for (r, row) in acc.iter_mut().enumerate() {
                                let s = v128_load32_splat(a.add(i * MR + r));
                                for (v, bj) in row.iter_mut().zip(&bv) {
                                    *v = madd(*v, s, *bj);
                                }
                            }
                        }
                    }
                }
            }
        }
        0
    }

    static KERNEL: LazyLock<DynKernel<MR, { 4 * NV }, f32>> = LazyLock::new(|| {
        let mut k = DynKernel::<MR, { 4 * NV }, f32>::new(
            OWN_KERNEL,
            kernel,
            f32::packing(MR).align(16),
            f32::packing(4 * NV).align(16),
        );
        k.arch = Some(Arch::Wasm32Simd128);
        k
    });

    fn make() -> Box<dyn MatMatMul> {
        KERNEL.mmm()
    }

    inventory::submit! { MmmRoutine { make } }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gemm_plan_computes_the_product() {
        let (m, k, n) = (5, 7, 13);
        let w: Vec<f32> = (0..m * k).map(|i| (i as f32 * 0.37).sin()).collect();
        let x: Vec<f32> = (0..k * n).map(|i| (i as f32 * 0.11).cos()).collect();
        let plan = gemm_plan(&w, m, k, n).unwrap();
        let y = run_gemm(&plan, &x, k, n).unwrap();
        for r in 0..m {
            for c in 0..n {
                let want: f32 = (0..k).map(|i| w[r * k + i] * x[i * n + c]).sum();
                assert!(
                    (y[r * n + c] - want).abs() < 1e-5,
                    "({r}, {c}): {} vs {want}",
                    y[r * n + c]
                );
            }
        }
        assert!(
            !plan_kernels(&plan).is_empty(),
            "the product ran as an OptMatMul"
        );
    }

    #[test]
    fn the_host_probe_knows_this_cpu() {
        #[cfg(target_arch = "x86_64")]
        assert!(host_is_x86());
        #[cfg(any(target_arch = "aarch64", target_arch = "riscv64"))]
        assert!(!host_is_x86());
    }

    #[test]
    fn natively_tracts_kernels_run() {
        let c = choose().unwrap();
        assert_eq!(c.kernel, TRACT_KERNEL);
        assert_eq!(c.by, "not wasm");
    }
}

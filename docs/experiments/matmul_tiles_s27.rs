// Issue 23 experiment (session 27, not part of the package): the tiles
// tried against tract's wasm_f32_8x8 before runtime::matmul_kernel adopted
// 3x12. This is docs/experiments/wasm_matmul_kernels.patch's
// crate/src/runtime/matmul_tier.rs with tiles 4-14 added (the knob
// OnnxModel.setMatmulTile: 4 2x16, 5 4x8, 6 8x4, 7 3x12, 8 2x12, 9 1x16,
// 10 2x8, 11 5x8, 12 3x16, 13 2x20, 14 3x8). To rerun: `git checkout
// 7da4d25`, `git apply docs/experiments/wasm_matmul_kernels.patch`, copy
// this file over crate/src/runtime/matmul_tier.rs, build the relaxed core
// (scripts/build-relaxed-core.sh) and run
// docs/experiments/bench_matmul_kernels.mjs with its `tiles` list edited.
// Results: docs/experiments/matmul_tiles_2026-12-04.jsonl.
//! Which matrix kernel runs our convolutions in wasm (issue 23).
//!
//! EXPERIMENT: a dispatch tier (tract-linalg's public `mmm_tiers` registry)
//! above tract's own wasm tier, choosing by a knob, and kernels of our own
//! registered through tract-linalg's public `mmm_routines` registry.

use std::arch::wasm32::*;
use std::sync::atomic::{AtomicU32, AtomicU8, Ordering};
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

static TILE: AtomicU8 = AtomicU8::new(0);
static ANSWERED: AtomicU32 = AtomicU32::new(0);
static STORES: AtomicU32 = AtomicU32::new(0);

/// 0: tract's choice; 1: tract's 4x16; 2: our 6x8; 3: our 4x12. Returns
/// how many output tiles our two kernels have stored so far (that they ran).
pub fn set_tile(t: u8) -> u32 {
    TILE.store(t, Ordering::Relaxed);
    STORES.load(Ordering::Relaxed)
}

fn preferred(_: &IsaSet, dt: DatumType, q: &Query, _: &[Suitable]) -> Option<&'static str> {
    if dt != DatumType::F32 {
        return None;
    }
    let wide = q.n.is_none_or(|n| n >= 16);
    let name = match TILE.load(Ordering::Relaxed) {
        1 if wide => "wasm_f32_4x16",
        2 if wide => "deeprep_wasm_f32_6x8",
        3 if wide => "deeprep_wasm_f32_4x12",
        4 if wide => "deeprep_wasm_f32_2x16",
        5 if wide => "deeprep_wasm_f32_4x8",
        6 => "deeprep_wasm_f32_8x4",
        7 if wide => "deeprep_wasm_f32_3x12",
        8 if wide => "deeprep_wasm_f32_2x12",
        9 if wide => "deeprep_wasm_f32_1x16",
        10 if wide => "deeprep_wasm_f32_2x8",
        11 if wide => "deeprep_wasm_f32_5x8",
        12 if wide => "deeprep_wasm_f32_3x16",
        13 if wide => "deeprep_wasm_f32_2x20",
        14 if wide => "deeprep_wasm_f32_3x8",
        _ => return None,
    };
    ANSWERED.fetch_add(1, Ordering::Relaxed);
    Some(name)
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

#[inline(always)]
unsafe fn each<const MR: usize, const NV: usize>(
    acc: &mut [[v128; NV]; MR],
    f: impl Fn(usize, usize, v128) -> v128,
) {
    for (r, row) in acc.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = f(r, j, *v);
        }
    }
}

/// An MR x (4 NV) f32 kernel: MR rows of NV v128 accumulators, A (the
/// weights, packed [k][MR]) broadcast by `v128.load32_splat`, B (packed
/// [k][4 NV]) read as NV vectors.
unsafe fn kernel<const MR: usize, const NV: usize>(spec: &[FusedKerSpec<f32>]) -> isize {
    let mut acc = [[f32x4_splat(0.0); NV]; MR];
    unsafe {
        for s in spec {
            match *s {
                FusedKerSpec::Done => break,
                FusedKerSpec::Clear => acc = [[f32x4_splat(0.0); NV]; MR],
                FusedKerSpec::LoadTile(_cols, rows) => {
                    let p = rows as *const v128;
                    each(&mut acc, |r, j, _| v128_load(p.add(r * NV + j)));
                }
                FusedKerSpec::ScalarMin(a) => each(&mut acc, |_, _, v| f32x4_min(f32x4_splat(a), v)),
                FusedKerSpec::ScalarMax(a) => each(&mut acc, |_, _, v| f32x4_max(f32x4_splat(a), v)),
                FusedKerSpec::ScalarAdd(a) => each(&mut acc, |_, _, v| f32x4_add(f32x4_splat(a), v)),
                FusedKerSpec::ScalarMul(a) => each(&mut acc, |_, _, v| f32x4_mul(f32x4_splat(a), v)),
                FusedKerSpec::ScalarSub(a) => each(&mut acc, |_, _, v| f32x4_sub(f32x4_splat(a), v)),
                FusedKerSpec::ScalarSubF(a) => each(&mut acc, |_, _, v| f32x4_sub(v, f32x4_splat(a))),
                FusedKerSpec::LeakyRelu(a) => each(&mut acc, |_, _, v| {
                    v128_bitselect(v, f32x4_mul(f32x4_splat(a), v), f32x4_gt(v, f32x4_splat(0.0)))
                }),
                FusedKerSpec::PerRowMin(p) => each(&mut acc, |r, _, v| f32x4_min(f32x4_splat(*p.add(r)), v)),
                FusedKerSpec::PerRowMax(p) => each(&mut acc, |r, _, v| f32x4_max(f32x4_splat(*p.add(r)), v)),
                FusedKerSpec::PerRowAdd(p) => each(&mut acc, |r, _, v| f32x4_add(f32x4_splat(*p.add(r)), v)),
                FusedKerSpec::PerRowMul(p) => each(&mut acc, |r, _, v| f32x4_mul(f32x4_splat(*p.add(r)), v)),
                FusedKerSpec::PerRowSub(p) => each(&mut acc, |r, _, v| f32x4_sub(f32x4_splat(*p.add(r)), v)),
                FusedKerSpec::PerRowSubF(p) => each(&mut acc, |r, _, v| f32x4_sub(v, f32x4_splat(*p.add(r)))),
                FusedKerSpec::PerColMin(p) => each(&mut acc, |_, j, v| f32x4_min(v128_load((p as *const v128).add(j)), v)),
                FusedKerSpec::PerColMax(p) => each(&mut acc, |_, j, v| f32x4_max(v128_load((p as *const v128).add(j)), v)),
                FusedKerSpec::PerColAdd(p) => each(&mut acc, |_, j, v| f32x4_add(v128_load((p as *const v128).add(j)), v)),
                FusedKerSpec::PerColMul(p) => each(&mut acc, |_, j, v| f32x4_mul(v128_load((p as *const v128).add(j)), v)),
                FusedKerSpec::PerColSub(p) => each(&mut acc, |_, j, v| f32x4_sub(v128_load((p as *const v128).add(j)), v)),
                FusedKerSpec::PerColSubF(p) => each(&mut acc, |_, j, v| f32x4_sub(v, v128_load((p as *const v128).add(j)))),
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
                    madd(v, f32x4_splat(*rows.add(r)), v128_load((cols as *const v128).add(j)))
                }),
                FusedKerSpec::AddUnicast(tile) => each(&mut acc, |r, j, v| {
                    let at = |c: usize| {
                        *(tile.ptr.offset(tile.row_byte_stride * r as isize + tile.col_byte_stride * c as isize)
                            as *const f32)
                    };
                    f32x4_add(f32x4(at(4 * j), at(4 * j + 1), at(4 * j + 2), at(4 * j + 3)), v)
                }),
                FusedKerSpec::Store(tile) => {
                    STORES.fetch_add(1, Ordering::Relaxed);
                    for (r, row) in acc.iter().enumerate() {
                        let p = tile.ptr.offset(tile.row_byte_stride * r as isize);
                        for (j, v) in row.iter().enumerate() {
                            if tile.col_byte_stride == 4 {
                                v128_store(p.add(16 * j) as *mut v128, *v);
                            } else {
                                let c = |l: usize| p.offset(tile.col_byte_stride * (4 * j + l) as isize) as *mut f32;
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
                        for r in 0..MR {
                            let s = v128_load32_splat(a.add(i * MR + r));
                            for j in 0..NV {
                                acc[r][j] = madd(acc[r][j], s, bv[j]);
                            }
                        }
                    }
                }
            }
        }
    }
    0
}

static K6X8: LazyLock<DynKernel<6, 8, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<6, 8, f32>::new(
        "deeprep_wasm_f32_6x8",
        kernel::<6, 2>,
        f32::packing(6).align(16),
        f32::packing(8).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

static K4X12: LazyLock<DynKernel<4, 12, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<4, 12, f32>::new(
        "deeprep_wasm_f32_4x12",
        kernel::<4, 3>,
        f32::packing(4).align(16),
        f32::packing(12).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k6x8() -> Box<dyn MatMatMul> {
    K6X8.mmm()
}

fn k4x12() -> Box<dyn MatMatMul> {
    K4X12.mmm()
}

inventory::submit! { MmmRoutine { make: k6x8 } }
inventory::submit! { MmmRoutine { make: k4x12 } }

static K2X16: LazyLock<DynKernel<2, 16, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<2, 16, f32>::new(
        "deeprep_wasm_f32_2x16",
        kernel::<2, 4>,
        f32::packing(2).align(16),
        f32::packing(16).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

static K4X8: LazyLock<DynKernel<4, 8, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<4, 8, f32>::new(
        "deeprep_wasm_f32_4x8",
        kernel::<4, 2>,
        f32::packing(4).align(16),
        f32::packing(8).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

static K8X4: LazyLock<DynKernel<8, 4, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<8, 4, f32>::new(
        "deeprep_wasm_f32_8x4",
        kernel::<8, 1>,
        f32::packing(8).align(16),
        f32::packing(4).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k2x16() -> Box<dyn MatMatMul> {
    K2X16.mmm()
}

fn k4x8() -> Box<dyn MatMatMul> {
    K4X8.mmm()
}

fn k8x4() -> Box<dyn MatMatMul> {
    K8X4.mmm()
}

inventory::submit! { MmmRoutine { make: k2x16 } }
inventory::submit! { MmmRoutine { make: k4x8 } }
inventory::submit! { MmmRoutine { make: k8x4 } }

static K3X12: LazyLock<DynKernel<3, 12, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<3, 12, f32>::new(
        "deeprep_wasm_f32_3x12",
        kernel::<3, 3>,
        f32::packing(3).align(16),
        f32::packing(12).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k3x12() -> Box<dyn MatMatMul> {
    K3X12.mmm()
}

inventory::submit! { MmmRoutine { make: k3x12 } }

static K2X12: LazyLock<DynKernel<2, 12, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<2, 12, f32>::new(
        "deeprep_wasm_f32_2x12",
        kernel::<2, 3>,
        f32::packing(2).align(16),
        f32::packing(12).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k2x12() -> Box<dyn MatMatMul> {
    K2X12.mmm()
}

inventory::submit! { MmmRoutine { make: k2x12 } }

static K1X16: LazyLock<DynKernel<1, 16, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<1, 16, f32>::new(
        "deeprep_wasm_f32_1x16",
        kernel::<1, 4>,
        f32::packing(1).align(16),
        f32::packing(16).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k1x16() -> Box<dyn MatMatMul> {
    K1X16.mmm()
}

inventory::submit! { MmmRoutine { make: k1x16 } }

static K2X8: LazyLock<DynKernel<2, 8, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<2, 8, f32>::new(
        "deeprep_wasm_f32_2x8",
        kernel::<2, 2>,
        f32::packing(2).align(16),
        f32::packing(8).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k2x8() -> Box<dyn MatMatMul> {
    K2X8.mmm()
}

inventory::submit! { MmmRoutine { make: k2x8 } }

static K5X8: LazyLock<DynKernel<5, 8, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<5, 8, f32>::new(
        "deeprep_wasm_f32_5x8",
        kernel::<5, 2>,
        f32::packing(5).align(16),
        f32::packing(8).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k5x8() -> Box<dyn MatMatMul> {
    K5X8.mmm()
}

inventory::submit! { MmmRoutine { make: k5x8 } }

static K3X16: LazyLock<DynKernel<3, 16, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<3, 16, f32>::new(
        "deeprep_wasm_f32_3x16",
        kernel::<3, 4>,
        f32::packing(3).align(16),
        f32::packing(16).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k3x16() -> Box<dyn MatMatMul> {
    K3X16.mmm()
}

inventory::submit! { MmmRoutine { make: k3x16 } }

static K2X20: LazyLock<DynKernel<2, 20, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<2, 20, f32>::new(
        "deeprep_wasm_f32_2x20",
        kernel::<2, 5>,
        f32::packing(2).align(16),
        f32::packing(20).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k2x20() -> Box<dyn MatMatMul> {
    K2X20.mmm()
}

inventory::submit! { MmmRoutine { make: k2x20 } }

static K3X8: LazyLock<DynKernel<3, 8, f32>> = LazyLock::new(|| {
    let mut k = DynKernel::<3, 8, f32>::new(
        "deeprep_wasm_f32_3x8",
        kernel::<3, 2>,
        f32::packing(3).align(16),
        f32::packing(8).align(16),
    );
    k.arch = Some(Arch::Wasm32Simd128);
    k
});

fn k3x8() -> Box<dyn MatMatMul> {
    K3X8.mmm()
}

inventory::submit! { MmmRoutine { make: k3x8 } }

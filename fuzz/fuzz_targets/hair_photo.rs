//! The hair photo input's size checks: the first four bytes give width and
//! height (any u16 values, including ones whose product wraps 32-bit
//! arithmetic), the rest are the grey image and hair mask. Inputs whose
//! sizes are consistent are only checked, not filtered: the Gabor filter
//! then always runs on a resampled 256 × 256 image (seconds per input in
//! an instrumented build), which the unit tests cover.
#![no_main]
use deeprep::hair::orientation::{network_input, Gabor};
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

fuzz_target!(|data: &[u8]| {
    static BANK: OnceLock<Gabor> = OnceLock::new();
    let bank = BANK.get_or_init(Gabor::default);
    if data.len() < 4 {
        return;
    }
    let w = u16::from_le_bytes([data[0], data[1]]) as usize;
    let h = u16::from_le_bytes([data[2], data[3]]) as usize;
    let px: Vec<f32> = data[4..].iter().map(|&b| b as f32 / 255.0).collect();
    let half = px.len() / 2;
    let consistent = w > 0 && h > 0 && w.checked_mul(h) == Some(half);
    if consistent && w <= 8192 && h <= 8192 {
        return;
    }
    assert!(network_input(&px[..half], &px[half..2 * half], None, w, h, bank).is_err());
});

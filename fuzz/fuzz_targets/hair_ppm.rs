//! The binary PPM reader `deeprep hair reconstruct --image` uses
//! (`hair::ppm::read_network_input`): any bytes give the 3 × 256 × 256
//! network input or an error whose message is plain text.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    match deeprep::hair::ppm::read_network_input(data) {
        Ok(image) => assert_eq!(image.len(), 3 * 256 * 256),
        Err(e) => assert!(e.to_string().is_ascii()),
    }
});

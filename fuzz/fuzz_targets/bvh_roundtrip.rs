//! BVH parse, then write → parse must give the same clip back.
#![no_main]
use deeprep::skeleton::Bvh;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(b) = Bvh::parse_bytes(data) {
        let text = b.write();
        let again = Bvh::parse(&text).expect("a written BVH parses");
        assert_eq!(again, b, "write → parse changed the clip");
    }
});

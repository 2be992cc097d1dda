//! OBJ text through the mesh system's whole set-up: the reader, welding,
//! joining pieces and graph sampling (`mesh::Template::from_obj`, what
//! `deeprep mesh topology` runs). Any input gives a topology or an error;
//! the sampling's work limits (`mesh::sampling::MAX_RING`,
//! `MAX_TABLE_CELLS`) keep high-valence fans from growing quadratically.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(t) = deeprep::mesh::Template::from_obj(&text) {
        let topo = &t.topology;
        assert!(topo.weld_map.iter().all(|&w| w < topo.rest.len()));
        for level in &topo.levels {
            assert_eq!(level.down.rows, level.selected.len());
        }
    }
});

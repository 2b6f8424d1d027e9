//! Fuzz target: any bytes read as an .igmesh (versions 1 to 4, zstd payloads included) must
//! give a mesh whose indices are all in range, or an error; never a panic or an allocation
//! beyond the limits. Run with `cargo +nightly fuzz run igmesh_read` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;
use luxfarm::formats::indigo::igmesh::{read, Limits};

fuzz_target!(|data: &[u8]| {
    let limits = Limits {
        max_array_len: 1 << 16,
        max_decompressed: 1 << 22,
    };
    if let Ok(m) = read(data, limits) {
        assert!(m.validate().is_ok());
        for s in 0..m.num_uv_sets.min(4) {
            for t in &m.tris {
                for &i in &t.uv {
                    assert!(m.uv(i, s).is_some());
                }
            }
        }
    }
});

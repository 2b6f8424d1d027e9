//! Fuzz target: any bytes given to the .lxs parser must parse or fail with an error, never
//! panic, hang or allocate without bound. Run with `cargo +nightly fuzz run lxs_parse` from
//! the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;
use luxfarm::lxs::{self, ParseOptions};

fuzz_target!(|data: &[u8]| {
    let opts = ParseOptions {
        // Includes may only reach files under the fuzzer's working directory.
        confine_to_root: true,
        max_include_depth: 4,
        max_array_len: 1 << 16,
        max_total_bytes: 1 << 20,
        frame: None,
    };
    let text = String::from_utf8_lossy(data);
    let _ = lxs::parse_str(&text, "fuzz.lxs", &opts);
});

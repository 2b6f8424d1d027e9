//! Fuzz target: any bytes given to the mental ray (.mi) importer must import or fail with a
//! located error, never panic, hang or allocate without bound. Run with
//! `cargo +nightly fuzz run mi_parse` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;
use luxfarm::formats::mi;
use luxfarm::lxs::ParseOptions;

fuzz_target!(|data: &[u8]| {
    let opts = ParseOptions {
        // Includes may only reach files under the fuzzer's working directory.
        confine_to_root: true,
        max_include_depth: 4,
        max_array_len: 1 << 16,
        max_total_bytes: 1 << 20,
        ..ParseOptions::default()
    };
    let text = String::from_utf8_lossy(data);
    let _ = mi::parse_str(&text, "fuzz.mi", &opts);
});

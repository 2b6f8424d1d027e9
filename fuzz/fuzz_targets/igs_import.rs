//! Fuzz target: any bytes given to the Indigo importer as a scene must import or fail with a
//! located error, never panic, hang or allocate without bound. Run with
//! `cargo +nightly fuzz run igs_import` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;
use luxfarm::formats::indigo;
use luxfarm::lxs::ParseOptions;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let opts = ParseOptions {
        // Includes and meshes may only reach files under the fuzzer's working directory.
        confine_to_root: true,
        max_include_depth: 4,
        max_array_len: 1 << 16,
        max_total_bytes: 1 << 20,
        ..ParseOptions::default()
    };
    let _ = indigo::import_bytes(Path::new("fuzz-input/scene.igs"), data, &opts);
});

//! Fuzz target: any bytes given to the LightWave object reader (LWO2, LWOB, and the refused
//! LWO3/LXOB forms) must read or fail with an error, never panic, hang or allocate beyond what
//! the bytes declare and hold. Run with `cargo +nightly fuzz run lwo_parse` from the
//! repository root (seed the corpus with `../shared/scenes/formats/lightwave/LWO/**/*.lwo`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = luxfarm::formats::lightwave::parse_object_bytes("fuzz.lwo", data);
});

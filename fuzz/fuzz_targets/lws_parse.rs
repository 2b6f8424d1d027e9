//! Fuzz target: any text given to the LightWave scene reader (LWSC tokenizer, items,
//! envelopes, hierarchy, motion evaluation) must read and place its items or fail with a
//! located error, never panic or hang. The first byte picks the frame (-128..127), the rest is
//! the scene. Run with `cargo +nightly fuzz run lws_parse` from the repository root (seed the
//! corpus with `../shared/scenes/formats/lightwave/LWS/*.lws` behind one extra byte).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let frame = i64::from(first as i8);
    let text = String::from_utf8_lossy(rest);
    let _ = luxfarm::formats::lightwave::parse_scene_text("fuzz.lws", &text, frame);
});

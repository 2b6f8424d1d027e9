//! Fuzz target: the FLM reader and the delta merge must never panic, whatever the bytes,
//! gzip-compressed or not; a refused delta leaves the film unchanged.
#![no_main]

use libfuzzer_sys::fuzz_target;
use luxfarm::film::{flm, Film};
use std::io::Write;

fn check(bytes: &[u8]) {
    let _ = flm::read_flm(bytes);
    let mut film = Film::new(4, 4, vec![]);
    let before = film.clone();
    if flm::merge_flm(&mut film, bytes).is_err() {
        assert_eq!(film, before);
    }
    if flm::merge_flm_bytes(&mut film, bytes).is_err() {
        assert_eq!(film, before);
    }
}

fuzz_target!(|data: &[u8]| {
    check(data);
    // Also as the payload of a valid gzip stream, so the header parser sees the bytes.
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    if e.write_all(data).is_ok() {
        if let Ok(gz) = e.finish() {
            check(&gz);
        }
    }
});

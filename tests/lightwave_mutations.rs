//! Malformed LightWave inputs, made deterministically from the samples (the fuzz targets in
//! `fuzz/` search wider): truncated and byte-flipped objects, truncated and token-mutated
//! scenes. Every one must read or fail with an error naming its file (and, for scenes, a
//! line), never panic.

mod lightwave_util;

use lightwave_util::samples;
use luxfarm::formats::lightwave::{parse_object_bytes, parse_scene_text};
use std::path::PathBuf;

/// A small deterministic generator (64-bit LCG, high bits).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) as usize) % n.max(1)
    }
}

fn files(dir: &str, ext: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![samples().join(dir)];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == ext) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Reads mutated object bytes; true when they were refused (with the file named).
fn check_object(bytes: &[u8], what: &str) -> bool {
    match parse_object_bytes("m.lwo", bytes) {
        Ok(_) => false,
        Err(e) => {
            assert_eq!(&*e.loc.file, "m.lwo", "{what}: {e}");
            true
        }
    }
}

#[test]
fn truncated_and_flipped_objects_fail_cleanly() {
    let objects = files("LWO", "lwo");
    assert!(objects.len() >= 15, "{objects:?}");
    let mut rng = Lcg(19);
    let (mut tried, mut refused) = (0, 0);
    for path in objects {
        let bytes = std::fs::read(&path).unwrap();
        let name = path.display().to_string();
        parse_object_bytes("m.lwo", &bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        let step = (bytes.len() / 200).max(1);
        for len in (0..bytes.len()).step_by(step) {
            tried += 1;
            refused += usize::from(check_object(&bytes[..len], &format!("{name} cut at {len}")));
        }
        for k in 0..200 {
            let mut m = bytes.clone();
            for _ in 0..1 + k % 4 {
                let at = rng.next(m.len());
                m[at] = match rng.next(4) {
                    0 => 0xff,
                    1 => 0,
                    2 => m[at] ^ (1 << rng.next(8)),
                    _ => rng.next(256) as u8,
                };
            }
            tried += 1;
            refused += usize::from(check_object(&m, &format!("{name} mutation {k}")));
        }
    }
    // most cuts and many flips break a chunk: the inputs do reach the error paths
    assert!(refused * 3 > tried, "{refused} of {tried} refused");
}

/// Reads mutated scene text; true when it was refused (with the file and a line named).
fn check_scene(text: &str, frame: i64, what: &str) -> bool {
    match parse_scene_text("s.lws", text, frame) {
        Ok(_) => false,
        Err(e) => {
            assert_eq!(&*e.loc.file, "s.lws", "{what}: {e}");
            assert!(e.loc.line >= 1, "{what}: no line: {e}");
            true
        }
    }
}

#[test]
fn truncated_and_mutated_scenes_fail_with_lines() {
    const TOKENS: &[&str] = &[
        "{",
        "}",
        "-1",
        "1e308",
        "nan",
        "inf",
        "99999999999",
        "",
        "Key",
        "Channel 9",
        "ParentItem 1",
        "ParentItem 10000000",
        "TargetItem 10000000",
        "NumChannels 99",
        "{ Envelope",
        "Plugin X 1 y",
        "EndPlugin",
        "AddCamera",
        "AddLight",
        "LightType 5",
    ];
    let scenes = files("LWS", "lws");
    assert!(scenes.len() >= 8, "{scenes:?}");
    let mut rng = Lcg(5);
    let (mut tried, mut refused) = (0, 0);
    for path in scenes {
        let text = std::fs::read_to_string(&path).unwrap();
        let name = path.display().to_string();
        let lines: Vec<&str> = text.lines().collect();
        let step = (lines.len() / 60).max(1);
        for n in (0..lines.len()).step_by(step) {
            tried += 1;
            let cut = lines[..n].join("\n");
            refused += usize::from(check_scene(&cut, 30, &format!("{name} cut at line {n}")));
        }
        for k in 0..150 {
            let mut m: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            for _ in 0..1 + k % 3 {
                let at = rng.next(m.len());
                let line: Vec<&str> = m[at].split(' ').collect();
                let w = rng.next(line.len());
                let tok = TOKENS[rng.next(TOKENS.len())];
                let mut words: Vec<String> = line.iter().map(|s| s.to_string()).collect();
                words[w] = tok.to_string();
                m[at] = words.join(" ");
            }
            let frame = rng.next(200) as i64 - 50;
            tried += 1;
            let what = format!("{name} mutation {k}");
            refused += usize::from(check_scene(&m.join("\n"), frame, &what));
        }
    }
    assert!(refused * 4 > tried, "{refused} of {tried} refused");
}

//! FLM files and film arithmetic: merges are exact sums, many small deltas lose nothing,
//! comparisons of a film with itself are zero, and every kind of bad input is a clear error.

use flate2::write::GzEncoder;
use flate2::Compression;
use luxfarm::film::{compare, flm, Film, FilmError, FilmParams, FlmDelta};
use std::io::Write;

/// A film with f32-exact, varied sums (so FLM round trips are exact).
fn film(w: u32, h: u32, seed: u32) -> Film {
    let mut f = Film::new(w, h, vec!["default".into(), "sun".into()]);
    let mut s = seed | 1;
    for g in 0..2 {
        for y in 0..h {
            for x in 0..w {
                s ^= s << 13;
                s ^= s >> 17;
                s ^= s << 5;
                let v = (s % 1000) as f32 / 64.0;
                f.add_splat(g, x, y, [v, v * 0.5, v * 0.25], 1.0, 1.0);
            }
        }
    }
    f.add_sample_count(f64::from(w * h));
    f
}

fn encode(f: &Film) -> Vec<u8> {
    let mut v = Vec::new();
    flm::write_flm(
        f,
        &FilmParams::with_resolution(f.width(), f.height()),
        &mut v,
    )
    .unwrap();
    v
}

fn gz(raw: &[u8]) -> Vec<u8> {
    let mut e = GzEncoder::new(Vec::new(), Compression::fast());
    e.write_all(raw).unwrap();
    e.finish().unwrap()
}

fn raw(bytes: &[u8]) -> Vec<u8> {
    use std::io::Read;
    let mut v = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .read_to_end(&mut v)
        .unwrap();
    v
}

#[test]
fn write_read_is_bit_identical() {
    let a = film(7, 5, 3);
    let (b, header) = flm::read_flm(&encode(&a)[..]).unwrap();
    assert_eq!(a, b);
    assert_eq!(b.groups(), ["default", "sun"]);
    assert_eq!(header.groups, 2);
}

#[test]
fn merge_equals_elementwise_sum_exactly() {
    let a = film(9, 4, 11);
    let b = film(9, 4, 12);
    let mut m = a.clone();
    m.merge(&b).unwrap();
    let mut streamed = a.clone();
    flm::merge_flm(&mut streamed, &encode(&b)[..]).unwrap();
    assert_eq!(m, streamed);
    let mut in_memory = a.clone();
    flm::merge_flm_bytes(&mut in_memory, &encode(&b)).unwrap();
    assert_eq!(m, in_memory);
    for g in 0..2 {
        let (pa, pb, pm) = (
            a.buffer(g, 0).unwrap(),
            b.buffer(g, 0).unwrap(),
            m.buffer(g, 0).unwrap(),
        );
        for i in 0..pm.len() {
            assert_eq!(pm[i], pa[i] + pb[i]);
        }
        assert_eq!(m.sample_count(g), a.sample_count(g) + b.sample_count(g));
    }
}

#[test]
fn compare_with_itself_is_zero() {
    let a = film(6, 6, 5);
    let c = compare(&a, &a).unwrap();
    assert_eq!((c.mse, c.rms, c.big, c.medium), (0.0, 0.0, 0, 0));
    let b = film(6, 6, 6);
    assert!(compare(&a, &b).unwrap().rms > 0.0);
}

#[test]
fn hundred_thousand_small_deltas_lose_no_precision() {
    let mut acc = Film::new(2, 1, vec![]);
    let mut reference = [0.0f64; 5];
    let mut delta = Film::new(2, 1, vec![]);
    for i in 0..100_000u32 {
        delta.clear();
        let v = 1e-3 + (i % 17) as f32 * 1e-7;
        delta.add_splat(0, 1, 0, [v, v, v], 0.5, 0.75);
        delta.add_sample_count(1.0);
        acc.merge(&delta).unwrap();
        let w = f64::from(0.75f32);
        reference[0] += w * f64::from(v);
        reference[3] += w * 0.5;
        reference[4] += w;
    }
    let p = acc.pixel(0, 0, 1, 0).unwrap();
    assert_eq!(p[0], reference[0]);
    assert_eq!(p[3], reference[3]);
    assert_eq!(p[4], reference[4]);
    assert_eq!(acc.sample_count(0), 100_000.0);
    // An f32 accumulator would be off by far more than this.
    let mut f32_sum = 0.0f32;
    for i in 0..100_000u32 {
        f32_sum += 0.75 * (1e-3 + (i % 17) as f32 * 1e-7);
    }
    assert!((f64::from(f32_sum) - reference[0]).abs() > 1e-6);
}

fn expect_err(bytes: &[u8]) -> FilmError {
    match flm::read_flm(bytes) {
        Ok(_) => panic!("accepted bad input"),
        Err(e) => {
            // The merge path must refuse it too, leaving the film untouched.
            let mut target = film(3, 2, 1);
            let before = target.clone();
            assert!(flm::merge_flm(&mut target, bytes).is_err());
            assert!(flm::merge_flm_bytes(&mut target, bytes).is_err());
            assert_eq!(target, before);
            e
        }
    }
}

#[test]
fn truncated_and_corrupt_gzip() {
    let good = encode(&film(5, 4, 9));
    for cut in [0, 5, 20, good.len() / 2, good.len() - 4, good.len() - 1] {
        let e = expect_err(&good[..cut]);
        assert!(matches!(e, FilmError::Corrupt { .. }), "cut {cut}: {e}");
    }
    let mut bad = good.clone();
    let n = bad.len();
    bad[n - 6] ^= 0xff; // CRC
    assert!(matches!(expect_err(&bad), FilmError::Corrupt { .. }));
    assert!(matches!(
        expect_err(b"not gzip at all"),
        FilmError::Corrupt { .. }
    ));
}

fn header(w: u32, h: u32, groups: u32, bufs: &[i32]) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(&0xCEBC_D816u32.to_le_bytes());
    b.extend_from_slice(&0i32.to_le_bytes());
    for v in [w, h, groups, bufs.len() as u32] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for t in bufs {
        b.extend_from_slice(&t.to_le_bytes());
    }
    b
}

#[test]
fn wrong_magic_version_and_absurd_sizes() {
    let mut data = raw(&encode(&film(2, 2, 1)));
    data[0] ^= 1;
    assert!(matches!(expect_err(&gz(&data)), FilmError::BadMagic { .. }));
    let mut data = raw(&encode(&film(2, 2, 1)));
    data[4] = 1;
    assert!(matches!(
        expect_err(&gz(&data)),
        FilmError::BadVersion { found: 1 }
    ));
    for (w, h) in [(65_537, 1), (65_536, 65_536), (0, 10)] {
        let mut b = header(w, h, 1, &[0]);
        b.extend_from_slice(&0u32.to_le_bytes());
        let e = expect_err(&gz(&b));
        assert!(
            matches!(e, FilmError::TooLarge { .. } | FilmError::BadHeader(_)),
            "{e}"
        );
    }
    let mut b = header(16_384, 16_384, 2, &[0]);
    b.extend_from_slice(&0u32.to_le_bytes());
    assert!(matches!(expect_err(&gz(&b)), FilmError::BadHeader(_)));
    let mut b = header(4, 4, 1, &[7]);
    b.extend_from_slice(&0u32.to_le_bytes());
    assert!(matches!(expect_err(&gz(&b)), FilmError::BadHeader(_)));
    let mut b = header(4, 4, 1, &[0]);
    b.extend_from_slice(&u32::MAX.to_le_bytes());
    assert!(matches!(expect_err(&gz(&b)), FilmError::BadHeader(_)));
}

#[test]
fn wrong_parameter_sizes() {
    for (ty, size) in [(0i32, 8u32), (2, 4), (1, 1 << 30), (5, 4)] {
        let mut b = header(1, 1, 1, &[0]);
        b.extend_from_slice(&1u32.to_le_bytes());
        for v in [ty as u32, size, 0, 0] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&[0u8; 8]);
        assert!(
            matches!(expect_err(&gz(&b)), FilmError::BadHeader(_)),
            "{ty} {size}"
        );
    }
}

#[test]
fn nan_inf_and_trailing_data() {
    let good = raw(&encode(&film(3, 2, 4)));
    let data_start = good.len() - 2 * (8 + 3 * 2 * 20);
    for (bits, offset) in [
        (f32::NAN.to_bits(), 8 + 4),
        (f32::INFINITY.to_bits(), 8 + 20 * 5),
    ] {
        let mut d = good.clone();
        d[data_start + offset..data_start + offset + 4].copy_from_slice(&bits.to_le_bytes());
        let e = expect_err(&gz(&d));
        assert!(matches!(e, FilmError::NonFinite { .. }), "{e}");
    }
    let mut d = good.clone();
    d[data_start..data_start + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    assert!(matches!(expect_err(&gz(&d)), FilmError::BadHeader(_)));
    let mut d = good.clone();
    d.extend_from_slice(b"junk");
    assert!(matches!(expect_err(&gz(&d)), FilmError::BadHeader(_)));
}

/// Peak resident memory of this process in kB (Linux; nextest runs each test in its own
/// process), after resetting the peak counter.
fn reset_peak_kb() -> Option<u64> {
    std::fs::write("/proc/self/clear_refs", "5").ok()?;
    peak_kb()
}

fn peak_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// A 100-byte stream whose header declares a 8192×8192 film of two buffers (2.7 GB of f32
/// sums) and holds none of it: decoding fails at the end of the stream without touching the
/// memory the header claims (fuzzing found the decoder resizing to it first), a merge
/// refuses the layout before reading pixels, and the in-memory decoder refuses a trailer
/// claiming more than deflate can expand the stream to.
#[test]
fn a_small_stream_declaring_a_huge_film_allocates_nothing_large() {
    let mut b = header(8192, 8192, 1, &[0, 1]);
    b.extend_from_slice(&0u32.to_le_bytes()); // no parameters
    b.extend_from_slice(&1.0f64.to_le_bytes()); // the group's sample count
    b.extend_from_slice(&[0u8; 64]); // a few pixel bytes
    let small = gz(&b);
    assert!(small.len() < 200, "{}", small.len());
    let before = reset_peak_kb();
    let mut d = FlmDelta::default();
    let e = d.decode(&small[..]).unwrap_err();
    assert!(matches!(e, FilmError::Corrupt { .. }), "{e}");
    if let (Some(a), Some(b)) = (before, peak_kb()) {
        assert!(b.saturating_sub(a) < 100_000, "peak grew by {} kB", b - a);
    }
    let mut target = Film::new(4, 4, vec![]);
    let untouched = target.clone();
    let e = flm::merge_flm(&mut target, &small[..]).unwrap_err();
    assert!(matches!(e, FilmError::Mismatch(_)), "{e}");
    // A forged trailer (ISIZE) matching the header's size.
    let mut forged = small.clone();
    let n = forged.len();
    let declared = (b.len() - 64 + 8192 * 8192 * 5 * 4 * 2) as u32;
    forged[n - 4..].copy_from_slice(&declared.to_le_bytes());
    let e = FlmDelta::default().decode_slice(&forged).unwrap_err();
    assert!(e.to_string().contains("cannot hold"), "{e}");
    assert!(flm::merge_flm_bytes(&mut target, &forged).is_err());
    assert_eq!(target, untouched);
}

#[test]
fn merge_refuses_other_layouts_unchanged() {
    let mut a = film(4, 4, 1);
    let before = a.clone();
    let other = Film::new(4, 5, vec!["default".into(), "sun".into()]);
    assert!(matches!(
        flm::merge_flm(&mut a, &encode(&other)[..]),
        Err(FilmError::Mismatch(_))
    ));
    let one_group = Film::new(4, 4, vec![]);
    assert!(flm::merge_flm(&mut a, &encode(&one_group)[..]).is_err());
    assert_eq!(a, before);
    let mut d = FlmDelta::default();
    d.decode(&encode(&film(4, 4, 2))[..]).unwrap();
    a.add_delta(&d).unwrap();
    assert_ne!(a, before);
}

#[test]
fn atomic_file_write_and_read() {
    let dir = std::env::temp_dir().join(format!("luxfarm-film-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("a.flm");
    let f = film(5, 3, 8);
    flm::write_flm_file(&path, &f, &FilmParams::with_resolution(5, 3)).unwrap();
    let (g, _) = flm::read_flm_file(&path).unwrap();
    assert_eq!(f, g);
    let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(leftovers.len(), 1, "temporary file left behind");
    let missing = flm::read_flm_file(&dir.join("missing.flm")).unwrap_err();
    assert!(missing.to_string().contains("missing.flm"));
    std::fs::remove_dir_all(&dir).unwrap();
}

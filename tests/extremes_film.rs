//! Numerical stability at the extremes, film level (issue 21, build point 4): the size limit
//! of films (16k×16k), FLM values that overflow f32, 10^6 samples in one pixel and 10^6 merged
//! deltas. Films keep f64 sums; FLM files store f32, so the writer must refuse a sum f32
//! cannot hold instead of writing an infinity no reader accepts. Rendered cases are in
//! `extremes.rs`.

use luxfarm::film::flm::{merge_flm_bytes, read_flm, write_flm};
use luxfarm::film::{check_size, Film, FilmError, FilmParams, MAX_PIXELS, PIXEL_VALUES};

/// 16384×16384 is exactly the pixel limit (2^28) and passes the check, which runs before any
/// allocation; one pixel more on either axis is refused with the limits in the message. The
/// accepted film's f64 sums take 40 B per pixel per group and buffer: 10 GiB (stated limit).
#[test]
fn film_16k_is_the_size_limit() {
    assert!(check_size(16_384, 16_384).is_ok());
    assert_eq!(16_384u64 * 16_384, MAX_PIXELS);
    let bytes = MAX_PIXELS * (PIXEL_VALUES * 8) as u64;
    assert_eq!(bytes, 10 << 30);
    for (w, h) in [(16_385, 16_384), (16_384, 16_385), (65_537, 1)] {
        let e = check_size(w, h).expect_err("over the limit");
        assert!(matches!(e, FilmError::TooLarge { .. }), "{e}");
        let msg = e.to_string();
        assert!(msg.contains(&format!("{w}x{h}")), "{msg}");
        assert!(msg.contains("2^28"), "{msg}");
    }
    let e = Film::with_buffers(
        16_385,
        16_385,
        vec![],
        vec![luxfarm::film::BufferType::PerPixel],
    );
    assert!(matches!(e, Err(FilmError::TooLarge { .. })));
}

fn flm_bytes(film: &Film) -> Result<Vec<u8>, FilmError> {
    let mut out = Vec::new();
    write_flm(film, &FilmParams::default(), &mut out)?;
    Ok(out)
}

/// f32 holds up to 3.4e38: a film whose f64 sum passes that (two 3e38 splats) is refused by
/// the FLM writer with the pixel named, rather than written as an infinity the reader (and
/// LuxRender) would refuse. The largest f32 values round-trip exactly.
#[test]
fn flm_values_that_overflow_f32_are_refused_when_written() {
    let mut f = Film::new(4, 4, vec![]);
    f.add_splat(0, 1, 2, [f32::MAX, f32::MAX, 1.0], 1.0, 1.0);
    f.add_sample_count(1.0);
    let bytes = flm_bytes(&f).expect("f32::MAX fits");
    let (back, _) = read_flm(&bytes[..]).expect("reads back");
    assert_eq!(back.pixel(0, 0, 1, 2), f.pixel(0, 0, 1, 2));
    f.add_splat(0, 1, 2, [3e38, 3e38, 1.0], 1.0, 1.0);
    let y = f.pixel(0, 0, 1, 2).expect("pixel")[1];
    assert!(y.is_finite() && y > f64::from(f32::MAX));
    let e = flm_bytes(&f).expect_err("overflow refused");
    let msg = e.to_string();
    assert!(matches!(e, FilmError::Overflow { x: 1, y: 2, .. }), "{msg}");
    assert!(msg.contains("f32"), "{msg}");
}

/// 10^6 samples of 0.1 and 10^4 alternately in one pixel: the f64 sums keep the mean to 1e-12
/// (an f32 accumulator drifts by more than 1e-4 on the same input — shown for contrast).
#[test]
fn a_million_samples_in_one_pixel_keep_the_mean() {
    let mut f = Film::new(1, 1, vec![]);
    let (a, b) = (0.1f32, 1.0e4f32);
    let mut f32_sum = 0.0f32;
    let n = 1_000_000u32;
    for i in 0..n {
        let v = if i % 2 == 0 { a } else { b };
        f.add_splat(0, 0, 0, [v, v, v], 1.0, 1.0);
        f32_sum += v;
    }
    let p = f.pixel(0, 0, 0, 0).expect("pixel");
    let exact = (f64::from(a) + f64::from(b)) / 2.0;
    let mean = p[1] / p[4];
    assert_eq!(p[4], f64::from(n));
    assert!(((mean - exact) / exact).abs() < 1e-12, "{mean} vs {exact}");
    let f32_mean = f64::from(f32_sum) / f64::from(n);
    assert!(((f32_mean - exact) / exact).abs() > 1e-4);
}

/// 10^6 deltas of one sample each merged with `Film::merge`: the mean and the sample count
/// stay within n·ε (2.2e-10) of exact; 1000 FLM deltas (f32 on the wire) merged with `merge_flm_bytes` keep
/// the mean to f32 rounding of one delta (1e-6).
#[test]
fn a_million_merged_deltas_keep_the_mean() {
    let mut total = Film::new(2, 1, vec![]);
    let mut delta = Film::new(2, 1, vec![]);
    let n = 1_000_000u32;
    for i in 0..n {
        delta.clear();
        let v = if i % 3 == 0 { 1.0e4f32 } else { 0.1f32 };
        delta.add_splat(0, 0, 0, [v, v, v], 1.0, 1.0);
        delta.add_splat(0, 1, 0, [0.3, 0.3, 0.3], 1.0, 1.0);
        delta.add_sample_count(1.0);
        total.merge(&delta).expect("same layout");
    }
    let thirds = f64::from(n.div_ceil(3));
    let exact = (thirds * 1.0e4 + (f64::from(n) - thirds) * f64::from(0.1f32)) / f64::from(n);
    let p = total.pixel(0, 0, 0, 0).expect("pixel");
    // Recursive f64 summation of n terms is within n·ε of the exact sum (2.2e-10 here).
    let bound = f64::from(n) * f64::EPSILON;
    let err = ((p[1] / p[4] - exact) / exact).abs();
    assert!(err < bound, "relative error {err:e} over {bound:e}");
    let q = total.pixel(0, 0, 1, 0).expect("pixel");
    assert!((q[1] / q[4] - f64::from(0.3f32)).abs() < 1e-12 * 0.3);
    assert_eq!(total.sample_count(0), f64::from(n));

    let mut film = Film::new(2, 1, vec![]);
    delta.clear();
    delta.add_splat(0, 0, 0, [0.7, 0.7, 0.7], 1.0, 1.0);
    delta.add_sample_count(1.0);
    let gz = flm_bytes(&delta).expect("writes");
    for _ in 0..1000 {
        merge_flm_bytes(&mut film, &gz).expect("merges");
    }
    let p = film.pixel(0, 0, 0, 0).expect("pixel");
    assert_eq!(p[4], 1000.0);
    assert!((p[1] / p[4] - f64::from(0.7f32)).abs() < 1e-12);
    assert_eq!(film.sample_count(0), 1000.0);
}

//! Unit tests of the samplers: determinism, range, stream independence, stratification.

use super::*;
use crate::lxs::{Entity, Loc, ParamSet, ParamValue};

fn sampler(kind: &str, params: &[(&str, ParamValue)]) -> Sampler {
    let mut ps = ParamSet::new();
    for (n, v) in params {
        ps.add(n, v.clone());
    }
    let e = Entity {
        kind: kind.into(),
        params: ps,
        loc: Loc::default(),
    };
    Sampler::build(Some(&e), &mut Vec::new()).expect("valid sampler")
}

fn all(n: i32) -> Vec<Sampler> {
    ["random", "lowdiscrepancy", "sobol"]
        .iter()
        .map(|k| sampler(k, &[("pixelsamples", ParamValue::Integer(vec![n]))]))
        .collect()
}

/// The first `dims` values (drawn as 2D pairs) of one sample.
fn draw(
    s: &Sampler,
    seed: u64,
    stream: u64,
    px: u32,
    py: u32,
    index: u64,
    dims: usize,
) -> Vec<f32> {
    let mut st = s.start(seed, stream, px, py, index);
    let mut v = Vec::new();
    while v.len() < dims {
        let p = st.next_2d();
        v.push(p.x);
        v.push(p.y);
    }
    v
}

#[test]
fn defaults_and_fallbacks() {
    let none = Sampler::build(None, &mut Vec::new()).unwrap();
    assert_eq!(
        (none.kind(), none.pixel_samples()),
        (SamplerKind::Random, 4)
    );
    assert_eq!(sampler("lowdiscrepancy", &[]).pixel_samples(), 4);
    assert_eq!(sampler("sobol", &[]).pixel_samples(), 4);
    let ld = sampler(
        "lowdiscrepancy",
        &[("pixelsamples", ParamValue::Integer(vec![5]))],
    );
    assert_eq!(ld.pixel_samples(), 8, "rounded up to a power of two");
    let r = sampler("random", &[("xsamples", ParamValue::Integer(vec![3]))]);
    assert_eq!(r.pixel_samples(), 6);
    let st = sampler("stratified", &[("xsamples", ParamValue::Integer(vec![4]))]);
    assert_eq!(
        (st.kind(), st.pixel_samples()),
        (SamplerKind::LowDiscrepancy, 8)
    );
    let m = sampler(
        "metropolis",
        &[
            ("largemutationprob", ParamValue::Float(vec![0.25])),
            ("maxconsecrejects", ParamValue::Integer(vec![64])),
        ],
    );
    assert_eq!(m.kind(), SamplerKind::Metropolis);
    assert!(m.per_screen());
    let p = m.mlt().copied().unwrap_or_default();
    assert_eq!((p.large_prob, p.max_rejects, p.range), (0.25, 64, None));
    let er = sampler("erpt", &[]);
    assert_eq!(er.kind(), SamplerKind::Erpt);
    assert!(er.per_screen());
    assert_eq!(er.pixel_samples(), 4);
    let p = er
        .erpt()
        .copied()
        .unwrap_or_else(|| panic!("erpt parameters"));
    assert_eq!(
        (p.init_samples, p.chain_length, p.range),
        (100_000, 2000, None)
    );
    assert_eq!(p.range_pixels(800.0, 600.0), 28.0);
    let er = sampler(
        "erpt",
        &[
            ("initsamples", ParamValue::Integer(vec![500])),
            ("chainlength", ParamValue::Integer(vec![64])),
            ("mutationrange", ParamValue::Float(vec![3.5])),
            ("pixelsamples", ParamValue::Integer(vec![2])),
        ],
    );
    let p = er.erpt().copied().unwrap_or_default();
    assert_eq!(
        (p.init_samples, p.chain_length, p.range),
        (500, 64, Some(3.5))
    );
    assert_eq!(er.pixel_samples(), 2);
    assert!(er.mlt().is_none() && m.erpt().is_none());
    assert_eq!(
        sampler("bestcandidate", &[]).kind(),
        SamplerKind::LowDiscrepancy
    );
    let e = Entity {
        kind: "magic".into(),
        params: ParamSet::new(),
        loc: Loc::default(),
    };
    assert!(Sampler::build(Some(&e), &mut Vec::new()).is_err());
    let e = Entity {
        kind: "random".into(),
        params: {
            let mut p = ParamSet::new();
            p.add("pixelsamples", ParamValue::Integer(vec![0]));
            p
        },
        loc: Loc::default(),
    };
    assert!(Sampler::build(Some(&e), &mut Vec::new()).is_err());
}

#[test]
fn deterministic_and_order_independent() {
    for s in all(16) {
        // Draw pixels in two different orders; every value must match.
        let mut a = std::collections::HashMap::new();
        for py in 0..4u32 {
            for px in 0..4u32 {
                for i in 0..20u64 {
                    a.insert((px, py, i), draw(&s, 7, 1, px, py, i, 12));
                }
            }
        }
        for i in (0..20u64).rev() {
            for px in (0..4u32).rev() {
                for py in 0..4u32 {
                    assert_eq!(
                        a[&(px, py, i)],
                        draw(&s, 7, 1, px, py, i, 12),
                        "{:?}",
                        s.kind()
                    );
                }
            }
        }
        // 1D and 2D draws count dimensions the same way.
        let mut st = s.start(7, 1, 2, 3, 5);
        let first = st.next_2d();
        assert_eq!(st.dimension(), 2);
        let _ = st.next_1d();
        assert_eq!(st.dimension(), 3);
        let mut again = s.start(7, 1, 2, 3, 5);
        assert_eq!(again.next_2d(), first);
        // Jumping to a dimension gives what sequential drawing gives there.
        let mut seq = s.start(7, 1, 2, 3, 5);
        for _ in 0..4 {
            seq.next_2d();
        }
        let mut jump = s.start(7, 1, 2, 3, 5);
        jump.set_dimension(8);
        assert_eq!(seq.next_2d(), jump.next_2d());
    }
}

#[test]
fn values_are_in_unit_interval() {
    for s in all(8) {
        for i in 0..2000u64 {
            let mut st = s.start(i * 31, i % 3, (i % 17) as u32, (i % 5) as u32, i);
            for _ in 0..40 {
                let v = st.next_1d();
                assert!((0.0..1.0).contains(&v), "{v}");
                let p = st.next_2d();
                assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
            }
        }
        // Far indices and dimensions (beyond sobol_burley's 2^16 x 256) stay valid.
        let mut st = s.start(1, 2, 3, 4, (1 << 20) + 3);
        for _ in 0..600 {
            let v = st.next_1d();
            assert!((0.0..1.0).contains(&v));
        }
    }
}

#[test]
fn streams_seeds_and_pixels_differ() {
    for s in all(4) {
        let base = draw(&s, 11, 0, 5, 5, 0, 16);
        assert_ne!(base, draw(&s, 11, 1, 5, 5, 0, 16), "stream");
        assert_ne!(base, draw(&s, 12, 0, 5, 5, 0, 16), "seed");
        assert_ne!(base, draw(&s, 11, 0, 6, 5, 0, 16), "pixel x");
        assert_ne!(base, draw(&s, 11, 0, 5, 6, 0, 16), "pixel y");
        assert_ne!(base, draw(&s, 11, 0, 5, 5, 1, 16), "index");
        // Two streams are uncorrelated: the mean product of matching values is ~1/4.
        let mut prod = 0.0f64;
        let n = 4000;
        for i in 0..n {
            let a = draw(&s, 3, 0, (i % 64) as u32, (i / 64) as u32, 0, 8);
            let b = draw(&s, 3, 1, (i % 64) as u32, (i / 64) as u32, 0, 8);
            prod += a
                .iter()
                .zip(&b)
                .map(|(x, y)| (*x as f64) * (*y as f64))
                .sum::<f64>()
                / 8.0;
        }
        let mean = prod / n as f64;
        assert!((mean - 0.25).abs() < 0.01, "{:?}: {mean}", s.kind());
    }
}

/// Exact L2 star discrepancy (Warnock's formula) of 2D points.
fn l2_star_discrepancy(p: &[(f64, f64)]) -> f64 {
    let n = p.len() as f64;
    let mut a = 0.0;
    for &(x, y) in p {
        a += (1.0 - x * x) * (1.0 - y * y);
    }
    let mut b = 0.0;
    for &(x1, y1) in p {
        for &(x2, y2) in p {
            b += (1.0 - x1.max(x2)) * (1.0 - y1.max(y2));
        }
    }
    (1.0 / 9.0 - a / (2.0 * n) + b / (n * n)).sqrt()
}

/// Average discrepancy over pixels of the `n` samples of one pixel, for dims (d, d+1).
fn mean_discrepancy(s: &Sampler, n: u64, skip_dims: usize) -> f64 {
    let pixels = if n > 256 { 3 } else { 8 };
    let mut total = 0.0;
    for px in 0..pixels {
        let pts: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let v = draw(s, 99, 0, px, 0, i, skip_dims + 2);
                (v[skip_dims] as f64, v[skip_dims + 1] as f64)
            })
            .collect();
        total += l2_star_discrepancy(&pts);
    }
    total / pixels as f64
}

#[test]
fn low_discrepancy_beats_random() {
    for n in [16u64, 256, 1024] {
        let ss = all(n as i32);
        let random = mean_discrepancy(&ss[0], n, 0);
        for s in &ss[1..] {
            for skip in [0, 2, 10] {
                let d = mean_discrepancy(s, n, skip);
                assert!(
                    d < 0.5 * random,
                    "{:?} n={n} dims {skip}: {d} vs random {random}",
                    s.kind()
                );
            }
        }
    }
}

/// Whether `pts` (2^m points) form a (0, m, 2)-net: one point in every elementary interval
/// of area 1 / 2^m.
fn is_net(pts: &[(f32, f32)]) -> bool {
    let n = pts.len();
    let m = n.trailing_zeros();
    (0..=m).all(|kx| {
        let (cx, cy) = (1usize << kx, 1usize << (m - kx));
        let mut cells = vec![0u32; n];
        for &(x, y) in pts {
            cells[(x * cx as f32) as usize + cx * (y * cy as f32) as usize] += 1;
        }
        cells.iter().all(|&c| c == 1)
    })
}

#[test]
fn lowdiscrepancy_and_sobol_are_nets_in_every_2d_request() {
    let ld = sampler(
        "lowdiscrepancy",
        &[("pixelsamples", ParamValue::Integer(vec![16]))],
    );
    let sobol = sampler("sobol", &[("pixelsamples", ParamValue::Integer(vec![16]))]);
    for dims in [0usize, 4, 6, 20] {
        let request = |s: &Sampler, i: u64| {
            let v = draw(s, 5, 0, 1, 2, i, dims + 2);
            (v[dims], v[dims + 1])
        };
        // Lowdiscrepancy: every pass of 16 samples is a net (fresh scrambles per pass).
        for pass in 0..3u64 {
            let pts: Vec<_> = (0..16).map(|i| request(&ld, pass * 16 + i)).collect();
            assert!(is_net(&pts), "lowdiscrepancy pass {pass} dims {dims}");
        }
        // Sobol: one sequence per pixel, every power-of-two prefix is a net.
        for n in [16u64, 32, 64] {
            let pts: Vec<_> = (0..n).map(|i| request(&sobol, i)).collect();
            assert!(is_net(&pts), "sobol first {n} dims {dims}");
        }
    }
}

#[test]
fn camera_sample_uses_the_documented_dimensions() {
    for s in all(4) {
        let mut a = s.start(1, 0, 10, 20, 3);
        let cs = a.camera_sample();
        assert_eq!(a.dimension(), 5);
        let mut b = s.start(1, 0, 10, 20, 3);
        let film = b.next_2d();
        let lens = b.next_2d();
        let time = b.next_1d();
        assert_eq!(cs.p_film, Vec2::new(10.0 + film.x, 20.0 + film.y));
        assert_eq!((cs.p_lens, cs.time), (lens, time));
        // Pixels outside the image (the filter's sample extent) work the same way.
        let mut c = s.start_at(1, 0, 10, 20, 3);
        assert_eq!(c.camera_sample(), cs);
        let mut d = s.start_at(1, 0, -2, -1, 3);
        let ds = d.camera_sample();
        assert!(
            ds.p_film.x >= -2.0 && ds.p_film.x < -1.0 && ds.p_film.y >= -1.0 && ds.p_film.y < 0.0
        );
        assert_eq!(d.pixel(), (-2, -1));
    }
}

/// The sampler of a scene text's `Sampler` statement, with its warnings.
fn from_text(text: &str) -> (Result<Sampler, BuildError>, Vec<Diagnostic>) {
    let text = format!("{text}\nWorldBegin\nWorldEnd\n");
    let desc = crate::lxs::parse_str(&text, "s.lxs", &crate::lxs::ParseOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let mut warnings = Vec::new();
    let s = Sampler::build(desc.sampler.as_ref(), &mut warnings);
    (s, warnings)
}

#[test]
fn erpt_bad_values_are_located_errors() {
    for (params, what) in [
        (
            "\"integer chainlength\" [0]",
            "chainlength must be at least 1, got 0",
        ),
        (
            "\"integer chainlength\" [-5]",
            "chainlength must be at least 1",
        ),
        (
            "\"integer initsamples\" [0]",
            "initsamples must be at least 1, got 0",
        ),
        (
            "\"float mutationrange\" [-2]",
            "mutationrange must be a positive",
        ),
        (
            "\"float mutationrange\" [0]",
            "mutationrange must be a positive",
        ),
        (
            "\"integer pixelsamples\" [0]",
            "pixelsamples must be at least 1",
        ),
    ] {
        let (s, _) = from_text(&format!("\n\nSampler \"erpt\" {params}"));
        let e = s.err().unwrap_or_else(|| panic!("{params} accepted"));
        let msg = e.to_string();
        assert!(msg.starts_with("s.lxs:3:1: "), "{msg}");
        assert!(msg.contains(what), "{msg}");
    }
}

#[test]
fn erpt_warns_only_about_what_it_ignores() {
    let (s, w) = from_text("Sampler \"erpt\" \"integer chainlength\" [100]");
    assert_eq!(s.map(|s| s.kind()), Ok(SamplerKind::Erpt));
    assert!(w.is_empty(), "{w:?}");
    let (s, w) = from_text(
        "Sampler \"erpt\" \"bool noiseaware\" [\"true\"] \"string basesampler\" [\"halton\"]",
    );
    let s = s.unwrap_or_else(|e| panic!("{e}"));
    assert!(!s.noise_aware(), "noiseaware ignored");
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(w.iter().any(|d| d.message.contains("noiseaware")));
    assert!(w
        .iter()
        .any(|d| d.message.contains("basesampler \"halton\"")));
    assert!(w.iter().all(|d| d.loc.line == 1));
}

#[test]
fn erpt_reads_its_base_sampler() {
    use super::erpt::BaseSampler;
    let base = |name: &str| {
        let (s, w) = from_text(&format!(
            "Sampler \"erpt\" \"string basesampler\" [\"{name}\"]"
        ));
        let s = s.unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(w.is_empty(), "{name}: {w:?}");
        s.erpt().map(|p| p.base)
    };
    assert_eq!(base("random"), Some(BaseSampler::Random));
    assert_eq!(base("lowdiscrepancy"), Some(BaseSampler::Stratified));
    assert_eq!(base("sobol"), Some(BaseSampler::Stratified));
    let (s, _) = from_text("\nSampler \"erpt\" \"string basesampler\" [\"metropolis\"]");
    let msg = s.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(
        msg.starts_with("s.lxs:2:1: ") && msg.contains("basesampler"),
        "{msg}"
    );
}

/// The first 64 seeds of a stratified base form a (0, 6, 2)-net over the frame: one seed in
/// each of the 8 × 8 cells (and each 64 × 1 and 1 × 64 elementary interval); the lens
/// request is stratified the same way. A random base fails this almost surely.
#[test]
fn erpt_stratified_seeds_cover_the_frame_evenly() {
    use super::erpt::seed_point;
    for (seed, stream) in [(1u64, 0u64), (1, 7), (99, 3)] {
        for first in [0u64, 64, 4096] {
            let mut film = [[0u32; 8]; 8];
            let (mut rows, mut cols, mut lens) = (vec![0u32; 64], vec![0u32; 64], [[0u32; 8]; 8]);
            for i in first..first + 64 {
                let mut st = Sampler::start_primary(Vec::new(), 5, Vec2::ZERO, Vec2::ONE)
                    .with_stratified_fresh(seed_point(seed, stream, i));
                let cs = st.camera_sample();
                let cell = |v: f32, n: usize| ((v * n as f32) as usize).min(n - 1);
                film[cell(cs.p_film.y, 8)][cell(cs.p_film.x, 8)] += 1;
                rows[cell(cs.p_film.y, 64)] += 1;
                cols[cell(cs.p_film.x, 64)] += 1;
                lens[cell(cs.p_lens.y, 8)][cell(cs.p_lens.x, 8)] += 1;
                // The values a chain starts from are the ones drawn.
                let v = st.into_values();
                assert_eq!(v.len(), 5);
                assert_eq!((v[0], v[1]), (cs.p_film.x, cs.p_film.y));
            }
            let flat = |g: [[u32; 8]; 8]| g.iter().flatten().all(|&c| c == 1);
            assert!(
                flat(film),
                "seeds {first}.. of ({seed}, {stream}): {film:?}"
            );
            assert!(flat(lens), "lens of seeds {first}..: {lens:?}");
            assert!(rows.iter().all(|&c| c == 1), "rows {rows:?}");
            assert!(cols.iter().all(|&c| c == 1), "columns {cols:?}");
        }
    }
    // Different streams draw differently scrambled sequences.
    let p = |stream| {
        let mut st = Sampler::start_primary(Vec::new(), 5, Vec2::ZERO, Vec2::ONE)
            .with_stratified_fresh(seed_point(1, stream, 0));
        st.camera_sample().p_film
    };
    assert_ne!(p(0), p(1));
}

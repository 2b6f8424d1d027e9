//! The same scene, seed and spp give a byte-identical FLM with 1 and 2 threads (the tiles are
//! merged in a fixed order and every sample's randomness is keyed by pixel and index).
//! Reduced to 48×48 pixels and 2 passes of the Cornell box: the claim does not depend on size.
//! A sweep of passes (`Session::render_passes`) gives the film of those passes one by one.

mod render_util;

use luxfarm::film::flm::write_flm;
use luxfarm::render::{Session, SessionOptions};
use render_util::*;

fn flm_bytes(threads: usize) -> Vec<u8> {
    let path = scene_path("cornell/cornell.lxs");
    let text = with_resolution(&std::fs::read_to_string(&path).unwrap(), 48);
    let desc = parse_text(&text, &path);
    let opts = SessionOptions {
        threads,
        seed: 7,
        stream: 3,
    };
    let mut s = Session::new(&desc, path.parent().unwrap(), opts).unwrap();
    s.render_pass();
    s.render_pass();
    let mut out = Vec::new();
    write_flm(s.film(), s.film_params(), &mut out).unwrap();
    out
}

#[test]
fn flm_identical_with_one_and_two_threads() {
    let a = flm_bytes(1);
    let b = flm_bytes(2);
    assert!(!a.is_empty());
    assert!(a == b, "FLMs differ between 1 and 2 threads");
}

#[test]
fn different_streams_give_different_estimates() {
    let path = scene_path("cornell/cornell.lxs");
    let text = with_resolution(&std::fs::read_to_string(&path).unwrap(), 16);
    let desc = parse_text(&text, &path);
    let base = path.parent().unwrap();
    let a = render(
        &desc,
        base,
        SessionOptions {
            threads: 2,
            seed: 1,
            stream: 0,
        },
        1,
    );
    let b = render(
        &desc,
        base,
        SessionOptions {
            threads: 2,
            seed: 1,
            stream: 1,
        },
        1,
    );
    assert!(rms(&a, &b) > 0.0);
}

/// A sweep of passes draws the samples of that many single passes: the same film up to the
/// order of f64 sums, the same sample count and pass count. Sweeps of several passes are
/// only offered where nothing changes between passes.
#[test]
fn a_sweep_of_passes_is_those_passes() {
    let path = scene_path("cornell/cornell.lxs");
    let text = with_resolution(&std::fs::read_to_string(&path).unwrap(), 24);
    let desc = parse_text(&text, &path);
    let opts = SessionOptions {
        threads: 2,
        seed: 5,
        stream: 1,
    };
    let base = path.parent().unwrap();
    let mut one = Session::new(&desc, base, opts).unwrap();
    let mut swept = Session::new(&desc, base, opts).unwrap();
    assert!(swept.sweep_passes() >= 3, "a 24×24 film sweeps many passes");
    for _ in 0..3 {
        assert!(one.render_pass().complete);
    }
    let st = swept.render_passes(3);
    assert_eq!((st.passes, swept.passes()), (3, 3));
    assert_eq!(st.samples, 3 * swept.pass_samples());
    assert_eq!(one.film().total_samples(), swept.film().total_samples());
    let (a, b) = (one.film(), swept.film());
    for (x, y) in [(0, 0), (5, 7), (12, 12), (23, 23)] {
        let (p, q) = (a.pixel(0, 0, x, y).unwrap(), b.pixel(0, 0, x, y).unwrap());
        for (u, v) in p.iter().zip(q) {
            assert!(
                (u - v).abs() <= 1e-12 * u.abs().max(1.0),
                "({x}, {y}): {p:?} {q:?}"
            );
        }
    }
    assert!(rms(a, b) < 1e-12);
    // A fourth pass after the sweep continues both sequences alike.
    one.render_pass();
    swept.render_pass();
    assert!(rms(one.film(), swept.film()) < 1e-12);
}

/// A noise-aware sampler changes its map between passes: its sessions never sweep.
#[test]
fn noise_aware_sessions_render_one_pass_at_a_time() {
    let path = scene_path("cornell/cornell.lxs");
    let text = with_resolution(&std::fs::read_to_string(&path).unwrap(), 16).replace(
        r#""integer pixelsamples" [1]"#,
        r#""integer pixelsamples" [1] "bool noiseaware" ["true"]"#,
    );
    let desc = parse_text(&text, &path);
    let opts = SessionOptions {
        threads: 1,
        seed: 5,
        stream: 0,
    };
    let mut s = Session::new(&desc, path.parent().unwrap(), opts).unwrap();
    assert_eq!(s.sweep_passes(), 1);
    assert_eq!(s.render_passes(8).passes, 1);
}

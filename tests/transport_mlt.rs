//! The metropolis sampler: with path and with bidirectional it converges to the image of
//! path + random (32×32-pixel block means of independent renders agree within the noise the
//! runs measure), its chains accept a sane share of proposals, its films do not depend on
//! the thread count, and the films of two workers (streams) merge into their exact sum.

mod transport_common;

use luxfarm::film::BufferType;
use transport_common::*;

const PATH: &str = "Sampler \"random\" \"integer pixelsamples\" [4]\nSurfaceIntegrator \"path\" \"integer maxdepth\" [16]";
const MLT_PATH: &str = "Sampler \"metropolis\" \"integer pixelsamples\" [4]\nSurfaceIntegrator \"path\" \"integer maxdepth\" [16]";
const MLT_BIDIR: &str = "Sampler \"metropolis\" \"integer pixelsamples\" [2]\nSurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [16] \"integer lightdepth\" [16]";

#[test]
fn cornell_metropolis_path_matches_random_path() {
    let (p, dir) = scene("cornell/cornell.lxs", PATH, 64, 64);
    let (m, _) = scene("cornell/cornell.lxs", MLT_PATH, 64, 64);
    let rp = runs(&p, &dir, 0, 6, 2, 32);
    let rm = runs(&m, &dir, 100, 6, 2, 32);
    assert_agree("cornell metropolis+path/random+path", &rp, &rm, 4.0, 0.0);
}

#[test]
fn cornell_metropolis_bidirectional_matches_random_path() {
    let (p, dir) = scene("cornell/cornell.lxs", PATH, 64, 64);
    let (m, _) = scene("cornell/cornell.lxs", MLT_BIDIR, 64, 64);
    let rp = runs(&p, &dir, 0, 6, 2, 32);
    let rm = runs(&m, &dir, 200, 6, 2, 32);
    assert_agree("cornell metropolis+bidir/random+path", &rp, &rm, 4.0, 0.0);
}

#[test]
fn metropolis_renders_per_screen_without_fallback_warning() {
    let s = cornell_session(MLT_BIDIR, 16, 1, 0);
    assert_eq!(s.buffers(), &[BufferType::PerScreen, BufferType::PerScreen]);
    assert!(
        !s.warnings()
            .iter()
            .any(|w| w.to_string().contains("metropolis")),
        "{:?}",
        s.warnings()
    );
}

#[test]
fn chains_accept_a_sane_share_of_proposals() {
    let mut s = cornell_session(MLT_PATH, 32, 2, 0);
    s.render_pass();
    s.render_pass();
    let st = s.chain_stats().expect("metropolis chains");
    // Two passes of sample extent pixels × pixelsamples steps: Cornell's 0.5-wide box
    // filter widens 32² to 33² (`luxfarm::render::extent`).
    assert_eq!(st.proposed, 2 * 33 * 33 * 4);
    let rate = st.accepted as f64 / st.proposed as f64;
    eprintln!("acceptance {rate:.3} over {} proposals", st.proposed);
    assert!(rate > 0.05 && rate < 0.95, "acceptance rate {rate}");
}

#[test]
fn metropolis_film_does_not_depend_on_threads() {
    assert_thread_independent(MLT_BIDIR);
}

/// Two workers on their own streams: the merged film is the exact sum of theirs (buffers
/// and sample counts) and differs from either (independent chains).
#[test]
fn two_workers_merge_as_an_exact_sum() {
    let a = assert_streams_merge_exactly(MLT_BIDIR);
    // Two passes of 25² extent pixels × 2 (24² widened by the box filter).
    assert_eq!(a.sample_count(0), f64::from(2 * 25 * 25 * 2));
}

/// A render cut into many short sessions (a farm's leases: each lease is a session with
/// fresh chains) has the image of one long render. Each session here is one pass of 16
/// steps per chain, far shorter than a chain needs to forget a uniform starting point:
/// chains started at uniform points gave a whole-image mean 24 % low on this scene; chains
/// started at bootstrap samples drawn in proportion to their luminance are at their
/// stationary distribution from the first step.
#[test]
fn many_short_sessions_are_unbiased() {
    let short = "Sampler \"metropolis\" \"integer pixelsamples\" [1]\nSurfaceIntegrator \"path\" \"integer maxdepth\" [3]";
    let reference = "Sampler \"random\" \"integer pixelsamples\" [4]\nSurfaceIntegrator \"path\" \"integer maxdepth\" [3]";
    let (m, dir) = scene("cornell/cornell.lxs", short, 16, 16);
    let (p, _) = scene("cornell/cornell.lxs", reference, 16, 16);
    let rp = runs(&p, &dir, 0, 12, 4, 16);
    let rm = runs(&m, &dir, 1000, 48, 1, 16);
    assert_agree("short metropolis sessions/random path", &rp, &rm, 4.0, 0.0);
}

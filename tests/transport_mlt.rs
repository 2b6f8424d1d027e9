//! The metropolis sampler: with path and with bidirectional it converges to the image of
//! path + random (32×32-pixel block means of independent renders agree within the noise the
//! runs measure), its chains accept a sane share of proposals, its films do not depend on
//! the thread count, and the films of two workers (streams) merge into their exact sum.
//! Under a user sampling map the chains gather where the map is high and the image stays
//! that of path + random.

mod transport_common;

use luxfarm::film::BufferType;
use luxfarm::sampler::map::SamplingMap;
use std::sync::Arc;
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

/// A user sampling map weighting the left half of a `size`² film 9:1 over the right.
fn left_heavy(size: u32) -> Arc<SamplingMap> {
    let w: Vec<f32> = (0..size * size)
        .map(|i| if i % size < size / 2 { 9.0 } else { 1.0 })
        .collect();
    Arc::new(SamplingMap::from_weights(&w, size, size).unwrap())
}

/// Per-pixel luminance of `runs` Cornell renders (32², metropolis + path, `passes` each)
/// on streams `first..`, each under `map` when given.
fn mlt_runs(map: Option<&Arc<SamplingMap>>, first: u64, runs: u64, passes: u32) -> Vec<Vec<f64>> {
    (first..first + runs)
        .map(|stream| {
            let mut s = cornell_session(MLT_PATH, 32, 2, stream);
            assert!(s.takes_maps());
            assert!(s.set_user_map(map.cloned()).unwrap());
            for _ in 0..passes {
                assert!(s.render_pass().complete);
            }
            luminance(&s.take_film())
        })
        .collect()
}

/// Mean per-pixel variance between runs over the left and the right halves of a 32² film.
fn half_variances(runs: &[Vec<f64>]) -> (f64, f64) {
    let n = runs.len() as f64;
    let (mut l, mut r) = (0.0, 0.0);
    for i in 0..32 * 32 {
        let m = runs.iter().map(|v| v[i]).sum::<f64>() / n;
        let var = runs.iter().map(|v| (v[i] - m).powi(2)).sum::<f64>() / (n - 1.0);
        if i % 32 < 16 {
            l += var;
        } else {
            r += var;
        }
    }
    (l / 512.0, r / 512.0)
}

fn blocks(lum: &[f64], block: usize) -> Vec<f64> {
    let bw = 32 / block;
    let mut out = vec![0.0; bw * bw];
    for (i, v) in lum.iter().enumerate() {
        let (x, y) = (i % 32, i / 32);
        out[(y / block) * bw + x / block] += v / (block * block) as f64;
    }
    out
}

/// LuxRender's metropolis takes the user sampling map (and the noise-aware one) as a weight
/// on its chains' target. The image stays that of path + random (8-pixel block means), and
/// the samples gather on the left: relative to a render without the map, the right half's
/// per-pixel variance rises against the left's.
#[test]
fn metropolis_follows_a_user_map_without_bias() {
    let map = left_heavy(32);
    let mapped = mlt_runs(Some(&map), 300, 8, 3);
    let plain = mlt_runs(None, 400, 8, 3);
    let (ml, mr) = half_variances(&mapped);
    let (pl, pr) = half_variances(&plain);
    let gain = (mr / ml) / (pr / pl);
    eprintln!("variance left/right: mapped {ml:.5}/{mr:.5}, plain {pl:.5}/{pr:.5}; gain {gain:.2}");
    assert!(
        gain > 3.0,
        "right/left variance only {gain:.2} times the unmapped ratio"
    );
    let (p, dir) = scene("cornell/cornell.lxs", PATH, 32, 32);
    let rp = runs(&p, &dir, 0, 8, 2, 8);
    let rm: Vec<Vec<f64>> = mapped.iter().map(|l| blocks(l, 8)).collect();
    assert_agree(
        "metropolis under a user map/random path",
        &rp,
        &rm,
        4.0,
        0.0,
    );
}

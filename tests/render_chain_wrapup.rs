//! A wrap-up of the chain samplers' passes (`luxfarm::render::stops`): a metropolis or erpt
//! pass given a deadline already past, or the wrap-up flag, ends after one batch (metropolis:
//! `CHAINS × BATCH` steps; erpt: `SEED_BATCH` seeds), counts the samples it took and keeps
//! its film. That film is, bit for bit, the film of a pass planned at that many samples, and
//! the next pass goes on as after such a pass (the chains and normaliser of metropolis, the
//! next seed of erpt); its image has the brightness of whole passes. A wrap-up flag set from
//! another thread ends a pass far too long to finish. Without a wrap-up nothing changes
//! (a far deadline shortens nothing; the determinism tests cover the rest).

mod transport_common;

use luxfarm::film::Film;
use luxfarm::render::erpt::SEED_BATCH;
use luxfarm::render::mlt::{BATCH, CHAINS};
use luxfarm::render::{Session, SessionOptions};
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};
use transport_common::*;

/// Emitters seen directly: L = 1.5 over the left half, L = 4 over the upper right quarter,
/// black below it, on a 63² film whose 0.5-wide box filter widens the sample extent to 64²
/// (4096 pixels). Cheap samples of a known, varied luminance.
fn emitters(sampler: &str) -> luxfarm::lxs::SceneDescription {
    let text = format!(
        "LookAt 0 0 -1  0 0 0  0 1 0\n\
         Camera \"orthographic\" \"float screenwindow\" [-1 1 -1 1]\n\
         Film \"fleximage\" \"integer xresolution\" [63] \"integer yresolution\" [63]\n\
         PixelFilter \"box\" \"float xwidth\" [0.5] \"float ywidth\" [0.5]\n\
         {sampler}\nSurfaceIntegrator \"path\"\nWorldBegin\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [1.5 1.5 1.5] \"float power\" [0]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 2 1 0 3 2] \"point P\" \
         [-2 -2 0  0 -2 0  0 2 0  -2 2 0]\nAttributeEnd\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [4 4 4] \"float power\" [0]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 2 1 0 3 2] \"point P\" \
         [0 0 0  2 0 0  2 2 0  0 2 0]\nAttributeEnd\n\
         WorldEnd\n"
    );
    scene_text(&text, &here().join("emitters.lxs"))
}

fn here() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn metropolis(pixelsamples: u32) -> String {
    format!("Sampler \"metropolis\" \"integer pixelsamples\" [{pixelsamples}]")
}

/// Chains of 63 mutations: a seed counts 64 samples, so a pass of 4096 × `pixelsamples`
/// traces has 64 × `pixelsamples` seeds.
fn erpt(pixelsamples: u32) -> String {
    format!(
        "Sampler \"erpt\" \"integer pixelsamples\" [{pixelsamples}] \
         \"integer chainlength\" [63] \"integer initsamples\" [2048]"
    )
}

fn session(sampler: &str, stream: u64) -> Session {
    let opts = SessionOptions {
        threads: 2,
        seed: 9,
        stream,
    };
    let s = Session::new(&emitters(sampler), here(), opts).expect("session builds");
    assert_eq!(s.renderable().setup.sample_extent().pixels(), 4096);
    s
}

fn image_mean(f: &Film) -> f64 {
    let y = luminance(f);
    y.iter().sum::<f64>() / y.len() as f64
}

/// The two films hold the same sums, bit for bit, and the same sample count.
fn assert_identical(a: &Film, b: &Film) {
    assert_eq!(a.sample_count(0), b.sample_count(0));
    for buf in 0..a.buffer_types().len() {
        assert_eq!(a.buffer(0, buf), b.buffer(0, buf), "buffer {buf}");
    }
    assert!(a.buffer(0, 0).unwrap().iter().any(|v| *v > 0.0));
}

#[test]
fn a_metropolis_pass_past_its_deadline_is_one_batch_kept_whole() {
    let one_batch = CHAINS as u64 * BATCH;
    assert_eq!(one_batch, 4096, "the planned pass below is one batch");
    // Planned at 64 × 4096 steps, wrapped up after the first batch of each chain.
    let mut short = session(&metropolis(64), 0);
    assert_eq!(short.pass_samples(), 64 * 4096);
    short.set_deadline(Some(Instant::now()));
    // Planned at exactly one batch per chain.
    let mut planned = session(&metropolis(1), 0);
    assert_eq!(planned.pass_samples(), one_batch);
    for pass in 1..=2u64 {
        let st = short.render_pass();
        assert!(st.complete && st.wrapped_up, "{st:?}");
        assert_eq!(st.samples, one_batch);
        let full = planned.render_pass();
        assert!(full.complete && !full.wrapped_up, "{full:?}");
        // The same deposits and the same count: the next pass went on as after a pass
        // of one batch (chains, normaliser).
        assert_identical(short.film(), planned.film());
        assert_eq!(short.film().total_samples(), (pass * one_batch) as f64);
        assert_eq!(short.passes(), pass);
    }
    // Brightness: whole passes of another stream have the image mean of the shortened ones
    // (a count of the planned samples would make them 64 times too dark). One batch's mean
    // wanders by about 1 % here (the normaliser from 8192 bootstrap samples); 10 % is far
    // beyond the noise.
    let mut whole = session(&metropolis(4), 1);
    for _ in 0..2 {
        let st = whole.render_pass();
        assert!(st.complete && !st.wrapped_up);
        assert_eq!(st.samples, 4 * 4096);
    }
    let (ms, mw) = (image_mean(short.film()), image_mean(whole.film()));
    eprintln!("image mean: wrapped-up passes {ms:.4}, whole passes {mw:.4}");
    assert!(mw > 0.0 && (ms / mw - 1.0).abs() < 0.1, "{ms} vs {mw}");
}

#[test]
fn an_erpt_pass_wrapped_up_ends_after_a_seed_batch_and_the_next_goes_on() {
    let batch_samples = SEED_BATCH * 64;
    // Planned at 16 × 64 seeds, wrapped up after the first 64 (the flag, set beforehand).
    let mut short = session(&erpt(16), 0);
    assert_eq!(short.pass_samples(), 16 * 4096);
    short.wrap_up_flag().store(true, Ordering::Relaxed);
    // Planned at exactly 64 seeds.
    let mut planned = session(&erpt(1), 0);
    assert_eq!(planned.pass_samples(), batch_samples);
    for pass in 1..=2u64 {
        let st = short.render_pass();
        assert!(st.complete && st.wrapped_up, "{st:?}");
        assert_eq!(st.samples, batch_samples);
        let full = planned.render_pass();
        assert!(full.complete && !full.wrapped_up, "{full:?}");
        // The second pass started at seed 64 in both: the shortened pass advanced the
        // seeds by those it did, not by the 1024 it planned.
        assert_identical(short.film(), planned.film());
        assert_eq!(short.film().total_samples(), (pass * batch_samples) as f64);
    }
    assert_eq!(short.chain_stats(), planned.chain_stats());
    // Brightness: 8 wrapped-up passes (512 seeds) against one whole pass of 1024 seeds on
    // another stream. A seed's energy (0, 1.5 or 4) varies by about 0.8 of the mean, so the
    // means have standard errors of about 4 % and 3 %; 25 % is five combined ones, and a
    // count of the planned samples would make the shortened passes 16 times too dark.
    for _ in 2..8 {
        assert!(short.render_pass().wrapped_up);
    }
    assert_eq!(short.film().total_samples(), (8 * batch_samples) as f64);
    short.wrap_up_flag().store(false, Ordering::Relaxed);
    let mut whole = session(&erpt(16), 1);
    let st = whole.render_pass();
    assert!(st.complete && !st.wrapped_up && st.samples == 16 * 4096);
    let (ms, mw) = (image_mean(short.film()), image_mean(whole.film()));
    eprintln!("image mean: wrapped-up passes {ms:.4}, a whole pass {mw:.4}");
    assert!(mw > 0.0 && (ms / mw - 1.0).abs() < 0.25, "{ms} vs {mw}");
}

/// The wrap-up flag set from another thread ends a metropolis pass planned far longer than
/// the test at a batch boundary, with its work (no timing is asserted: the pass could not
/// have ended on its own).
#[test]
fn the_wrap_up_flag_ends_a_long_pass_from_another_thread() {
    let mut s = session(&metropolis(65536), 2);
    let planned = s.pass_samples();
    let flag = s.wrap_up_flag();
    let setter = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(300));
        flag.store(true, Ordering::Relaxed);
    });
    let st = s.render_pass();
    setter.join().unwrap();
    assert!(st.complete && st.wrapped_up, "{st:?}");
    assert!(st.samples > 0 && st.samples < planned, "{st:?}");
    assert_eq!(st.samples % (CHAINS as u64 * BATCH), 0, "whole batches");
    assert_eq!(s.film().total_samples(), st.samples as f64);
    assert!(image_mean(s.film()) > 0.0);
}

/// A deadline far ahead shortens nothing: the pass is the planned one.
#[test]
fn a_far_deadline_leaves_passes_whole() {
    for sampler in [metropolis(2), erpt(2)] {
        let mut s = session(&sampler, 3);
        s.set_deadline(Some(Instant::now() + Duration::from_secs(3600)));
        let st = s.render_pass();
        assert!(st.complete && !st.wrapped_up, "{sampler}: {st:?}");
        assert_eq!(st.samples, s.pass_samples(), "{sampler}");
    }
}

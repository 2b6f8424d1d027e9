//! Admission control at submission: what a job will cost the master and whether it can
//! render, decided before it is queued, with a 4xx naming the figure or the scene location.
//!
//! ```text
//! SceneInfo (film size, light groups, camera, shapes, lights) + SubmitOptions
//!   --check_overrides--> halt overrides in range
//!   --admit--> film memory within --max-job-memory, light groups and delta size within what
//!              the delta codec carries, a camera and something to see, a halt rule
//!              (the master's default when none is given, noted on the job)
//! ```
//!
//! Tags (what jobs ask of workers and workers offer) are cleaned here too ([`clean_tags`]),
//! for submissions and worker registrations alike.
//!
//! A job's memory on the master: its merged film (pixels x light groups x buffers x 5 f64),
//! a copy of it while a checkpoint is written, and one decoded delta per merge slot.

use crate::config::Config;
use crate::error::{Result, ServerError};
use crate::scene::SceneInfo;
use luxfarm::film::PIXEL_VALUES;
use luxfarm_wire::codec;

/// Submission options (halt overrides, seed, priority, scene choice) and who submits.
#[derive(Clone, Debug, Default)]
pub struct SubmitOptions {
    /// Job name (default: the Film's filename, else the scene's file stem).
    pub name: Option<String>,
    pub haltspp: Option<f64>,
    pub halttime: Option<f64>,
    pub haltthreshold: Option<f64>,
    pub seed: Option<u64>,
    pub priority: Option<i32>,
    /// Path of the .lxs inside a bundle holding several.
    pub scene: Option<String>,
    /// The animation frame to render (animated scene formats).
    pub frame: Option<i64>,
    /// The submitter (a token's name; set by the API from the caller's identity).
    pub owner: String,
    /// The sequence the job is a frame of (its id) and the frame's number there.
    pub sequence: Option<String>,
    pub sequence_frame: Option<i64>,
    /// Tags a worker must all have; memory (MiB) it must have; most workers at once.
    pub tags: Vec<String>,
    pub min_memory_mb: Option<u64>,
    pub max_workers: Option<u32>,
    /// The job's own webhook URL (http or https), posted to when the job ends.
    pub webhook: Option<String>,
}

/// What admission decided: the job's halt rules and the notes shown with it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Admitted {
    pub haltspp: Option<f64>,
    pub halttime: Option<f64>,
    pub haltthreshold: Option<f64>,
    pub notes: Vec<String>,
}

/// Refuses halt overrides that are not finite positive numbers, or beyond the master's
/// limits, a priority outside 0–100, and a job webhook that is not an http(s) URL of at most
/// 2048 bytes (or any job webhook with `--no-job-webhooks`).
pub fn check_overrides(cfg: &Config, o: &SubmitOptions) -> Result<()> {
    if let Some(p) = o.priority.filter(|p| !(0..=100).contains(p)) {
        return Err(ServerError::BadRequest(format!(
            "priority {p}: priorities run from 0 (default) to 100 (first)"
        )));
    }
    if let Some(url) = o.webhook.as_deref().filter(|u| !u.is_empty()) {
        if cfg.no_job_webhooks {
            return Err(ServerError::BadRequest(
                "webhook: this master takes no webhooks of single jobs (--no-job-webhooks); \
                 its own hook, if any, reports every job"
                    .into(),
            ));
        }
        crate::config::check_hook_url(url)
            .map_err(|e| ServerError::BadRequest(format!("webhook: {e}")))?;
    }
    check_halts(cfg, o.haltspp, o.halttime, o.haltthreshold)
}

fn check_halts(
    cfg: &Config,
    spp: Option<f64>,
    time: Option<f64>,
    threshold: Option<f64>,
) -> Result<()> {
    let bad = |m: String| Err(ServerError::BadRequest(m));
    if let Some(v) = spp {
        if !(v.is_finite() && v > 0.0) {
            return bad("haltspp must be a positive number".into());
        }
        if v > cfg.max_haltspp {
            return bad(format!(
                "haltspp {v} is more than the master allows ({}, --max-haltspp)",
                cfg.max_haltspp
            ));
        }
    }
    if let Some(v) = time {
        if !(v.is_finite() && v > 0.0) {
            return bad("halttime must be a positive number".into());
        }
        if v > cfg.max_halttime {
            return bad(format!(
                "halttime {v} s is more than the master allows ({} s, --max-halttime)",
                cfg.max_halttime
            ));
        }
    }
    if threshold.is_some_and(|v| !(v.is_finite() && v > 0.0 && v < 1.0)) {
        return bad("haltthreshold must be in (0, 1)".into());
    }
    Ok(())
}

/// Bytes of one film of the scene's layout (f64 sums), with its depth buffer (a sum and a
/// weight per pixel) when an output asks for Z, and its variance sums (three per pixel) when
/// the sampler is noise-aware.
pub fn film_bytes(info: &SceneInfo) -> u64 {
    let per_pixel = (PIXEL_VALUES * 8) as u64;
    let depth = if info.params.wants_zbuf() {
        info.pixels.saturating_mul(DEPTH_BYTES_PER_PIXEL)
    } else {
        0
    };
    let variance = if info.noise_aware {
        info.pixels.saturating_mul(VARIANCE_BYTES_PER_PIXEL)
    } else {
        0
    };
    info.pixels
        .saturating_mul(info.groups.len() as u64)
        .saturating_mul(info.buffers.len().max(1) as u64)
        .saturating_mul(per_pixel)
        .saturating_add(depth)
        .saturating_add(variance)
}

/// A depth buffer's bytes per pixel: an f64 sum and an f64 weight (`luxfarm::film::ZBuffer`).
const DEPTH_BYTES_PER_PIXEL: u64 = 16;

/// Variance sums' bytes per pixel: Σw, Σw·Y and Σw·Y² as f64
/// (`luxfarm::film::VarianceBuffer`).
const VARIANCE_BYTES_PER_PIXEL: u64 = 24;

/// Decides whether a scene may be queued, and with which halt rules.
pub fn admit(
    cfg: &Config,
    merge_slots: usize,
    info: &SceneInfo,
    o: &SubmitOptions,
) -> Result<Admitted> {
    renderable(info)?;
    let groups = info.groups.len();
    if groups > codec::MAX_GROUPS {
        return Err(ServerError::BadRequest(format!(
            "{}: {groups} light groups, more than the {} a film delta carries",
            info.scene,
            codec::MAX_GROUPS
        )));
    }
    let film = film_bytes(info);
    let copies = 2 + merge_slots as u64;
    let need = film.saturating_mul(copies);
    if need > cfg.max_job_memory {
        return Err(ServerError::TooLarge(format!(
            "{}: the film ({}x{} pixels x {groups} light group(s)) takes {}; with a checkpoint \
             copy and {merge_slots} decoded deltas the job needs {}, more than the master's \
             budget of {} (--max-job-memory)",
            info.scene,
            info.width,
            info.height,
            human(film),
            human(need),
            human(cfg.max_job_memory)
        )));
    }
    if film > codec::MAX_DECODED {
        return Err(ServerError::BadRequest(format!(
            "{}: a delta of the film ({}x{} pixels x {groups} light group(s)) takes {}, more \
             than the {} a delta carries",
            info.scene,
            info.width,
            info.height,
            human(film),
            human(codec::MAX_DECODED)
        )));
    }
    let mut a = Admitted {
        haltspp: o.haltspp.or(info.haltspp),
        halttime: o.halttime.or(info.halttime),
        haltthreshold: o.haltthreshold.or(info.haltthreshold),
        notes: Vec::new(),
    };
    // The scene's own halt rules are held to the same limits as overrides.
    check_halts(cfg, a.haltspp, a.halttime, a.haltthreshold)?;
    if a.haltspp.is_none() && a.halttime.is_none() && a.haltthreshold.is_none() {
        a.haltspp = Some(cfg.default_haltspp);
        a.notes.push(format!(
            "no halt rule given: the master's default haltspp {} applies (--default-haltspp)",
            cfg.default_haltspp
        ));
    }
    Ok(a)
}

/// Refuses a scene that cannot render: no camera, or nothing in it.
fn renderable(info: &SceneInfo) -> Result<()> {
    if !info.has_camera {
        return Err(ServerError::BadRequest(format!(
            "{}:1:1: the scene has no Camera statement: nothing can be rendered",
            info.scene
        )));
    }
    if info.shapes == 0 && info.lights == 0 {
        return Err(ServerError::BadRequest(format!(
            "{}:1:1: the scene has no shapes and no lights: there is nothing to see",
            info.scene
        )));
    }
    Ok(())
}

/// A byte count for people (binary units).
fn human(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = bytes as f64;
    let mut unit = 0;
    while v >= 1024.0 && unit + 1 < UNITS.len() {
        v /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{v:.1} {} ({bytes} bytes)", UNITS[unit])
    }
}

/// A job name fit for lists and terminals: control characters become spaces, at most 200
/// characters.
pub fn clean_name(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .take(200)
        .collect::<String>()
        .trim()
        .to_string()
}

/// Most tags a worker or a job may carry, and the longest tag.
pub const MAX_TAGS: usize = 32;
pub const MAX_TAG_LEN: usize = 64;

/// Tags as the master keeps them: trimmed, lowercased, only `[a-z0-9._-]`, sorted, without
/// duplicates; a tag with another character is refused (it would not match what users type).
pub fn clean_tags(tags: &[String]) -> Result<Vec<String>> {
    let mut out: Vec<String> = Vec::new();
    for t in tags.iter().flat_map(|t| t.split(',')) {
        let t = t.trim().to_ascii_lowercase();
        if t.is_empty() {
            continue;
        }
        let ok = t.len() <= MAX_TAG_LEN
            && t.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
        if !ok {
            let shown: String = t.chars().take(MAX_TAG_LEN).collect();
            return Err(ServerError::BadRequest(format!(
                "tag {shown:?}: tags are 1 to {MAX_TAG_LEN} of a-z 0-9 . _ -"
            )));
        }
        out.push(t);
    }
    out.sort();
    out.dedup();
    if out.len() > MAX_TAGS {
        return Err(ServerError::BadRequest(format!(
            "{} tags: at most {MAX_TAGS}",
            out.len()
        )));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use luxfarm::film::FilmParams;

    fn info(w: u32, h: u32, groups: usize) -> SceneInfo {
        SceneInfo {
            params: FilmParams::from_entity(None).unwrap(),
            width: w,
            height: h,
            pixels: u64::from(w) * u64::from(h),
            pass_pixels: u64::from(w + 4) * u64::from(h + 4),
            groups: (0..groups).map(|i| format!("g{i}")).collect(),
            buffers: vec![luxfarm::film::BufferType::PerPixel],
            haltspp: None,
            halttime: None,
            haltthreshold: None,
            convergence_step: 32.0,
            noise_aware: false,
            map_refusal: None,
            basename: "s".into(),
            name: "s".into(),
            scene: "s.lxs".into(),
            has_camera: true,
            shapes: 1,
            lights: 1,
        }
    }

    fn cfg() -> Config {
        Config::local("unused".into())
    }

    #[test]
    fn a_film_beyond_the_memory_budget_is_refused_with_its_figure() {
        let e = admit(&cfg(), 2, &info(16384, 16384, 1), &SubmitOptions::default()).unwrap_err();
        assert!(matches!(e, ServerError::TooLarge(_)), "{e}");
        let m = e.to_string();
        assert!(m.contains("16384x16384"), "{m}");
        assert!(m.contains("10737418240 bytes"), "{m}");
        assert!(m.contains("--max-job-memory"), "{m}");
        admit(&cfg(), 2, &info(1920, 1080, 1), &SubmitOptions::default()).unwrap();
    }

    #[test]
    fn a_z_output_adds_its_depth_buffer_to_the_film() {
        let plain = info(100, 50, 2);
        let mut z = info(100, 50, 2);
        z.params.exr.enabled = true;
        z.params.exr.zbuf = true;
        assert_eq!(film_bytes(&z) - film_bytes(&plain), 100 * 50 * 16);
        // Z asked of an output that is not written renders no depth.
        z.params.exr.enabled = false;
        assert_eq!(film_bytes(&z), film_bytes(&plain));
    }

    #[test]
    fn a_noise_aware_sampler_adds_its_variance_sums_to_the_film() {
        let plain = info(100, 50, 2);
        let mut na = info(100, 50, 2);
        na.noise_aware = true;
        assert_eq!(film_bytes(&na) - film_bytes(&plain), 100 * 50 * 24);
    }

    #[test]
    fn light_groups_are_bounded_by_the_codec_and_the_budget() {
        let e = admit(&cfg(), 2, &info(8, 8, 1100), &SubmitOptions::default()).unwrap_err();
        assert!(e.to_string().contains("1100 light groups"), "{e}");
        // 20 groups on a 1080p film fit a delta, not the memory budget.
        let e = admit(&cfg(), 2, &info(1920, 1080, 20), &SubmitOptions::default());
        assert!(matches!(e, Err(ServerError::TooLarge(_))), "{e:?}");
        // With any memory budget, 1000 groups on a 1080p film are more than a delta carries.
        let mut big = cfg();
        big.max_job_memory = u64::MAX;
        let e = admit(&big, 2, &info(1920, 1080, 1000), &SubmitOptions::default());
        assert!(matches!(e, Err(ServerError::BadRequest(_))), "{e:?}");
        assert!(e.unwrap_err().to_string().contains("a delta carries"));
    }

    #[test]
    fn a_scene_without_camera_or_content_is_refused() {
        let mut i = info(8, 8, 1);
        i.has_camera = false;
        let e = admit(&cfg(), 2, &i, &SubmitOptions::default()).unwrap_err();
        assert!(e.to_string().starts_with("s.lxs:1:1: "), "{e}");
        let mut i = info(8, 8, 1);
        i.shapes = 0;
        i.lights = 0;
        let e = admit(&cfg(), 2, &i, &SubmitOptions::default()).unwrap_err();
        assert!(e.to_string().contains("nothing to see"), "{e}");
    }

    #[test]
    fn a_job_without_halt_rule_gets_the_default_and_says_so() {
        let a = admit(&cfg(), 2, &info(8, 8, 1), &SubmitOptions::default()).unwrap();
        assert_eq!(a.haltspp, Some(256.0));
        assert!(a.notes[0].contains("default haltspp 256"), "{:?}", a.notes);
        let o = SubmitOptions {
            halttime: Some(60.0),
            ..SubmitOptions::default()
        };
        let a = admit(&cfg(), 2, &info(8, 8, 1), &o).unwrap();
        assert_eq!((a.haltspp, a.halttime), (None, Some(60.0)));
        assert!(a.notes.is_empty());
    }

    #[test]
    fn halt_rules_beyond_the_limits_are_refused() {
        for o in [
            SubmitOptions {
                haltspp: Some(1e308),
                ..SubmitOptions::default()
            },
            SubmitOptions {
                halttime: Some(1e12),
                ..SubmitOptions::default()
            },
            SubmitOptions {
                haltspp: Some(f64::NAN),
                ..SubmitOptions::default()
            },
            SubmitOptions {
                haltthreshold: Some(1.0),
                ..SubmitOptions::default()
            },
        ] {
            assert!(check_overrides(&cfg(), &o).is_err(), "{o:?}");
        }
        // The scene's own haltspp too.
        let mut i = info(8, 8, 1);
        i.haltspp = Some(1e9);
        assert!(admit(&cfg(), 2, &i, &SubmitOptions::default()).is_err());
    }

    #[test]
    fn names_lose_control_characters() {
        assert_eq!(clean_name("a\u{1b}[31mb\n"), "a [31mb");
        assert_eq!(clean_name(&"x".repeat(300)).len(), 200);
    }

    #[test]
    fn tags_are_normalised_and_bad_ones_refused() {
        let t = |v: &[&str]| clean_tags(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        assert_eq!(t(&["GPU", " big-mem,gpu", ""]).unwrap(), ["big-mem", "gpu"]);
        assert!(t(&["a b"]).is_err());
        assert!(t(&["../x"]).is_err());
        assert!(t(&[&"x".repeat(65)]).is_err());
        let many: Vec<String> = (0..33).map(|i| format!("t{i}")).collect();
        assert!(clean_tags(&many).is_err());
    }

    #[test]
    fn a_job_webhook_must_be_a_short_http_url_and_allowed() {
        let mut c = cfg();
        let hook = |u: &str| SubmitOptions {
            webhook: Some(u.into()),
            ..SubmitOptions::default()
        };
        assert!(check_overrides(&c, &hook("https://hooks.example/x")).is_ok());
        let e = check_overrides(&c, &hook("gopher://x/")).unwrap_err();
        assert!(
            matches!(e, ServerError::BadRequest(ref m) if m.starts_with("webhook:")),
            "{e}"
        );
        let long = format!("http://h/{}", "x".repeat(3000));
        assert!(check_overrides(&c, &hook(&long)).is_err());
        c.no_job_webhooks = true;
        let e = check_overrides(&c, &hook("https://hooks.example/x")).unwrap_err();
        assert!(e.to_string().contains("--no-job-webhooks"), "{e}");
        assert!(check_overrides(&c, &SubmitOptions::default()).is_ok());
    }
}

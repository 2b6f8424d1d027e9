//! The TestSuite's LuxRender 0.6-era daylight scenes (`LightSource "sunsky"`) build and render:
//! sunsky_low/mid/high (a sun at 12.6°, 44° and 90° elevation over the same geometry) and
//! uvmaptest. Reduced to 64×48 pixels and 2 spp (debug builds are slow): every film must be
//! finite, without rejected samples, and lit; and a low sun must give a darker scene than a
//! high one.

mod render_util;

use luxfarm::film::Film;
use luxfarm::light::Light;
use luxfarm::lxs::{ParamValue, SceneDescription};
use luxfarm::render::{Session, SessionOptions};
use render_util::*;

const SUNSKY: &str = "testsuite/sunsky_low-mid-high";

/// The scene at 64×48 pixels and 2 samples per pixel.
fn reduced(rel: &str) -> (SceneDescription, std::path::PathBuf) {
    let path = scene_path(rel);
    reduce(parse(&path), path)
}

fn reduce(
    mut desc: SceneDescription,
    path: std::path::PathBuf,
) -> (SceneDescription, std::path::PathBuf) {
    let film = desc.film.as_mut().expect("scene has a Film");
    film.params
        .add("xresolution", ParamValue::Integer(vec![64]));
    film.params
        .add("yresolution", ParamValue::Integer(vec![48]));
    let sampler = desc.sampler.as_mut().expect("scene has a Sampler");
    sampler
        .params
        .add("pixelsamples", ParamValue::Integer(vec![2]));
    (desc, path)
}

struct Rendered {
    film: Film,
    rejected: u64,
    lights: Vec<&'static str>,
    warnings: Vec<String>,
}

fn render_reduced(rel: &str) -> Rendered {
    let (desc, path) = reduced(rel);
    render_desc(&desc, &path)
}

fn render_desc(desc: &SceneDescription, path: &std::path::Path) -> Rendered {
    let opts = SessionOptions {
        threads: 2,
        seed: 5,
        stream: 0,
    };
    let mut s = Session::new(desc, path.parent().unwrap(), opts).expect("scene builds");
    let lights = s
        .renderable()
        .world
        .lights()
        .iter()
        .map(|l| match l {
            Light::Sun(_) => "sun",
            Light::Sky(_) => "sky",
            _ => "other",
        })
        .collect();
    let warnings = s.warnings().iter().map(|w| w.to_string()).collect();
    let stats = s.render_pass();
    assert!(stats.complete);
    Rendered {
        film: s.take_film(),
        rejected: stats.rejected,
        lights,
        warnings,
    }
}

/// Mean film Y over the image, after checking every pixel is finite and lit.
fn mean_y(r: &Rendered, what: &str) -> f64 {
    assert_eq!(
        r.lights,
        ["sun", "sky"],
        "{what}: sunsky is a sun and a sky"
    );
    assert_eq!(r.rejected, 0, "{what}: NaN/Inf/negative samples");
    // 0.x exporters wrote a "color L" that LuxRender 1.x's sun and sky do not read.
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("LightSource \"sunsky\": unused parameter \"L\"")),
        "{what}: {:?}",
        r.warnings
    );
    let xyz = normalized_xyz(&r.film);
    assert_eq!(xyz.len(), 64 * 48);
    assert!(
        xyz.iter().flatten().all(|v| v.is_finite() && *v >= 0.0),
        "{what}"
    );
    let lit = xyz.iter().filter(|p| p[1] > 0.0).count();
    assert!(lit > xyz.len() * 9 / 10, "{what}: only {lit} lit pixels");
    let mean = xyz.iter().map(|p| p[1]).sum::<f64>() / xyz.len() as f64;
    eprintln!("{what}: mean Y {mean:.1} cd/m²");
    mean
}

#[test]
fn sunsky_low_mid_high_render_and_a_low_sun_is_darker() {
    let low = mean_y(&render_reduced(&format!("{SUNSKY}/sunsky_low.lxs")), "low");
    let mid = mean_y(&render_reduced(&format!("{SUNSKY}/sunsky_mid.lxs")), "mid");
    let high = mean_y(
        &render_reduced(&format!("{SUNSKY}/sunsky_high.lxs")),
        "high",
    );
    assert!(low < 0.8 * high, "low {low} vs high {high}");
    assert!(low < mid, "low {low} vs mid {mid}");
    // Daylight scale: sky and sunlit white surfaces are thousands of cd/m².
    assert!(high > 1e3 && high < 1e6, "{high}");
}

#[test]
fn uvmaptest_renders() {
    mean_y(
        &render_reduced("testsuite/uvmaptest/uvmaptest.lxs"),
        "uvmaptest",
    );
}

/// SunSky_Params.lxs's light (Perez multipliers aconst..econst, relsize 2; its own geometry
/// file is missing on purpose) over sunsky_low's geometry: every parameter is consumed.
#[test]
fn sunsky_params_light_is_understood() {
    let path = scene_path(&format!("{SUNSKY}/sunsky_low.lxs"));
    let text = std::fs::read_to_string(&path).unwrap();
    let params = "\"float turbidity\" [2.000000]\n\
        \"float aconst\" [0.500000] \"float bconst\" [0.500000] \"float cconst\" [1.000000] \
        \"float dconst\" [1.000000] \"float econst\" [1.000000]\n\"float relsize\" [2.000000]\n";
    assert!(text.contains("\"float turbidity\" [2.000000]"));
    let text = text.replace("\"float turbidity\" [2.000000]", params);
    let (desc, path) = reduce(parse_text(&text, &path), path);
    let r = render_desc(&desc, &path);
    mean_y(&r, "sunsky_params light");
    let about_light: Vec<_> = r
        .warnings
        .iter()
        .filter(|w| w.contains("LightSource"))
        .collect();
    assert_eq!(about_light.len(), 1, "{about_light:?}");
}

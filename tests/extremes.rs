//! Numerical stability at the extremes, rendered (issue 21, build point 4): a small Cornell-like
//! box (big ceiling lamp, matte walls, one matte and one exchangeable sphere) is generated as
//! scene text with the scale, translation, lamp radiance, field of view and second-sphere
//! material under test, parsed, rendered at 32×32 for a few passes, and compared with the
//! scale-1 render. Every case also counts the contributions the film refused as NaN/Inf
//! (`PassStats.rejected`): it must stay 0. Film-level cases (16k films, FLM overflow, 10^6 spp,
//! 10^6 merges) are in `extremes_film.rs`; the README's "Numerical stability at the extremes"
//! table lists every case with its tolerance.
//!
//! "Within noise" compares 4×4 block means of Y: the difference to the reference must stay
//! close to the difference between two independent renders (another stream) of the reference.

mod render_util;

use luxfarm::film::Film;
use luxfarm::lxs::SceneDescription;
use luxfarm::render::{Session, SessionOptions};
use render_util::*;
use std::path::Path;

const RES: u32 = 32;
const PASSES: u32 = 8;
/// Second sphere's default material (the reference).
const MATTE: &str = r#""string type" ["matte"] "color Kd" [0.5 0.5 0.5]"#;
const LAMP: [f64; 3] = [4.0, 3.5, 3.0];

/// What a generated box varies.
#[derive(Clone)]
struct Box_ {
    scale: f64,
    offset: f64,
    radiance: f64,
    fov: f64,
    /// Parameters of the second sphere's material; `None`: no second sphere.
    sphere2: Option<String>,
    /// Orthographic camera 1000 box units in front of the box instead of the perspective one.
    ortho: bool,
    /// Leave the orthographic camera's `hither` at LuxRender's default (1e-3 world units)
    /// instead of 1e-3 box units.
    default_hither: bool,
}

impl Default for Box_ {
    fn default() -> Box_ {
        Box_ {
            scale: 1.0,
            offset: 0.0,
            radiance: 1.0,
            fov: 39.3,
            sphere2: Some(MATTE.to_string()),
            ortho: false,
            default_hither: false,
        }
    }
}

impl Box_ {
    fn text(&self) -> String {
        let (s, o) = (self.scale, self.offset);
        let p = |x: f64, y: f64, z: f64| format!("{:e} {:e} {:e}", x * s + o, y * s + o, z * s + o);
        let l = LAMP.map(|c| format!("{:e}", c * self.radiance)).join(" ");
        let sphere2 = match &self.sphere2 {
            Some(m) => format!(
                "AttributeBegin\n MakeNamedMaterial \"s2\" {m}\n NamedMaterial \"s2\"\n \
                 Translate 0.45 -0.3 0.35\n Shape \"sphere\" \"float radius\" [0.35]\nAttributeEnd\n"
            ),
            None => String::new(),
        };
        let camera = if self.ortho {
            // The near plane as the perspective camera's: at scale 1e-6 LuxRender's default
            // hither (1e-3) would lie at the box's centre plane, 1000 units from the camera.
            let w = 1.1 * s;
            let hither = if self.default_hither {
                String::new()
            } else {
                format!(" \"float hither\" [{:e}]", 1e-3 * s)
            };
            format!(
                "LookAt {} {} 0 0 1\nCamera \"orthographic\" \"float screenwindow\" [{:e} {w:e} {:e} {w:e}]{hither}",
                p(0.0, -1000.0, 1.0),
                p(0.0, 0.0, 1.0),
                -w,
                -w,
            )
        } else {
            format!(
                "LookAt {} {} 0 0 1\nCamera \"perspective\" \"float fov\" [{}] \"float hither\" [{:e}]",
                p(0.0, -3.9, 1.0),
                p(0.0, 0.0, 1.0),
                self.fov,
                1e-3 * s
            )
        };
        format!(
            r#"{camera}
Film "fleximage" "integer xresolution" [{RES}] "integer yresolution" [{RES}]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [1]
SurfaceIntegrator "path" "integer maxdepth" [6] "string rrstrategy" ["none"]
WorldBegin
Translate {o:e} {o:e} {o:e}
Scale {s:e} {s:e} {s:e}
MakeNamedMaterial "white" "string type" ["matte"] "color Kd" [0.75 0.75 0.75]
MakeNamedMaterial "red" "string type" ["matte"] "color Kd" [0.63 0.065 0.05]
AttributeBegin
  NamedMaterial "white"
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3 4 6 5 4 7 6 8 9 10 8 10 11 12 14 13 12 15 14]
    "point P" [-1 -1 0 1 -1 0 1 1 0 -1 1 0 -1 -1 2 1 -1 2 1 1 2 -1 1 2 -1 1 0 1 1 0 1 1 2 -1 1 2
               1 -1 0 1 1 0 1 1 2 1 -1 2]
AttributeEnd
AttributeBegin
  NamedMaterial "red"
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-1 -1 0 -1 1 0 -1 1 2 -1 -1 2]
AttributeEnd
AttributeBegin
  NamedMaterial "white"
  AreaLightSource "area" "color L" [{l}] "float power" [0] "float efficacy" [0]
  Shape "trianglemesh" "integer indices" [0 2 1 0 3 2]
    "point P" [-0.5 -0.5 1.99 0.5 -0.5 1.99 0.5 0.5 1.99 -0.5 0.5 1.99]
AttributeEnd
AttributeBegin
  NamedMaterial "white"
  Translate -0.4 0.3 0.4
  Shape "sphere" "float radius" [0.4]
AttributeEnd
{sphere2}WorldEnd
"#,
        )
    }

    fn desc(&self) -> SceneDescription {
        parse_text(&self.text(), Path::new("extremes.lxs"))
    }
}

/// Renders a description; returns the film and the contributions refused over all passes.
fn render_counted(desc: &SceneDescription, stream: u64, passes: u32) -> (Film, u64) {
    let opts = SessionOptions {
        threads: 2,
        seed: 21,
        stream,
    };
    let mut s = Session::new(desc, Path::new("."), opts).expect("session builds");
    let mut rejected = 0;
    for _ in 0..passes {
        let st = s.render_pass();
        assert!(st.complete);
        rejected += st.rejected;
    }
    (s.take_film(), rejected)
}

/// Renders a box, asserting that no NaN/Inf reached the film and every pixel is finite.
fn render_box(b: &Box_, stream: u64) -> Film {
    let (film, rejected) = render_counted(&b.desc(), stream, PASSES);
    assert_eq!(rejected, 0, "NaN/Inf contributions refused by the film");
    let xyz = normalized_xyz(&film);
    assert!(xyz.iter().flatten().all(|v| v.is_finite()));
    film
}

struct Reference {
    a: Vec<f64>,
    noise: f64,
    mean: f64,
}

fn reference() -> Reference {
    let b = Box_::default();
    let a = block_means(&render_box(&b, 0), 4);
    let a2 = block_means(&render_box(&b, 1), 4);
    let mean = a.iter().sum::<f64>() / a.len() as f64;
    assert!(mean > 0.0, "black reference");
    Reference {
        noise: rmse(&a, &a2),
        a,
        mean,
    }
}

impl Reference {
    /// Same image within noise: RMSE of the 4×4 block means ≤ 1.6 × the stream-to-stream
    /// RMSE + 1% of the mean.
    fn assert_same(&self, other: &Film, what: &str) {
        let b = block_means(other, 4);
        let diff = rmse(&self.a, &b);
        assert!(
            diff <= 1.6 * self.noise + 0.01 * self.mean,
            "{what}: difference {diff:.5} vs noise {:.5} (mean {:.4})",
            self.noise,
            self.mean
        );
    }
}

/// The perspective box at scale 1e-4 and 1e6 renders the same image (same seed: identical
/// here); below 1e-4 the whole box is nearer than LuxRender's hither floor (1e-4 units) and is
/// clipped (black, the stated limit). Through an orthographic camera 1000 box units away the
/// box at scale 1e-5 and 1e6 renders like scale 1 within noise (1e-6: see below).
#[test]
fn scene_scale_1e_minus6_and_1e6_render_like_scale_1() {
    let r = reference();
    for scale in [1e-4, 1e6] {
        let b = Box_ {
            scale,
            ..Box_::default()
        };
        r.assert_same(&render_box(&b, 2), &format!("scale {scale:e}"));
    }
    let tiny = Box_ {
        scale: 1e-6,
        ..Box_::default()
    };
    assert_eq!(mean_y(&render_box(&tiny, 2)), 0.0, "hither floor");
    let r = ortho_reference();
    for scale in [1e-5, 1e6] {
        let b = Box_ {
            scale,
            ortho: true,
            ..Box_::default()
        };
        r.assert_same(
            &render_box(&b, 2),
            &format!("orthographic, scale {scale:e}"),
        );
    }
}

fn ortho_reference() -> Reference {
    let ortho = Box_ {
        ortho: true,
        ..Box_::default()
    };
    let a = block_means(&render_box(&ortho, 0), 4);
    let a2 = block_means(&render_box(&ortho, 1), 4);
    let r = Reference {
        noise: rmse(&a, &a2),
        mean: a.iter().sum::<f64>() / a.len() as f64,
        a,
    };
    assert!(r.mean > 0.0, "black orthographic reference");
    r
}

/// Once a finding (issue 21): at scale 1e-6 the analytic spheres rendered about 5× darker
/// than at scale 1 while the walls did not change. The cause was the scene, not the spheres:
/// the orthographic camera stands 1000 box units away, 1e-3 at that scale, which is exactly
/// LuxRender's default `hither`, so everything in front of the box's centre plane was clipped
/// and camera rays started inside both spheres (the walls seen are all behind that plane).
/// With the near plane set as for the perspective camera (1e-3 box units, floored at 1e-4
/// by the camera) the box renders like scale 1; `orthographic_default_hither_clips_at_1e_minus6`
/// keeps the clipping itself.
#[test]
fn orthographic_scale_1e_minus6_renders_like_scale_1() {
    let r = ortho_reference();
    let b = Box_ {
        scale: 1e-6,
        ortho: true,
        ..Box_::default()
    };
    r.assert_same(&render_box(&b, 2), "orthographic, scale 1e-6");
}

/// LuxRender's default `hither` (1e-3 world units) holds for the orthographic camera too: at
/// scale 1e-6 the camera, 1e-3 from the box's centre plane, clips the front half of the box,
/// and the spheres, cut open there, render far from the unclipped image.
#[test]
fn orthographic_default_hither_clips_at_1e_minus6() {
    let r = ortho_reference();
    let b = Box_ {
        scale: 1e-6,
        ortho: true,
        default_hither: true,
        ..Box_::default()
    };
    let clipped = block_means(&render_box(&b, 2), 4);
    // The blocks on the spheres lose most of their light; the largest block difference
    // stands far above the stream-to-stream noise of a block.
    let worst =
        r.a.iter()
            .zip(&clipped)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f64, f64::max);
    let same = 1.6 * r.noise + 0.01 * r.mean;
    assert!(
        worst > 3.0 * same,
        "default hither at scale 1e-6: largest block difference {worst:.5}, same-image bound {same:.5}"
    );
}

/// Translation by 1e4 (f32 spacing 1e-3, 5e-4 of the box) renders the same image; at 1e7 the
/// f32 spacing of positions is 1.0, half the box: only a finite film is required there (the
/// stated limit, see README), and a box scaled by 1e4 at 1e7 renders the same again.
#[test]
fn geometry_far_from_the_origin() {
    let r = reference();
    let near = Box_ {
        offset: 1e4,
        ..Box_::default()
    };
    r.assert_same(&render_box(&near, 2), "translated by 1e4");
    let far = Box_ {
        offset: 1e7,
        ..Box_::default()
    };
    render_box(&far, 2);
    let far_big = Box_ {
        offset: 1e7,
        scale: 1e4,
        ..Box_::default()
    };
    r.assert_same(&render_box(&far_big, 2), "scaled 1e4, translated by 1e7");
}

/// Same seed and stream: the lamp radiance only scales every path's value, so each pixel
/// scales by the same factor up to f32 rounding.
#[test]
fn radiance_1e_minus10_and_1e10_scale_linearly() {
    let base = normalized_xyz(&render_box(&Box_::default(), 0));
    for k in [1e-10, 1e10] {
        let b = Box_ {
            radiance: k,
            ..Box_::default()
        };
        let img = normalized_xyz(&render_box(&b, 0));
        let mut worst: f64 = 0.0;
        for (p, q) in base.iter().zip(&img) {
            for c in 0..3 {
                let rel = (q[c] / k - p[c]).abs() / p[c].abs().max(1e-3);
                worst = worst.max(rel);
            }
        }
        assert!(
            worst <= 1e-4,
            "radiance ×{k:e}: worst relative error {worst:e}"
        );
    }
}

fn mean_y(f: &Film) -> f64 {
    let xyz = normalized_xyz(f);
    xyz.iter().map(|p| p[1]).sum::<f64>() / xyz.len() as f64
}

/// fov 0.01°: the image is the centre of the back wall: uniform and equal to the centre
/// pixels of the fov-39.3° render (within 15%); fov 179° from inside the box: finite, lit, no
/// refused sample (no reference image).
#[test]
fn fov_0_01_and_179_degrees() {
    let wide = render_box(&Box_::default(), 0);
    let xyz = normalized_xyz(&wide);
    let c = RES as usize / 2;
    let centre: f64 = [(c - 1, c - 1), (c - 1, c), (c, c - 1), (c, c)]
        .iter()
        .map(|&(x, y)| xyz[y * RES as usize + x][1])
        .sum::<f64>()
        / 4.0;
    let narrow = render_box(
        &Box_ {
            fov: 0.01,
            ..Box_::default()
        },
        0,
    );
    let blocks = block_means(&narrow, 8);
    let m = blocks.iter().sum::<f64>() / blocks.len() as f64;
    assert!(m > 0.0);
    for b in &blocks {
        assert!((b - m).abs() <= 0.1 * m, "fov 0.01: block {b} vs mean {m}");
    }
    assert!(
        (m - centre).abs() <= 0.15 * centre,
        "fov 0.01 mean {m} vs centre of fov 39.3 {centre}"
    );
    // Inside the box (0.1 from the open front), so that the 179° view is filled with it.
    let text = Box_ {
        fov: 179.0,
        ..Box_::default()
    }
    .text()
    .replace("LookAt 0e0 -3.9e0 1e0", "LookAt 0 -0.9 1");
    let (fisheye, rejected) =
        render_counted(&parse_text(&text, Path::new("fov179.lxs")), 0, PASSES);
    assert_eq!(rejected, 0);
    assert!(normalized_xyz(&fisheye)
        .iter()
        .flatten()
        .all(|v| v.is_finite()));
    assert!(mean_y(&fisheye) > 0.0, "fov 179: black image");
}

/// The largest Y any pixel can hold: the lamp seen straight on (fov 1° aimed at it).
fn lamp_y() -> f64 {
    let text = Box_::default()
        .text()
        .replace(
            "LookAt 0e0 -3.9e0 1e0 0e0 0e0 1e0 0 0 1",
            "LookAt 0 0 1 0 0 2 0 1 0",
        )
        .replace("[39.3]", "[1]");
    let (f, rej) = render_counted(&parse_text(&text, Path::new("lamp.lxs")), 0, 1);
    assert_eq!(rej, 0);
    let y = mean_y(&f);
    assert!(y > 0.0, "lamp not seen");
    y
}

/// Roughness 0 and 1e-6 for glossy, metal and roughglass: no NaN, the image mean stays below
/// the lamp's Y, and 1e-6 renders like 0 (the specular limit) within noise.
#[test]
fn roughness_0_and_1e_minus6() {
    let ly = lamp_y();
    let noise = reference().noise;
    for (name, params) in [
        (
            "glossy",
            r#""string type" ["glossy"] "color Kd" [0.3 0.3 0.3] "color Ks" [0.5 0.5 0.5]"#,
        ),
        (
            "metal",
            r#""string type" ["metal"] "string name" ["aluminium"]"#,
        ),
        (
            "roughglass",
            r#""string type" ["roughglass"] "float index" [1.5]"#,
        ),
    ] {
        let mut blocks = Vec::new();
        for (i, r) in ["0", "1e-6"].iter().enumerate() {
            let m = format!(r#"{params} "float uroughness" [{r}] "float vroughness" [{r}]"#);
            let f = render_box(
                &Box_ {
                    sphere2: Some(m),
                    ..Box_::default()
                },
                i as u64,
            );
            let y = mean_y(&f);
            assert!(
                y > 0.0 && y <= ly,
                "{name} roughness {r}: mean {y} vs lamp {ly}"
            );
            blocks.push(block_means(&f, 4));
        }
        // Two roughnesses on two streams, against the matte box's stream-to-stream noise.
        let mean = blocks[0].iter().sum::<f64>() / blocks[0].len() as f64;
        let diff = rmse(&blocks[0], &blocks[1]);
        assert!(
            diff <= 1.6 * noise + 0.01 * mean,
            "{name}: roughness 1e-6 vs 0 differ by {diff} (noise {noise})"
        );
    }
}

/// Glass of index 1.0 refracts nothing and reflects nothing: the image equals the box without
/// the sphere, within noise. Index 10 (Fresnel reflectance 0.67 at normal incidence): finite,
/// mean below the lamp's Y.
#[test]
fn ior_1_and_10() {
    let without = Box_ {
        sphere2: None,
        ..Box_::default()
    };
    let a = block_means(&render_box(&without, 0), 4);
    let a2 = block_means(&render_box(&without, 1), 4);
    let r = Reference {
        noise: rmse(&a, &a2),
        mean: a.iter().sum::<f64>() / a.len() as f64,
        a,
    };
    let glass = |index: &str| Box_ {
        sphere2: Some(format!(
            r#""string type" ["glass"] "color Kr" [1 1 1] "color Kt" [1 1 1] "float index" [{index}]"#
        )),
        ..Box_::default()
    };
    r.assert_same(&render_box(&glass("1.0"), 2), "glass index 1.0");
    let y = mean_y(&render_box(&glass("10"), 2));
    let ly = lamp_y();
    assert!(y > 0.0 && y <= ly, "glass index 10: mean {y} vs lamp {ly}");
}

/// A Lambertian plane lit by a distant light 89° from its normal, seen at 0.6°-1.6° above the
/// plane: direct light only (no other geometry), so every pixel below the horizon has the same
/// value Kd/π·E·cos 89°; it must match the plane seen from straight above within 1% (acne or
/// self-shadowing would blacken pixels).
#[test]
fn grazing_incidence() {
    let scene = |eye: &str, target: &str, up: &str, fov: f64| {
        format!(
            r#"LookAt {eye} {target} {up}
Camera "perspective" "float fov" [{fov}]
Film "fleximage" "integer xresolution" [{RES}] "integer yresolution" [{RES}]
PixelFilter "box" "float xwidth" [0.5] "float ywidth" [0.5]
Sampler "random" "integer pixelsamples" [1]
SurfaceIntegrator "path" "integer maxdepth" [4] "string rrstrategy" ["none"]
WorldBegin
LightSource "distant" "point from" [0 0.9998477 0.0174524] "point to" [0 0 0] "color L" [3 3 3]
Material "matte" "color Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [-1000 -1000 0 1000 -1000 0 1000 1000 0 -1000 1000 0]
WorldEnd
"#
        )
    };
    let top = scene("0 0 1", "0 0 0", "0 1 0", 10.0);
    let (f, rej) = render_counted(&parse_text(&top, Path::new("top.lxs")), 0, 2);
    assert_eq!(rej, 0);
    let reference = mean_y(&f);
    assert!(reference > 0.0, "plane not lit");
    let graze = scene("0 0 0.01", "0 1 0", "0 0 1", 2.0);
    let (g, rej) = render_counted(&parse_text(&graze, Path::new("graze.lxs")), 0, 2);
    assert_eq!(rej, 0);
    let xyz = normalized_xyz(&g);
    // Bottom half of the image: fully on the plane.
    for (i, p) in xyz.iter().enumerate().skip((RES * RES / 2) as usize) {
        assert!(
            (p[1] - reference).abs() <= 0.01 * reference,
            "pixel {i}: {} vs {reference}",
            p[1]
        );
    }
}

/// Writes a scene with the given mesh points to a temporary file and builds a session from it.
fn session_from_file(name: &str, points: &str, indices: &str) -> Result<Session, String> {
    let dir = std::env::temp_dir().join(format!("luxfarm-extremes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let path = dir.join(name);
    let text = format!(
        r#"LookAt 0 -3 1 0 0 1 0 0 1
Camera "perspective" "float fov" [40]
Film "fleximage" "integer xresolution" [16] "integer yresolution" [16]
Sampler "random" "integer pixelsamples" [1]
SurfaceIntegrator "path" "integer maxdepth" [3]
WorldBegin
AttributeBegin
  AreaLightSource "area" "color L" [2 2 2]
  Shape "trianglemesh" "integer indices" [0 1 2] "point P" [-1 -1 2.5 1 -1 2.5 0 1 2.5]
AttributeEnd
Shape "trianglemesh" "integer indices" [{indices}]
  "point P" [{points}]
WorldEnd
"#
    );
    std::fs::write(&path, text).map_err(|e| e.to_string())?;
    let parsed = luxfarm::lxs::parse_file(&path, &luxfarm::lxs::ParseOptions::default())
        .map_err(|e| e.to_string())?;
    Session::new(&parsed, &dir, SessionOptions::default()).map_err(|e| e.to_string())
}

/// Degenerate triangles (repeated vertex, collinear vertices) render as nothing: the film gets
/// no NaN and the image equals the one without them.
#[test]
fn degenerate_triangles_render_without_nan() {
    let pts = "-1 -1 0 1 -1 0 1 1 0 -1 1 0 0 0 1 0 0 1 2 2 2 3 3 3 4 4 4";
    let with = session_from_file("degenerate.lxs", pts, "0 1 2 0 2 3 4 5 6 6 7 8 4 4 4");
    let without = session_from_file("plain.lxs", pts, "0 1 2 0 2 3");
    let mut films = Vec::new();
    for s in [with, without] {
        let mut s = s.expect("scene builds");
        let mut rejected = 0;
        for _ in 0..2 {
            rejected += s.render_pass().rejected;
        }
        assert_eq!(rejected, 0);
        films.push(s.take_film());
    }
    let d = rms(&films[0], &films[1]);
    assert!(d == 0.0, "degenerate triangles changed the image (rms {d})");
}

/// NaN is not a number in scene syntax (a located parse error); a coordinate that overflows
/// f32 (1e39) is refused by the parser, naming file:line:column.
#[test]
fn nan_and_inf_vertices_are_refused_with_a_location() {
    let e = session_from_file("nan.lxs", "0 0 0 1 0 0 nan 1 0", "0 1 2")
        .err()
        .expect("NaN refused");
    assert!(e.contains("nan.lxs:"), "{e}");
    let e = session_from_file("inf.lxs", "0 0 0 1 0 0 1e39 1 0", "0 1 2")
        .err()
        .expect("Inf refused");
    assert!(e.contains("inf.lxs:12:26:"), "{e}");
    assert!(e.contains("out of range"), "{e}");
}

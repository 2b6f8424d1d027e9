//! Portals (issue 17): a closed room of our own with one window in a wall, lit only by a
//! light at infinity through that window, rendered with and without a `PortalShape` covering
//! the window. With the portal the light is sampled through the window:
//!
//! - the image is the same within the noise (8-pixel block means of independent renders,
//!   z-scores as `transport_mlt.rs` computes them) for the constant infinite light, `sky2`,
//!   and — through a wider window, where the estimates without portal converge sooner — the
//!   legacy `sky`, `sunsky`, `sunsky2` and infinite lights with a map in each mapping; and
//!   with a portal that leaves an opening uncovered (the room open above) at one bounce, with
//!   path and with directlighting;
//! - at equal samples per pixel the noise — the per-pixel standard deviation over independent
//!   renders, averaged over the image — is lower; the ratio is printed with both render times
//!   and must stay under 0.7 (the issue's target) for the infinite light and under 0.9 for
//!   sky2, so the test fails if portal sampling stops helping;
//! - portals tie to the light of their scope, PortalInstance places an object as a portal,
//!   and portals the renderer cannot use are reported at their line.

mod transport_common;

use luxfarm::film::Film;
use luxfarm::lxs::SceneDescription;
use luxfarm::render::{Session, SessionOptions};
use std::path::Path;
use transport_common::{assert_agree, block_means, luminance, scene_text};

/// A quad (two triangles) as a trianglemesh statement.
fn quad(p: [[f32; 3]; 4]) -> String {
    let pts: Vec<String> = p
        .iter()
        .map(|v| format!("{} {} {}", v[0], v[1], v[2]))
        .collect();
    format!(
        "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" [{}]\n",
        pts.join(" ")
    )
}

/// The room: x, y ∈ [-2, 2], z ∈ [0, 2.5], with a window (y0, y1, z0, z1) in the wall
/// x = 2; without `ceiling` it is open to the sky above as well.
#[derive(Clone, Copy)]
struct Room {
    ceiling: bool,
    window: [f32; 4],
}

/// The closed room with a small window (0.8 m², the noise test's).
const CLOSED: Room = Room {
    ceiling: true,
    window: [-0.5, 0.5, 1.0, 1.8],
};
/// The same open above: light arrives through an opening no portal covers.
const OPEN_TOP: Room = Room {
    ceiling: false,
    window: CLOSED.window,
};
/// The closed room with a wide window (the comparisons of every light kind converge faster).
const WIDE: Room = Room {
    ceiling: true,
    window: [-1.6, 1.6, 0.4, 2.2],
};

impl Room {
    fn shapes(&self) -> String {
        let (x0, x1, y0, y1, z0, z1) = (-2.0, 2.0, -2.0, 2.0, 0.0, 2.5);
        let [wy0, wy1, wz0, wz1] = self.window;
        let mut s = String::new();
        s += &quad([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0]]); // floor
        if self.ceiling {
            s += &quad([[x0, y0, z1], [x0, y1, z1], [x1, y1, z1], [x1, y0, z1]]);
        }
        s += &quad([[x0, y0, z0], [x0, y1, z0], [x0, y1, z1], [x0, y0, z1]]); // back wall
        s += &quad([[x0, y0, z0], [x0, y0, z1], [x1, y0, z1], [x1, y0, z0]]); // side
        s += &quad([[x0, y1, z0], [x1, y1, z0], [x1, y1, z1], [x0, y1, z1]]); // side
                                                                              // The window wall, four pieces around the hole.
        s += &quad([[x1, y0, z0], [x1, y0, wz0], [x1, y1, wz0], [x1, y1, z0]]);
        s += &quad([[x1, y0, wz1], [x1, y0, z1], [x1, y1, z1], [x1, y1, wz1]]);
        s += &quad([[x1, y0, wz0], [x1, y0, wz1], [x1, wy0, wz1], [x1, wy0, wz0]]);
        s += &quad([[x1, wy1, wz0], [x1, wy1, wz1], [x1, y1, wz1], [x1, y1, wz0]]);
        s
    }

    /// The window as a portal (the same rectangle as the hole).
    fn portal(&self) -> String {
        let [y0, y1, z0, z1] = self.window;
        format!(
            "PortalShape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \
             \"point P\" [2 {y0} {z0}  2 {y1} {z0}  2 {y1} {z1}  2 {y0} {z1}]\n"
        )
    }
}

const SIZE: u32 = 32;

/// The scene text: `light` (LightSource statements) in one attribute block with `portal`
/// (PortalShape statements, or nothing).
fn scene_with(room: Room, light: &str, portal: &str, spp: u32, integrator: &str) -> String {
    format!(
        r#"
LookAt -1.8 -0.3 1.3  2 0.2 0.6  0 0 1
Camera "perspective" "float fov" [75]
Film "fleximage" "integer xresolution" [{SIZE}] "integer yresolution" [{SIZE}]
PixelFilter "box"
Sampler "random" "integer pixelsamples" [{spp}]
SurfaceIntegrator {integrator}
WorldBegin
AttributeBegin
{light}
{portal}AttributeEnd
Material "matte" "color Kd" [0.7 0.7 0.7]
{shapes}WorldEnd
"#,
        shapes = room.shapes()
    )
}

/// [`scene_with`] in the closed room with its window as portal, or none.
fn scene(light: &str, with_portal: bool, spp: u32, integrator: &str) -> String {
    let portal = if with_portal {
        CLOSED.portal()
    } else {
        String::new()
    };
    scene_with(CLOSED, light, &portal, spp, integrator)
}

const PATH: &str = "\"path\" \"integer maxdepth\" [4]";

fn render(desc: &SceneDescription, dir: &Path, stream: u64) -> Film {
    let opts = SessionOptions {
        threads: 2,
        seed: 17,
        stream,
    };
    let mut s = Session::new(desc, dir, opts).expect("session builds");
    assert!(s.render_pass().complete);
    s.take_film()
}

/// Luminance images of `n` independent one-pass renders (streams `first`…).
fn images(desc: &SceneDescription, dir: &Path, first: u64, n: u64) -> Vec<Film> {
    (first..first + n).map(|s| render(desc, dir, s)).collect()
}

/// Mean over pixels of the per-pixel standard deviation of Y across the renders.
fn mean_pixel_sd(films: &[Film]) -> f64 {
    let ys: Vec<Vec<f64>> = films.iter().map(luminance).collect();
    let n = ys.len() as f64;
    let k = ys.first().map_or(0, Vec::len);
    let mut total = 0.0;
    for i in 0..k {
        let m = ys.iter().map(|y| y[i]).sum::<f64>() / n;
        let v = ys.iter().map(|y| (y[i] - m).powi(2)).sum::<f64>() / (n - 1.0);
        total += v.sqrt();
    }
    total / k as f64
}

/// Renders the closed room without and with the portal (`n` runs each).
fn both(light: &str, spp: u32, n: u64, dir: &Path) -> (Vec<Film>, Vec<Film>) {
    compare(CLOSED, light, PATH, spp, n, dir)
}

/// Renders `room` without a portal and with its window as portal, `n` runs each of `spp`.
fn compare(
    room: Room,
    light: &str,
    integrator: &str,
    spp: u32,
    n: u64,
    dir: &Path,
) -> (Vec<Film>, Vec<Film>) {
    let at = dir.join("room.lxs");
    let plain = scene_text(&scene_with(room, light, "", spp, integrator), &at);
    let ported = scene_text(
        &scene_with(room, light, &room.portal(), spp, integrator),
        &at,
    );
    let t0 = std::time::Instant::now();
    let a = images(&plain, dir, 0, n);
    let t1 = std::time::Instant::now();
    let b = images(&ported, dir, 1000, n);
    let (ta, tb) = ((t1 - t0).as_secs_f64(), t1.elapsed().as_secs_f64());
    // Reported only (no timed assertion): the noise at equal time scales as sqrt(time).
    eprintln!(
        "render time without portal {ta:.2} s, with {tb:.2} s (time ratio {:.3})",
        tb / ta
    );
    (a, b)
}

fn blocks(films: &[Film]) -> Vec<Vec<f64>> {
    films.iter().map(|f| block_means(f, 8)).collect()
}

const INFINITE: &str = "LightSource \"infinite\" \"color L\" [1 1 1]";

#[test]
fn portal_attaches_to_the_light_and_is_not_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let desc = scene_text(
        &scene(INFINITE, true, 1, PATH),
        &dir.path().join("room.lxs"),
    );
    let portal = desc.shapes.iter().find(|s| s.portal).expect("portal shape");
    assert_eq!(portal.portal_light, Some(0));
    let s = Session::new(&desc, dir.path(), SessionOptions::default()).expect("builds");
    let world = &s.renderable().world;
    let p = world.lights()[0]
        .portals()
        .expect("the light has the portal");
    assert_eq!(p.triangle_count(), 2);
    assert!((p.area() - 0.8).abs() < 1e-5, "{}", p.area());
    // 9 quads of room, the portal is not among the shapes.
    assert_eq!(world.geometry().shape_count(), 9);
}

#[test]
fn portal_on_a_point_light_or_without_light_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let text = scene(
        "LightSource \"point\" \"point from\" [0 0 2]",
        true,
        1,
        PATH,
    );
    let desc = scene_text(&text, &dir.path().join("room.lxs"));
    let s = Session::new(&desc, dir.path(), SessionOptions::default()).expect("builds");
    assert!(
        s.warnings()
            .iter()
            .any(|w| w.to_string().contains("portals ignored") && w.loc.line == 11),
        "{:?}",
        s.warnings()
    );
    // Bidirectional samples through portals too: nothing to report.
    let desc = scene_text(
        &scene(INFINITE, true, 1, "\"bidirectional\""),
        &dir.path().join("room.lxs"),
    );
    let s = Session::new(&desc, dir.path(), SessionOptions::default()).expect("builds");
    assert!(
        !s.warnings()
            .iter()
            .any(|w| w.to_string().contains("portal")),
        "{:?}",
        s.warnings()
    );
}

/// (a) and (b) for the constant infinite light, the light portals help most.
#[test]
fn infinite_light_through_a_portal_same_image_less_noise() {
    same_image_less_noise("infinite", INFINITE, 0.7);
}

/// (a) and (b) for sky2 (the sun low, shining through the window side).
#[test]
fn sky2_through_a_portal_same_image_less_noise() {
    let light = "LightSource \"sky2\" \"vector sundir\" [0.6 0.1 0.5] \"float turbidity\" [3] \
                 \"float gain\" [0.02]";
    same_image_less_noise("sky2", light, 0.9);
}

/// (a) the room lit by `light` renders the same image with and without the window's portal;
/// (b) with it, the mean per-pixel standard deviation is below `max_ratio` of that without.
fn same_image_less_noise(name: &str, light: &str, max_ratio: f64) {
    let dir = tempfile::tempdir().unwrap();
    let (plain, ported) = both(light, 8, 8, dir.path());
    assert_same_image_less_noise(name, &plain, &ported, max_ratio);
}

/// (a) and (b) of [`same_image_less_noise`] for renders without and with the portal.
fn assert_same_image_less_noise(name: &str, plain: &[Film], ported: &[Film], max_ratio: f64) {
    assert_agree(
        &format!("{name}: portal vs none"),
        &blocks(plain),
        &blocks(ported),
        4.0,
        0.0,
    );
    let (a, b) = (mean_pixel_sd(plain), mean_pixel_sd(ported));
    let ratio = b / a;
    eprintln!("{name}: mean per-pixel sd without portal {a:.5}, with {b:.5}: ratio {ratio:.3}");
    assert!(ratio < max_ratio, "portal noise ratio {ratio:.3}");
}

const BIDIR: &str = "\"bidirectional\" \"integer eyedepth\" [4] \"integer lightdepth\" [4]";

/// Bidirectional samples the sky through the portal in its direct connections and starts
/// most of its light subpaths through it: the closed room renders the same image with and
/// without the portal, with less noise; and in the room open above, light through the
/// opening no portal covers still arrives.
#[test]
fn bidirectional_samples_through_a_portal_without_bias() {
    let dir = tempfile::tempdir().unwrap();
    let (plain, ported) = compare(CLOSED, INFINITE, BIDIR, 4, 8, dir.path());
    assert_same_image_less_noise("bidirectional", &plain, &ported, 0.8);
    let (plain, ported) = compare(OPEN_TOP, INFINITE, BIDIR, 4, 8, dir.path());
    assert_agree(
        "bidirectional, open top, portal on the window",
        &blocks(&plain),
        &blocks(&ported),
        4.0,
        0.0,
    );
}

/// An opening no portal covers: with paths of one bounce (light samples take the full
/// weight at the last vertex) in the room open above, the sky seen through the open top
/// still arrives, so the image is unchanged — with path and
/// with directlighting.
#[test]
fn light_through_an_opening_without_portal_is_not_lost() {
    let dir = tempfile::tempdir().unwrap();
    for integrator in [
        "\"path\" \"integer maxdepth\" [1]",
        "\"directlighting\" \"integer maxdepth\" [1]",
    ] {
        let (plain, ported) = compare(OPEN_TOP, INFINITE, integrator, 8, 8, dir.path());
        let what = format!("open top, portal on the window, {integrator}");
        assert_agree(&what, &blocks(&plain), &blocks(&ported), 4.0, 0.0);
    }
}

/// The legacy sky, sunsky and sunsky2 (the sun is not sampled through portals, the sky half
/// is) and infinite lights with a map in each mapping: the same image with the portal, in
/// the room with a wide window.
#[test]
fn sky_sunsky_and_mapped_infinite_lights_agree_through_a_portal() {
    let dir = tempfile::tempdir().unwrap();
    let map = image::RgbImage::from_fn(16, 8, |x, y| {
        image::Rgb([(40 + 12 * x) as u8, (200 - 20 * y) as u8, 120])
    });
    map.save(dir.path().join("env.png")).unwrap();
    let lights = [
        "LightSource \"sky\" \"vector sundir\" [0.6 0.1 0.5] \"float gain\" [0.02]".to_string(),
        "LightSource \"sunsky\" \"vector sundir\" [0.6 0.1 0.5] \"float gain\" [0.005]".to_string(),
        "LightSource \"sunsky2\" \"vector sundir\" [0.6 0.1 0.5] \"float gain\" [0.005]".to_string(),
        "LightSource \"infinite\" \"string mapname\" [\"env.png\"]".to_string(),
        "LightSource \"infinite\" \"string mapname\" [\"env.png\"] \"string mapping\" [\"angular\"]".to_string(),
        "LightSource \"infinite\" \"string mapname\" [\"env.png\"] \"string mapping\" [\"vcross\"]".to_string(),
    ];
    for light in &lights {
        let (plain, ported) = compare(WIDE, light, PATH, 8, 6, dir.path());
        let (a, b) = (mean_pixel_sd(&plain), mean_pixel_sd(&ported));
        eprintln!(
            "{light}: mean per-pixel sd without portal {a:.5}, with {b:.5}: ratio {:.3}",
            b / a
        );
        assert_agree(light, &blocks(&plain), &blocks(&ported), 4.0, 0.0);
    }
}

/// `PortalInstance` places an object's shapes as portals of the light in scope.
#[test]
fn portal_instance_gives_the_light_its_portal() {
    let dir = tempfile::tempdir().unwrap();
    let text = scene(INFINITE, false, 1, PATH).replace(
        "WorldBegin\n",
        "WorldBegin\nObjectBegin \"window\"\nShape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \
         \"point P\" [0 -0.5 1  0 0.5 1  0 0.5 1.8  0 -0.5 1.8]\nObjectEnd\n",
    );
    let text = text.replace(
        &format!("{INFINITE}\n"),
        &format!("{INFINITE}\nTranslate 2 0 0\nPortalInstance \"window\"\n"),
    );
    let desc = scene_text(&text, &dir.path().join("room.lxs"));
    let s = Session::new(&desc, dir.path(), SessionOptions::default()).expect("builds");
    let world = &s.renderable().world;
    let p = world.lights()[0]
        .portals()
        .expect("the instance is the light's portal");
    assert_eq!(p.triangle_count(), 2);
    assert!((p.area() - 0.8).abs() < 1e-5);
    // Through the window from the room's centre: the instance is placed at x = 2.
    let at = luxfarm::geometry::Interaction::default();
    let through = glam::Vec3A::new(2.0, 0.0, 1.4).normalize();
    assert!(p.pdf(at.p, through) > 0.0);
    assert_eq!(p.pdf(at.p, -through), 0.0);
}

/// A portal belongs to the last LightSource of its attribute scope (LuxRender's graphics
/// state): a light declared in a block that has ended is not it. For sunsky the sky half
/// takes the portal, the sun does not.
#[test]
fn portal_belongs_to_the_light_in_scope_and_to_the_sky_half() {
    let dir = tempfile::tempdir().unwrap();
    let light = "LightSource \"sunsky\" \"vector sundir\" [0.6 0.1 0.5]\nAttributeBegin\n\
                 LightSource \"point\" \"point from\" [0 0 2]\nAttributeEnd";
    let text = scene_with(CLOSED, light, &CLOSED.portal(), 1, PATH);
    let desc = scene_text(&text, &dir.path().join("room.lxs"));
    let portal = desc.shapes.iter().find(|s| s.portal).expect("portal shape");
    assert_eq!(
        portal.portal_light,
        Some(0),
        "the sunsky, not the point light"
    );
    let s = Session::new(&desc, dir.path(), SessionOptions::default()).expect("builds");
    let kinds: Vec<(bool, bool)> = s
        .renderable()
        .world
        .lights()
        .iter()
        .map(|l| (l.is_infinite(), l.portals().is_some()))
        .collect();
    // sun (at infinity, no portals), sky (portals), point.
    assert_eq!(kinds, vec![(true, false), (true, true), (false, false)]);
    assert!(s
        .warnings()
        .iter()
        .all(|w| !w.to_string().contains("portal")));
}

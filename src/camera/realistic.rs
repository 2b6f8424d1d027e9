//! The realistic camera (LuxRender's `realistic`): rays traced from the film through a lens
//! system described by a lens file (`specfile`), after Galoppo's realistic camera as
//! LuxRender 1.x implements it.
//!
//! Lens file: one element per line, front (object side) to back (film side), four numbers
//! separated by whitespace: signed radius of curvature, distance to the next element along
//! the axis, index of refraction of the medium behind the element, and aperture diameter.
//! A radius of 0 is the aperture stop, whose diameter is the camera's `aperture_diameter`
//! (1). Blank lines and lines starting with `#` are skipped. Units are scene units.
//!
//! Camera space: the front element's vertex is at z = 0 and the camera looks along +z; element
//! i's vertex sits at z = -(sum of the distances before it), a positive radius puts its centre
//! behind the vertex (convex towards the scene). The film lies `filmdistance` (70) behind the
//! last element, sized by `filmdiag` (35, the diagonal) with the image's aspect. A ray leaves a
//! film point towards a uniformly sampled point of the back element's aperture disc and is
//! refracted (Snell) through every element back to front; a ray stopped by an aperture or by
//! total internal reflection is not generated. Its weight is cos⁴θ of its angle to the axis at
//! the film (the natural vignetting).
//!
//! Differences from LuxRender, on purpose: LuxRender samples the back disc with a radius equal
//! to the back element's *diameter* and weighs rays by cos⁴θ / filmdistance² (which darkens
//! every image by the square of the film distance); here the radius is half the diameter and
//! the weight cos⁴θ. The lens file is read confined to the scene's directory.

use super::FilmGeometry;
use crate::fileio::SceneFiles;
use crate::plugin::{BuildError, Stmt};
use crate::sampling::concentric_disc;
use glam::{Vec2, Vec3A};

/// Largest lens file read (bytes) and element count.
pub const MAX_LENS_FILE: u64 = 1 << 20;
pub const MAX_ELEMENTS: usize = 256;

/// Reads a `realistic` statement: `specfile` (read from `base_dir`), `filmdistance` (70),
/// `aperture_diameter` (1), `filmdiag` (35). The lens covers the whole image (no crop window
/// or screen window, as LuxRender).
pub(super) fn build(
    s: &Stmt,
    film: &FilmGeometry,
    files: Option<&SceneFiles>,
) -> Result<Realistic, BuildError> {
    let p = s.params();
    let files = files.ok_or_else(|| s.err("the realistic camera needs the scene's files"))?;
    let rows = read_lens_file(files, p.string_or("specfile", "")).map_err(|m| s.err(m))?;
    for name in [
        "lensradius",
        "focaldistance",
        "frameaspectratio",
        "screenwindow",
    ] {
        let _ = p.floats(name);
    }
    Realistic::new(
        &rows,
        p.float_or("filmdistance", 70.0),
        p.float_or("aperture_diameter", 1.0),
        p.float_or("filmdiag", 35.0),
        film.xres,
        film.yres,
    )
    .map_err(|m| s.err(format!("realistic camera: {m}")))
}

/// One row of a lens file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensRow {
    pub radius: f32,
    pub thickness: f32,
    pub ior: f32,
    pub aperture: f32,
}

/// Parses a lens file's text; errors name the 1-based line.
pub fn parse_lens(text: &str) -> Result<Vec<LensRow>, String> {
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let v: Vec<f32> = t
            .split_whitespace()
            .map(|w| w.parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("line {}: {e}", i + 1))?;
        let [radius, thickness, ior, aperture] = v[..] else {
            return Err(format!(
                "line {}: expected 4 numbers, got {}",
                i + 1,
                v.len()
            ));
        };
        if !v.iter().all(|x| x.is_finite()) || aperture <= 0.0 || (radius != 0.0 && ior <= 0.0) {
            return Err(format!(
                "line {}: needs finite values, an aperture > 0 and an index of refraction > 0",
                i + 1
            ));
        }
        rows.push(LensRow {
            radius,
            thickness,
            ior,
            aperture,
        });
        if rows.len() > MAX_ELEMENTS {
            return Err(format!("more than {MAX_ELEMENTS} lens elements"));
        }
    }
    if rows.is_empty() {
        return Err("no lens elements".into());
    }
    Ok(rows)
}

/// Reads a lens file through the scene's files (confined to the bundle on the farm).
pub fn read_lens_file(files: &SceneFiles, name: &str) -> Result<Vec<LensRow>, String> {
    if name.is_empty() {
        return Err("no lens file (specfile) given".into());
    }
    let text = files
        .read_small_text(name, MAX_LENS_FILE)
        .map_err(|e| format!("lens file {e}"))?;
    parse_lens(&text).map_err(|e| format!("lens file \"{name}\": {e}"))
}

#[derive(Clone, Debug, PartialEq)]
enum Surface {
    /// The aperture stop: a disc.
    Stop,
    /// A spherical cap; `radius` signed as in the file, `centre_z` on the axis.
    Sphere { radius: f32, centre_z: f32 },
}

#[derive(Clone, Debug, PartialEq)]
struct Element {
    surface: Surface,
    vertex_z: f32,
    /// Half the aperture.
    reach: f32,
    /// Index ratio (behind / in front) used when a ray crosses from behind.
    eta: f32,
}

/// The realistic camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Realistic {
    elements: Vec<Element>,
    /// Film plane z (camera space).
    film_z: f32,
    back_z: f32,
    back_reach: f32,
    /// Raster pixels per film unit, and the film's size.
    scale: f32,
    film_w: f32,
    film_h: f32,
}

impl Realistic {
    /// Builds the lens system; `film_distance`, `aperture_diameter` and `film_diag` as the
    /// statement gives them, `xres` x `yres` the image.
    pub fn new(
        rows: &[LensRow],
        film_distance: f32,
        aperture_diameter: f32,
        film_diag: f32,
        xres: u32,
        yres: u32,
    ) -> Result<Realistic, String> {
        if !(film_distance.is_finite() && film_diag.is_finite() && film_diag > 0.0) {
            return Err("filmdistance and filmdiag must be finite, filmdiag > 0".into());
        }
        if !(aperture_diameter.is_finite() && aperture_diameter > 0.0) {
            return Err("aperture_diameter must be > 0".into());
        }
        let (mut elements, mut z, mut n_front) = (Vec::new(), 0.0f32, 1.0f32);
        for r in rows {
            let vertex_z = -z;
            let e = if r.radius == 0.0 {
                n_front = 1.0;
                Element {
                    surface: Surface::Stop,
                    vertex_z,
                    reach: aperture_diameter / 2.0,
                    eta: 1.0,
                }
            } else {
                let e = Element {
                    surface: Surface::Sphere {
                        radius: r.radius,
                        centre_z: vertex_z - r.radius,
                    },
                    vertex_z,
                    reach: r.aperture / 2.0,
                    eta: r.ior / n_front,
                };
                n_front = r.ior;
                e
            };
            elements.push(e);
            z += r.thickness;
        }
        let back_reach = rows.last().map_or(0.0, |r| r.aperture / 2.0);
        let diag = ((xres as f32).powi(2) + (yres as f32).powi(2)).sqrt();
        let scale = diag / film_diag;
        Ok(Realistic {
            elements,
            film_z: -z - film_distance,
            back_z: -z,
            back_reach,
            scale,
            film_w: xres as f32 / scale,
            film_h: yres as f32 / scale,
        })
    }

    /// The camera-space point of the film for raster point `p` (the lens inverts the image).
    pub fn film_point(&self, p: Vec2) -> Vec3A {
        Vec3A::new(
            self.film_w / 2.0 - p.x / self.scale,
            p.y / self.scale - self.film_h / 2.0,
            self.film_z,
        )
    }

    /// The ray leaving the front of the lens for raster point `p` and lens sample `lens`:
    /// origin, unit direction and weight; `None` when the lens stops it.
    pub fn ray(&self, p: Vec2, lens: Vec2) -> Option<(Vec3A, Vec3A, f32)> {
        let from = self.film_point(p);
        let l = concentric_disc(lens) * self.back_reach;
        let d = (Vec3A::new(l.x, l.y, self.back_z) - from).normalize_or_zero();
        let cos2 = d.z * d.z;
        self.trace(from, d).map(|(o, d)| (o, d, cos2 * cos2))
    }

    /// Traces a ray from the film side through the elements, back to front.
    pub fn trace(&self, mut o: Vec3A, mut d: Vec3A) -> Option<(Vec3A, Vec3A)> {
        for e in self.elements.iter().rev() {
            match e.surface {
                Surface::Stop => {
                    if d.z <= 0.0 {
                        return None;
                    }
                    let t = (e.vertex_z - o.z) / d.z;
                    let p = o + d * t;
                    if t < 0.0 || p.x * p.x + p.y * p.y > e.reach * e.reach {
                        return None;
                    }
                    o = p;
                }
                Surface::Sphere { radius, centre_z } => {
                    let (p, n) = hit_cap(o, d, radius, centre_z, e.reach)?;
                    d = refract(d, n, e.eta)?;
                    o = p;
                }
            }
        }
        (d.z > 0.0 && o.is_finite() && d.is_finite()).then_some((o, d))
    }
}

/// The hit of a ray with an element's spherical cap within its reach: point and the normal
/// facing the ray's origin.
fn hit_cap(o: Vec3A, d: Vec3A, radius: f32, centre_z: f32, reach: f32) -> Option<(Vec3A, Vec3A)> {
    let c = Vec3A::new(0.0, 0.0, centre_z);
    let r = radius.abs();
    let oc = o - c;
    let b = oc.dot(d);
    let disc = b * b - (oc.dot(oc) - r * r);
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    // The cap is the half of the sphere holding the vertex: in front of the centre for a
    // positive radius, behind it for a negative one.
    let on_cap = |p: Vec3A| {
        if radius > 0.0 {
            p.z > centre_z
        } else {
            p.z < centre_z
        }
    };
    let t = [-b - s, -b + s]
        .into_iter()
        .find(|&t| t > 1e-6 && on_cap(o + d * t))?;
    let p = o + d * t;
    if p.x * p.x + p.y * p.y > reach * reach {
        return None;
    }
    let outward = (p - c) / r;
    let n = if radius < 0.0 { outward } else { -outward };
    Some((p, n))
}

/// Snell refraction of unit `d` at a surface with normal `n` (facing against `d`) and index
/// ratio `eta` (incident / transmitted); `None` on total internal reflection.
fn refract(d: Vec3A, n: Vec3A, eta: f32) -> Option<Vec3A> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    Some((n * (eta * cos_i - cos_t) + d * eta).normalize_or_zero())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A biconvex singlet: R1 = 50, R2 = -50, thickness 5, n = 1.5, aperture 4.
    const SINGLET: &str = "# biconvex singlet\n50 5 1.5 4\n-50 0 1 4\n";

    /// Thick lens: 1/f = (n-1) (1/R1 - 1/R2 + (n-1) d / (n R1 R2)) = 0.0196667, f = 50.8475;
    /// back focal length f (1 - (n-1) d / (n R1)) = 49.1525; the principal planes sit
    /// f - BFL = 1.6949 inside each vertex.
    const F: f32 = 50.847_46;
    const BFL: f32 = 49.152_54;

    fn camera(film_distance: f32) -> Realistic {
        let rows = parse_lens(SINGLET).unwrap();
        Realistic::new(&rows, film_distance, 1.0, 35.0, 100, 100).unwrap()
    }

    /// Where the rays from the film centre through lens points at `radius` cross the axis.
    fn axis_crossing(cam: &Realistic, radius: f32) -> f32 {
        let from = Vec3A::new(0.0, 0.0, cam.film_z);
        let to = Vec3A::new(radius, 0.0, cam.back_z);
        let (o, d) = cam.trace(from, (to - from).normalize()).unwrap();
        o.z - o.x * d.z / d.x
    }

    #[test]
    fn parses_and_refuses_bad_files() {
        let rows = parse_lens(SINGLET).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[1].radius, -50.0);
        assert!(parse_lens("50 5 1.5\n").is_err());
        assert!(parse_lens("50 5 x 4\n").unwrap_err().contains("line 1"));
        assert!(parse_lens("# nothing\n").is_err());
        let dir = tempfile::tempdir().unwrap();
        let files = SceneFiles::confined(dir.path(), dir.path()).unwrap();
        assert!(read_lens_file(&files, "../etc/passwd").is_err());
        assert!(read_lens_file(&files, "/etc/passwd").is_err());
    }

    #[test]
    fn film_at_the_back_focal_length_focuses_at_infinity() {
        let cam = camera(BFL);
        // Paraxial rays from the on-axis film point leave parallel to the axis.
        for r in [0.2f32, 0.5, 1.0] {
            let from = Vec3A::new(0.0, 0.0, cam.film_z);
            let to = Vec3A::new(r, 0.0, cam.back_z);
            let (_, d) = cam.trace(from, (to - from).normalize()).unwrap();
            assert!(d.x.abs() < 2e-4 * r.max(1.0) * 10.0, "r {r}: {d:?}");
        }
    }

    #[test]
    fn focus_at_a_finite_distance_matches_the_thick_lens_formula() {
        // film 60 behind the back vertex: image distance from the back principal plane
        // s' = 60 + 1.6949 = 61.6949; 1/s = 1/f - 1/s' gives s = 289.19, so the object in
        // focus is 289.19 - 1.6949 = 287.50 in front of the front vertex (z = 0).
        let cam = camera(60.0);
        let h = F - BFL;
        let s_img = 60.0 + h;
        let s_obj = 1.0 / (1.0 / F - 1.0 / s_img);
        let expect = s_obj - h;
        assert!((expect - 287.5).abs() < 0.1, "{expect}");
        let z = axis_crossing(&cam, 0.3);
        assert!((z - expect).abs() / expect < 0.01, "{z} vs {expect}");
    }

    #[test]
    fn image_is_inverted_and_weight_falls_off() {
        let cam = camera(BFL);
        // The top-left raster corner looks up and to the left (-x, +y), as the other cameras.
        let (_, d, w) = cam.ray(Vec2::new(0.0, 0.0), Vec2::new(0.5, 0.5)).unwrap();
        assert!(d.x < 0.0 && d.y > 0.0, "{d:?}");
        let (_, dc, wc) = cam.ray(Vec2::new(50.0, 50.0), Vec2::new(0.5, 0.5)).unwrap();
        assert!(dc.x.abs() < 1e-5 && dc.y.abs() < 1e-5);
        assert!((wc - 1.0).abs() < 1e-6 && w < wc);
    }

    #[test]
    fn the_stop_blocks_rays() {
        let rows = parse_lens("50 2 1.5 10\n0 2 1 10\n-50 0 1 10\n").unwrap();
        let cam = Realistic::new(&rows, 50.0, 0.5, 35.0, 10, 10).unwrap();
        let film = Vec3A::new(0.0, 0.0, cam.film_z);
        let through = |r: f32| {
            let to = Vec3A::new(r, 0.0, cam.back_z);
            cam.trace(film, (to - film).normalize())
        };
        assert!(through(0.05).is_some());
        assert!(through(3.0).is_none());
    }
}

//! The camera as a sensor, for light subpaths that end on it (bidirectional path tracing):
//! which film position a point of the scene is seen at, and the importance the camera gives
//! to light arriving from it.
//!
//! Only the perspective camera is connectable (pinhole or thin lens, fixed or moving). Eye
//! samples are spread uniformly over the Film's sample extent (its pixels widened by the
//! filter's reach, [`Camera::sample_extent`]; see `crate::render::extent`), and light paths
//! are accepted over the same extent, as LuxRender's perspective camera does: otherwise a
//! border pixel would lack the part of its filter footprint beyond the image in the light
//! buffer while its eye samples cover it. Over the plane z = 1 in camera space the
//! directional density of camera rays is `1 / (A cos³θ)`, A the extent's area on that plane
//! (LuxRender's `Apixel`) and θ the angle from the optical axis; the importance is the same
//! function. A light path connected to the lens at distance d then contributes
//! `β·f·|cos| / (A cos³θ d²)`; the render session scales it by extent pixels / image pixels
//! and the per-screen buffer by image pixels / samples, which gives the same pixel value as
//! the camera paths (each sample traces one light path).
//!
//! Data flow: `integrator::bidirectional` asks [`Camera::connect`] for every light vertex it
//! joins to the camera vertex of its eye path, and [`Camera::dir_pdf`] when it weighs a path
//! against the strategies that would have traced it from the camera.

use super::{Camera, CameraModel};
use crate::geometry::transform::{to_f32, to_f64};
use glam::{Vec2, Vec3A};

/// A scene point seen by the camera.
#[derive(Clone, Copy, Debug)]
pub struct CameraHit {
    /// Raster position over the full image.
    pub raster: Vec2,
    /// Importance over the lens-to-point density, `1 / (A cos³θ d²)`: multiplied by the
    /// light arriving at the lens (β·f·|cos| at the point) it gives the sample's value.
    pub weight: f32,
    /// Unit world direction from the lens point toward the scene point.
    pub dir: Vec3A,
}

impl Camera {
    /// Whether light paths may end on this camera (the perspective camera).
    pub fn connectable(&self) -> bool {
        matches!(self.model, CameraModel::Perspective(_))
    }

    /// Camera-to-world as (point, vector) maps at `time`.
    fn frame_at(&self, time: f32) -> (glam::Affine3A, Option<glam::DAffine3>) {
        match &self.fixed {
            Some(a) => (*a, None),
            None => (glam::Affine3A::IDENTITY, Some(self.motion.at(time))),
        }
    }

    fn to_camera_point(&self, p: Vec3A, time: f32) -> Vec3A {
        match self.frame_at(time) {
            (a, None) => a.inverse().transform_point3a(p),
            (_, Some(m)) => to_f32(m.inverse().transform_point3(to_f64(p))),
        }
    }

    fn to_camera_vector(&self, v: Vec3A, time: f32) -> Vec3A {
        match self.frame_at(time) {
            (a, None) => a.inverse().transform_vector3a(v),
            (_, Some(m)) => to_f32(m.inverse().transform_vector3(to_f64(v))),
        }
    }

    /// Where a camera ray (from [`Camera::generate_ray`]) left the lens: the world point of
    /// the ray on the camera-space plane z = 0 (the pinhole for a pinhole camera).
    pub fn lens_point(&self, ray: &crate::geometry::Ray) -> Vec3A {
        let oc = self.to_camera_point(ray.o, ray.time);
        let dc = self.to_camera_vector(ray.d, ray.time);
        if dc.z == 0.0 {
            return ray.o;
        }
        ray.o - ray.d * (oc.z / dc.z)
    }

    /// Area of the sample extent on the plane z = 1 in camera space (perspective camera).
    fn film_area(&self) -> f32 {
        let CameraModel::Perspective(c) = &self.model else {
            return 0.0;
        };
        let [x0, x1, y0, y1] = self.sample_extent();
        let w = c.screen.window;
        let (sx, sy) = (
            (w[1] - w[0]).abs() / c.screen.xres,
            (w[3] - w[2]).abs() / c.screen.yres,
        );
        let t = c.tan_half_fov;
        let (nx, ny) = (f64::from(x1) - f64::from(x0), f64::from(y1) - f64::from(y0));
        (nx * ny) as f32 * sx * sy * t * t
    }

    /// Raster position of a camera-space ray from lens point `lens` (z = 0) along `d`
    /// (d.z > 0): where its focus-plane point projects through the pinhole.
    fn raster_of(&self, lens: Vec3A, d: Vec3A) -> Option<Vec2> {
        let CameraModel::Perspective(c) = &self.model else {
            return None;
        };
        let mut p = Vec2::new(d.x / d.z, d.y / d.z);
        if c.lens_radius > 0.0 {
            let f = c.focal_distance;
            p += Vec2::new(lens.x, lens.y) / f;
        }
        let s = p / c.tan_half_fov;
        let [x0, x1, y0, y1] = c.screen.window;
        let rx = (s.x - x0) / (x1 - x0) * c.screen.xres;
        let ry = (s.y - y1) / (y0 - y1) * c.screen.yres;
        let r = Vec2::new(rx, ry);
        r.is_finite().then_some(r)
    }

    /// Whether a raster position lies in the sample extent.
    fn in_extent(&self, r: Vec2) -> bool {
        let [x0, x1, y0, y1] = self.sample_extent();
        r.x >= x0 as f32 && r.x < x1 as f32 && r.y >= y0 as f32 && r.y < y1 as f32
    }

    /// The film position at which the world point `p` is seen through the lens point `lens`
    /// (world space, from [`Camera::lens_point`]) at `time`, and the connection's weight;
    /// `None` outside the sample extent, behind the camera or outside the clipping planes.
    pub fn connect(&self, lens: Vec3A, p: Vec3A, time: f32) -> Option<CameraHit> {
        if !self.connectable() {
            return None;
        }
        let lc = self.to_camera_point(lens, time);
        let pc = self.to_camera_point(p, time);
        let d = pc - lc;
        if d.z <= 0.0 || d.z.is_nan() || pc.z < self.hither || pc.z > self.yon {
            return None;
        }
        let dist2 = d.length_squared();
        let cos = d.z / dist2.sqrt();
        let lens_plane = Vec3A::new(lc.x, lc.y, 0.0);
        let raster = self.raster_of(lens_plane, d)?;
        if !self.in_extent(raster) {
            return None;
        }
        let area = self.film_area();
        let weight = 1.0 / (area * cos * cos * cos * dist2);
        let dir = (p - lens).normalize_or_zero();
        (weight.is_finite() && weight > 0.0 && dir != Vec3A::ZERO).then_some(CameraHit {
            raster,
            weight,
            dir,
        })
    }

    /// Solid-angle density with which the camera's rays leave in world direction `dir` at
    /// `time`: `1 / (A cos³θ)`, A the sample extent's area on the plane z = 1; 0 for cameras
    /// light paths cannot reach.
    pub fn dir_pdf(&self, dir: Vec3A, time: f32) -> f32 {
        if !self.connectable() {
            return 0.0;
        }
        let d = self.to_camera_vector(dir, time).normalize_or_zero();
        if d.z <= 0.0 {
            return 0.0;
        }
        let area = self.film_area();
        let v = 1.0 / (area * d.z * d.z * d.z);
        if v.is_finite() {
            v
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::camera::{Camera, CameraSample, FilmGeometry};
    use crate::lxs::{parse_str, ParseOptions};
    use glam::{Vec2, Vec3A};

    fn camera(extra: &str, film: FilmGeometry) -> Camera {
        let text = format!(
            "LookAt 0 0 0  0 1 0  0 0 1\nCamera \"perspective\" \"float fov\" [40] {extra}\nWorldBegin\nWorldEnd\n"
        );
        let desc = parse_str(&text, "t.lxs", &ParseOptions::default()).unwrap();
        let mut w = Vec::new();
        Camera::build(desc.camera.as_ref().unwrap(), &film, &mut w).unwrap()
    }

    /// A camera ray's hit point maps back to the raster position that generated it, and
    /// the direction density integrates to 1 over the frustum.
    #[test]
    fn connection_inverts_ray_generation() {
        let film = FilmGeometry::new(64, 48);
        for extra in [
            "",
            "\"float lensradius\" [0.05] \"float focaldistance\" [3]",
        ] {
            let cam = camera(extra, film);
            for (px, py, lx, ly) in [(10.3, 20.7, 0.2, 0.9), (50.5, 3.25, 0.7, 0.4)] {
                let cs = CameraSample {
                    p_film: Vec2::new(px, py),
                    p_lens: Vec2::new(lx, ly),
                    time: 0.0,
                };
                let (ray, _) = cam.generate_ray(&cs).unwrap();
                let p = ray.o + ray.d * 5.0;
                let lens = cam.lens_point(&ray);
                let hit = cam.connect(lens, p, 0.0).unwrap();
                assert!(
                    (hit.raster - cs.p_film).length() < 2e-3,
                    "{extra}: {:?} vs {:?}",
                    hit.raster,
                    cs.p_film
                );
                assert!((hit.dir - ray.d).length() < 1e-4);
            }
        }
        // ∫ pdf dω over the frustum = 1: a grid of directions through the film.
        let cam = camera("", film);
        let n = 200;
        let mut total = 0.0f64;
        let t = (20f32).to_radians().tan();
        // Frame aspect 64/48 > 1: the screen is [-a, a] × [-1, 1] scaled by tan(fov/2).
        let a = 64.0 / 48.0;
        for i in 0..n {
            for j in 0..n {
                let x = (-a + 2.0 * a * (i as f32 + 0.5) / n as f32) * t;
                let z = (-1.0 + 2.0 * (j as f32 + 0.5) / n as f32) * t;
                // LookAt along +y with z up: camera +z is world +y.
                let d = Vec3A::new(x, 1.0, z);
                let cos = 1.0 / d.length();
                let cell = (2.0 * a * t / n as f32) * (2.0 * t / n as f32);
                total += f64::from(cam.dir_pdf(d.normalize(), 0.0) * cell * cos * cos * cos);
            }
        }
        assert!((total - 1.0).abs() < 1e-3, "{total}");
        assert!(cam
            .connect(Vec3A::ZERO, Vec3A::new(0.0, -1.0, 0.0), 0.0)
            .is_none());
    }

    /// Light paths reach the camera over the sample extent, margin included, and the
    /// importance is normalised over the extent's area: hits in the margin are accepted,
    /// beyond it refused, and the density scales by the crop area over the extent's.
    #[test]
    fn connections_cover_the_sample_extent() {
        let film = FilmGeometry::new(64, 48);
        let mut cam = camera("", film);
        assert_eq!(cam.sample_extent(), [0, 64, 0, 48]);
        let seen_at = |cam: &Camera, x: f32, y: f32| {
            let cs = CameraSample {
                p_film: Vec2::new(x, y),
                p_lens: Vec2::new(0.5, 0.5),
                time: 0.0,
            };
            let (ray, _) = cam.generate_ray(&cs).unwrap();
            cam.connect(cam.lens_point(&ray), ray.o + ray.d * 5.0, 0.0)
        };
        let inside = seen_at(&cam, 30.5, 20.5).unwrap();
        assert!(
            seen_at(&cam, -1.5, 20.5).is_none(),
            "margin refused without an extent"
        );
        cam.set_sample_extent([-2, 66, -2, 50]);
        let margin = seen_at(&cam, -1.5, 20.5).expect("margin accepted");
        assert!((margin.raster - Vec2::new(-1.5, 20.5)).length() < 2e-3);
        assert!(seen_at(&cam, -2.5, 20.5).is_none());
        assert!(seen_at(&cam, 30.5, 50.5).is_none());
        let wider = seen_at(&cam, 30.5, 20.5).unwrap();
        let ratio = inside.weight / wider.weight;
        assert!(
            (ratio - 68.0 * 52.0 / (64.0 * 48.0)).abs() < 1e-3,
            "{ratio}"
        );
        // An empty extent is ignored.
        cam.set_sample_extent([5, 5, 0, 10]);
        assert_eq!(cam.sample_extent(), [-2, 66, -2, 50]);
    }
}

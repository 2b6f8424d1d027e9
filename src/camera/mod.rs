//! Cameras: perspective, orthographic, environment (one file per plugin).
//!
//! [`Camera::build`] reads a `Camera` statement with LuxRender's parameter names and defaults
//! (the shared ones here, each model's in its file; screen window and lens in `projective`):
//! `hither` (1e-3, at least 1e-4), `yon` (1e30), `shutteropen` (0), `shutterclose` (1),
//! `shutterdistribution` (uniform|gaussian), `lensradius` (0), `focaldistance` (1e30),
//! `autofocus` (false), `frameaspectratio` (xres/yres), `screenwindow`, perspective `fov` (90),
//! `blades` (0), `distribution`, `power`.
//!
//! Conventions (LuxRender's): camera space looks down +z with +y up and +x to the right
//! (LuxRender's `LookAt` builds `right = dir x up`, so a world point to the camera's right
//! lands on the right of the image); raster coordinates cover the **full** image (the Film
//! crop window does not move them), (0, 0) is the top-left corner, y grows downwards.
//! [`Camera::generate_ray`] returns a world-space ray with a unit direction, starting on the
//! near clipping plane and ending (`t_max`) on the far one, with the shutter time; the weight
//! is 1 for all three models (as LuxRender's `GenerateRay`).

mod environment;
mod importance;
mod lens;
mod lens_distribution;
mod motion;
mod orthographic;
mod perspective;
mod projective;
pub mod realistic;

pub use environment::Environment;
pub use importance::CameraHit;
pub use lens::{Aperture, Shutter, ShutterDistribution};
pub use motion::CameraMotion;
pub use orthographic::Orthographic;
pub use perspective::Perspective;
pub use realistic::Realistic;

use crate::geometry::transform::{to_f32, to_f64};
use crate::geometry::Ray;
use crate::lxs::{CameraDesc, Diagnostic};
use crate::plugin::{BuildError, Stmt};
use glam::{Affine3A, DMat4, DVec3, Vec2, Vec3A};

/// The image the camera renders: full resolution and the Film `cropwindow` in NDC
/// (`[xmin, xmax, ymin, ymax]`, [0, 1] each, y down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmGeometry {
    pub xres: u32,
    pub yres: u32,
    pub crop: [f32; 4],
}

impl FilmGeometry {
    /// A film without crop window.
    pub fn new(xres: u32, yres: u32) -> FilmGeometry {
        FilmGeometry {
            xres,
            yres,
            crop: [0.0, 1.0, 0.0, 1.0],
        }
    }

    /// The pixels of the crop window as LuxRender computes them: `[x0, x1, y0, y1]`,
    /// half-open, `x0 = ceil(xres * crop[0])`, `x1 = max(x0 + 1, ceil(xres * crop[1]))`
    /// (crop values ordered and clamped to [0, 1]).
    pub fn pixel_bounds(&self) -> [u32; 4] {
        let c = |v: f32| {
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        let (a, b) = (c(self.crop[0]), c(self.crop[1]));
        let (cx0, cx1) = (a.min(b), a.max(b));
        let (a, b) = (c(self.crop[2]), c(self.crop[3]));
        let (cy0, cy1) = (a.min(b), a.max(b));
        let axis = |res: u32, lo: f32, hi: f32| {
            let start = ((res as f32 * lo).ceil() as u32).min(res.saturating_sub(1));
            let end = ((res as f32 * hi).ceil() as u32).min(res).max(start + 1);
            (start, end)
        };
        let (x0, x1) = axis(self.xres, cx0, cx1);
        let (y0, y1) = axis(self.yres, cy0, cy1);
        [x0, x1, y0, y1]
    }
}

/// Where a sample is: raster position over the full image, lens sample in [0, 1)², shutter
/// sample in [0, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    pub p_film: Vec2,
    pub p_lens: Vec2,
    pub time: f32,
}

/// Raster to screen mapping: raster (0, 0) is screen (xmin, ymax), raster (xres, yres) is
/// screen (xmax, ymin).
#[derive(Clone, Debug, PartialEq)]
pub struct RasterToScreen {
    pub window: [f32; 4],
    pub xres: f32,
    pub yres: f32,
}

impl RasterToScreen {
    pub fn apply(&self, p: Vec2) -> Vec2 {
        let [x0, x1, y0, y1] = self.window;
        Vec2::new(
            x0 + (x1 - x0) * p.x / self.xres,
            y1 + (y0 - y1) * p.y / self.yres,
        )
    }
}

/// The camera model.
#[derive(Clone, Debug, PartialEq)]
pub enum CameraModel {
    Perspective(Perspective),
    Orthographic(Orthographic),
    Environment(Environment),
    Realistic(Box<Realistic>),
}

/// A camera ready to generate rays.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub model: CameraModel,
    pub motion: CameraMotion,
    pub shutter: Shutter,
    pub hither: f32,
    pub yon: f32,
    pub autofocus: bool,
    film: FilmGeometry,
    /// The raster pixels `[x0, x1, y0, y1]` (half-open, possibly beyond the image) that eye
    /// samples are drawn over and light paths may reach: the Film's sample extent
    /// (`crate::render::extent`), the crop window's pixels until the render setup sets it.
    sample_extent: [i32; 4],
    /// Camera-to-world in f32 when the camera does not move: rays are transformed in f32
    /// (the f64 transform cost 2% of a Cornell render). A ray's origin is not on a surface,
    /// so the few extra ulps of its position need no offset; moving cameras interpolate
    /// their keys in f64.
    fixed: Option<Affine3A>,
}

impl Camera {
    /// Builds the camera of a `Camera` statement for a film of this geometry: the parameters
    /// every camera shares (clipping, shutter, autofocus) are read here, the model's own in
    /// its file.
    pub fn build(
        desc: &CameraDesc,
        film: &FilmGeometry,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Camera, BuildError> {
        Camera::build_in(desc, film, None, warnings)
    }

    /// As [`Camera::build`], with the scene's files the realistic camera's lens file is read
    /// from (without them, a realistic camera is an error).
    pub fn build_in(
        desc: &CameraDesc,
        film: &FilmGeometry,
        files: Option<&crate::fileio::SceneFiles>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Camera, BuildError> {
        let e = &desc.entity;
        let mut s = Stmt::new("camera", e, warnings);
        if film.xres == 0 || film.yres == 0 {
            return Err(s.err(format!(
                "film resolution {}x{} is empty",
                film.xres, film.yres
            )));
        }
        let p = s.params();
        let motion = CameraMotion::from_xform(&desc.world_to_camera).map_err(|m| s.err(m))?;
        if let Some(name) = p.string("endtransform") {
            s.warn(format!(
                "camera \"endtransform\" \"{name}\" is not supported here; use a MotionBegin block"
            ));
        }
        let hither = p.float_or("hither", 1e-3).max(1e-4);
        let yon = p.float_or("yon", 1e30).min(1e30).max(hither);
        if !(hither.is_finite() && yon.is_finite()) {
            return Err(s.err("hither/yon must be finite"));
        }
        let shutter = Shutter::build(&mut s)?;
        let autofocus = p.bool_or("autofocus", false);
        let model = match e.kind.as_str() {
            "perspective" => CameraModel::Perspective(Perspective::build(&mut s, film)?),
            "orthographic" => CameraModel::Orthographic(Orthographic::build(&mut s, film)?),
            "environment" => CameraModel::Environment(Environment::build(&s, film)),
            "realistic" => CameraModel::Realistic(Box::new(realistic::build(&s, film, files)?)),
            other => {
                return Err(s.err(format!(
                    "unknown camera \"{other}\" (known: perspective, orthographic, environment, realistic)"
                )))
            }
        };
        if autofocus && matches!(model, CameraModel::Environment(_)) {
            s.warn("autofocus has no effect on the environment camera");
        }
        let fixed = match &motion {
            CameraMotion::Fixed(a) => Some(Affine3A::from_mat4(DMat4::from(*a).as_mat4())),
            CameraMotion::Keys(_) => None,
        };
        Ok(Camera {
            model,
            motion,
            shutter,
            hither,
            yon,
            autofocus,
            film: *film,
            sample_extent: film
                .pixel_bounds()
                .map(|v| i32::try_from(v).unwrap_or(i32::MAX)),
            fixed,
        })
    }

    pub fn film(&self) -> &FilmGeometry {
        &self.film
    }

    /// The raster pixels `[x0, x1, y0, y1]` (half-open) eye samples cover and light paths
    /// may reach (see [`Camera::set_sample_extent`]).
    pub fn sample_extent(&self) -> [i32; 4] {
        self.sample_extent
    }

    /// Sets the sample extent: the pixels the sampler draws camera samples over (the Film's
    /// pixels widened by the filter's reach), which light paths connected to the camera
    /// must cover too. An empty extent is ignored.
    pub fn set_sample_extent(&mut self, extent: [i32; 4]) {
        let [x0, x1, y0, y1] = extent;
        if x0 < x1 && y0 < y1 {
            self.sample_extent = extent;
        }
    }

    /// The world-space ray for a camera sample, and its weight (1). `None` when the sample is
    /// not finite.
    pub fn generate_ray(&self, s: &CameraSample) -> Option<(Ray, f32)> {
        if !(s.p_film.is_finite() && s.p_lens.is_finite() && s.time.is_finite()) {
            return None;
        }
        let time = self.shutter.time(s.time);
        if let CameraModel::Realistic(c) = &self.model {
            let (o, d, w) = c.ray(s.p_film, s.p_lens)?;
            let t_far = (self.yon - self.hither) / d.z;
            return self.to_world(o, d, t_far, time).map(|r| (r, w));
        }
        let (o, d, t_far) = self.camera_ray(s.p_film, s.p_lens);
        self.to_world(o, d, t_far, time).map(|r| (r, 1.0))
    }

    /// Camera-space origin (on the near plane), unit direction and parametric far distance.
    fn camera_ray(&self, p: Vec2, lens: Vec2) -> (Vec3A, Vec3A, f32) {
        match &self.model {
            CameraModel::Perspective(c) => {
                let (o, d) = c.ray(p, lens);
                let d = d.normalize();
                // Near and far clipping planes are z = hither, z = yon.
                (
                    o + d * (self.hither / d.z),
                    d,
                    (self.yon - self.hither) / d.z,
                )
            }
            CameraModel::Orthographic(c) => {
                let (o, d) = c.ray(p, lens, self.hither);
                let d = d.normalize();
                (o, d, (self.yon - self.hither) / d.z)
            }
            CameraModel::Environment(c) => {
                let d = c.direction(p);
                (d * self.hither, d, self.yon - self.hither)
            }
            // Traced through its lens in `generate_ray`; the axis ray as a fallback.
            CameraModel::Realistic(_) => (Vec3A::ZERO, Vec3A::Z, self.yon - self.hither),
        }
    }

    fn to_world(&self, o: Vec3A, d: Vec3A, t_far: f32, time: f32) -> Option<Ray> {
        let (ow, dw, len) = match &self.fixed {
            Some(a) => {
                let dw = a.transform_vector3a(d);
                let len = dw.length();
                (a.transform_point3a(o), dw / len, f64::from(len))
            }
            None => {
                let c2w = self.motion.at(time);
                let ow = c2w.transform_point3(to_f64(o));
                let dw = c2w.transform_vector3(to_f64(d));
                let len = dw.length();
                (to_f32(ow), to_f32(dw / len), len)
            }
        };
        if !(len > 0.0 && len.is_finite() && ow.is_finite() && dw.is_finite()) {
            return None;
        }
        Some(Ray {
            o: ow,
            d: dw,
            t_max: (t_far as f64 * len).min(f32::MAX as f64) as f32,
            time,
        })
    }

    /// The depth the Z buffer records for a hit at distance `t` along a ray this camera made:
    /// the distance from the lens, since rays start on the near clipping plane (`hither` in
    /// front of the lens along the view axis; along the ray for the environment camera).
    pub fn hit_depth(&self, ray: &Ray, t: f32) -> f32 {
        match self.model {
            CameraModel::Environment(_) => return t + self.hither,
            CameraModel::Realistic(_) => return t,
            _ => {}
        }
        let forward = match &self.fixed {
            Some(a) => a.transform_vector3a(Vec3A::Z),
            None => to_f32(self.motion.at(ray.time).transform_vector3(DVec3::Z)),
        };
        let cos = ray.d.dot(forward.normalize_or_zero());
        if cos > 1e-6 {
            t + self.hither / cos
        } else {
            t
        }
    }

    /// Whether the scene asked for autofocus (perspective or orthographic).
    pub fn needs_autofocus(&self) -> bool {
        self.autofocus
            && !matches!(
                self.model,
                CameraModel::Environment(_) | CameraModel::Realistic(_)
            )
    }

    /// The focal distance in use (projective cameras).
    pub fn focal_distance(&self) -> Option<f32> {
        match &self.model {
            CameraModel::Perspective(c) => Some(c.focal_distance),
            CameraModel::Orthographic(c) => Some(c.focal_distance),
            CameraModel::Environment(_) | CameraModel::Realistic(_) => None,
        }
    }

    /// LuxRender's autofocus: when `autofocus` is set, traces the pinhole ray through the
    /// image centre at shutter open (`trace` returns the hit distance along the ray) and
    /// sets the focal distance to the camera-space depth of the hit. Without a hit the focal
    /// distance is kept (with a warning). Returns the focal distance in use.
    pub fn autofocus(&mut self, trace: impl Fn(&Ray) -> Option<f32>) -> Option<f32> {
        if !self.needs_autofocus() {
            return self.focal_distance();
        }
        let centre = Vec2::new(self.film.xres as f32 / 2.0, self.film.yres as f32 / 2.0);
        let time = self.shutter.open;
        let (o, d, t_far) = match &self.model {
            CameraModel::Perspective(c) => {
                let pin = Perspective {
                    lens_radius: 0.0,
                    ..c.clone()
                };
                let (o, d) = pin.ray(centre, Vec2::ZERO);
                let d = d.normalize();
                (
                    o + d * (self.hither / d.z),
                    d,
                    (self.yon - self.hither) / d.z,
                )
            }
            CameraModel::Orthographic(c) => {
                let s = c.screen.apply(centre);
                (
                    Vec3A::new(s.x, s.y, self.hither),
                    Vec3A::Z,
                    self.yon - self.hither,
                )
            }
            CameraModel::Environment(_) | CameraModel::Realistic(_) => return None,
        };
        let ray = self.to_world(o, d, t_far, time)?;
        let w2c = self.motion.at(time).inverse();
        let depth = trace(&ray).filter(|t| t.is_finite() && *t >= 0.0).map(|t| {
            let hit = ray.o + ray.d * t;
            // Camera-space depth of the hit point.
            w2c.transform_point3(DVec3::new(hit.x as f64, hit.y as f64, hit.z as f64))
                .z as f32
        });
        match depth {
            Some(z) if z > 0.0 => {
                tracing::info!("autofocus focal distance: {z}");
                self.set_focal_distance(z);
            }
            _ => tracing::warn!(
                "unable to define the autofocus focal distance: the centre ray hits nothing"
            ),
        }
        self.focal_distance()
    }

    fn set_focal_distance(&mut self, z: f32) {
        match &mut self.model {
            CameraModel::Perspective(c) => c.focal_distance = z,
            CameraModel::Orthographic(c) => c.focal_distance = z,
            CameraModel::Environment(_) | CameraModel::Realistic(_) => {}
        }
    }
}

#[cfg(test)]
mod tests;

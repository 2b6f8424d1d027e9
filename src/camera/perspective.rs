//! The perspective camera (LuxRender's `perspective`).
//!
//! Screen space: `screenwindow` [xmin xmax ymin ymax], by default [-a, a] x [-1, 1] for a frame
//! aspect ratio a = `frameaspectratio` (xres/yres) > 1, else [-1, 1] x [-1/a, 1/a]: `fov`
//! (degrees, default 90) spans the shorter image axis. Raster (0, 0) is the top-left corner of
//! the full image: raster x grows with screen x, raster y grows downwards (screen y shrinks).
//! The screen point (sx, sy) is the camera-space direction (sx tan(fov/2), sy tan(fov/2), 1).
//!
//! Thin lens (`lensradius` > 0): the ray leaves a point of the aperture and passes through the
//! pinhole ray's point on the plane z = `focaldistance` (default 1e30). Rays start on the
//! plane z = `hither` and end on z = `yon`.

use super::lens::Aperture;
use super::projective::Projective;
use super::{FilmGeometry, RasterToScreen};
use crate::plugin::{BuildError, Stmt};
use glam::{Vec2, Vec3A};

#[derive(Clone, Debug, PartialEq)]
pub struct Perspective {
    pub screen: RasterToScreen,
    /// tan(fov / 2).
    pub tan_half_fov: f32,
    pub lens_radius: f32,
    pub focal_distance: f32,
    pub aperture: Aperture,
}

impl Perspective {
    /// Reads a `perspective` statement: `fov` (degrees, default 90) and the projective
    /// parameters.
    pub(super) fn build(s: &mut Stmt, film: &FilmGeometry) -> Result<Perspective, BuildError> {
        let fov = s.params().float_or("fov", 90.0);
        if !(fov > 0.0 && fov < 180.0) {
            return Err(s.err(format!(
                "perspective fov must be in (0, 180) degrees, got {fov}"
            )));
        }
        let pr = Projective::build(s, film)?;
        Ok(Perspective {
            screen: pr.screen,
            tan_half_fov: (fov.to_radians() / 2.0).tan(),
            lens_radius: pr.lens_radius,
            focal_distance: pr.focal_distance,
            aperture: pr.aperture,
        })
    }

    /// Camera-space origin and (unnormalised) direction of the ray through raster point `p`.
    pub fn ray(&self, p: Vec2, lens: Vec2) -> (Vec3A, Vec3A) {
        let s = self.screen.apply(p) * self.tan_half_fov;
        let dir = Vec3A::new(s.x, s.y, 1.0);
        if self.lens_radius <= 0.0 {
            return (Vec3A::ZERO, dir);
        }
        let l = self.aperture.sample(lens) * self.lens_radius;
        let origin = Vec3A::new(l.x, l.y, 0.0);
        // Towards the pinhole ray's point on z = focal distance, scaled by 1 / focal distance
        // so the default distance (1e30) does not overflow.
        (origin, dir - origin / self.focal_distance)
    }
}

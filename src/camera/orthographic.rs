//! The orthographic camera (LuxRender's `orthographic`).
//!
//! The screen window (same defaults as the perspective camera) is the camera-space rectangle
//! the rays cross: the ray for raster point p starts at (sx, sy, hither) and runs along +z.
//! Thin lens: the origin moves by the lens offset scaled by (focaldistance - hither) /
//! focaldistance and the ray aims at (sx, sy, focaldistance), as LuxRender does.

use super::lens::Aperture;
use super::projective::Projective;
use super::{FilmGeometry, RasterToScreen};
use crate::plugin::{BuildError, Stmt};
use glam::{Vec2, Vec3A};

#[derive(Clone, Debug, PartialEq)]
pub struct Orthographic {
    pub screen: RasterToScreen,
    pub lens_radius: f32,
    pub focal_distance: f32,
    pub aperture: Aperture,
}

impl Orthographic {
    /// Reads an `orthographic` statement (the projective parameters).
    pub(super) fn build(s: &mut Stmt, film: &FilmGeometry) -> Result<Orthographic, BuildError> {
        let pr = Projective::build(s, film)?;
        Ok(Orthographic {
            screen: pr.screen,
            lens_radius: pr.lens_radius,
            focal_distance: pr.focal_distance,
            aperture: pr.aperture,
        })
    }

    /// Camera-space origin (on z = hither) and direction of the ray through raster point `p`.
    pub fn ray(&self, p: Vec2, lens: Vec2, hither: f32) -> (Vec3A, Vec3A) {
        let s = self.screen.apply(p);
        let origin = Vec3A::new(s.x, s.y, hither);
        if self.lens_radius <= 0.0 {
            return (origin, Vec3A::Z);
        }
        let f = self.focal_distance;
        let l = self.aperture.sample(lens) * self.lens_radius * ((f - hither) / f);
        let o = origin + Vec3A::new(l.x, l.y, 0.0);
        // Towards (sx, sy, f), scaled by 1 / f so a huge focal distance does not overflow.
        let d = Vec3A::new((s.x - o.x) / f, (s.y - o.y) / f, (f - hither) / f);
        (o, d)
    }
}

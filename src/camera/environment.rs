//! The environment camera (LuxRender's `environment`): a latitude-longitude panorama of the
//! full sphere around the camera position.
//!
//! With raster (x, y) over the full image: theta = pi y / yres from camera +y (top row) to -y
//! (bottom row), phi = 2 pi x / xres, and the camera-space direction is
//! (-sin theta sin phi, cos theta, -sin theta cos phi): the left and right image edges look
//! backwards (-z), the image centre looks forwards (+z), a quarter of the width looks to
//! camera -x (left), three quarters to +x (right). Screen window and lens are ignored.

use super::FilmGeometry;
use crate::plugin::Stmt;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    pub xres: f32,
    pub yres: f32,
}

impl Environment {
    /// Reads an `environment` statement: LuxRender reads and ignores the lens and screen
    /// parameters for this camera.
    pub(super) fn build(s: &Stmt, film: &FilmGeometry) -> Environment {
        for name in [
            "lensradius",
            "focaldistance",
            "frameaspectratio",
            "screenwindow",
        ] {
            let _ = s.params().floats(name);
        }
        Environment {
            xres: film.xres as f32,
            yres: film.yres as f32,
        }
    }

    /// Unit camera-space direction for raster point `p`.
    pub fn direction(&self, p: Vec2) -> Vec3A {
        let theta = PI * p.y / self.yres;
        let phi = 2.0 * PI * p.x / self.xres;
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        Vec3A::new(-st * sp, ct, -st * cp)
    }
}

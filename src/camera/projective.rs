//! What the perspective and orthographic cameras share: the screen window (from
//! `frameaspectratio` and `screenwindow`) and the thin lens (`lensradius`, `focaldistance`,
//! `blades`, `distribution`, `power`), read from the `Camera` statement.

use super::lens::{Aperture, LensDistribution};
use super::{FilmGeometry, RasterToScreen};
use crate::plugin::{BuildError, Stmt};

/// Screen window and lens of a projective camera.
pub(super) struct Projective {
    pub screen: RasterToScreen,
    pub lens_radius: f32,
    pub focal_distance: f32,
    pub aperture: Aperture,
}

impl Projective {
    pub(super) fn build(s: &mut Stmt, film: &FilmGeometry) -> Result<Projective, BuildError> {
        let p = s.params();
        let mut lens_radius = p.float_or("lensradius", 0.0);
        let mut focal_distance = p.float_or("focaldistance", 1e30);
        if !(lens_radius.is_finite() && lens_radius >= 0.0) {
            return Err(s.err(format!("lensradius must be >= 0, got {lens_radius}")));
        }
        // Old exporters write "focaldistance" [0] next to a zero lens radius: only a lens needs
        // a usable focal distance (autofocus may still provide it).
        if !(focal_distance.is_finite() && focal_distance > 0.0) {
            if lens_radius > 0.0 && !p.bool_or("autofocus", false) {
                s.warn(format!(
                    "focaldistance {focal_distance} is unusable; depth of field disabled"
                ));
                lens_radius = 0.0;
            }
            focal_distance = 1e30;
        }
        let screen = screen_window(s, film)?;
        let aperture = aperture(s);
        if p.floats("clippingplane").is_some() {
            s.warn(
                "camera clipping plane is not supported (LuxRender supports it only in LuxCore)",
            );
        }
        Ok(Projective {
            screen,
            lens_radius,
            focal_distance,
            aperture,
        })
    }
}

/// The screen window: [-a, a] x [-1, 1] for a frame aspect a > 1, else [-1, 1] x [-1/a, 1/a],
/// or `screenwindow` when given.
fn screen_window(s: &mut Stmt, film: &FilmGeometry) -> Result<RasterToScreen, BuildError> {
    let p = s.params();
    let frame = p.float_or("frameaspectratio", film.xres as f32 / film.yres as f32);
    if !(frame.is_finite() && frame > 0.0) {
        return Err(s.err(format!("frameaspectratio must be > 0, got {frame}")));
    }
    let mut window = if frame > 1.0 {
        [-frame, frame, -1.0, 1.0]
    } else {
        [-1.0, 1.0, -1.0 / frame, 1.0 / frame]
    };
    match p.floats("screenwindow") {
        Some(sw) if sw.len() == 4 && sw.iter().all(|v| v.is_finite()) => {
            window.copy_from_slice(sw);
        }
        Some(sw) => s.warn(format!(
            "screenwindow needs 4 finite values, got {sw:?}; ignored"
        )),
        None => {}
    }
    Ok(RasterToScreen {
        window,
        xres: film.xres as f32,
        yres: film.yres as f32,
    })
}

/// The aperture shape: a polygon of `blades` (>= 3) sides, else a disc.
fn aperture(s: &mut Stmt) -> Aperture {
    let p = s.params();
    let blades = p.int_or("blades", 0);
    let name = p.string_or("distribution", "uniform").to_string();
    let power = p.int_or("power", 3);
    let distribution = LensDistribution::from_name(&name, power).unwrap_or_else(|| {
        s.warn(format!(
            "lens distribution \"{name}\" unknown, using \"uniform\""
        ));
        LensDistribution::Uniform
    });
    // As LuxRender: the distribution shapes polygonal apertures; a disc is sampled uniformly.
    if blades >= 3 {
        match distribution {
            LensDistribution::Uniform => Aperture::Polygon(blades as u32),
            d => Aperture::PolygonDistributed(blades as u32, d),
        }
    } else {
        Aperture::Disc
    }
}

//! `camera "name" ... end camera`: the lens, the image, and the files written — and their
//! LuxRender equivalents.
//!
//! ```text
//! camera block --parse--> MiCamera --camera_entity--> Camera "perspective"|"orthographic"
//!                                  --film_entity-->   Film "fleximage" (resolution, outputs)
//! ```
//!
//! mental ray's camera looks down its −z axis with y up; `focal` is the distance to the
//! image plane and `aperture` that plane's width (same units), `aspect` the image's width
//! over height, so the half-width at unit distance is aperture / (2·focal) and the
//! half-height that over aspect. LuxRender's `fov` spans the shorter image axis; when the
//! aspect differs from the resolution's the `screenwindow` says so. `focal infinity` is an
//! orthographic camera whose image plane is `aperture` wide. `clip near far` → `hither`,
//! `yon`.
//!
//! Outputs: the primary framebuffer's `filename` (mental ray 3.11+) or the first `output`
//! statement's file names the Film's `filename` (its stem) and, by extension, what is
//! written: `.exr` → EXR, `.png` → PNG, `.tga` → TGA (other formats: PNG with a note).
//! mental ray stores a framebuffer's values as the render computed them (no tone mapping),
//! so an EXR is written linear (`write_exr_applyimaging` false), in 32-bit floats when the
//! primary framebuffer's data type is a `_fp` one and in half floats otherwise.
//! Other framebuffers (AOVs: `user on`) are not rendered by luxfarm: one note each.

use super::cursor::{Cursor, MiResult};
use super::lexer::Tok;
use crate::lxs::{Diagnostic, Entity, Loc, Param, ParamSet, ParamValue};

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Framebuffer {
    pub name: String,
    pub loc: Loc,
    pub primary: bool,
    pub user: bool,
    pub datatype: Option<String>,
    pub filename: Option<String>,
}

#[derive(Clone, Debug, Default)]
pub struct MiCamera {
    pub name: String,
    pub loc: Loc,
    /// `None`: `focal infinity` (orthographic).
    pub focal: Option<f64>,
    pub focal_given: bool,
    pub aperture: Option<f64>,
    pub aspect: Option<f64>,
    pub resolution: Option<(u32, u32, Loc)>,
    pub clip: Option<(f64, f64, Loc)>,
    pub framebuffers: Vec<Framebuffer>,
    /// `output "type" ["format"] "file"`: (file, where).
    pub outputs: Vec<(String, Loc)>,
    /// Statements luxfarm does not use, with where.
    pub ignored: Vec<(String, Loc)>,
}

/// Largest image side accepted.
pub const MAX_RESOLUTION: i64 = 1 << 16;

const FRAMEBUFFER_ATTRS: &[&str] = &[
    "datatype",
    "filtering",
    "primary",
    "user",
    "filename",
    "filetype",
    "compression",
    "dither",
    "premultiplied",
    "premultiply",
    "colorprofile",
    "gamma",
    "interpolate",
    "useprevious",
];

/// Reads the block after `camera "name"` up to and including `end camera`.
pub fn parse(c: &mut Cursor, name: String, loc: Loc, max_len: usize) -> MiResult<MiCamera> {
    let mut cam = MiCamera {
        name,
        loc,
        focal: Some(1.0),
        ..MiCamera::default()
    };
    loop {
        let at = c.loc()?;
        let w = match c.peek()? {
            Tok::Word(w) => *w,
            Tok::Eof => return Err(c.unexpected("'end camera'")),
            _ => return Err(c.unexpected("a camera statement or 'end camera'")),
        };
        c.next()?;
        match w {
            "end" => {
                c.expect_word("camera")?;
                return Ok(cam);
            }
            "focal" => {
                cam.focal_given = true;
                cam.focal = if c.eat_word("infinity")? {
                    None
                } else {
                    Some(positive(c, "focal")?)
                };
            }
            "aperture" => cam.aperture = Some(positive(c, "aperture")?),
            "aspect" => cam.aspect = Some(positive(c, "aspect")?),
            "resolution" => {
                let x = c.int("the x resolution", 1, MAX_RESOLUTION)? as u32;
                let y = c.int("the y resolution", 1, MAX_RESOLUTION)? as u32;
                cam.resolution = Some((x, y, at));
            }
            "clip" => {
                let [near, far] = c.numbers::<2>("the clip distances")?;
                cam.clip = Some((near, far, at));
            }
            "framebuffer" => {
                if cam.framebuffers.len() >= max_len {
                    return Err(c.error(
                        crate::lxs::LxsErrorKind::ArrayTooLong,
                        "too many framebuffers",
                    ));
                }
                let name = c.string("a framebuffer name")?;
                cam.framebuffers.push(framebuffer(c, name, at)?);
            }
            "output" => {
                let mut strings = Vec::new();
                if c.eat_punct(b'=')? {
                    c.string("an output shader")?;
                    cam.ignored.push(("output shader".into(), at));
                    continue;
                }
                while c.at_string()? && strings.len() < 3 {
                    strings.push(c.string("an output argument")?);
                }
                match strings.last() {
                    Some(file) if strings.len() >= 2 => cam.outputs.push((file.clone(), at)),
                    _ => return Err(c.unexpected("output \"type\" [\"format\"] \"file\"")),
                }
            }
            "lens" | "volume" | "environment" | "pass" => {
                while super::params::parse_ref(c, max_len)?.is_some() {}
                cam.ignored.push((format!("{w} shader"), at));
            }
            other => {
                // offset, window, frame, field, data, ...: their values are on their line.
                c.skip_line()?;
                cam.ignored.push((other.to_string(), at));
            }
        }
    }
}

fn positive(c: &mut Cursor, what: &str) -> MiResult<f64> {
    let loc = c.loc()?;
    let v = c.number(what)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(crate::lxs::LxsError::new(
            crate::lxs::LxsErrorKind::InvalidValue,
            loc,
            format!("{what} must be positive, got {v}"),
        ))
    }
}

/// The attributes after `framebuffer "name"`.
fn framebuffer(c: &mut Cursor, name: String, loc: Loc) -> MiResult<Framebuffer> {
    let mut fb = Framebuffer {
        name,
        loc,
        ..Framebuffer::default()
    };
    while let Tok::Word(w) = c.peek()? {
        let w = *w;
        if !FRAMEBUFFER_ATTRS.contains(&w) {
            break;
        }
        c.next()?;
        match w {
            "primary" => fb.primary = c.flag()?,
            "user" => fb.user = c.flag()?,
            "datatype" => fb.datatype = Some(c.string("a data type")?),
            "filename" => fb.filename = Some(c.string("a file name")?),
            _ => c.skip_values()?,
        }
    }
    Ok(fb)
}

fn param(name: &str, value: ParamValue, loc: &Loc) -> Param {
    Param::new(name, value, loc.clone())
}

/// The resolution, mental ray's default (768 × 576, with a note) when none is given.
pub fn resolution(cam: &MiCamera, warnings: &mut Vec<Diagnostic>) -> (u32, u32) {
    match &cam.resolution {
        Some((x, y, _)) => (*x, *y),
        None => {
            warnings.push(Diagnostic {
                loc: cam.loc.clone(),
                message: "camera without a resolution: 768 × 576".into(),
            });
            (768, 576)
        }
    }
}

/// The LuxRender camera statement for the mental ray camera (see the module docs).
pub fn camera_entity(cam: &MiCamera, warnings: &mut Vec<Diagnostic>) -> Entity {
    let (xres, yres) = resolution(cam, warnings);
    let aperture = cam.aperture.unwrap_or_else(|| {
        warnings.push(Diagnostic {
            loc: cam.loc.clone(),
            message: "camera without an aperture: 1 (mental ray's default)".into(),
        });
        1.0
    });
    let aspect = cam.aspect.unwrap_or(f64::from(xres) / f64::from(yres));
    let mut params = ParamSet::new();
    let loc = &cam.loc;
    let kind = match cam.focal {
        Some(focal) => {
            let hx = aperture / (2.0 * focal);
            let hy = hx / aspect;
            let half = hx.min(hy);
            let fov = (2.0 * half.atan()).to_degrees();
            params.push(param("fov", ParamValue::Float(vec![fov as f32]), loc));
            let window = [-hx / half, hx / half, -hy / half, hy / half];
            push_window(&mut params, window, xres, yres, loc);
            "perspective"
        }
        None => {
            let hx = aperture / 2.0;
            let hy = hx / aspect;
            push_window(&mut params, [-hx, hx, -hy, hy], 0, 0, loc);
            "orthographic"
        }
    };
    if let Some((near, far, at)) = &cam.clip {
        params.push(param("hither", ParamValue::Float(vec![*near as f32]), at));
        params.push(param("yon", ParamValue::Float(vec![*far as f32]), at));
    }
    for (what, at) in &cam.ignored {
        warnings.push(Diagnostic {
            loc: at.clone(),
            message: format!("camera statement \"{what}\" is not used by luxfarm"),
        });
    }
    Entity {
        kind: kind.into(),
        params,
        loc: loc.clone(),
    }
}

/// Adds `screenwindow` unless it is LuxRender's default for this resolution (when `xres`
/// is 0 the window is always written).
fn push_window(params: &mut ParamSet, w: [f64; 4], xres: u32, yres: u32, loc: &Loc) {
    if xres > 0 {
        let a = f64::from(xres) / f64::from(yres);
        let default = if a > 1.0 {
            [-a, a, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / a, 1.0 / a]
        };
        if w.iter()
            .zip(default)
            .all(|(x, d)| (x - d).abs() <= 1e-6 * d.abs())
        {
            return;
        }
    }
    let v = w.iter().map(|x| *x as f32).collect();
    params.push(param("screenwindow", ParamValue::Float(v), loc));
}

/// The Film: resolution, the file name and formats the camera's outputs ask for, and the
/// samples per pixel (`haltspp`) when the options give them.
pub fn film_entity(
    cam: &MiCamera,
    haltspp: Option<(i32, Loc)>,
    warnings: &mut Vec<Diagnostic>,
) -> Entity {
    let (xres, yres) = cam.resolution.as_ref().map_or((768, 576), |r| (r.0, r.1));
    let loc = cam.resolution.as_ref().map_or(&cam.loc, |r| &r.2);
    let mut params = ParamSet::new();
    params.push(param(
        "xresolution",
        ParamValue::Integer(vec![xres as i32]),
        loc,
    ));
    params.push(param(
        "yresolution",
        ParamValue::Integer(vec![yres as i32]),
        loc,
    ));
    if let Some((n, at)) = haltspp {
        params.push(param("haltspp", ParamValue::Integer(vec![n]), &at));
    }
    let primary_fb = cam
        .framebuffers
        .iter()
        .find(|f| f.primary && f.filename.is_some());
    let full_float = primary_fb
        .and_then(|f| f.datatype.as_deref())
        .is_some_and(|d| d.ends_with("_fp"));
    let primary = primary_fb.and_then(|f| Some((f.filename.clone()?, f.loc.clone())));
    let file = primary.or_else(|| cam.outputs.first().cloned());
    for fb in cam.framebuffers.iter().filter(|f| !f.primary) {
        warnings.push(Diagnostic {
            loc: fb.loc.clone(),
            message: format!(
                "framebuffer \"{}\" is not rendered: luxfarm writes the primary image only",
                fb.name
            ),
        });
    }
    for (f, at) in cam.outputs.iter().skip(usize::from(file.is_some())) {
        warnings.push(Diagnostic {
            loc: at.clone(),
            message: format!("output \"{f}\" is not written: luxfarm writes one image"),
        });
    }
    if let Some((file, at)) = file {
        let path = std::path::Path::new(&file);
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("luxout");
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        params.push(param(
            "filename",
            ParamValue::String(vec![stem.to_string()]),
            &at,
        ));
        let (exr, png, tga) = match ext.as_str() {
            "exr" => (true, false, false),
            "png" => (false, true, false),
            "tga" => (false, false, true),
            other => {
                warnings.push(Diagnostic {
                    loc: at.clone(),
                    message: format!(
                        "image format \"{other}\" is not written by luxfarm: PNG instead"
                    ),
                });
                (false, true, false)
            }
        };
        params.push(param("write_exr", ParamValue::Bool(vec![exr]), &at));
        if exr {
            params.push(param(
                "write_exr_applyimaging",
                ParamValue::Bool(vec![false]),
                &at,
            ));
            params.push(param(
                "write_exr_halftype",
                ParamValue::Bool(vec![!full_float]),
                &at,
            ));
        }
        params.push(param("write_png", ParamValue::Bool(vec![png]), &at));
        params.push(param("write_tga", ParamValue::Bool(vec![tga]), &at));
    }
    Entity {
        kind: "fleximage".into(),
        params,
        loc: cam.loc.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(text: &str) -> MiCamera {
        let mut c = Cursor::new(text, "t.mi".into());
        parse(&mut c, "cam".into(), Loc::default(), 100).unwrap()
    }

    #[test]
    fn the_sample_camera() {
        let cam = camera(
            "framebuffer \"primary\" datatype \"rgba_h\" filtering on primary on user off\n\
             filename \"mental_ray.exr\"\n framebuffer \"aov\" datatype \"rgb_h\" primary off\n\
             user on filename \"aov.exr\"\n focal 45.0\n aperture 32.0\n aspect 1.0\n\
             resolution 500 500\nend camera",
        );
        let mut w = Vec::new();
        let e = camera_entity(&cam, &mut w);
        assert_eq!(e.kind, "perspective");
        // 2·atan(16/45) = 39.1463°, the .lxs twin's fov.
        assert!((e.params.float("fov").unwrap() - 39.146_25).abs() < 1e-3);
        assert!(e.params.floats("screenwindow").is_none());
        let f = film_entity(&cam, Some((100, Loc::default())), &mut w);
        assert_eq!(f.params.string("filename"), Some("mental_ray"));
        assert_eq!(f.params.bool("write_exr"), Some(true));
        // Linear half floats, as the "rgba_h" framebuffer holds them.
        assert_eq!(f.params.bool("write_exr_applyimaging"), Some(false));
        assert_eq!(f.params.bool("write_exr_halftype"), Some(true));
        assert_eq!(f.params.int("haltspp"), Some(100));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].message.contains("\"aov\""));
    }

    #[test]
    fn aspect_and_orthographic_windows() {
        // A wide image: the fov spans the height, aperture/aspect.
        let cam = camera("focal 1 aperture 2 aspect 2 resolution 200 100 end camera");
        let e = camera_entity(&cam, &mut Vec::new());
        assert!((e.params.float("fov").unwrap() - 53.130_1).abs() < 1e-3);
        assert!(e.params.floats("screenwindow").is_none());
        let cam = camera("focal infinity aperture 4 aspect 2 resolution 20 10 end camera");
        let e = camera_entity(&cam, &mut Vec::new());
        assert_eq!(e.kind, "orthographic");
        assert_eq!(
            e.params.floats("screenwindow"),
            Some(&[-2.0, 2.0, -1.0, 1.0][..])
        );
        let cam = camera(
            "framebuffer \"primary\" datatype \"rgba_fp\" primary on filename \"f.exr\"\n\
             resolution 8 8 end camera",
        );
        let f = film_entity(&cam, None, &mut Vec::new());
        assert_eq!(f.params.bool("write_exr_halftype"), Some(false));
        let cam = camera("framebuffer \"primary\" primary on filename \"f.png\" end camera");
        let f = film_entity(&cam, None, &mut Vec::new());
        assert_eq!(f.params.bool("write_png"), Some(true));
        assert_eq!(f.params.bool("write_exr_applyimaging"), None);
        let mut c = Cursor::new("resolution 0 10 end camera", "t.mi".into());
        assert!(parse(&mut c, "c".into(), Loc::default(), 100).is_err());
    }
}

//! `FilmParams`: every parameter of LuxRender's fleximage film, with LuxRender 1.x defaults.
//!
//! Built from the scene's `Film` statement (`fleximage`, or the legacy `multiimage` of old
//! exporters). Unknown names of enumerated options (`tonemapkernel`, `ldr_clamp_method`,
//! channel sets, ...) are errors naming the parameter's file:line:column, where LuxRender
//! warned and fell back; a scene keeps its meaning or says why not. The imaging parameters
//! (tonemapping, false colours, colour space, effects) are read in `imaging_params.rs`.

use super::buffer::check_size;
pub use super::image_output::{Channels, ExrCompression, ExrOptions, ImageOutput, ZBufNorm};
use super::imaging::TonemapParams;
use super::imaging_params::{bad, choice, effects, loc_of, tonemap_params};
use super::FilmError;
use crate::lxs::{Entity, Loc, ParamSet};

/// Every fleximage parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmParams {
    pub xres: u32,
    pub yres: u32,
    /// `cropwindow` as given (x0, x1, y0, y1 in [0, 1]).
    pub crop: [f32; 4],
    /// Buffer pixel bounds from the crop window: start and count per axis.
    pub x_pixel_start: u32,
    pub y_pixel_start: u32,
    pub x_pixel_count: u32,
    pub y_pixel_count: u32,
    pub filename: String,
    pub premultiply_alpha: bool,
    pub write_interval: u32,
    pub flm_write_interval: u32,
    pub display_interval: u32,
    pub haltspp: Option<u32>,
    pub halttime: Option<u32>,
    pub haltthreshold: Option<f32>,
    /// Spp between convergence tests (at least 4, default 32).
    pub convergence_step: f64,
    /// k of the k-nearest outlier rejection; 0 disables it.
    pub outlier_rejection_k: u32,
    pub debug: bool,
    pub filter_quality: u32,
    pub tile_count: i32,
    pub png: ImageOutput,
    pub png_16bit: bool,
    pub tga: ImageOutput,
    pub exr: ImageOutput,
    pub exr_options: ExrOptions,
    pub write_resume_flm: bool,
    pub restart_resume_flm: bool,
    pub write_flm_direct: bool,
    pub usersamplingmap_filename: String,
    pub disable_noisemap_update: bool,
    /// Tonemapping and the image effects (bloom, glare, vignetting, aberration, camera
    /// response), applied by `tonemap` and written to FLM headers.
    pub tonemap: TonemapParams,
    /// FLM parameters luxfarm does not model, carried from a read FLM to the FLMs written
    /// from it (noise filter settings, layer flags).
    pub flm_extra: Vec<crate::film::FlmParam>,
}

impl Default for FilmParams {
    fn default() -> Self {
        // An empty Film statement: LuxRender's defaults.
        let e = Entity {
            kind: "fleximage".into(),
            ..Entity::default()
        };
        FilmParams::build(&e).unwrap_or_else(|_| unreachable_defaults())
    }
}

/// Never reached: defaults always parse. Kept total so `Default` cannot panic.
fn unreachable_defaults() -> FilmParams {
    FilmParams::with_resolution(800, 600)
}

fn positive_int(ps: &ParamSet, loc: &Loc, name: &str, default: i32) -> Result<u32, FilmError> {
    let v = ps.int_or(name, default);
    u32::try_from(v).ok().filter(|&v| v > 0).ok_or_else(|| {
        bad(
            &loc_of(ps, name, loc),
            name,
            format!("{v} is not a positive integer"),
        )
    })
}

fn image_output(
    ps: &ParamSet,
    loc: &Loc,
    prefix: &str,
    enabled_default: bool,
    norm_default: &str,
    premultiply: bool,
) -> Result<ImageOutput, FilmError> {
    let name = |s: &str| format!("write_{prefix}{s}");
    let mut channels = choice(ps, loc, &name("_channels"), "RGB", Channels::from_name)?;
    if premultiply {
        channels = channels.with_alpha();
    }
    Ok(ImageOutput {
        enabled: ps.bool_or(&name(""), enabled_default),
        channels,
        gamutclamp: ps.bool_or(&name("_gamutclamp"), true),
        zbuf: ps.bool_or(&name("_ZBuf"), false),
        zbuf_norm: choice(
            ps,
            loc,
            &name("_zbuf_normalizationtype"),
            norm_default,
            ZBufNorm::from_name,
        )?,
    })
}

impl FilmParams {
    /// Parses the scene's Film statement (`None`: no statement, all defaults).
    pub fn from_entity(e: Option<&Entity>) -> Result<FilmParams, FilmError> {
        match e {
            Some(e) => FilmParams::build(e),
            None => Ok(FilmParams::default()),
        }
    }

    /// Defaults at a given resolution (tests and tools).
    pub fn with_resolution(xres: u32, yres: u32) -> FilmParams {
        let mut ps = ParamSet::new();
        ps.add(
            "xresolution",
            crate::lxs::ParamValue::Integer(vec![xres as i32]),
        );
        ps.add(
            "yresolution",
            crate::lxs::ParamValue::Integer(vec![yres as i32]),
        );
        let e = Entity {
            kind: "fleximage".into(),
            params: ps,
            loc: Loc::default(),
        };
        match FilmParams::build(&e) {
            Ok(p) => p,
            Err(_) => FilmParams::minimal(xres.max(1), yres.max(1)),
        }
    }

    fn minimal(xres: u32, yres: u32) -> FilmParams {
        FilmParams {
            xres,
            yres,
            crop: [0.0, 1.0, 0.0, 1.0],
            x_pixel_start: 0,
            y_pixel_start: 0,
            x_pixel_count: xres,
            y_pixel_count: yres,
            filename: "luxout".into(),
            premultiply_alpha: false,
            write_interval: 60,
            flm_write_interval: 60,
            display_interval: 12,
            haltspp: None,
            halttime: None,
            haltthreshold: None,
            convergence_step: 32.0,
            outlier_rejection_k: 0,
            debug: false,
            filter_quality: 16,
            tile_count: 0,
            png: ImageOutput {
                enabled: true,
                channels: Channels::Rgb,
                gamutclamp: true,
                zbuf: false,
                zbuf_norm: ZBufNorm::MinMax,
            },
            png_16bit: false,
            tga: ImageOutput {
                enabled: false,
                channels: Channels::Rgb,
                gamutclamp: true,
                zbuf: false,
                zbuf_norm: ZBufNorm::MinMax,
            },
            exr: ImageOutput {
                enabled: false,
                channels: Channels::Rgb,
                gamutclamp: true,
                zbuf: false,
                zbuf_norm: ZBufNorm::None,
            },
            exr_options: ExrOptions {
                halftype: true,
                compression: ExrCompression::Piz,
                applyimaging: true,
                straightcolors: false,
            },
            write_resume_flm: false,
            restart_resume_flm: false,
            write_flm_direct: false,
            usersamplingmap_filename: String::new(),
            disable_noisemap_update: false,
            tonemap: TonemapParams::default(),
            flm_extra: Vec::new(),
        }
    }

    fn build(e: &Entity) -> Result<FilmParams, FilmError> {
        if !matches!(e.kind.as_str(), "fleximage" | "multiimage") {
            return Err(bad(
                &e.loc,
                "Film",
                format!("unknown film type \"{}\"", e.kind),
            ));
        }
        let ps = &e.params;
        let loc = &e.loc;
        let xres = positive_int(ps, loc, "xresolution", 800)?;
        let yres = positive_int(ps, loc, "yresolution", 600)?;
        let mut p = FilmParams::minimal(xres, yres);
        p.set_crop(ps, loc)?;
        p.premultiply_alpha = ps.bool_or("premultiplyalpha", false);
        p.filename = ps.string_or("filename", "luxout").to_string();
        p.write_interval = ps.int_or("writeinterval", 60).max(0) as u32;
        p.flm_write_interval = ps
            .int_or("flmwriteinterval", p.write_interval as i32)
            .max(0) as u32;
        p.display_interval = ps.int_or("displayinterval", 12).max(0) as u32;
        p.set_halt(ps);
        p.outlier_rejection_k = ps.int_or("outlierrejection_k", 0).max(0) as u32;
        p.debug = ps.bool_or("debug", false);
        p.filter_quality = 1 << ps.int_or("filterquality", 4).clamp(1, 6);
        p.tile_count = ps.int_or("tilecount", 0);
        p.set_outputs(ps, loc)?;
        p.usersamplingmap_filename = ps.string_or("usersamplingmap_filename", "").to_string();
        p.disable_noisemap_update = ps.bool_or("disable_noisemap_update", false);
        p.tonemap = tonemap_params(ps, loc, &e.kind)?;
        p.tonemap.effects = effects(ps);
        // Accepted and ignored as LuxRender 1.x does (0.x warm-up of the old rejection).
        ps.int("reject_warmup");
        Ok(p)
    }

    fn set_crop(&mut self, ps: &ParamSet, loc: &Loc) -> Result<(), FilmError> {
        if let Some(&[a, b, c, d]) = ps.floats("cropwindow") {
            if ![a, b, c, d].iter().all(|v| v.is_finite()) {
                return Err(bad(
                    &loc_of(ps, "cropwindow", loc),
                    "cropwindow",
                    "not finite",
                ));
            }
            self.crop = [
                a.min(b).clamp(0.0, 1.0),
                a.max(b).clamp(0.0, 1.0),
                c.min(d).clamp(0.0, 1.0),
                c.max(d).clamp(0.0, 1.0),
            ];
        }
        let (xs, xc) = pixel_bounds(self.xres, self.crop[0], self.crop[1]);
        let (ys, yc) = pixel_bounds(self.yres, self.crop[2], self.crop[3]);
        (self.x_pixel_start, self.x_pixel_count) = (xs, xc);
        (self.y_pixel_start, self.y_pixel_count) = (ys, yc);
        check_size(xc, yc).map_err(|e| bad(loc, "xresolution/yresolution", e))
    }

    fn set_halt(&mut self, ps: &ParamSet) {
        self.haltspp = u32::try_from(ps.int_or("haltspp", -1))
            .ok()
            .filter(|&v| v > 0);
        self.halttime = u32::try_from(ps.int_or("halttime", -1))
            .ok()
            .filter(|&v| v > 0);
        self.haltthreshold = Some(ps.float_or("haltthreshold", -1.0)).filter(|&v| v >= 0.0);
        self.convergence_step = f64::from(ps.float_or("convergencestep", 32.0)).max(4.0);
    }

    fn set_outputs(&mut self, ps: &ParamSet, loc: &Loc) -> Result<(), FilmError> {
        let pm = self.premultiply_alpha;
        self.exr = image_output(ps, loc, "exr", false, "None", pm)?;
        self.exr_options = ExrOptions {
            halftype: ps.bool_or("write_exr_halftype", true),
            compression: choice(
                ps,
                loc,
                "write_exr_compressiontype",
                "PIZ (lossless)",
                ExrCompression::from_name,
            )?,
            applyimaging: ps.bool_or("write_exr_applyimaging", true),
            straightcolors: ps.bool_or("write_exr_straightcolors", false),
        };
        self.png = image_output(ps, loc, "png", true, "Min/Max", pm)?;
        self.png_16bit = ps.bool_or("write_png_16bit", false);
        self.tga = image_output(ps, loc, "tga", false, "Min/Max", pm)?;
        if self.tga.channels == Channels::Ya {
            return Err(bad(
                loc,
                "write_tga_channels",
                "TGA has no YA output (Y, RGB, RGBA)",
            ));
        }
        self.write_resume_flm = ps.bool_or("write_resume_flm", false);
        self.restart_resume_flm = ps.bool_or("restart_resume_flm", false);
        self.write_flm_direct = ps.bool_or("write_flm_direct", false);
        Ok(())
    }

    /// Number of buffer pixels (crop window).
    pub fn pixel_count(&self) -> u64 {
        u64::from(self.x_pixel_count) * u64::from(self.y_pixel_count)
    }

    /// Whether an output with a Z channel is asked for: only EXR has one (LuxRender 1.x's
    /// PNG and TGA writers ignore their `_ZBuf` flags, and so does luxfarm, with a warning).
    pub fn wants_zbuf(&self) -> bool {
        self.exr.enabled && self.exr.zbuf
    }
}

/// First pixel and pixel count of a crop window along one axis, as LuxRender computes them.
pub fn pixel_bounds(res: u32, c0: f32, c1: f32) -> (u32, u32) {
    let start = (res as f32 * c0).ceil() as u32;
    let end = (res as f32 * c1).ceil() as u32;
    (start, end.saturating_sub(start).max(1))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::film::imaging::{ClampMethod, ColorSpaceParams, Kernel};
    use crate::lxs::ParamValue;

    /// A `fleximage` film statement with `params` (shared with the imaging tests).
    pub(crate) fn film(params: &[(&str, ParamValue)]) -> Result<FilmParams, FilmError> {
        let mut ps = ParamSet::new();
        for (n, v) in params {
            ps.add(n, v.clone());
        }
        FilmParams::from_entity(Some(&Entity {
            kind: "fleximage".into(),
            params: ps,
            loc: Loc::default(),
        }))
    }

    #[test]
    fn defaults_are_luxrenders() {
        let p = FilmParams::from_entity(None).unwrap();
        assert_eq!((p.xres, p.yres), (800, 600));
        assert_eq!(p.tonemap.kernel, Kernel::AutoLinear);
        assert_eq!(p.tonemap.clamp_method, ClampMethod::Cut);
        assert_eq!(p.tonemap.gamma, 2.2);
        assert_eq!(p.tonemap.reinhard_burn, 6.0);
        assert_eq!(p.filename, "luxout");
        assert!(p.png.enabled && !p.exr.enabled && !p.tga.enabled);
        assert!(p.exr_options.halftype && p.exr_options.applyimaging);
        assert_eq!(p.haltspp, None);
        assert_eq!(p.convergence_step, 32.0);
        assert_eq!(p.tonemap.colorspace, ColorSpaceParams::default());
    }

    #[test]
    fn crop_window_gives_pixel_bounds() {
        let p = film(&[
            ("xresolution", ParamValue::Integer(vec![100])),
            ("yresolution", ParamValue::Integer(vec![50])),
            ("cropwindow", ParamValue::Float(vec![0.5, 0.25, 0.75, 0.25])),
        ])
        .unwrap();
        assert_eq!((p.x_pixel_start, p.x_pixel_count), (25, 25));
        assert_eq!((p.y_pixel_start, p.y_pixel_count), (13, 25));
    }

    #[test]
    fn halt_conditions_and_names() {
        let p = film(&[
            ("haltspp", ParamValue::Integer(vec![127])),
            ("haltthreshold", ParamValue::Float(vec![0.01])),
            ("convergencestep", ParamValue::Float(vec![1.0])),
            ("tonemapkernel", ParamValue::String(vec!["reinhard".into()])),
            ("ldr_clamp_method", ParamValue::String(vec!["lum".into()])),
            ("premultiplyalpha", ParamValue::Bool(vec![true])),
        ])
        .unwrap();
        assert_eq!(p.haltspp, Some(127));
        assert_eq!(p.halttime, None);
        assert_eq!(p.haltthreshold, Some(0.01));
        assert_eq!(p.convergence_step, 4.0);
        assert_eq!(p.tonemap.kernel, Kernel::Reinhard);
        assert_eq!(p.tonemap.clamp_method, ClampMethod::Lum);
        assert_eq!(p.png.channels, Channels::Rgba);
    }

    #[test]
    fn bad_values_are_errors() {
        assert!(film(&[("tonemapkernel", ParamValue::String(vec!["x".into()]))]).is_err());
        assert!(film(&[("xresolution", ParamValue::Integer(vec![0]))]).is_err());
        assert!(film(&[("xresolution", ParamValue::Integer(vec![70000]))]).is_err());
        assert!(film(&[("write_png_channels", ParamValue::String(vec!["BGR".into()]))]).is_err());
    }
}

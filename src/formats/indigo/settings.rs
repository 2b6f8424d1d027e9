//! `<renderer_settings>` and `<tonemapping>` turned into LuxRender's Film, PixelFilter,
//! Sampler and SurfaceIntegrator.
//!
//! ```text
//! width, height, halt_time, halt_samples_per_pixel, render_region --> Film
//! splat_filter (box/fastbox, gaussian σ 0.35 px, mn_cubic B C radius) --> PixelFilter
//! metropolis --> Sampler "metropolis" | "random";  bidirectional, max_depth --> SurfaceIntegrator
//! layer_setting names --> light group names (by layer index)
//! tonemapping linear | reinhard | camera --> Film tonemapkernel and its parameters
//! ```
//!
//! Indigo's image unit: a uniform spectral radiance v (W m⁻³ sr⁻¹) reaches the image as its
//! luminance `v ∫ȳ(λ) dλ` (λ in metres); the importer hands v to LuxRender as the RGB
//! `(v, v, v)`, whose film luminance is LuxRender's `Y(L)`. The linear tonemap's `scale` is
//! applied to Indigo's value, so LuxRender's linear kernel gets the factor
//! `scale ∫ȳ dλ / Y(white)`; the camera tonemap is LuxRender's linear (camera) kernel with
//! the film ISO (times 2^ev_adjust), the exposure duration and the f-number of the camera,
//! scaled by the same unit ratio times 683 lm/W (its input is photometric).

use super::ctx::Ctx;
use super::node::Elem;
use crate::lxs::{Entity, Loc, LxsError, Param, ParamSet, ParamValue};

/// Settings with no bearing on the image luxfarm renders (GUI, threads, file output,
/// Indigo's acceleration structures and sampler internals).
const NO_IMAGE_EFFECT: &[&str] = &[
    "uid",
    "name",
    "logging",
    "verbose",
    "save_untonemapped_exr",
    "save_tonemapped_exr",
    "save_igi",
    "save_png",
    "image_save_period",
    "auto_choose_num_threads",
    "num_threads",
    "frame_upload_period",
    "display_period",
    "cache_trees",
    "watermark",
    "info_overlay",
    "bih_tri_threshold",
    "large_mutation_prob",
    "max_change",
    "max_num_consec_rejections",
    "ray_origin_nudge_distance",
    "write_aperture_preview",
    "wait_for_slave_frames_on_stop",
    "close_gui_on_halt",
    "save_images_on_close",
    "glass_acceleration",
    "merging",
    "dithering",
    "batched",
    "gpu",
    "gpu_path_tracing",
    "hybrid",
    "super_sample_factor",
    "downsize_filter",
    "version_three_point_four_compat_env_sphere",
];

/// Boolean settings luxfarm cannot honour when true (false is what it renders).
const OFF_ONLY: &[&str] = &[
    "aperture_diffraction",
    "post_process_diffraction",
    "render_foreground_alpha",
    "material_id_tracer",
    "depth_pass",
    "shadow_pass",
    "vignetting",
];

/// The option statements and what the world needs from the settings.
#[derive(Debug)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub film: ParamSet,
    pub filter: Option<Entity>,
    pub sampler: Entity,
    pub integrator: Entity,
    /// Light layer names by index.
    pub layers: Vec<String>,
    pub loc: Loc,
}

fn p(name: &str, v: ParamValue, loc: &Loc) -> Param {
    Param::new(name, v, loc.clone())
}

fn int(v: i64) -> ParamValue {
    ParamValue::Integer(vec![v.clamp(i32::MIN as i64, i32::MAX as i64) as i32])
}

fn flt(v: f64) -> ParamValue {
    ParamValue::Float(vec![v as f32])
}

fn dim(e: &Elem, ctx: &Ctx, name: &str, default: i64) -> Result<u32, LxsError> {
    match e.child(ctx, name) {
        Some(c) => {
            let v = c.int(ctx)?;
            u32::try_from(v)
                .ok()
                .filter(|&v| v > 0 && v <= 1 << 16)
                .ok_or_else(|| {
                    super::ctx::err(
                        crate::lxs::LxsErrorKind::InvalidValue,
                        &c.loc,
                        format!("<{name}> must be 1 to 65536, got {v}"),
                    )
                })
        }
        None => Ok(default as u32),
    }
}

/// Reads `<renderer_settings>` (None: Indigo's defaults). `stem` names the output files.
pub fn read(e: Option<&Elem>, stem: &str, ctx: &Ctx, root_loc: &Loc) -> Result<Settings, LxsError> {
    let loc = e.map(|e| e.loc.clone()).unwrap_or_else(|| root_loc.clone());
    let mut film = ParamSet::new();
    film.push(p(
        "filename",
        ParamValue::String(vec![stem.to_string()]),
        &loc,
    ));
    let mut s = Settings {
        width: 600,
        height: 450,
        film: ParamSet::new(),
        filter: None,
        sampler: Entity {
            kind: "metropolis".into(),
            params: ParamSet::new(),
            loc: loc.clone(),
        },
        integrator: Entity {
            kind: "bidirectional".into(),
            params: ParamSet::new(),
            loc: loc.clone(),
        },
        layers: Vec::new(),
        loc: loc.clone(),
    };
    let Some(e) = e else {
        film.push(p("xresolution", int(600), &loc));
        film.push(p("yresolution", int(450), &loc));
        s.film = film;
        return Ok(s);
    };
    e.mark_used();
    e.ignore(NO_IMAGE_EFFECT);
    for name in OFF_ONLY {
        if let Some(c) = e.child(ctx, name) {
            if c.bool(ctx)? {
                ctx.warn(
                    &c.loc,
                    format!("<{name}> is not supported by luxfarm: rendered without it"),
                );
            }
        }
    }
    s.width = dim(e, ctx, "width", 600)?;
    s.height = dim(e, ctx, "height", 450)?;
    film.push(p("xresolution", int(s.width as i64), &loc));
    film.push(p("yresolution", int(s.height as i64), &loc));
    if let Some(c) = e.child(ctx, "halt_time") {
        let t = c.num(ctx)?;
        if t > 0.0 {
            film.push(p("halttime", int(t.ceil() as i64), &c.loc));
        }
    }
    if let Some(c) = e.child(ctx, "halt_samples_per_pixel") {
        let n = c.num(ctx)?;
        if n > 0.0 {
            film.push(p("haltspp", int(n.ceil() as i64), &c.loc));
        }
    }
    if let Some(r) = e.child(ctx, "render_region") {
        let v = |n: &str| -> Result<f64, LxsError> { r.need(ctx, n)?.num(ctx) };
        let (x1, y1, x2, y2) = (v("x1")?, v("y1")?, v("x2")?, v("y2")?);
        let (w, h) = (s.width as f64, s.height as f64);
        if !(0.0 <= x1 && x1 < x2 && x2 <= w && 0.0 <= y1 && y1 < y2 && y2 <= h) {
            return Err(super::ctx::err(
                crate::lxs::LxsErrorKind::InvalidValue,
                &r.loc,
                format!("render_region ({x1}, {y1})-({x2}, {y2}) is not inside the {w}x{h} image"),
            ));
        }
        let crop = vec![
            (x1 / w) as f32,
            (x2 / w) as f32,
            (y1 / h) as f32,
            (y2 / h) as f32,
        ];
        film.push(p("cropwindow", ParamValue::Float(crop), &r.loc));
    }
    if let Some(wp) = e.child(ctx, "white_point") {
        let xy = wp.nums(ctx)?;
        let e_point =
            xy.len() == 2 && (xy[0] - 1.0 / 3.0).abs() < 1e-3 && (xy[1] - 1.0 / 3.0).abs() < 1e-3;
        if !e_point {
            ctx.warn(
                &wp.loc,
                "white balance other than E is not applied by luxfarm",
            );
        }
    }
    s.filter = filter(e, ctx)?;
    if !e.child_bool_or(ctx, "metropolis", true)? {
        s.sampler.kind = "random".into();
    }
    let bidir = e.child_bool_or(ctx, "bidirectional", true)?;
    let depth = e
        .child_int(ctx, "max_depth")?
        .unwrap_or(10_000)
        .clamp(1, 100_000);
    if bidir {
        s.integrator.params.push(p("eyedepth", int(depth), &loc));
        s.integrator.params.push(p("lightdepth", int(depth), &loc));
    } else {
        s.integrator.kind = "path".into();
        s.integrator.params.push(p("maxdepth", int(depth), &loc));
    }
    s.layers = layers(e, ctx)?;
    s.film = film;
    Ok(s)
}

fn filter(e: &Elem, ctx: &Ctx) -> Result<Option<Entity>, LxsError> {
    let Some(f) = e.child(ctx, "splat_filter") else {
        return Ok(None);
    };
    let Some(k) = f.children.first() else {
        return Ok(None);
    };
    k.mark_used();
    let mut ps = ParamSet::new();
    let kind = match k.name.as_str() {
        "box" | "fastbox" => {
            ps.push(p("xwidth", flt(0.5), &k.loc));
            ps.push(p("ywidth", flt(0.5), &k.loc));
            "box"
        }
        "gaussian" => {
            // Indigo's gaussian has a standard deviation of 0.35 pixels: e^(-x²/2σ²),
            // cut at 3σ.
            let sigma: f64 = 0.35;
            ps.push(p("alpha", flt(1.0 / (2.0 * sigma * sigma)), &k.loc));
            ps.push(p("xwidth", flt(3.0 * sigma), &k.loc));
            ps.push(p("ywidth", flt(3.0 * sigma), &k.loc));
            "gaussian"
        }
        "mn_cubic" => {
            ps.push(p("B", flt(k.child_num_or(ctx, "blur", 0.6)?), &k.loc));
            ps.push(p("C", flt(k.child_num_or(ctx, "ring", 0.2)?), &k.loc));
            let r = k.child_num_or(ctx, "radius", 2.0)?;
            ps.push(p("xwidth", flt(r), &k.loc));
            ps.push(p("ywidth", flt(r), &k.loc));
            "mitchell"
        }
        other => {
            ctx.warn(
                &k.loc,
                format!("splat filter <{other}> is not known: LuxRender's default used"),
            );
            return Ok(None);
        }
    };
    Ok(Some(Entity {
        kind: kind.into(),
        params: ps,
        loc: k.loc.clone(),
    }))
}

/// Light layer names, by layer index (`layer_setting` elements in order).
fn layers(e: &Elem, ctx: &Ctx) -> Result<Vec<String>, LxsError> {
    let mut names = Vec::new();
    for (i, l) in e.all("layer_setting").enumerate() {
        let name = l
            .child_str(ctx, "name")
            .map(str::to_string)
            .filter(|n| !n.is_empty())
            .unwrap_or_else(|| format!("layer {i}"));
        if let Some(s) = l.child(ctx, "layer_scale") {
            let v = super::spectrum::of(s, ctx)?;
            if v.iter().any(|c| (c - 1.0).abs() > 1e-6) {
                ctx.warn(
                    &s.loc,
                    format!("layer \"{name}\" scale {v:?}: luxfarm renders light groups unscaled"),
                );
            }
        }
        l.ignore(&["enabled"]);
        names.push(name);
    }
    Ok(names)
}

/// The luminance of a uniform spectral radiance of 1 W m⁻³ sr⁻¹ as Indigo's image holds it
/// (∫ȳ dλ, λ in metres), over LuxRender's film luminance of the RGB (1, 1, 1).
pub fn unit_ratio() -> f64 {
    let ybar: f64 = (360..=830)
        .map(|nm| f64::from(crate::spectrum::cie::cmf(nm as f32)[1]))
        .sum::<f64>()
        * 1e-9;
    ybar / f64::from(crate::spectrum::illuminant_y(crate::spectrum::Rgb::WHITE))
}

/// LuxRender's linear kernel factor for sensitivity 1, exposure 1, f-stop 1 at `gamma`.
fn lux_linear_unit(gamma: f64) -> f64 {
    0.65 / 10.0 * (118.0f64 / 255.0).powf(gamma)
}

/// What the camera tells the camera tonemap.
#[derive(Clone, Copy, Debug)]
pub struct Exposure {
    pub duration: f64,
    pub fstop: f64,
}

/// Adds the Film tonemapping parameters of `<tonemapping>` to `film`.
pub fn tonemap(
    e: Option<&Elem>,
    exposure: Exposure,
    film: &mut ParamSet,
    ctx: &Ctx,
) -> Result<(), LxsError> {
    let Some(e) = e else { return Ok(()) };
    e.mark_used();
    e.ignore(&["uid", "name"]);
    let Some(k) = e.first_child_except(&["uid", "name"]) else {
        return Ok(());
    };
    k.mark_used();
    let loc = k.loc.clone();
    let gamma = 2.2;
    let kernel = |film: &mut ParamSet, name: &str| {
        film.push(p(
            "tonemapkernel",
            ParamValue::String(vec![name.into()]),
            &loc,
        ));
    };
    match k.name.as_str() {
        "linear" => {
            let scale = k.child_num_or(ctx, "scale", 1.0)?;
            let factor = scale * unit_ratio();
            kernel(film, "linear");
            film.push(p(
                "linear_sensitivity",
                flt(factor / lux_linear_unit(gamma)),
                &loc,
            ));
            film.push(p("linear_exposure", flt(1.0), &loc));
            film.push(p("linear_fstop", flt(1.0), &loc));
            film.push(p("linear_gamma", flt(gamma), &loc));
        }
        "reinhard" => {
            kernel(film, "reinhard");
            film.push(p(
                "reinhard_prescale",
                flt(k.child_num_or(ctx, "pre_scale", 1.0)?),
                &loc,
            ));
            film.push(p(
                "reinhard_postscale",
                flt(k.child_num_or(ctx, "post_scale", 1.0)?),
                &loc,
            ));
            film.push(p(
                "reinhard_burn",
                flt(k.child_num_or(ctx, "burn", 10.0)?),
                &loc,
            ));
        }
        "camera" => {
            let iso = k.child_num_or(ctx, "film_iso", 100.0)?;
            let ev = k.child_num_or(ctx, "ev_adjust", 0.0)?;
            kernel(film, "linear");
            let sens = iso * 2f64.powf(ev) * unit_ratio() * 683.0;
            film.push(p("linear_sensitivity", flt(sens), &loc));
            film.push(p("linear_exposure", flt(exposure.duration), &loc));
            film.push(p("linear_fstop", flt(exposure.fstop), &loc));
            film.push(p("linear_gamma", flt(gamma), &loc));
            if let Some(r) = k.child(ctx, "response_function_path") {
                let path = super::ctx::normalise_path(r.str());
                film.push(p("cameraresponse", ParamValue::String(vec![path]), &r.loc));
            }
        }
        other => {
            ctx.warn(
                &k.loc,
                format!("tonemapping <{other}> is not supported: LuxRender's default used"),
            );
            k.mark_all_used();
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::indigo::xml;
    use crate::lxs::ParseOptions;
    use std::path::Path;

    #[test]
    fn settings_map_to_options() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let doc = "<renderer_settings><width>200</width><height>100</height><metropolis>false</metropolis>\
                   <bidirectional>false</bidirectional><max_depth>7</max_depth><halt_samples_per_pixel>16.5</halt_samples_per_pixel>\
                   <render_region><x1>50</x1><y1>0</y1><x2>150</x2><y2>50</y2></render_region>\
                   <splat_filter><mn_cubic><blur>0.5</blur><ring>0.25</ring></mn_cubic></splat_filter>\
                   <aperture_diffraction>true</aperture_diffraction><num_threads>4</num_threads>\
                   <layer_setting><name>sky</name></layer_setting><layer_setting><name>lamps</name></layer_setting></renderer_settings>";
        let p = xml::parse(doc.as_bytes(), &"t.igs".into()).unwrap();
        let s = read(Some(&p.root), "t", &ctx, &Loc::default()).unwrap();
        assert_eq!((s.width, s.height), (200, 100));
        assert_eq!(s.film.int("haltspp"), Some(17));
        assert_eq!(
            s.film.floats("cropwindow").unwrap(),
            &[0.25, 0.75, 0.0, 0.5]
        );
        assert_eq!(s.sampler.kind, "random");
        assert_eq!(s.integrator.kind, "path");
        assert_eq!(s.integrator.params.int("maxdepth"), Some(7));
        let f = s.filter.unwrap();
        assert_eq!(
            (f.kind.as_str(), f.params.float("B")),
            ("mitchell", Some(0.5))
        );
        assert_eq!(s.layers, vec!["sky".to_string(), "lamps".to_string()]);
        p.root.report_unused(&ctx);
        let w = ctx.take_warnings();
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].message.contains("aperture_diffraction"));
    }

    #[test]
    fn tonemaps() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let exp = Exposure {
            duration: 0.01,
            fstop: 8.0,
        };
        let mut film = ParamSet::new();
        let p = xml::parse(b"<tonemapping><reinhard><pre_scale>2</pre_scale><burn>6</burn></reinhard></tonemapping>", &"t.igs".into()).unwrap();
        tonemap(Some(&p.root), exp, &mut film, &ctx).unwrap();
        assert_eq!(film.string("tonemapkernel"), Some("reinhard"));
        assert_eq!(film.float("reinhard_prescale"), Some(2.0));
        assert_eq!(film.float("reinhard_burn"), Some(6.0));
        let mut film = ParamSet::new();
        let p = xml::parse(
            b"<tonemapping><linear><scale>3</scale></linear></tonemapping>",
            &"t.igs".into(),
        )
        .unwrap();
        tonemap(Some(&p.root), exp, &mut film, &ctx).unwrap();
        let s = film.float("linear_sensitivity").unwrap() as f64;
        // The kernel factor times the film luminance of (1,1,1) is 3 ∫ȳ dλ.
        let factor = s * lux_linear_unit(2.2);
        let y = f64::from(crate::spectrum::illuminant_y(crate::spectrum::Rgb::WHITE));
        assert!(
            (factor * y / (3.0 * 106.856e-9) - 1.0).abs() < 0.01,
            "{}",
            factor * y
        );
        let mut film = ParamSet::new();
        let p = xml::parse(b"<tonemapping><camera><film_iso>200</film_iso><ev_adjust>1</ev_adjust><response_function_path>data\\crf.txt</response_function_path></camera></tonemapping>", &"t.igs".into()).unwrap();
        tonemap(Some(&p.root), exp, &mut film, &ctx).unwrap();
        assert_eq!(film.float("linear_fstop"), Some(8.0));
        assert_eq!(film.string("cameraresponse"), Some("data/crf.txt"));
    }
}

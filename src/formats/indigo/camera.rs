//! `<camera>` turned into LuxRender's camera: a LookAt per keyframe and the `Camera`
//! statement.
//!
//! ```text
//! pos (or keyframe pos + rotation_quaternion), forwards, up --> LookAt eye, eye + forwards, up
//! sensor_width, lens_sensor_dist, width/height --> fov on the shorter image axis
//! aperture_radius, focus_distance, autofocus, aperture_shape/generated/num_blades
//!     --> lensradius, focaldistance, autofocus, blades
//! lens_shift_right/up_distance --> screenwindow shifted by distance / half the shorter sensor side
//! camera_type thin-lens-perspective | orthographic | spherical --> perspective | orthographic | environment
//! ```
//!
//! The sensor is `sensor_width` wide and `sensor_width / aspect` high, `lens_sensor_dist`
//! behind the lens, so the angle across an axis of sensor size s is `2 atan(s / 2d)`.
//! Orthographic cameras take `sensor_width` as the width of the view in world units.

use super::ctx::{err, Ctx};
use super::node::Elem;
use super::settings::Exposure;
use crate::lxs::{Entity, Loc, LxsError, LxsErrorKind, Param, ParamSet, ParamValue};
use glam::{DQuat, DVec3};

/// One camera pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub time: f32,
    pub eye: [f64; 3],
    pub target: [f64; 3],
    pub up: [f64; 3],
}

/// The converted camera.
#[derive(Clone, Debug)]
pub struct CameraOut {
    pub poses: Vec<Pose>,
    pub entity: Entity,
    pub exposure: Exposure,
}

/// A rotation given as `<rotation_quaternion><axis/><angle/></...>` (angle in radians).
pub fn axis_angle(e: &Elem, ctx: &Ctx) -> Result<DQuat, LxsError> {
    let axis = DVec3::from(e.need(ctx, "axis")?.vec3(ctx)?);
    let angle = e.need(ctx, "angle")?.num(ctx)?;
    if angle == 0.0 {
        return Ok(DQuat::IDENTITY);
    }
    let len = axis.length();
    if !(len > 0.0 && len.is_finite()) {
        return Err(err(
            LxsErrorKind::InvalidValue,
            &e.loc,
            "rotation axis must be a non-zero vector",
        ));
    }
    Ok(DQuat::from_axis_angle(axis / len, angle))
}

/// The keyframes of an element: (time, pos, rotation). None when it has no keyframe.
pub fn keyframes(e: &Elem, ctx: &Ctx) -> Result<Vec<(f32, DVec3, DQuat)>, LxsError> {
    let mut out = Vec::new();
    for k in e.all("keyframe") {
        let t = k.child_num_or(ctx, "time", 0.0)?;
        let pos = DVec3::from(k.need(ctx, "pos")?.vec3(ctx)?);
        let rot = match k.child(ctx, "rotation_quaternion") {
            Some(q) => axis_angle(q, ctx)?,
            None => DQuat::IDENTITY,
        };
        out.push((t as f32, pos, rot));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(out)
}

fn p(name: &str, v: ParamValue, loc: &Loc) -> Param {
    Param::new(name, v, loc.clone())
}

fn flt(v: f64) -> ParamValue {
    ParamValue::Float(vec![v as f32])
}

fn positive(e: &Elem, ctx: &Ctx, name: &str, default: f64) -> Result<f64, LxsError> {
    match e.child(ctx, name) {
        Some(c) => c.positive(ctx),
        None => Ok(default),
    }
}

/// Reads `<camera>` for an image of `width` × `height` pixels.
pub fn read(e: &Elem, width: u32, height: u32, ctx: &Ctx) -> Result<CameraOut, LxsError> {
    e.mark_used();
    e.ignore(&["uid", "name"]);
    let loc = e.loc.clone();
    let forwards = DVec3::from(e.need(ctx, "forwards")?.vec3(ctx)?);
    let up = DVec3::from(e.need(ctx, "up")?.vec3(ctx)?);
    let mut frames = keyframes(e, ctx)?;
    if let Some(pos) = e.child_vec3(ctx, "pos")? {
        if frames.is_empty() {
            frames.push((0.0, DVec3::from(pos), DQuat::IDENTITY));
        } else {
            ctx.warn(
                &loc,
                "camera has both <pos> and keyframes: the keyframes are used",
            );
        }
    }
    if frames.is_empty() {
        return Err(err(
            LxsErrorKind::WrongValueCount,
            &loc,
            "camera needs <pos> or a <keyframe>",
        ));
    }
    let poses = frames
        .iter()
        .map(|(t, pos, rot)| {
            let f = *rot * forwards;
            let u = *rot * up;
            Pose {
                time: *t,
                eye: pos.to_array(),
                target: (*pos + f).to_array(),
                up: u.to_array(),
            }
        })
        .collect();

    let aspect = width as f64 / height as f64;
    if let Some(a) = e.child_num(ctx, "aspect_ratio")? {
        if (a - aspect).abs() > 0.01 * aspect {
            ctx.warn(
                &loc,
                format!(
                    "aspect_ratio {a} differs from width/height {aspect:.4}: width/height is used"
                ),
            );
        }
    }
    let sensor_w = positive(e, ctx, "sensor_width", 0.036)?;
    let lsd = positive(e, ctx, "lens_sensor_dist", 0.02)?;
    let aperture = e.child_num_or(ctx, "aperture_radius", 0.0)?.max(0.0);
    let focus = positive(e, ctx, "focus_distance", 1e30)?;
    let duration = positive(e, ctx, "exposure_duration", 1.0 / 30.0)?;
    let fstop = if aperture > 0.0 {
        lsd / (2.0 * aperture)
    } else {
        8.0
    };
    let short_side = if aspect >= 1.0 {
        sensor_w / aspect
    } else {
        sensor_w
    };

    let mut ps = ParamSet::new();
    let kind = match e.child_str(ctx, "camera_type").unwrap_or("thin-lens-perspective") {
        "thin-lens-perspective" | "perspective" => {
            let fov = 2.0 * (short_side / (2.0 * lsd)).atan();
            ps.push(p("fov", flt(fov.to_degrees()), &loc));
            "perspective"
        }
        "orthographic" => {
            let (hw, hh) = (sensor_w / 2.0, sensor_w / 2.0 / aspect);
            let sw = vec![-hw as f32, hw as f32, -hh as f32, hh as f32];
            ps.push(p("screenwindow", ParamValue::Float(sw), &loc));
            "orthographic"
        }
        "spherical" => "environment",
        other => {
            return Err(err(
                LxsErrorKind::Unsupported,
                &loc,
                format!("camera_type \"{other}\" is not supported (thin-lens-perspective, orthographic, spherical)"),
            ))
        }
    };
    if kind != "environment" {
        ps.push(p("lensradius", flt(aperture), &loc));
        if focus < 1e30 {
            ps.push(p("focaldistance", flt(focus), &loc));
        }
        if e.has(ctx, "autofocus") {
            ps.push(p("autofocus", ParamValue::Bool(vec![true]), &loc));
        }
        aperture_shape(e, ctx, &mut ps)?;
        lens_shift(e, ctx, kind, aspect, short_side, &mut ps)?;
    }
    if let Some(wb) = e.child_str(ctx, "white_balance") {
        if !wb.eq_ignore_ascii_case("e") {
            ctx.warn(
                &loc,
                format!("white balance {wb} is not applied by luxfarm"),
            );
        }
    }
    if let Some(o) = e.child(ctx, "obstacle_map") {
        o.mark_all_used();
        ctx.warn(
            &o.loc,
            "obstacle maps act on aperture diffraction, which luxfarm does not render: ignored",
        );
    }
    Ok(CameraOut {
        poses,
        entity: Entity {
            kind: kind.into(),
            params: ps,
            loc,
        },
        exposure: Exposure { duration, fstop },
    })
}

fn aperture_shape(e: &Elem, ctx: &Ctx, ps: &mut ParamSet) -> Result<(), LxsError> {
    let Some(a) = e.child(ctx, "aperture_shape") else {
        return Ok(());
    };
    a.ignore(&["circular"]);
    if let Some(g) = a.child(ctx, "generated") {
        let blades = g.need(ctx, "num_blades")?.int(ctx)?;
        if blades < 3 {
            return Err(err(
                LxsErrorKind::InvalidValue,
                &g.loc,
                format!("num_blades must be >= 3, got {blades}"),
            ));
        }
        ps.push(p(
            "blades",
            ParamValue::Integer(vec![blades.min(64) as i32]),
            &g.loc,
        ));
        g.ignore(&["start_angle", "blade_offset", "blade_curvature_radius"]);
        ctx.warn(&g.loc, "aperture blade angle, offset and curvature have no LuxRender equivalent: straight blades used");
    }
    if let Some(i) = a.child(ctx, "image") {
        i.mark_all_used();
        ctx.warn(
            &i.loc,
            "image aperture shapes are not supported: circular aperture used",
        );
    }
    Ok(())
}

fn lens_shift(
    e: &Elem,
    ctx: &Ctx,
    kind: &str,
    aspect: f64,
    short_side: f64,
    ps: &mut ParamSet,
) -> Result<(), LxsError> {
    let right = e.child_num_or(ctx, "lens_shift_right_distance", 0.0)?;
    let up = e.child_num_or(ctx, "lens_shift_up_distance", 0.0)?;
    if right == 0.0 && up == 0.0 {
        return Ok(());
    }
    if kind != "perspective" {
        ctx.warn(
            &e.loc,
            "lens shift applies to perspective cameras only: ignored",
        );
        return Ok(());
    }
    let (sx, sy) = (right / (short_side / 2.0), up / (short_side / 2.0));
    let (w, h) = if aspect >= 1.0 {
        (aspect, 1.0)
    } else {
        (1.0, 1.0 / aspect)
    };
    let sw = vec![
        (-w + sx) as f32,
        (w + sx) as f32,
        (-h + sy) as f32,
        (h + sy) as f32,
    ];
    ps.push(p("screenwindow", ParamValue::Float(sw), &e.loc));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::indigo::xml;
    use crate::lxs::ParseOptions;
    use std::path::Path;

    fn cam(doc: &str, w: u32, h: u32) -> Result<CameraOut, LxsError> {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let p = xml::parse(doc.as_bytes(), &"t.igs".into()).unwrap();
        read(&p.root, w, h, &ctx)
    }

    #[test]
    fn fov_spans_the_shorter_axis() {
        let doc = "<camera><pos>0 -2 1</pos><up>0 0 1</up><forwards>0 1 0</forwards><sensor_width>0.036</sensor_width><lens_sensor_dist>0.02</lens_sensor_dist></camera>";
        let c = cam(doc, 800, 600).unwrap();
        let fov = c.entity.params.float("fov").unwrap() as f64;
        let expect = 2.0
            * (0.036 / (800.0 / 600.0) / 2.0 / 0.02f64)
                .atan()
                .to_degrees();
        assert!((fov - expect).abs() < 1e-4);
        let c = cam(doc, 600, 800).unwrap();
        let fov = c.entity.params.float("fov").unwrap() as f64;
        assert!((fov - 2.0 * (0.018 / 0.02f64).atan().to_degrees()).abs() < 1e-4);
        assert_eq!(c.poses[0].target, [0.0, -1.0, 1.0]);
    }

    #[test]
    fn keyframes_rotate_the_view_and_orthographic_uses_sensor_width() {
        let doc = "<camera><up>0 0 1</up><forwards>0 1 0</forwards><camera_type>orthographic</camera_type><sensor_width>4</sensor_width>\
                   <keyframe><time>1</time><pos>1 0 0</pos><rotation_quaternion><axis>0 0 1</axis><angle>1.5707963267948966</angle></rotation_quaternion></keyframe>\
                   <keyframe><time>0</time><pos>0 0 0</pos></keyframe></camera>";
        let c = cam(doc, 200, 100).unwrap();
        assert_eq!(c.entity.kind, "orthographic");
        assert_eq!(
            c.entity.params.floats("screenwindow").unwrap(),
            &[-2.0, 2.0, -1.0, 1.0]
        );
        assert_eq!(c.poses.len(), 2);
        assert_eq!(c.poses[0].time, 0.0);
        let t = c.poses[1].target;
        assert!(
            (t[0] - 0.0).abs() < 1e-9 && (t[1] - 0.0).abs() < 1e-9,
            "{t:?}"
        );
    }

    #[test]
    fn lens_blades_shift_and_errors() {
        let doc = "<camera><pos>0 0 0</pos><up>0 0 1</up><forwards>0 1 0</forwards><aperture_radius>0.01</aperture_radius><focus_distance>3</focus_distance>\
                   <lens_sensor_dist>0.05</lens_sensor_dist><sensor_width>0.036</sensor_width><lens_shift_up_distance>0.009</lens_shift_up_distance>\
                   <aperture_shape><generated><num_blades>6</num_blades><start_angle>0</start_angle></generated></aperture_shape></camera>";
        let c = cam(doc, 100, 100).unwrap();
        assert_eq!(c.entity.params.int("blades"), Some(6));
        assert_eq!(c.entity.params.float("lensradius"), Some(0.01));
        assert_eq!(
            c.entity.params.floats("screenwindow").unwrap(),
            &[-1.0, 1.0, -0.5, 1.5]
        );
        assert!((c.exposure.fstop - 2.5).abs() < 1e-12);
        assert!(cam(
            "<camera><up>0 0 1</up><forwards>0 1 0</forwards></camera>",
            10,
            10
        )
        .is_err());
        let e = cam("<camera><pos>0 0 0</pos><up>0 0 1</up><forwards>0 1 0</forwards><camera_type>fisheye</camera_type></camera>", 10, 10).unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::Unsupported);
    }
}

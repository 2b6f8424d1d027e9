//! `light "name" ... end light` — mental ray's `miLight` — and the luxfarm light it becomes.
//!
//! ```text
//! light block --parse--> MiLight { shader, origin, direction, spread, area primitive,
//!                                  samples, visible, exponent, energy, photons }
//! MiLight + its shader + light→world --light_entity--> LightSource (point, spot, distant,
//!                                                      rectangle, disc, sphere, cylinder)
//! MiLight (object primitive) + shader + emitter area --object_area_entity--> AreaLightSource
//! ```
//!
//! The type comes from what is given (the seed): `origin` alone is a point light,
//! `direction` alone a directional one, `origin` + `direction` + `spread` (the cosine of the
//! outer half-angle) a spot; an area primitive (`rectangle` edge_u edge_v, `disc` normal
//! radius, `sphere` radius, `cylinder` axis radius, `object "instance"`) centred on the
//! origin makes an area light, each followed by up to five sample counts: u v [low_level
//! [low_u low_v]] (defaults 3 3, low 2 2 from level 3; mental ray samples u × v points, so
//! luxfarm takes u·v shadow rays, `lownsamples` from `lowlevel`). `visible` (default off)
//! shows area lights to the camera.
//!
//! What the light shader means, from its source and manual (flux Φ, distance r):
//! - `physical_light` (`color` is energy): point and spot lights emit Φ/(4π) per steradian
//!   with the light's `exponent` falloff 1/r^k (k from [`crate::light::mental_ray_exponent`]);
//!   spots fall off linearly in the cosine from the shader's `cone` to the light's `spread`;
//!   a directional light gives irradiance Φ. Its area lights average their samples with
//!   weight cos_l/(π r^k) for rectangles and discs (with `cos_exp`), 1/(4π r^k) for spheres
//!   and cylinders (isotropic) and cos_l/(4π r^k) for objects: per unit area of the emitter
//!   that is radiance Φ/(πA), an isotropic Φ/(4πA) on both sides, and radiance Φ/(4πA).
//! - `mib_light_point`, `mib_light_spot` (base shaders): intensity `color` with no falloff
//!   (k = 0) — `atten` start/stop ramps are not modelled, with a note; `mib_light_spot`'s
//!   `spread` is the inner cone; area lights with them are isotropic emitters of color/A
//!   per unit area on both sides. `mib_light_infinite`: a directional light of `color`.
//! - other shaders: a warning, and `physical_light`'s meaning with the light's `energy` (or
//!   the shader's `color`, or white).
//!
//! Photon settings (`energy` beside a shader, `caustic`/`globillum photons`), shadow maps
//! and user area lights have no meaning in a path tracer: notes.
//!
//! The block is read in `light_block.rs`; this file turns what it read into lights.

pub use super::light_block::{parse, AreaPrim, MiLight, Samples};
use super::params::ShaderParams;
use crate::light::mental_ray_exponent;
use crate::lxs::{Diagnostic, Entity, Loc, Param, ParamSet, ParamValue};
use glam::{DMat4, DVec3};
use std::f64::consts::PI;

/// How the light shader makes light (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Model {
    /// physical_light: `color` is energy; inner spot cone cosine.
    Physical {
        color: [f64; 3],
        cone: Option<f64>,
        cos_exp: f64,
    },
    /// mib_light_point / mib_light_spot: `color` is intensity, no falloff.
    Base { color: [f64; 3], cone: Option<f64> },
}

fn model(
    l: &MiLight,
    shader: Option<(&str, &ShaderParams, &Loc)>,
    w: &mut Vec<Diagnostic>,
) -> Model {
    let energy = l.energy.as_ref().map(|e| e.0);
    let Some((kind, p, sloc)) = shader else {
        w.push(Diagnostic {
            loc: l.loc.clone(),
            message: format!(
                "light \"{}\" has no light shader: its energy (or white) lights as physical_light would",
                l.name
            ),
        });
        return Model::Physical {
            color: energy.unwrap_or([1.0; 3]),
            cone: None,
            cos_exp: 1.0,
        };
    };
    if p.is_connected("color") {
        w.push(Diagnostic {
            loc: sloc.clone(),
            message: format!(
                "\"color\" of {kind} is connected to another shader: its default is used"
            ),
        });
    }
    let colour = |default: [f64; 3]| {
        if p.is_connected("color") {
            default
        } else {
            p.color("color").unwrap_or(default)
        }
    };
    match kind {
        "physical_light" => Model::Physical {
            color: colour(energy.unwrap_or([1.0; 3])),
            cone: p.scalar("cone"),
            cos_exp: p.scalar("cos_exp").filter(|e| *e > 0.0).unwrap_or(1.0),
        },
        "mib_light_point" | "mib_light_spot" | "mib_light_infinite" => {
            if p.boolean("atten").unwrap_or(false) {
                w.push(Diagnostic {
                    loc: sloc.clone(),
                    message: format!(
                        "{kind}: the linear attenuation between \"start\" and \"stop\" is not modelled; the light does not fall off"
                    ),
                });
            }
            let cone = if kind == "mib_light_spot" {
                p.scalar("spread")
            } else {
                None
            };
            Model::Base {
                color: colour([1.0; 3]),
                cone,
            }
        }
        other => {
            w.push(Diagnostic {
                loc: sloc.clone(),
                message: format!(
                    "light shader \"{other}\" has no luxfarm equivalent: lit as physical_light with {}",
                    if energy.is_some() { "the light's energy" } else { "its color (or white)" }
                ),
            });
            Model::Physical {
                color: energy.or(p.color("color")).unwrap_or([1.0; 3]),
                cone: None,
                cos_exp: 1.0,
            }
        }
    }
}

fn param(name: &str, value: ParamValue, loc: &Loc) -> Param {
    Param::new(name, value, loc.clone())
}

fn color(c: [f64; 3], s: f64) -> ParamValue {
    ParamValue::Color(vec![c.map(|x| (x * s) as f32)])
}

fn point(p: [f64; 3]) -> ParamValue {
    ParamValue::Point(vec![p.map(|x| x as f32)])
}

fn vector(p: [f64; 3]) -> ParamValue {
    ParamValue::Vector(vec![p.map(|x| x as f32)])
}

fn float(x: f64) -> ParamValue {
    ParamValue::Float(vec![x as f32])
}

/// Notes for what the light says that a path tracer does not use.
fn notes(l: &MiLight, physical: bool, w: &mut Vec<Diagnostic>) {
    for (what, at) in &l.ignored {
        w.push(Diagnostic {
            loc: at.clone(),
            message: format!(
                "light \"{}\": \"{what}\" is not used by luxfarm's path tracer",
                l.name
            ),
        });
    }
    if let (Some((_, at)), false) = (&l.energy, physical) {
        w.push(Diagnostic {
            loc: at.clone(),
            message: format!(
                "light \"{}\": the photon energy is not used (its shader's colour sets the light)",
                l.name
            ),
        });
    }
}

/// The shadow-ray counts of an area light.
fn sample_params(l: &MiLight, ps: &mut ParamSet, loc: &Loc) {
    let s = &l.samples;
    let n = (s.u.max(1) * s.v.max(1)) as i32;
    let low = (s.low_u.max(1) * s.low_v.max(1)) as i32;
    ps.push(param("nsamples", ParamValue::Integer(vec![n]), loc));
    if s.level > 0 {
        ps.push(param("lownsamples", ParamValue::Integer(vec![low]), loc));
        ps.push(param(
            "lowlevel",
            ParamValue::Integer(vec![s.level as i32]),
            loc,
        ));
    }
}

/// What a mental ray light becomes.
#[derive(Clone, Debug, PartialEq)]
pub enum LightOut {
    /// A `LightSource` in the light's own space.
    Source(Entity),
    /// An area light on the geometry of this instance ([`object_area_entity`]).
    Object(String),
    /// Nothing luxfarm can render (a note was given).
    Nothing,
}

/// World-space area of the primitive of this light under `l2w`, as the core measures it.
fn world_area(prim: &AreaPrim, l2w: &DMat4) -> f64 {
    let across = |n: DVec3| {
        let (s, t) = n.normalize_or(DVec3::Z).any_orthonormal_pair();
        l2w.transform_vector3(s)
            .cross(l2w.transform_vector3(t))
            .length()
    };
    match prim {
        AreaPrim::Rectangle(u, v) => l2w
            .transform_vector3(DVec3::from(*u))
            .cross(l2w.transform_vector3(DVec3::from(*v)))
            .length(),
        AreaPrim::Disc(n, r) => PI * r * r * across(DVec3::from(*n)),
        AreaPrim::Sphere(r) => {
            let det = glam::DMat3::from_mat4(*l2w).determinant().abs();
            4.0 * PI * (r * det.cbrt()).powi(2)
        }
        AreaPrim::Cylinder(axis, r) => {
            let a = DVec3::from(*axis);
            2.0 * PI * r * across(a).sqrt() * l2w.transform_vector3(a).length()
        }
        AreaPrim::Object(_) | AreaPrim::User => 0.0,
    }
}

/// The luxfarm light for a mental ray light (not an object light) placed by `l2w`.
pub fn light_entity(
    l: &MiLight,
    shader: Option<(&str, &ShaderParams, &Loc)>,
    l2w: &DMat4,
    w: &mut Vec<Diagnostic>,
) -> LightOut {
    let loc = &l.loc;
    let m = model(l, shader, w);
    let physical = matches!(m, Model::Physical { .. });
    notes(l, physical, w);
    let (col, cone) = match m {
        Model::Physical { color, cone, .. } | Model::Base { color, cone } => (color, cone),
    };
    let k = match m {
        Model::Physical { .. } => mental_ray_exponent(l.exponent.unwrap_or(2.0) as f32) as f64,
        Model::Base { .. } => 0.0,
    };
    let origin = l.origin.unwrap_or([0.0; 3]);
    let mut ps = ParamSet::new();
    if let Some((prim, at)) = &l.area {
        let kind = match prim {
            AreaPrim::Object(inst) => return LightOut::Object(inst.clone()),
            AreaPrim::User => {
                w.push(Diagnostic {
                    loc: at.clone(),
                    message: format!(
                        "light \"{}\": user area lights are not supported; the light is left out",
                        l.name
                    ),
                });
                return LightOut::Nothing;
            }
            AreaPrim::Rectangle(u, v) => {
                ps.push(param("edgeu", vector(*u), at));
                ps.push(param("edgev", vector(*v), at));
                "rectangle"
            }
            AreaPrim::Disc(n, r) => {
                ps.push(param(
                    "normal",
                    ParamValue::Normal(vec![n.map(|x| x as f32)]),
                    at,
                ));
                ps.push(param("radius", float(*r), at));
                "disc"
            }
            AreaPrim::Sphere(r) => {
                ps.push(param("radius", float(*r), at));
                "sphere"
            }
            AreaPrim::Cylinder(a, r) => {
                ps.push(param("axis", vector(*a), at));
                ps.push(param("radius", float(*r), at));
                "cylinder"
            }
        };
        if l.spread.is_some() && l.direction.is_some() {
            w.push(Diagnostic {
                loc: at.clone(),
                message: format!("light \"{}\": the spot cone of an area light is not modelled; it lights every direction", l.name),
            });
        }
        let a = world_area(prim, l2w);
        if !(a > 0.0 && a.is_finite()) {
            w.push(Diagnostic {
                loc: at.clone(),
                message: format!(
                    "light \"{}\": the area primitive has no area; the light is left out",
                    l.name
                ),
            });
            return LightOut::Nothing;
        }
        let flat = matches!(prim, AreaPrim::Rectangle(..) | AreaPrim::Disc(..));
        let (scale, cos_exp, two_sided) = match m {
            Model::Physical { cos_exp, .. } if flat => (1.0 / (PI * a), cos_exp, false),
            Model::Physical { .. } => (1.0 / (4.0 * PI * a), 0.0, true),
            Model::Base { .. } => (1.0 / a, 0.0, true),
        };
        ps.push(param("from", point(origin), loc));
        ps.push(param("L", color(col, scale), loc));
        ps.push(param("cosineexponent", float(cos_exp), loc));
        ps.push(param("twosided", ParamValue::Bool(vec![two_sided]), loc));
        ps.push(param("falloffexponent", float(k), loc));
        ps.push(param("visible", ParamValue::Bool(vec![l.visible]), loc));
        sample_params(l, &mut ps, at);
        return LightOut::Source(Entity {
            kind: kind.into(),
            params: ps,
            loc: loc.clone(),
        });
    }
    let intensity = if physical { 1.0 / (4.0 * PI) } else { 1.0 };
    let kind = match (l.origin, l.direction, l.spread) {
        (_, Some(d), None) | (None, Some(d), _) => {
            // Directional (with or without an origin): irradiance `color` along d.
            ps.push(param("from", point([0.0; 3]), loc));
            ps.push(param("to", point(d), loc));
            ps.push(param("L", color(col, 1.0), loc));
            "distant"
        }
        (Some(o), Some(d), Some(spread)) => {
            ps.push(param("from", point(o), loc));
            ps.push(param(
                "to",
                point([o[0] + d[0], o[1] + d[1], o[2] + d[2]]),
                loc,
            ));
            ps.push(param("spread", float(spread), loc));
            if let Some(c) = cone {
                ps.push(param("cone", float(c), loc));
            }
            ps.push(param("L", color(col, intensity), loc));
            ps.push(param("falloffexponent", float(k), loc));
            "spot"
        }
        (o, None, _) => {
            if o.is_none() {
                w.push(Diagnostic {
                    loc: loc.clone(),
                    message: format!("light \"{}\" has neither origin nor direction: a point light at its instance's origin", l.name),
                });
            }
            ps.push(param("from", point(origin), loc));
            ps.push(param("L", color(col, intensity), loc));
            ps.push(param("falloffexponent", float(k), loc));
            "point"
        }
    };
    LightOut::Source(Entity {
        kind: kind.into(),
        params: ps,
        loc: loc.clone(),
    })
}

/// The AreaLightSource for an object light whose emitting geometry has world-space area
/// `area` (see the module docs).
pub fn object_area_entity(
    l: &MiLight,
    shader: Option<(&str, &ShaderParams, &Loc)>,
    area: f64,
    w: &mut Vec<Diagnostic>,
) -> Entity {
    let m = model(l, shader, w);
    notes(l, matches!(m, Model::Physical { .. }), w);
    let loc = l.area.as_ref().map_or(&l.loc, |a| &a.1);
    let a = if area > 0.0 && area.is_finite() {
        area
    } else {
        1.0
    };
    let (col, scale, cos_exp, two_sided, k) = match m {
        Model::Physical { color, cos_exp, .. } => (
            color,
            1.0 / (4.0 * PI * a),
            cos_exp,
            false,
            mental_ray_exponent(l.exponent.unwrap_or(2.0) as f32) as f64,
        ),
        Model::Base { color, .. } => (color, 1.0 / a, 0.0, true, 0.0),
    };
    let mut ps = ParamSet::new();
    ps.push(param("power", float(0.0), loc));
    ps.push(param("L", color(col, scale), loc));
    ps.push(param("cosineexponent", float(cos_exp), loc));
    ps.push(param("twosided", ParamValue::Bool(vec![two_sided]), loc));
    ps.push(param("falloffexponent", float(k), loc));
    ps.push(param("visible", ParamValue::Bool(vec![l.visible]), loc));
    sample_params(l, &mut ps, loc);
    Entity {
        kind: "area".into(),
        params: ps,
        loc: l.loc.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::super::cursor::Cursor;
    use super::super::params::ShaderRef;
    use super::*;

    fn light(text: &str) -> MiLight {
        let mut c = Cursor::new(text, "t.mi".into());
        parse(&mut c, "l".into(), Loc::default(), 100).unwrap()
    }

    fn inline(l: &MiLight) -> Option<(&str, &ShaderParams, &Loc)> {
        match l.shader.as_ref()? {
            ShaderRef::Inline { kind, params, loc } => Some((kind.as_str(), params, loc)),
            ShaderRef::Named { .. } => None,
        }
    }

    #[test]
    fn the_sample_object_light() {
        let l = light("= \"Emitter_mat\"\n origin 0.0 0.0 0.0\n object \"Light_inst\"\n 16 1 1 1 1\n visible on\n end light");
        assert_eq!(
            l.area.as_ref().unwrap().0,
            AreaPrim::Object("Light_inst".into())
        );
        assert_eq!(
            l.samples,
            Samples {
                u: 16,
                v: 1,
                level: 1,
                low_u: 1,
                low_v: 1
            }
        );
        assert!(l.visible);
        let p = ShaderParams::default();
        let mut w = Vec::new();
        let e = object_area_entity(
            &l,
            Some(("physical_light", &p, &Loc::default())),
            2.0,
            &mut w,
        );
        assert_eq!(e.params.int("nsamples"), Some(16));
        assert_eq!(e.params.int("lowlevel"), Some(1));
        // color 1 (energy default) over 4π·2.
        let want = 1.0 / (8.0 * PI);
        assert!((e.params.color("L").unwrap()[0] as f64 - want).abs() < 1e-7);
        assert_eq!(e.params.bool("visible"), Some(true));
    }

    #[test]
    fn point_spot_and_directional_lights() {
        let mut w = Vec::new();
        let l = light("\"mib_light_point\" (\"color\" 2 2 2) origin 1 2 3 end light");
        let LightOut::Source(e) = light_entity(&l, inline(&l), &DMat4::IDENTITY, &mut w) else {
            panic!()
        };
        assert_eq!(e.kind, "point");
        assert_eq!(e.params.color("L"), Some([2.0; 3]));
        assert_eq!(e.params.float("falloffexponent"), Some(0.0));
        let l = light("\"physical_light\" (\"color\" 4 4 4, \"cone\" 0.9) origin 0 0 0 direction 0 0 -1 spread 0.8 exponent 1 end light");
        let LightOut::Source(e) = light_entity(&l, inline(&l), &DMat4::IDENTITY, &mut w) else {
            panic!()
        };
        assert_eq!(e.kind, "spot");
        assert_eq!(e.params.float("spread"), Some(0.8));
        assert_eq!(e.params.float("cone"), Some(0.9));
        assert_eq!(e.params.float("falloffexponent"), Some(1.0));
        assert!((e.params.color("L").unwrap()[0] as f64 - 1.0 / PI).abs() < 1e-6);
        let l = light("\"mib_light_infinite\" (\"color\" 1 1 1) direction 0 -1 0 end light");
        let LightOut::Source(e) = light_entity(&l, inline(&l), &DMat4::IDENTITY, &mut w) else {
            panic!()
        };
        assert_eq!(e.kind, "distant");
        assert!(w.is_empty(), "{w:?}");
    }

    #[test]
    fn area_primitives_normalise_by_their_world_area() {
        let mut w = Vec::new();
        let l = light("\"physical_light\" (\"color\" 8 8 8) origin 0 0 1 rectangle 2 0 0 0 1 0 4 4 visible end light");
        let l2w = DMat4::from_scale(DVec3::splat(2.0));
        let LightOut::Source(e) = light_entity(&l, inline(&l), &l2w, &mut w) else {
            panic!()
        };
        assert_eq!(e.kind, "rectangle");
        // World area 2·1·4 = 8: L = 8 / (π·8).
        assert!((e.params.color("L").unwrap()[0] as f64 - 1.0 / PI).abs() < 1e-6);
        assert_eq!(e.params.int("nsamples"), Some(16));
        let l = light("\"mib_light_point\" (\"color\" 1 1 1) sphere 0.5 end light");
        let LightOut::Source(e) = light_entity(&l, inline(&l), &DMat4::IDENTITY, &mut w) else {
            panic!()
        };
        assert_eq!(e.params.float("cosineexponent"), Some(0.0));
        assert_eq!(e.params.bool("twosided"), Some(true));
        assert_eq!(e.params.bool("visible"), Some(false));
        let mut c = Cursor::new("disc 0 0 1 -2 end light", "t.mi".into());
        assert!(parse(&mut c, "l".into(), Loc::default(), 100).is_err());
    }
}

//! Indigo's lights other than emitting materials: the environment (`background`,
//! `skylight`, `env_map`, the 3.x/4.x `background_settings` material), `rectanglelight` and
//! `meshlight`.
//!
//! ```text
//! background spectrum                  --> LightSource "infinite" L
//! skylight sundir turbidity            --> LightSource "sunsky" sundir turbidity
//! env_map latlong path gain            --> LightSource "infinite" mapname gain
//! background_settings/background_material: sunsky, or diffuse with a (textured) emission
//!                                      --> sunsky | infinite L | infinite mapname gain
//! rectanglelight pos width height spectrum efficacy_scale
//!                                      --> a quad facing -z with an area light
//! meshlight mesh_name pos rotation scale spectrum efficacy_scale
//!                                      --> the mesh, black, with an area light
//! ```
//!
//! An area light's `L` is the spectrum's RGB (Indigo's spectral radiance) with LuxRender's
//! power normalisation off, unless `efficacy_scale` gives the power drawn and the luminous
//! efficacy: then LuxRender's `power` and `efficacy` scale it to that luminous flux, which is
//! what Indigo does.

use super::ctx::{err, Ctx};
use super::node::Elem;
use super::spectrum;
use crate::lxs::{Entity, Loc, LxsError, LxsErrorKind, Param, ParamSet, ParamValue};
use std::path::Path;

/// A `LightSource` statement with its light group.
#[derive(Clone, Debug)]
pub struct LightOut {
    pub entity: Entity,
    pub group: String,
}

/// An `AreaLightSource "area"`: `L`, power normalisation and light group.
#[derive(Clone, Debug)]
pub struct AreaOut {
    pub l: ParamValue,
    pub power: f64,
    pub efficacy: f64,
    pub ies: Option<String>,
    pub group: String,
    pub loc: Loc,
}

impl AreaOut {
    pub fn entity(&self) -> Entity {
        let loc = &self.loc;
        let mut ps = ParamSet::new();
        ps.push(Param::new("L", self.l.clone(), loc.clone()));
        ps.push(Param::new(
            "power",
            ParamValue::Float(vec![self.power as f32]),
            loc.clone(),
        ));
        ps.push(Param::new(
            "efficacy",
            ParamValue::Float(vec![self.efficacy as f32]),
            loc.clone(),
        ));
        if let Some(ies) = &self.ies {
            ps.push(Param::new(
                "iesname",
                ParamValue::String(vec![ies.clone()]),
                loc.clone(),
            ));
        }
        Entity {
            kind: "area".into(),
            params: ps,
            loc: loc.clone(),
        }
    }
}

fn p(name: &str, v: ParamValue, loc: &Loc) -> Param {
    Param::new(name, v, loc.clone())
}

fn rgb(c: [f64; 3]) -> ParamValue {
    ParamValue::Color(vec![c.map(|v| v as f32)])
}

fn light(kind: &str, ps: ParamSet, loc: &Loc, group: &str) -> LightOut {
    LightOut {
        entity: Entity {
            kind: kind.into(),
            params: ps,
            loc: loc.clone(),
        },
        group: group.to_string(),
    }
}

/// `<background>`.
pub fn background(e: &Elem, group: &str, ctx: &Ctx) -> Result<LightOut, LxsError> {
    e.mark_used();
    let c = spectrum::of(e, ctx)?;
    let mut ps = ParamSet::new();
    ps.push(p("L", rgb(c), &e.loc));
    Ok(light("infinite", ps, &e.loc, group))
}

/// `<skylight>` or a `<sunsky>` background material.
pub fn sunsky(e: &Elem, group: &str, ctx: &Ctx) -> Result<LightOut, LxsError> {
    e.mark_used();
    e.ignore(&["model", "sun_layer", "sky_layer"]);
    let dir = e.need(ctx, "sundir")?.vec3(ctx)?;
    if dir[2] <= 0.0 {
        ctx.warn(
            &e.loc,
            "sundir has no upward component: the sun is below the horizon",
        );
    }
    let mut ps = ParamSet::new();
    ps.push(p(
        "sundir",
        ParamValue::Vector(vec![dir.map(|v| v as f32)]),
        &e.loc,
    ));
    if let Some(t) = e.child(ctx, "turbidity") {
        ps.push(p(
            "turbidity",
            ParamValue::Float(vec![t.positive(ctx)? as f32]),
            &t.loc,
        ));
    }
    if e.child_bool_or(ctx, "extra_atmospheric", false)? {
        ctx.warn(&e.loc, "extra_atmospheric sun and sky are not supported: the sky is rendered with the atmosphere");
    }
    Ok(light("sunsky", ps, &e.loc, group))
}

/// `<env_map>`: latlong maps; spherical .float probes are reported and skipped.
pub fn env_map(e: &Elem, dir: &Path, group: &str, ctx: &Ctx) -> Result<Option<LightOut>, LxsError> {
    e.mark_used();
    let map = e.child(ctx, "latlong").or_else(|| e.child(ctx, "lat_long"));
    let Some(map) = map else {
        if let Some(s) = e.child(ctx, "spherical") {
            s.mark_all_used();
            ctx.warn(
                &s.loc,
                "spherical (.float) environment maps are not supported: ignored",
            );
        }
        return Ok(None);
    };
    let path = map.need(ctx, "path")?;
    let mut ps = ParamSet::new();
    ps.push(p(
        "mapname",
        ParamValue::String(vec![ctx.scene_relative(path.str(), dir, &path.loc)?]),
        &path.loc,
    ));
    ps.push(p(
        "gain",
        ParamValue::Float(vec![map.child_num_or(ctx, "gain", 1.0)? as f32]),
        &map.loc,
    ));
    Ok(Some(light("infinite", ps, &e.loc, group)))
}

/// The material of `<background_settings>` (inline `<background_material><material>`).
pub fn background_settings(
    e: &Elem,
    dir: &Path,
    layer_group: &dyn Fn(i64) -> String,
    ctx: &Ctx,
) -> Result<Option<LightOut>, LxsError> {
    e.mark_used();
    e.ignore(&["uid", "name"]);
    let Some(bm) = e.child(ctx, "background_material") else {
        return Ok(None);
    };
    let Some(m) = bm.child(ctx, "material") else {
        return Ok(None);
    };
    m.ignore(&["name", "uid"]);
    if let Some(s) = m.child(ctx, "sunsky") {
        return sunsky(s, &layer_group(0), ctx).map(Some);
    }
    let Some(d) = m.child(ctx, "diffuse") else {
        if let Some(other) = m.first_child_except(&["name", "uid"]) {
            other.mark_all_used();
            ctx.warn(
                &other.loc,
                format!(
                    "background material <{}> is not supported: no environment light",
                    other.name
                ),
            );
        }
        return Ok(None);
    };
    let group = layer_group(d.child_int(ctx, "layer")?.unwrap_or(0));
    d.ignore(&["albedo", "albedo_spectrum", "random_triangle_colours"]);
    let base = super::texture::color(d, "base_emission", ctx)?;
    let modul = super::texture::color(d, "emission", ctx)?;
    let textures: Vec<&Elem> = d.all("texture").collect();
    let mut ps = ParamSet::new();
    let scale = |v: &Option<super::texture::Value>| match v {
        Some(super::texture::Value::Const(c)) => *c,
        _ => [1.0; 3],
    };
    let tex = [&base, &modul].into_iter().find_map(|v| match v {
        Some(super::texture::Value::Tex(i, l)) => Some((*i, l.clone())),
        _ => None,
    });
    match tex {
        Some((i, l)) => {
            let def = textures.get(i).ok_or_else(|| {
                err(
                    LxsErrorKind::Undefined,
                    &l,
                    format!(
                        "texture_index {i}: the material defines {} texture(s)",
                        textures.len()
                    ),
                )
            })?;
            def.mark_all_used();
            let path = def.need(ctx, "path")?;
            ps.push(p(
                "mapname",
                ParamValue::String(vec![ctx.scene_relative(path.str(), dir, &path.loc)?]),
                &path.loc,
            ));
            let g = [scale(&base), scale(&modul)];
            let gain = (0..3).map(|k| g[0][k] * g[1][k]).sum::<f64>() / 3.0;
            ps.push(p("gain", ParamValue::Float(vec![gain as f32]), &d.loc));
            if def.has(ctx, "tex_coord_generation") {
                ctx.warn(&def.loc, "environment map rotation is not applied: LuxRender's latlong orientation is used");
            }
        }
        None if base.is_some() => {
            let (b, m) = (scale(&base), scale(&modul));
            ps.push(p("L", rgb([0, 1, 2].map(|k| b[k] * m[k])), &d.loc));
        }
        None => return Ok(None),
    }
    Ok(Some(light("infinite", ps, &e.loc, &group)))
}

/// `efficacy_scale` (also spelt `efficiacy_scale`): (power drawn in W, lm/W).
fn efficacy(e: &Elem, ctx: &Ctx) -> Result<Option<(f64, f64)>, LxsError> {
    let Some(s) = e
        .child(ctx, "efficacy_scale")
        .or_else(|| e.child(ctx, "efficiacy_scale"))
    else {
        return Ok(None);
    };
    let w = s.need(ctx, "power_drawn")?.positive(ctx)?;
    let eff = match s
        .child(ctx, "overall_luminous_efficacy")
        .or_else(|| s.child(ctx, "overall_luminous_efficiacy"))
    {
        Some(x) => x.positive(ctx)?,
        None => {
            return Err(err(
                LxsErrorKind::WrongValueCount,
                &s.loc,
                "efficacy_scale needs <overall_luminous_efficacy>",
            ))
        }
    };
    Ok(Some((w, eff)))
}

/// The area light of a `rectanglelight` or `meshlight`.
pub fn area_of(e: &Elem, group: &str, dir: &Path, ctx: &Ctx) -> Result<AreaOut, LxsError> {
    let c = spectrum::of(e, ctx)?;
    let (power, eff) = efficacy(e, ctx)?.unwrap_or((0.0, 0.0));
    let ies = match e.child(ctx, "ies_profile") {
        Some(i) => {
            let path = i.need(ctx, "path")?;
            Some(ctx.scene_relative(path.str(), dir, &path.loc)?)
        }
        None => None,
    };
    if let Some(t) = e.child(ctx, "texture") {
        t.mark_all_used();
        ctx.warn(
            &t.loc,
            "a texture on a mesh light is not applied: uniform emission",
        );
    }
    Ok(AreaOut {
        l: rgb(c),
        power,
        efficacy: eff,
        ies,
        group: group.to_string(),
        loc: e.loc.clone(),
    })
}

/// `<rectanglelight>`: the quad's `trianglemesh` parameters (normal -z) and its area light.
pub fn rectangle(
    e: &Elem,
    group: &str,
    dir: &Path,
    ctx: &Ctx,
) -> Result<(ParamSet, AreaOut), LxsError> {
    e.mark_used();
    let c = e.need(ctx, "pos")?.vec3(ctx)?;
    let w = e.need(ctx, "width")?.positive(ctx)? / 2.0;
    let h = e.need(ctx, "height")?.positive(ctx)? / 2.0;
    let pts = [[-w, -h], [-w, h], [w, h], [w, -h]]
        .map(|d| [(c[0] + d[0]) as f32, (c[1] + d[1]) as f32, c[2] as f32]);
    let mut ps = ParamSet::new();
    ps.push(p("P", ParamValue::Point(pts.to_vec()), &e.loc));
    ps.push(p(
        "triindices",
        ParamValue::Integer(vec![0, 1, 2, 0, 2, 3]),
        &e.loc,
    ));
    let area = area_of(e, group, dir, ctx)?;
    Ok((ps, area))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::indigo::xml;
    use crate::lxs::ParseOptions;

    fn root(doc: &str) -> Elem {
        xml::parse(doc.as_bytes(), &"t.igs".into()).unwrap().root
    }

    #[test]
    fn environment_lights() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let b = background(
            &root(
                "<background><spectrum><uniform><value>2</value></uniform></spectrum></background>",
            ),
            "g",
            &ctx,
        )
        .unwrap();
        assert_eq!(b.entity.kind, "infinite");
        assert_eq!(b.entity.params.color("L"), Some([2.0; 3]));
        let s = sunsky(
            &root("<skylight><sundir>0 0.6 1</sundir><turbidity>2</turbidity></skylight>"),
            "g",
            &ctx,
        )
        .unwrap();
        assert_eq!(s.entity.params.vector("sundir"), Some([0.0, 0.6, 1.0]));
        let m = env_map(
            &root(
                "<env_map><latlong><path>probes\\sky.exr</path><gain>3</gain></latlong></env_map>",
            ),
            Path::new(""),
            "g",
            &ctx,
        )
        .unwrap()
        .unwrap();
        assert_eq!(m.entity.params.string("mapname"), Some("probes/sky.exr"));
        assert!(env_map(
            &root("<env_map><spherical><path>a.float</path></spherical></env_map>"),
            Path::new(""),
            "g",
            &ctx
        )
        .unwrap()
        .is_none());
        let layer = |i: i64| format!("layer {i}");
        let bg = background_settings(
            &root("<background_settings><background_material><material><name>bg</name><diffuse>\
                   <texture><path>env.exr</path><exponent>1</exponent></texture>\
                   <base_emission><constant><uniform><value>5</value></uniform></constant></base_emission>\
                   <emission><texture><texture_index>0</texture_index></texture></emission><layer>1</layer></diffuse></material></background_material></background_settings>"),
            Path::new(""),
            &layer,
            &ctx,
        )
        .unwrap()
        .unwrap();
        assert_eq!(bg.entity.params.string("mapname"), Some("env.exr"));
        assert_eq!(bg.entity.params.float("gain"), Some(5.0));
        assert_eq!(bg.group, "layer 1");
        let sky = background_settings(
            &root("<background_settings><background_material><material><name>s</name><sunsky><sundir>0 0 1</sundir><turbidity>3</turbidity></sunsky></material></background_material></background_settings>"),
            Path::new(""),
            &layer,
            &ctx,
        )
        .unwrap()
        .unwrap();
        assert_eq!(sky.entity.kind, "sunsky");
        assert!(background_settings(
            &root("<background_settings><uid>14</uid></background_settings>"),
            Path::new(""),
            &layer,
            &ctx
        )
        .unwrap()
        .is_none());
    }

    #[test]
    fn rectangle_light_faces_down_with_efficacy() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let (ps, a) = rectangle(
            &root("<rectanglelight><pos>0 0 1.9</pos><width>0.2</width><height>0.4</height><spectrum><peak><peak_min>300</peak_min><peak_width>550</peak_width><base_value>0</base_value><peak_value>200</peak_value></peak></spectrum>\
                   <efficiacy_scale><power_drawn>100</power_drawn><overall_luminous_efficiacy>17.5</overall_luminous_efficiacy></efficiacy_scale></rectanglelight>"),
            "g",
            Path::new(""),
            &ctx,
        )
        .unwrap();
        let p = ps.points("P").unwrap();
        let (a0, a1, a2) = (
            glam::Vec3::from(p[0]),
            glam::Vec3::from(p[1]),
            glam::Vec3::from(p[2]),
        );
        assert!((a1 - a0).cross(a2 - a0).z < 0.0);
        assert_eq!((a.power, a.efficacy), (100.0, 17.5));
        assert_eq!(a.entity().params.float("power"), Some(100.0));
    }
}

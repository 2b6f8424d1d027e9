//! Indigo materials turned into LuxRender named materials, their textures, and the area
//! light their emission becomes.
//!
//! ```text
//! <material> name, uid, <type> { params, texture*, bump, base_emission, emission, layer }
//!   --> MatOut { MakeNamedMaterial params (+ Texture statements), Emission, interior medium }
//! ```
//!
//! | Indigo | LuxRender |
//! | --- | --- |
//! | diffuse (albedo) | matte Kd |
//! | oren_nayar (albedo, sigma in radians) | matte Kd, sigma in degrees |
//! | phong (diffuse_albedo, ior, exponent) | glossy Kd, Ks 1 with index = ior, roughness 1/exponent |
//! | phong with nk_data | metal with the .nk file as `name`, roughness 1/exponent |
//! | phong with specular_reflectivity | glossy Kd 0, Ks = reflectivity, roughness 1/exponent |
//! | specular (transparent) | glass Kr 1, Kt 1 (0 when not transparent), index and cauchyb of the internal medium |
//! | glossy_transparent | roughglass with the internal medium's index, roughness 1/exponent |
//! | diffuse_transmitter (albedo) | mattetranslucent Kr 0, Kt = albedo |
//! | blend (a, b, blend, step_blend) | mix namedmaterial1 a, namedmaterial2 b, amount = blend |
//! | null_material | null |
//!
//! The exponent-to-roughness rule is LuxRender's own (a Blinn exponent of 1/roughness).
//! Emission is `base_emission × emission` (a `scale` texture when either is a texture) as the
//! area light's `L`, with LuxRender's power normalisation off (`power` 0): the value is
//! Indigo's spectral radiance. `layer` picks the light group.
//!
//! The parameters of one material are read by the converter in `material_conv.rs`; this file
//! says what each Indigo type becomes.

use super::ctx::{err, Ctx};
use super::material_conv::Conv;
pub use super::material_conv::{Emission, MatOut};
use super::medium::Medium;
use super::node::Elem;
use super::texture::{self, Value};
use crate::lxs::{Loc, LxsError, LxsErrorKind, ParamSet, ParamValue};
use std::collections::HashMap;
use std::path::Path;

/// Where materials and media are found by name or uid (filled in file order, so a reference
/// must follow what it names, as in Indigo).
#[derive(Default)]
pub struct Lookup {
    pub by_name: HashMap<String, String>,
    pub by_uid: HashMap<i64, String>,
    pub media: HashMap<String, Medium>,
    pub media_by_uid: HashMap<i64, String>,
}

impl Lookup {
    /// The LuxRender name of the material named `name` (or uid `uid`) at `loc`.
    pub fn material(
        &self,
        name: Option<&str>,
        uid: Option<i64>,
        loc: &Loc,
    ) -> Result<String, LxsError> {
        let found = match (name, uid) {
            (_, Some(u)) => self.by_uid.get(&u),
            (Some(n), None) => self.by_name.get(n),
            (None, None) => None,
        };
        found.cloned().ok_or_else(|| {
            let what = match (name, uid) {
                (_, Some(u)) => format!("uid {u}"),
                (Some(n), _) => format!("\"{n}\""),
                _ => "(none given)".into(),
            };
            err(
                LxsErrorKind::Undefined,
                loc,
                format!("material {what} is not defined before this reference"),
            )
        })
    }

    fn medium(&self, e: &Elem, ctx: &Ctx) -> Result<Option<&Medium>, LxsError> {
        let name = if let Some(n) = e.child_str(ctx, "internal_medium_name") {
            Some((n.to_string(), e.loc.clone()))
        } else if let Some(u) = e.child(ctx, "internal_medium_uid") {
            let uid = u.int(ctx)?;
            let n = self.media_by_uid.get(&uid).ok_or_else(|| {
                err(
                    LxsErrorKind::Undefined,
                    &u.loc,
                    format!("medium uid {uid} is not defined before this reference"),
                )
            })?;
            Some((n.clone(), u.loc.clone()))
        } else {
            None
        };
        match name {
            None => Ok(None),
            Some((n, loc)) => self.media.get(&n).map(Some).ok_or_else(|| {
                err(
                    LxsErrorKind::Undefined,
                    &loc,
                    format!("medium \"{n}\" is not defined before this reference"),
                )
            }),
        }
    }
}

/// Children of `<material>` that are not its type element.
const NOT_TYPE: [&str; 2] = ["name", "uid"];

/// Converts `<material>` element `m` written in a file of directory `dir`; `name` is the
/// LuxRender name chosen for it.
pub fn convert(
    m: &Elem,
    name: &str,
    dir: &Path,
    look: &Lookup,
    ctx: &Ctx,
) -> Result<MatOut, LxsError> {
    m.mark_used();
    m.ignore(&NOT_TYPE);
    let Some(te) = m.first_child_except(&NOT_TYPE) else {
        return Err(err(
            LxsErrorKind::WrongValueCount,
            &m.loc,
            format!("material \"{name}\" has no type element (diffuse, phong, specular, ...)"),
        ));
    };
    te.mark_used();
    let defs: Vec<&Elem> = te.all("texture").collect();
    let mut c = Conv {
        ctx,
        dir,
        te,
        defs,
        out: MatOut {
            name: name.to_string(),
            loc: m.loc.clone(),
            textures: Vec::new(),
            params: ParamSet::new(),
            emission: None,
            uv_set: None,
            interior: None,
            deps: Vec::new(),
        },
    };
    match te.name.as_str() {
        "diffuse" => {
            c.kind("matte");
            let found = c.color("albedo", "Kd")?
                || c.color("albedo_spectrum", "Kd")?
                || c.color("colour", "Kd")?;
            if !found && !c.defs.is_empty() {
                // Indigo 1.x: a diffuse material's texture is its albedo.
                let loc = c.defs[0].loc.clone();
                let n = c.texture(0, &loc, "Kd", "color")?;
                c.put("Kd", ParamValue::Texture(n), &loc);
            }
            random_colours(te, ctx)?;
        }
        "oren_nayar" => {
            c.kind("matte");
            c.color("albedo", "Kd")?;
            c.float("sigma", &["sigma"], f64::to_degrees, false)?;
        }
        "phong" => phong(&mut c)?,
        "specular" | "glossy_transparent" => {
            let medium = look.medium(te, ctx)?.cloned();
            let (ior, cauchy) = medium.as_ref().map_or((1.5, 0.0), |m| (m.ior, m.cauchy_b));
            if medium.is_none() {
                ctx.warn(
                    &te.loc,
                    "no internal medium: index of refraction 1.5 assumed",
                );
            }
            let loc = te.loc.clone();
            if te.name == "specular" {
                c.kind("glass");
                let transparent = te.child_bool_or(ctx, "transparent", true)?;
                c.put("Kr", ParamValue::Color(vec![[1.0; 3]]), &loc);
                let kt = if transparent { 1.0 } else { 0.0 };
                c.put("Kt", ParamValue::Color(vec![[kt; 3]]), &loc);
                c.put("cauchyb", ParamValue::Float(vec![cauchy as f32]), &loc);
            } else {
                c.kind("roughglass");
                c.put("Kr", ParamValue::Color(vec![[1.0; 3]]), &loc);
                c.put("Kt", ParamValue::Color(vec![[1.0; 3]]), &loc);
                c.exponent_roughness()?;
            }
            c.put("index", ParamValue::Float(vec![ior as f32]), &loc);
            c.out.interior = medium.filter(|m| m.volume.is_some()).map(|m| m.name);
        }
        "diffuse_transmitter" => {
            c.kind("mattetranslucent");
            let loc = te.loc.clone();
            c.put("Kr", ParamValue::Color(vec![[0.0; 3]]), &loc);
            c.color("albedo", "Kt")?;
        }
        "blend" => blend(&mut c, look)?,
        "null_material" => c.kind("null"),
        other => {
            te.mark_all_used();
            ctx.warn(
                &te.loc,
                format!(
                    "material type <{other}> is not supported by luxfarm: rendered as grey matte"
                ),
            );
            c.kind("matte");
            return Ok(c.out);
        }
    }
    c.bump()?;
    c.emission()?;
    Ok(c.out)
}

fn random_colours(te: &Elem, ctx: &Ctx) -> Result<(), LxsError> {
    if te.child_bool_or(ctx, "random_triangle_colours", false)? {
        ctx.warn(
            &te.loc,
            "random_triangle_colours is a debugging aid luxfarm does not draw: ignored",
        );
    }
    Ok(())
}

fn phong(c: &mut Conv) -> Result<(), LxsError> {
    let (te, ctx) = (c.te, c.ctx);
    if let Some(Value::Const(v)) = texture::float(te, "fresnel_scale", ctx)? {
        if v[0] != 1.0 {
            ctx.warn(
                &te.loc,
                format!("fresnel_scale {} has no LuxRender equivalent: 1 used", v[0]),
            );
        }
    }
    let nk = te.child(ctx, "nk_data").filter(|n| !n.str().is_empty());
    if let Some(nk) = nk {
        c.kind("metal");
        let path = ctx.scene_relative(nk.str(), c.dir, &nk.loc)?;
        c.put("name", ParamValue::String(vec![path]), &nk.loc.clone());
        c.exponent_roughness()?;
        te.ignore(&["diffuse_albedo", "ior", "specular_reflectivity"]);
        return Ok(());
    }
    c.kind("glossy");
    let loc = te.loc.clone();
    if te.has(ctx, "specular_reflectivity") {
        c.put("Kd", ParamValue::Color(vec![[0.0; 3]]), &loc);
        c.color("specular_reflectivity", "Ks")?;
        c.put("index", ParamValue::Float(vec![0.0]), &loc);
        te.ignore(&["diffuse_albedo", "ior"]);
    } else {
        let found = c.color("diffuse_albedo", "Kd")? || c.color("diffuse", "Kd")?;
        if !found && !c.defs.is_empty() {
            let l = c.defs[0].loc.clone();
            let n = c.texture(0, &l, "Kd", "color")?;
            c.put("Kd", ParamValue::Texture(n), &l);
        }
        c.put("Ks", ParamValue::Color(vec![[1.0; 3]]), &loc);
        let ior = te.child_num_or(ctx, "ior", 1.5)?;
        if ior < 1.0 {
            return Err(err(
                LxsErrorKind::InvalidValue,
                &loc,
                format!("phong ior must be >= 1, got {ior}"),
            ));
        }
        c.put("index", ParamValue::Float(vec![ior as f32]), &loc);
    }
    c.exponent_roughness()
}

fn blend(c: &mut Conv, look: &Lookup) -> Result<(), LxsError> {
    let (te, ctx) = (c.te, c.ctx);
    c.kind("mix");
    for (side, lux) in [("a", "namedmaterial1"), ("b", "namedmaterial2")] {
        let name = te.child_str(ctx, &format!("{side}_name"));
        let uid = match te
            .child(ctx, &format!("{side}_mat_uid"))
            .or_else(|| te.child(ctx, &format!("{side}_uid")))
        {
            Some(u) => Some(u.int(ctx)?),
            None => None,
        };
        let target = look.material(name, uid, &te.loc)?;
        c.out.deps.push(target.clone());
        c.put(lux, ParamValue::String(vec![target]), &te.loc.clone());
    }
    let step = te.child_bool_or(ctx, "step_blend", false)?;
    let stepf = move |x: f64| {
        if step {
            if x >= 0.5 {
                1.0
            } else {
                0.0
            }
        } else {
            x.clamp(0.0, 1.0)
        }
    };
    if step {
        if let Some(Value::Tex(_, loc)) = texture::float(te, "blend", ctx)? {
            ctx.warn(&loc, "step_blend on a textured blend cannot be expressed in LuxRender: smooth blend used");
        }
    }
    c.float("blend", &["amount"], stepf, true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::indigo::{medium, xml};
    use crate::lxs::ParseOptions;

    fn conv(doc: &str, look: &Lookup) -> Result<(MatOut, Vec<String>), LxsError> {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let p = xml::parse(doc.as_bytes(), &"t.igs".into()).unwrap();
        let out = convert(&p.root, "m", Path::new(""), look, &ctx)?;
        p.root.report_unused(&ctx);
        Ok((
            out,
            ctx.take_warnings().into_iter().map(|w| w.message).collect(),
        ))
    }

    #[test]
    fn diffuse_with_emission_layer_and_texture() {
        let (m, w) = conv(
            "<material><name>m</name><diffuse><texture><uv_set>albedo</uv_set><path>a.png</path><exponent>2.2</exponent></texture>\
             <albedo><texture><texture_index>0</texture_index></texture></albedo>\
             <base_emission><constant><uniform><value>100</value></uniform></constant></base_emission>\
             <emission><constant><rgb><rgb>1 0.5 0.5</rgb><gamma>1</gamma></rgb></constant></emission>\
             <layer>2</layer></diffuse></material>",
            &Lookup::default(),
        )
        .unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(m.params.string("type"), Some("matte"));
        assert_eq!(
            m.params.get("Kd").unwrap().value,
            ParamValue::Texture("m.Kd".into())
        );
        assert_eq!(
            m.textures[0].entity.params.string("filename"),
            Some("a.png")
        );
        assert_eq!(m.uv_set.as_deref(), Some("albedo"));
        let e = m.emission.unwrap();
        assert_eq!(e.l, ParamValue::Color(vec![[100.0, 50.0, 50.0]]));
        assert_eq!(e.layer, 2);
    }

    #[test]
    fn phong_specular_and_oren_nayar_map_their_parameters() {
        let (m, _) = conv(
            "<material><name>p</name><phong><ior>1.5</ior><exponent><constant>10</constant></exponent>\
             <diffuse_albedo><constant><uniform><value>0.3</value></uniform></constant></diffuse_albedo></phong></material>",
            &Lookup::default(),
        )
        .unwrap();
        assert_eq!(m.params.string("type"), Some("glossy"));
        assert_eq!(m.params.float("index"), Some(1.5));
        assert!((m.params.float("uroughness").unwrap() - 0.1).abs() < 1e-6);
        assert_eq!(m.params.color("Kd"), Some([0.3; 3]));

        let (m, _) = conv(
            "<material><name>o</name><oren_nayar><albedo><constant><uniform><value>0.7</value></uniform></constant></albedo>\
             <sigma><constant>0.2</constant></sigma></oren_nayar></material>",
            &Lookup::default(),
        )
        .unwrap();
        assert!((m.params.float("sigma").unwrap() - 11.459156).abs() < 1e-4);

        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let med = xml::parse(b"<medium><name>glass</name><ior>1.33</ior><cauchy_b_coeff>0.01</cauchy_b_coeff></medium>", &"t.igs".into()).unwrap();
        let mut look = Lookup::default();
        look.media
            .insert("glass".into(), medium::read(&med.root, &ctx).unwrap());
        let (m, _) = conv(
            "<material><name>g</name><specular><transparent>false</transparent><internal_medium_name>glass</internal_medium_name></specular></material>",
            &look,
        )
        .unwrap();
        assert_eq!(m.params.string("type"), Some("glass"));
        assert_eq!(m.params.float("index"), Some(1.33));
        assert_eq!(m.params.float("cauchyb"), Some(0.01));
        assert_eq!(m.params.color("Kt"), Some([0.0; 3]));
        assert_eq!(m.interior.as_deref(), Some("glass"));
        let e = conv(
            "<material><name>g</name><specular><internal_medium_name>water</internal_medium_name></specular></material>",
            &look,
        )
        .unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::Undefined);
    }

    #[test]
    fn blend_nk_and_unknown_types() {
        let mut look = Lookup::default();
        look.by_name.insert("a".into(), "a".into());
        look.by_uid.insert(9, "b#9".into());
        let (m, _) = conv(
            "<material><name>x</name><blend><a_name>a</a_name><b_mat_uid>9</b_mat_uid><blend><constant>0.7</constant></blend><step_blend>true</step_blend></blend></material>",
            &look,
        )
        .unwrap();
        assert_eq!(m.params.string("namedmaterial2"), Some("b#9"));
        assert_eq!(m.params.float("amount"), Some(1.0));
        assert_eq!(m.deps, vec!["a".to_string(), "b#9".to_string()]);
        let (m, _) = conv(
            "<material><name>al</name><phong><nk_data>nkdata\\al.nk</nk_data><exponent><constant>1000</constant></exponent></phong></material>",
            &look,
        )
        .unwrap();
        assert_eq!(m.params.string("type"), Some("metal"));
        assert_eq!(m.params.string("name"), Some("nkdata/al.nk"));
        let (m, w) = conv(
            "<material><name>c</name><coating><thickness>1</thickness></coating></material>",
            &look,
        )
        .unwrap();
        assert_eq!(m.params.string("type"), Some("matte"));
        assert!(w[0].contains("coating"), "{w:?}");
    }
}

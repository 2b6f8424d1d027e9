//! Indigo media (`<medium>`): the index of refraction and dispersion that specular and
//! glossy transparent materials take from their internal medium, and the LuxRender volume
//! that describes what the medium absorbs and scatters.
//!
//! ```text
//! <medium> name, uid, precedence, basic { ior, cauchy_b_coeff, absorption_coefficient_spectrum,
//!          subsurface_scattering { scattering_coefficient_spectrum, phase_function } }
//!   --> Medium { ior, cauchy_b } + MakeNamedVolume "clear" (absorption) or "homogeneous"
//! ```
//!
//! Indigo 2.x writes the basic parameters directly under `<medium>`, later versions inside
//! `<basic>`; both are read. Skin media (`epidermis`, `dermis`) have no LuxRender equivalent:
//! reported, and read as a clear medium of index 1.4 (skin's). `air` is predefined (index 1).

use super::ctx::Ctx;
use super::node::Elem;
use super::spectrum;
use crate::lxs::{Entity, Loc, LxsError, Param, ParamSet, ParamValue};

/// What a material needs to know of its internal medium.
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    /// The LuxRender volume name (the Indigo name).
    pub name: String,
    pub uid: Option<i64>,
    pub ior: f64,
    pub cauchy_b: f64,
    /// The `MakeNamedVolume` to emit (None for the predefined air).
    pub volume: Option<Entity>,
    pub loc: Loc,
}

impl Medium {
    /// Indigo's predefined scene medium.
    pub fn air() -> Medium {
        Medium {
            name: "air".into(),
            uid: None,
            ior: 1.0,
            cauchy_b: 0.0,
            volume: None,
            loc: Loc::default(),
        }
    }
}

fn color(name: &str, c: [f64; 3], loc: &Loc) -> Param {
    Param::new(
        name,
        ParamValue::Color(vec![c.map(|v| v as f32)]),
        loc.clone(),
    )
}

/// Reads a `<medium>` element.
pub fn read(e: &Elem, ctx: &Ctx) -> Result<Medium, LxsError> {
    e.mark_used();
    let name = e.need(ctx, "name")?.str().to_string();
    let uid = e.child_int(ctx, "uid")?;
    e.ignore(&["precedence"]);
    let skin = ["epidermis", "dermis"].iter().find_map(|k| e.child(ctx, k));
    let body = if let Some(s) = skin {
        s.mark_all_used();
        ctx.warn(
            &s.loc,
            format!(
                "skin medium <{}> is not supported by LuxRender: read as a clear medium of index 1.4",
                s.name
            ),
        );
        None
    } else {
        Some(e.child(ctx, "basic").unwrap_or(e))
    };
    let mut ior = 1.4;
    let mut cauchy_b = 0.0;
    let mut ps = ParamSet::new();
    let mut kind = "clear";
    if let Some(b) = body {
        ior = b.child_num_or(ctx, "ior", 1.5)?;
        cauchy_b = b.child_num_or(ctx, "cauchy_b_coeff", 0.0)?;
        let absorption = match b.child(ctx, "absorption_coefficient_spectrum") {
            Some(a) => spectrum::of(a, ctx)?,
            None => [0.0; 3],
        };
        ps.push(color("absorption", absorption, &b.loc));
        if let Some(sss) = b.child(ctx, "subsurface_scattering") {
            kind = "homogeneous";
            let sigma_s = match sss.child(ctx, "scattering_coefficient_spectrum") {
                Some(s) => spectrum::of(s, ctx)?,
                None => [0.0; 3],
            };
            let mut g = [0.0; 3];
            if let Some(pf) = sss.child(ctx, "phase_function") {
                pf.ignore(&["uniform"]);
                if let Some(hg) = pf.child(ctx, "henyey_greenstein") {
                    g = spectrum::of(hg.need(ctx, "g_spectrum")?, ctx)?
                        .map(|v| v.clamp(-0.99, 0.99));
                }
            }
            ps = ParamSet::new();
            ps.push(color("sigma_a", absorption, &b.loc));
            ps.push(color("sigma_s", sigma_s, &sss.loc));
            ps.push(color("g", g, &sss.loc));
        }
    }
    ps.push(Param::new(
        "fresnel",
        ParamValue::Float(vec![ior as f32]),
        e.loc.clone(),
    ));
    Ok(Medium {
        name,
        uid,
        ior,
        cauchy_b,
        volume: Some(Entity {
            kind: kind.into(),
            params: ps,
            loc: e.loc.clone(),
        }),
        loc: e.loc.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::indigo::xml;
    use crate::lxs::ParseOptions;
    use std::path::Path;

    #[test]
    fn both_dialects_and_skin() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let doc = "<s><medium><name>glass</name><precedence>10</precedence><ior>1.5</ior><cauchy_b_coeff>0.004</cauchy_b_coeff>\
                   <absorption_coefficient_spectrum><rgb><rgb>1 2 3</rgb><gamma>1</gamma></rgb></absorption_coefficient_spectrum></medium>\
                   <medium><name>milk</name><uid>7</uid><basic><ior>1.35</ior><subsurface_scattering><scattering_coefficient_spectrum><uniform><value>10</value></uniform></scattering_coefficient_spectrum>\
                   <phase_function><henyey_greenstein><g_spectrum><uniform><value>2</value></uniform></g_spectrum></henyey_greenstein></phase_function></subsurface_scattering></basic></medium>\
                   <medium><name>skin</name><epidermis><melanin_fraction>0.1</melanin_fraction></epidermis></medium></s>";
        let p = xml::parse(doc.as_bytes(), &"t.igs".into()).unwrap();
        let g = read(&p.root.children[0], &ctx).unwrap();
        assert_eq!((g.ior, g.cauchy_b), (1.5, 0.004));
        let v = g.volume.unwrap();
        assert_eq!(v.kind, "clear");
        assert_eq!(v.params.color("absorption"), Some([1.0, 2.0, 3.0]));
        let m = read(&p.root.children[1], &ctx).unwrap();
        assert_eq!((m.ior, m.uid), (1.35, Some(7)));
        let v = m.volume.unwrap();
        assert_eq!(v.kind, "homogeneous");
        assert_eq!(v.params.color("g"), Some([0.99; 3]));
        let s = read(&p.root.children[2], &ctx).unwrap();
        assert_eq!(s.ior, 1.4);
        let w = ctx.take_warnings();
        assert_eq!(w.len(), 1);
        assert!(w[0].message.contains("epidermis"));
        p.root.report_unused(&ctx);
        assert!(ctx.take_warnings().is_empty());
    }
}

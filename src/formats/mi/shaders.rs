//! `shader "name" "type" (params)` and `material "name" ... end material`, and the luxfarm
//! material each mental ray material becomes.
//!
//! ```text
//! shader statement   --parse_shader-->   MiShader { kind, params }
//! material block     --parse_material--> MiMaterial { surface shader reference, ... }
//! surface shader (kind, params) --material_entity--> Material "matte" | "glossy" | "glass" ...
//! ```
//!
//! Shaders with an obvious luxfarm meaning:
//! - `mib_illum_lambert`: `diffuse` → matte `Kd` (ambient terms have no meaning in a path
//!   tracer).
//! - `one_color`: a constant, unlit colour → matte `Kd` = `color` (the closest lit surface; on
//!   the emitting geometry of an object light it is what the light's shader shines through).
//! - `mia_material`, `mia_material_x`: the basics. `diffuse` × `diffuse_weight` (defaults 0.5
//!   grey × 1) is the base; `reflectivity` (0.6) × `refl_color` (1) × the reflectance at
//!   normal incidence (`brdf_0_degree_refl`, 0.2; with `brdf_fresnel` on, ((ior − 1)/(ior +
//!   1))² of `refr_ior`) becomes a glossy coating `Ks` with roughness (1 − `refl_gloss`)²
//!   (`refl_gloss` 1 is a mirror-like coating; luxfarm clamps roughness to ≥ 0.006);
//!   `transparency` ≥ 0.5 makes it glass (`refr_ior`, 1.4; `refr_color`; rough glass when
//!   `refr_gloss` < 1); with no coating left it is matte. Textures, bump, cutout, anisotropy
//!   and the rest are ignored with a note.
//!
//! Any other shader (mental ray's other base and architectural shaders, MDL materials such
//! as an exporter's `mdl::...::matte`, phenomena): a located warning and a matte fallback
//! whose `Kd` is the shader's first colour parameter among `diffuse`, `color`, `tint`,
//! `base_color`, `diffuse_color`, `Kd` (LuxRender's default matte otherwise). A parameter
//! connected to another shader (`= "tex"`) is not evaluated: its default is used, with a
//! note.

use super::cursor::{Cursor, MiResult};
use super::lexer::Tok;
use super::params::{parse_list, parse_ref, ShaderParams, ShaderRef};
use crate::lxs::{Diagnostic, Entity, Loc, LxsErrorKind, Param, ParamSet, ParamValue};

#[derive(Clone, Debug, PartialEq)]
pub struct MiShader {
    pub name: String,
    pub loc: Loc,
    pub kind: String,
    pub params: ShaderParams,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct MiMaterial {
    pub name: String,
    pub loc: Loc,
    pub surface: Option<ShaderRef>,
    /// Other shader slots (displace, shadow, photon, ...), by name, with where.
    pub ignored: Vec<(String, Loc)>,
}

/// Reads `"type" ( params )` after `shader "name"`.
pub fn parse_shader(c: &mut Cursor, name: String, loc: Loc, max_len: usize) -> MiResult<MiShader> {
    let kind = c.string("the shader's type (a quoted name)")?;
    let params = parse_list(c, max_len)?;
    Ok(MiShader {
        name,
        loc,
        kind,
        params,
    })
}

/// Reads the block after `material "name"` up to and including `end material`.
pub fn parse_material(
    c: &mut Cursor,
    name: String,
    loc: Loc,
    max_len: usize,
) -> MiResult<MiMaterial> {
    let mut m = MiMaterial {
        name,
        loc,
        ..MiMaterial::default()
    };
    c.eat_word("opaque")?;
    loop {
        let at = c.loc()?;
        if let Some(r) = parse_ref(c, max_len)? {
            if m.surface.is_none() {
                m.surface = Some(r);
            } else {
                m.ignored.push(("surface shader list".into(), at));
            }
            continue;
        }
        match c.peek()? {
            Tok::Word("end") => {
                c.next()?;
                c.expect_word("material")?;
                return Ok(m);
            }
            Tok::Word(w) => {
                let w = w.to_string();
                c.next()?;
                while parse_ref(c, max_len)?.is_some() {}
                m.ignored.push((w, at));
            }
            _ => return Err(c.unexpected("a shader, a shader slot or 'end material'")),
        }
    }
}

fn param(name: &str, value: ParamValue, loc: &Loc) -> Param {
    Param::new(name, value, loc.clone())
}

fn color(v: [f64; 3]) -> ParamValue {
    ParamValue::Color(vec![v.map(|x| x as f32)])
}

fn scale(v: [f64; 3], s: f64) -> [f64; 3] {
    v.map(|x| x * s)
}

/// Notes each parameter connected to another shader (its default is used instead).
fn note_connections(params: &ShaderParams, kind: &str, w: &mut Vec<Diagnostic>) {
    for p in params.0.iter().filter(|p| params.is_connected(&p.name)) {
        w.push(Diagnostic {
            loc: p.loc.clone(),
            message: format!(
                "\"{}\" of {kind} is connected to another shader, which luxfarm does not evaluate: its default is used",
                p.name
            ),
        });
    }
}

/// A colour parameter unless connected.
fn col(p: &ShaderParams, name: &str, default: [f64; 3]) -> [f64; 3] {
    if p.is_connected(name) {
        default
    } else {
        p.color(name).unwrap_or(default)
    }
}

fn num(p: &ShaderParams, name: &str, default: f64) -> f64 {
    if p.is_connected(name) {
        default
    } else {
        p.scalar(name).unwrap_or(default)
    }
}

/// The luxfarm material for a mental ray material whose surface shader is `kind` with
/// `params` (`None`: no surface shader), named `name` (see the module docs).
pub fn material_entity(
    name: &str,
    loc: &Loc,
    surface: Option<(&str, &ShaderParams, &Loc)>,
    w: &mut Vec<Diagnostic>,
) -> Entity {
    let mut ps = ParamSet::new();
    let Some((kind, sp, sloc)) = surface else {
        w.push(Diagnostic {
            loc: loc.clone(),
            message: format!("material \"{name}\" has no surface shader: rendered as matte"),
        });
        return Entity {
            kind: "matte".into(),
            params: ps,
            loc: loc.clone(),
        };
    };
    note_connections(sp, kind, w);
    let kind_out = match kind {
        "mib_illum_lambert" => {
            ps.push(param("Kd", color(col(sp, "diffuse", [0.0; 3])), sloc));
            "matte"
        }
        "one_color" => {
            ps.push(param("Kd", color(col(sp, "color", [0.0; 3])), sloc));
            "matte"
        }
        "mia_material" | "mia_material_x" | "mia_material_x_passes" => mia(sp, sloc, &mut ps, w),
        other => {
            let found = [
                "diffuse",
                "color",
                "tint",
                "base_color",
                "diffuse_color",
                "Kd",
            ]
            .into_iter()
            .find(|n| !sp.is_connected(n) && sp.color(n).is_some());
            let how = match found {
                Some(n) => {
                    ps.push(param("Kd", color(col(sp, n, [0.5; 3])), sloc));
                    format!("its \"{n}\" as the diffuse colour")
                }
                None => "LuxRender's default matte".into(),
            };
            w.push(Diagnostic {
                loc: sloc.clone(),
                message: format!(
                    "shader \"{other}\" of material \"{name}\" has no luxfarm equivalent: rendered as matte with {how}"
                ),
            });
            "matte"
        }
    };
    Entity {
        kind: kind_out.into(),
        params: ps,
        loc: sloc.clone(),
    }
}

/// mia_material's basics (see the module docs); returns the luxfarm material kind.
fn mia(sp: &ShaderParams, loc: &Loc, ps: &mut ParamSet, w: &mut Vec<Diagnostic>) -> &'static str {
    let kd = scale(col(sp, "diffuse", [0.5; 3]), num(sp, "diffuse_weight", 1.0));
    let ior = num(sp, "refr_ior", 1.4);
    let transparency = num(sp, "transparency", 0.0);
    if transparency >= 0.5 {
        let gloss = num(sp, "refr_gloss", 1.0).clamp(0.0, 1.0);
        ps.push(param("Kt", color(col(sp, "refr_color", [1.0; 3])), loc));
        ps.push(param("Kr", color(col(sp, "refl_color", [1.0; 3])), loc));
        ps.push(param("index", ParamValue::Float(vec![ior as f32]), loc));
        if gloss < 1.0 {
            let r = ((1.0 - gloss) * (1.0 - gloss)).max(1e-3) as f32;
            ps.push(param("uroughness", ParamValue::Float(vec![r]), loc));
            ps.push(param("vroughness", ParamValue::Float(vec![r]), loc));
            return "roughglass";
        }
        return "glass";
    }
    if transparency > 0.0 {
        w.push(Diagnostic {
            loc: loc.clone(),
            message: format!(
                "mia_material transparency {transparency} below 0.5 is ignored (opaque)"
            ),
        });
    }
    let normal_refl = if sp.boolean("brdf_fresnel").unwrap_or(false) {
        ((ior - 1.0) / (ior + 1.0)).powi(2)
    } else {
        num(sp, "brdf_0_degree_refl", 0.2)
    };
    let ks = scale(
        col(sp, "refl_color", [1.0; 3]),
        num(sp, "reflectivity", 0.6) * normal_refl,
    );
    let metal = sp.boolean("refl_is_metal").unwrap_or(false);
    if ks.iter().all(|x| *x <= 0.0) && !metal {
        ps.push(param("Kd", color(kd), loc));
        return "matte";
    }
    let gloss = num(sp, "refl_gloss", 1.0).clamp(0.0, 1.0);
    let r = ((1.0 - gloss) * (1.0 - gloss)) as f32;
    if metal {
        // The reflection takes the diffuse colour; nothing is left for a diffuse base.
        ps.push(param("Kd", color([0.0; 3]), loc));
        ps.push(param(
            "Ks",
            color(scale(kd, num(sp, "reflectivity", 0.6))),
            loc,
        ));
    } else {
        ps.push(param("Kd", color(kd), loc));
        ps.push(param("Ks", color(ks), loc));
    }
    ps.push(param("uroughness", ParamValue::Float(vec![r]), loc));
    ps.push(param("vroughness", ParamValue::Float(vec![r]), loc));
    "glossy"
}

/// An error for a material referring to a shader that does not exist.
pub fn undefined_shader(name: &str, loc: &Loc) -> crate::lxs::LxsError {
    crate::lxs::LxsError::new(
        LxsErrorKind::Undefined,
        loc.clone(),
        format!("shader \"{name}\" is not defined"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shader(text: &str) -> MiShader {
        let mut c = Cursor::new(text, "t.mi".into());
        parse_shader(&mut c, "s".into(), Loc::default(), 100).unwrap()
    }

    fn entity(s: &MiShader, w: &mut Vec<Diagnostic>) -> Entity {
        material_entity("m", &Loc::default(), Some((&s.kind, &s.params, &s.loc)), w)
    }

    #[test]
    fn obvious_shaders_map() {
        let mut w = Vec::new();
        let s = shader("\"mib_illum_lambert\" (\"diffuse\" 0.2 0.3 0.4, \"ambient\" 0 0 0)");
        let e = entity(&s, &mut w);
        assert_eq!(e.kind, "matte");
        assert_eq!(e.params.color("Kd"), Some([0.2, 0.3, 0.4]));
        let s = shader("\"one_color\" (\"color\" 1 1 1 1,)");
        assert_eq!(entity(&s, &mut w).params.color("Kd"), Some([1.0; 3]));
        // mia defaults: glossy coating 0.6 × 0.2 over a 0.5 grey base, mirror-like.
        let e = entity(&shader("\"mia_material\" ()"), &mut w);
        assert_eq!(e.kind, "glossy");
        assert!((e.params.color("Ks").unwrap()[0] - 0.12).abs() < 1e-6);
        assert_eq!(e.params.float("uroughness"), Some(0.0));
        let e = entity(
            &shader("\"mia_material_x\" (\"transparency\" 1.0, \"refr_ior\" 1.5)"),
            &mut w,
        );
        assert_eq!(e.kind, "glass");
        assert_eq!(e.params.float("index"), Some(1.5));
        let e = entity(
            &shader("\"mia_material\" (\"reflectivity\" 0, \"diffuse\" 1 0 0)"),
            &mut w,
        );
        assert_eq!(
            (e.kind.as_str(), e.params.color("Kd")),
            ("matte", Some([1.0, 0.0, 0.0]))
        );
        assert!(w.is_empty(), "{w:?}");
    }

    #[test]
    fn unknown_shaders_fall_back_to_matte_with_a_located_warning() {
        let mut w = Vec::new();
        let s = shader("\"mdl::export_multi::matte\" (\"tint\" 0.5 0 0, \"roughness\" 0.5)");
        let e = entity(&s, &mut w);
        assert_eq!(e.kind, "matte");
        assert_eq!(e.params.color("Kd"), Some([0.5, 0.0, 0.0]));
        assert_eq!(w.len(), 1);
        assert!(w[0].message.contains("\"tint\""), "{}", w[0].message);
        let s = shader("\"mib_illum_lambert\" (\"diffuse\" = \"tex\")");
        let e = entity(&s, &mut w);
        assert_eq!(e.params.color("Kd"), Some([0.0; 3]));
        assert!(w[1].message.contains("connected"), "{}", w[1].message);
    }

    #[test]
    fn materials_take_their_first_shader_as_surface() {
        let mut c = Cursor::new(
            "opaque \"one_color\" (\"color\" 1 0 0) shadow = \"sh\" photon \"x\" () end material",
            "t.mi".into(),
        );
        let m = parse_material(&mut c, "m".into(), Loc::default(), 100).unwrap();
        assert!(
            matches!(m.surface, Some(ShaderRef::Inline { ref kind, .. }) if kind == "one_color")
        );
        assert_eq!(m.ignored.len(), 2);
    }
}

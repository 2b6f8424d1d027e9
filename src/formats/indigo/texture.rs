//! Indigo material parameters (constant, texture or shader) and Indigo textures turned into
//! LuxRender `Texture` statements.
//!
//! ```text
//! <albedo><constant>spectrum</constant></albedo>        --> Value::Const(rgb)
//! <albedo><texture><texture_index>i</texture_index>...  --> Value::Tex(i) --texture_stmts-->
//!     Texture "m.albedo" "color" "imagemap" (filename, gamma = exponent, gain = b, uv mapping)
//!     [+ Texture "m.albedo+c" "add" when the quadratic's constant c is not 0]
//! ```
//!
//! Indigo evaluates a texel x as `f = a·g² + b·g + c` with `g = x^exponent`; LuxRender's
//! imagemap gives `gain · x^gamma`, so `exponent` maps to `gamma`, `b` to `gain`, `c` to an
//! added constant, and a non-zero `a` is reported and dropped. The uv transform (2×2 matrix and
//! translation) maps to LuxRender's uv scale and offset, with v flipped (Indigo's v grows
//! upwards, LuxRender's image rows downwards); a matrix with off-diagonal terms is reported.
//! Shader parameters cannot be evaluated: reported, and the parameter keeps its default.

use super::ctx::{err, Ctx};
use super::node::Elem;
use super::spectrum;
use crate::lxs::{Entity, Loc, LxsError, LxsErrorKind, Param, ParamSet, ParamValue};
use std::path::Path;

/// A material parameter's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Const([f64; 3]),
    /// A texture of the material's list, by index.
    Tex(usize, Loc),
}

/// A LuxRender `Texture` statement to emit.
#[derive(Clone, Debug)]
pub struct TexOut {
    pub name: String,
    /// "color" or "float".
    pub ty: &'static str,
    pub entity: Entity,
}

fn param(name: &str, value: ParamValue, loc: &Loc) -> Param {
    Param::new(name, value, loc.clone())
}

/// Reads a wavelength-dependent (colour) parameter `name` of `parent`. Accepts the
/// `constant`/`texture`/`shader` forms, and the older forms: a spectrum element directly, or
/// `r g b` text. Shaders give `None` with a warning.
pub fn color(parent: &Elem, name: &str, ctx: &Ctx) -> Result<Option<Value>, LxsError> {
    let Some(e) = parent.child(ctx, name) else {
        return Ok(None);
    };
    value(e, ctx, true)
}

/// Reads a wavelength-independent (scalar) parameter `name` of `parent`: `constant` holding a
/// number (or a spectrum, averaged), `texture`, `shader`, or a bare number.
pub fn float(parent: &Elem, name: &str, ctx: &Ctx) -> Result<Option<Value>, LxsError> {
    let Some(e) = parent.child(ctx, name) else {
        return Ok(None);
    };
    value(e, ctx, false)
}

fn value(e: &Elem, ctx: &Ctx, colour: bool) -> Result<Option<Value>, LxsError> {
    if let Some(c) = e.child(ctx, "constant") {
        if let Some(s) = spectrum::find(c, ctx) {
            return spectrum::read(s, ctx).map(|v| Some(Value::Const(v)));
        }
        let v = c.num(ctx)?;
        return Ok(Some(Value::Const([v; 3])));
    }
    if let Some(t) = e.child(ctx, "texture") {
        let i = t.need(ctx, "texture_index")?.int(ctx)?;
        let i = usize::try_from(i).map_err(|_| {
            err(
                LxsErrorKind::InvalidValue,
                &t.loc,
                format!("texture_index {i} must be >= 0"),
            )
        })?;
        return Ok(Some(Value::Tex(i, t.loc.clone())));
    }
    if let Some(s) = e.child(ctx, "shader") {
        s.mark_all_used();
        ctx.warn(
            &s.loc,
            format!(
                "<{}> is an ISL shader, which luxfarm cannot evaluate: the parameter keeps its default",
                e.name
            ),
        );
        return Ok(None);
    }
    if let Some(s) = spectrum::find(e, ctx) {
        return spectrum::read(s, ctx).map(|v| Some(Value::Const(v)));
    }
    let n = e.nums(ctx)?;
    match (n.len(), colour) {
        (1, _) => Ok(Some(Value::Const([n[0]; 3]))),
        (3, true) => Ok(Some(Value::Const([n[0], n[1], n[2]]))),
        _ => Err(err(
            LxsErrorKind::WrongValueCount,
            &e.loc,
            format!(
                "<{}> needs <constant>, <texture> or <shader> (or {} number(s))",
                e.name,
                if colour { "1 or 3" } else { "1" }
            ),
        )),
    }
}

/// The LuxRender statements for Indigo texture `def`, used as a `ty` ("color"/"float")
/// texture named `name` (the last statement bears that name). `dir` is the directory of the
/// file the texture was written in.
pub fn statements(
    def: &Elem,
    name: &str,
    ty: &'static str,
    dir: &Path,
    ctx: &Ctx,
) -> Result<Vec<TexOut>, LxsError> {
    def.mark_used();
    let loc = &def.loc;
    let path = def.need(ctx, "path")?;
    let filename = ctx.scene_relative(path.str(), dir, &path.loc)?;
    let gamma = def.child_num_or(ctx, "exponent", 2.2)?;
    let a = def.child_num_or(ctx, "a", 0.0)?;
    let b = def.child_num_or(ctx, "b", 1.0)?;
    let c = def.child_num_or(ctx, "c", 0.0)?;
    def.child(ctx, "uv_set");
    if a != 0.0 {
        ctx.warn(
            loc,
            format!("texture quadratic term a = {a} cannot be expressed in LuxRender: dropped"),
        );
    }
    let mut ps = ParamSet::new();
    ps.push(param(
        "filename",
        ParamValue::String(vec![filename]),
        &path.loc,
    ));
    ps.push(param("gamma", ParamValue::Float(vec![gamma as f32]), loc));
    ps.push(param("gain", ParamValue::Float(vec![b as f32]), loc));
    ps.push(param("mapping", ParamValue::String(vec!["uv".into()]), loc));
    let (scale, delta) = uv_transform(def, ctx)?;
    ps.push(param(
        "uscale",
        ParamValue::Float(vec![scale[0] as f32]),
        loc,
    ));
    ps.push(param(
        "vscale",
        ParamValue::Float(vec![-scale[1] as f32]),
        loc,
    ));
    ps.push(param(
        "udelta",
        ParamValue::Float(vec![delta[0] as f32]),
        loc,
    ));
    ps.push(param(
        "vdelta",
        ParamValue::Float(vec![(1.0 - delta[1]) as f32]),
        loc,
    ));
    let image_name = if c != 0.0 {
        format!("{name}.image")
    } else {
        name.to_string()
    };
    let mut out = vec![TexOut {
        name: image_name.clone(),
        ty,
        entity: Entity {
            kind: "imagemap".into(),
            params: ps,
            loc: loc.clone(),
        },
    }];
    if c != 0.0 {
        let mut add = ParamSet::new();
        add.push(param("tex1", ParamValue::Texture(image_name), loc));
        let cv = if ty == "color" {
            ParamValue::Color(vec![[c as f32; 3]])
        } else {
            ParamValue::Float(vec![c as f32])
        };
        add.push(param("tex2", cv, loc));
        out.push(TexOut {
            name: name.to_string(),
            ty,
            entity: Entity {
                kind: "add".into(),
                params: add,
                loc: loc.clone(),
            },
        });
    }
    Ok(out)
}

/// The uv scale and offset of `tex_coord_generation/uv` (identity when absent).
fn uv_transform(def: &Elem, ctx: &Ctx) -> Result<([f64; 2], [f64; 2]), LxsError> {
    let Some(gen) = def.child(ctx, "tex_coord_generation") else {
        return Ok(([1.0, 1.0], [0.0, 0.0]));
    };
    let Some(uv) = gen.child(ctx, "uv") else {
        return Ok(([1.0, 1.0], [0.0, 0.0]));
    };
    let m = match uv.child(ctx, "matrix") {
        Some(m) => m.n_nums(ctx, 4)?,
        None => vec![1.0, 0.0, 0.0, 1.0],
    };
    let t = match uv.child(ctx, "translation") {
        Some(t) => t.n_nums(ctx, 2)?,
        None => vec![0.0, 0.0],
    };
    if m[1] != 0.0 || m[2] != 0.0 {
        ctx.warn(
            &uv.loc,
            "uv matrix with rotation or shear: LuxRender's uv mapping only scales and offsets; \
             the off-diagonal terms are dropped",
        );
    }
    Ok(([m[0], m[3]], [t[0], t[1]]))
}

/// The `uv_set` named by a texture definition, if any.
pub fn uv_set(def: &Elem) -> Option<String> {
    def.children
        .iter()
        .find(|c| c.name == "uv_set")
        .map(|c| c.str().to_string())
        .filter(|s| !s.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::indigo::xml;
    use crate::lxs::ParseOptions;

    fn parsed(text: &str) -> xml::Parsed {
        xml::parse(text.as_bytes(), &"t.igs".into()).unwrap()
    }

    #[test]
    fn parameter_forms() {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let p = parsed(
            "<m><a><constant><rgb><rgb>1 0.5 0</rgb><gamma>1</gamma></rgb></constant></a>\
             <b><texture><texture_index>1</texture_index></texture></b>\
             <c><constant>10</constant></c><d>0 1 0</d><e>3</e>\
             <f><shader><shader>def eval() real: 1.0</shader></shader></f></m>",
        );
        let r = &p.root;
        assert_eq!(
            color(r, "a", &ctx).unwrap(),
            Some(Value::Const([1.0, 0.5, 0.0]))
        );
        assert!(matches!(
            color(r, "b", &ctx).unwrap(),
            Some(Value::Tex(1, _))
        ));
        assert_eq!(float(r, "c", &ctx).unwrap(), Some(Value::Const([10.0; 3])));
        assert_eq!(
            color(r, "d", &ctx).unwrap(),
            Some(Value::Const([0.0, 1.0, 0.0]))
        );
        assert_eq!(float(r, "e", &ctx).unwrap(), Some(Value::Const([3.0; 3])));
        assert_eq!(float(r, "f", &ctx).unwrap(), None);
        assert_eq!(float(r, "missing", &ctx).unwrap(), None);
        assert!(float(r, "d", &ctx).is_err());
        assert_eq!(ctx.take_warnings().len(), 1);
    }

    #[test]
    fn texture_maps_to_imagemap_with_flipped_v_and_added_constant() {
        let ctx = Ctx::new(Path::new("scenes/t.igs"), &ParseOptions::default());
        let p = parsed(
            "<texture><uv_set>albedo</uv_set><path>tex\\wood.png</path><exponent>2.2</exponent>\
             <b>0.5</b><c>0.1</c><tex_coord_generation><uv><matrix>2 0 0 3</matrix>\
             <translation>0.5 0.25</translation></uv></tex_coord_generation></texture>",
        );
        let out = statements(&p.root, "m.Kd", "color", Path::new("scenes"), &ctx).unwrap();
        assert_eq!(out.len(), 2);
        let img = &out[0].entity.params;
        assert_eq!(img.string("filename"), Some("tex/wood.png"));
        assert_eq!(img.float("gain"), Some(0.5));
        assert_eq!(img.float("vscale"), Some(-3.0));
        assert_eq!(img.float("vdelta"), Some(0.75));
        assert_eq!(out[1].name, "m.Kd");
        assert_eq!(out[1].entity.kind, "add");
        assert_eq!(uv_set(&p.root).as_deref(), Some("albedo"));
    }
}

//! What one Indigo material becomes ([`MatOut`], with its [`Emission`]) and the converter
//! that reads the material's parameters into it: textures by index, colours, scalars, bump
//! and emission. `material.rs` picks the LuxRender material for each Indigo type and calls
//! these readers; it re-exports the output types.

use super::ctx::{err, Ctx};
use super::node::Elem;
use super::texture::{self, TexOut, Value};
use crate::lxs::{Entity, Loc, LxsError, LxsErrorKind, Param, ParamSet, ParamValue};
use std::path::Path;

/// An emitting material's area light.
#[derive(Clone, Debug)]
pub struct Emission {
    /// `L`: a colour or the name of a colour texture.
    pub l: ParamValue,
    pub layer: i64,
    pub loc: Loc,
}

/// A converted material.
#[derive(Clone, Debug)]
pub struct MatOut {
    /// The LuxRender material name.
    pub name: String,
    pub loc: Loc,
    pub textures: Vec<TexOut>,
    /// `MakeNamedMaterial` parameters, `string type` included.
    pub params: ParamSet,
    pub emission: Option<Emission>,
    /// The uv set its textures ask for.
    pub uv_set: Option<String>,
    /// The LuxRender volume inside shapes of this material.
    pub interior: Option<String>,
    /// LuxRender names of the materials it mixes (emitted before it).
    pub deps: Vec<String>,
}

/// Converts one material's body.
pub(super) struct Conv<'a> {
    pub(super) ctx: &'a Ctx,
    pub(super) dir: &'a Path,
    pub(super) te: &'a Elem,
    pub(super) defs: Vec<&'a Elem>,
    pub(super) out: MatOut,
}

impl<'a> Conv<'a> {
    pub(super) fn put(&mut self, name: &str, v: ParamValue, loc: &Loc) {
        self.out.params.push(Param::new(name, v, loc.clone()));
    }

    fn def(&self, i: usize, loc: &Loc) -> Result<&'a Elem, LxsError> {
        self.defs.get(i).copied().ok_or_else(|| {
            err(
                LxsErrorKind::Undefined,
                loc,
                format!(
                    "texture_index {i}: the material defines {} texture(s)",
                    self.defs.len()
                ),
            )
        })
    }

    /// A texture of this material as a LuxRender texture of type `ty`; returns its name.
    pub(super) fn texture(
        &mut self,
        i: usize,
        loc: &Loc,
        lux: &str,
        ty: &'static str,
    ) -> Result<String, LxsError> {
        let def = self.def(i, loc)?;
        let name = format!("{}.{lux}", self.out.name);
        let stmts = texture::statements(def, &name, ty, self.dir, self.ctx)?;
        if let Some(set) = texture::uv_set(def) {
            match &self.out.uv_set {
                Some(s) if *s != set => self.ctx.warn(
                    &def.loc,
                    format!(
                        "textures of one material use uv sets \"{s}\" and \"{set}\": LuxRender has one uv set per mesh, \"{s}\" is used"
                    ),
                ),
                Some(_) => {}
                None => self.out.uv_set = Some(set),
            }
        }
        self.out.textures.extend(stmts);
        Ok(name)
    }

    /// A colour parameter as a LuxRender parameter value.
    fn color_value(&mut self, v: Value, lux: &str) -> Result<ParamValue, LxsError> {
        Ok(match v {
            Value::Const(c) => ParamValue::Color(vec![c.map(|x| x as f32)]),
            Value::Tex(i, loc) => ParamValue::Texture(self.texture(i, &loc, lux, "color")?),
        })
    }

    pub(super) fn color(&mut self, indigo: &str, lux: &str) -> Result<bool, LxsError> {
        match texture::color(self.te, indigo, self.ctx)? {
            Some(v) => {
                let loc = self
                    .te
                    .child(self.ctx, indigo)
                    .map(|e| e.loc.clone())
                    .unwrap_or_default();
                let pv = self.color_value(v, lux)?;
                self.put(lux, pv, &loc);
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// A scalar parameter mapped through `f` when constant; textures pass through unmapped
    /// when `f` is the identity (`tex_ok`), else are reported.
    pub(super) fn float(
        &mut self,
        indigo: &str,
        lux: &[&str],
        f: impl Fn(f64) -> f64,
        tex_ok: bool,
    ) -> Result<(), LxsError> {
        let Some(v) = texture::float(self.te, indigo, self.ctx)? else {
            return Ok(());
        };
        let loc = self
            .te
            .child(self.ctx, indigo)
            .map(|e| e.loc.clone())
            .unwrap_or_default();
        let pv = match v {
            Value::Const(c) => ParamValue::Float(vec![f((c[0] + c[1] + c[2]) / 3.0) as f32]),
            Value::Tex(i, tloc) if tex_ok => {
                ParamValue::Texture(self.texture(i, &tloc, lux[0], "float")?)
            }
            Value::Tex(_, tloc) => {
                self.ctx.warn(
                    &tloc,
                    format!(
                        "a texture for <{indigo}> cannot be mapped to LuxRender's {}: default kept",
                        lux[0]
                    ),
                );
                return Ok(());
            }
        };
        for l in lux {
            self.put(l, pv.clone(), &loc);
        }
        Ok(())
    }

    pub(super) fn exponent_roughness(&mut self) -> Result<(), LxsError> {
        self.float(
            "exponent",
            &["uroughness", "vroughness"],
            |e| if e > 0.0 { 1.0 / e } else { 1.0 },
            false,
        )
    }

    pub(super) fn kind(&mut self, k: &str) {
        let loc = self.te.loc.clone();
        self.put("type", ParamValue::String(vec![k.into()]), &loc);
    }

    /// bump (displacement parameter) and the older bump_map texture element.
    pub(super) fn bump(&mut self) -> Result<(), LxsError> {
        if let Some(b) = self.te.child(self.ctx, "bump_map") {
            let name = format!("{}.bumpmap", self.out.name);
            let stmts = texture::statements(b, &name, "float", self.dir, self.ctx)?;
            self.out.textures.extend(stmts);
            self.put("bumpmap", ParamValue::Texture(name), &b.loc.clone());
            return Ok(());
        }
        match texture::float(self.te, "bump", self.ctx)? {
            Some(Value::Tex(i, loc)) => {
                let name = self.texture(i, &loc, "bumpmap", "float")?;
                self.put("bumpmap", ParamValue::Texture(name), &loc);
            }
            // A constant displacement moves nothing.
            Some(Value::Const(_)) | None => {}
        }
        if let Some(d) = self.te.child(self.ctx, "displacement") {
            d.mark_all_used();
            self.ctx.warn(
                &d.loc,
                "displacement needs subdivision, which luxfarm does not do: ignored",
            );
        }
        Ok(())
    }

    pub(super) fn emission(&mut self) -> Result<(), LxsError> {
        let base = texture::color(self.te, "base_emission", self.ctx)?;
        let modul = texture::color(self.te, "emission", self.ctx)?;
        let layer = self.te.child_int(self.ctx, "layer")?.unwrap_or(0);
        let Some(base) = base else {
            return Ok(());
        };
        let loc = self
            .te
            .child(self.ctx, "base_emission")
            .map(|e| e.loc.clone())
            .unwrap_or_default();
        let l = match (base, modul) {
            (Value::Const(b), None) => ParamValue::Color(vec![b.map(|x| x as f32)]),
            (Value::Const(b), Some(Value::Const(m))) => {
                ParamValue::Color(vec![[0, 1, 2].map(|k| (b[k] * m[k]) as f32)])
            }
            (b, m) => {
                let t1 = self.color_value(b, "L.base")?;
                let t2 = match m {
                    Some(m) => self.color_value(m, "L.emission")?,
                    None => ParamValue::Color(vec![[1.0; 3]]),
                };
                let name = format!("{}.L", self.out.name);
                let mut ps = ParamSet::new();
                ps.push(Param::new("tex1", t1, loc.clone()));
                ps.push(Param::new("tex2", t2, loc.clone()));
                self.out.textures.push(TexOut {
                    name: name.clone(),
                    ty: "color",
                    entity: Entity {
                        kind: "scale".into(),
                        params: ps,
                        loc: loc.clone(),
                    },
                });
                ParamValue::Texture(name)
            }
        };
        let black =
            matches!(&l, ParamValue::Color(c) if c.iter().all(|v| v.iter().all(|x| *x <= 0.0)));
        if !black {
            self.out.emission = Some(Emission { l, layer, loc });
        }
        Ok(())
    }
}

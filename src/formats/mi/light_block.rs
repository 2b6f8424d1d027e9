//! The `light "name" ... end light` block read into [`MiLight`]: the seed (origin, direction,
//! spread), the area primitive with its sample counts, the shader, and the statements that
//! mean nothing to luxfarm, kept for notes. `lights.rs` turns a `MiLight` into luxfarm's
//! lights and re-exports what is here.

use super::cursor::{Cursor, MiResult};
use super::lexer::Tok;
use super::params::{parse_ref, ShaderRef};
use crate::lxs::{Loc, LxsError, LxsErrorKind};

#[derive(Clone, Debug, PartialEq)]
pub enum AreaPrim {
    Rectangle([f64; 3], [f64; 3]),
    Disc([f64; 3], f64),
    Sphere(f64),
    Cylinder([f64; 3], f64),
    Object(String),
    User,
}

/// Area sample counts: u, v, low level, low u, low v.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Samples {
    pub u: i64,
    pub v: i64,
    pub level: i64,
    pub low_u: i64,
    pub low_v: i64,
}

impl Default for Samples {
    fn default() -> Self {
        Samples {
            u: 3,
            v: 3,
            level: 3,
            low_u: 2,
            low_v: 2,
        }
    }
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct MiLight {
    pub name: String,
    pub loc: Loc,
    pub shader: Option<ShaderRef>,
    pub origin: Option<[f64; 3]>,
    pub direction: Option<[f64; 3]>,
    pub spread: Option<f64>,
    pub area: Option<(AreaPrim, Loc)>,
    pub samples: Samples,
    pub visible: bool,
    pub energy: Option<([f64; 3], Loc)>,
    pub exponent: Option<f64>,
    /// Statements with no meaning for luxfarm (photons, shadow maps, emitter ...).
    pub ignored: Vec<(String, Loc)>,
}

/// Largest area sample count per direction.
const MAX_SAMPLES: i64 = 1024;

/// Reads the block after `light "name"` up to and including `end light`.
pub fn parse(c: &mut Cursor, name: String, loc: Loc, max_len: usize) -> MiResult<MiLight> {
    let mut l = MiLight {
        name,
        loc,
        ..MiLight::default()
    };
    loop {
        let at = c.loc()?;
        if let Some(r) = parse_ref(c, max_len)? {
            if l.shader.is_none() {
                l.shader = Some(r);
            } else {
                l.ignored.push(("second light shader".into(), at));
            }
            continue;
        }
        let w = match c.peek()? {
            Tok::Word(w) => *w,
            _ => return Err(c.unexpected("a light statement or 'end light'")),
        };
        c.next()?;
        match w {
            "end" => {
                c.expect_word("light")?;
                return Ok(l);
            }
            "origin" => l.origin = Some(c.numbers::<3>("the origin's x y z")?),
            "direction" => l.direction = Some(c.numbers::<3>("the direction's x y z")?),
            "spread" => l.spread = Some(c.number("the spread (a cosine)")?),
            "rectangle" => {
                let [a, b, cc, d, e, f] = c.numbers::<6>("the two edge vectors")?;
                area(c, &mut l, AreaPrim::Rectangle([a, b, cc], [d, e, f]), at)?;
            }
            "disc" => {
                let n = c.numbers::<3>("the disc's normal")?;
                let r = c.number("the disc's radius")?;
                area(c, &mut l, AreaPrim::Disc(n, r), at)?;
            }
            "sphere" => {
                let r = c.number("the sphere's radius")?;
                area(c, &mut l, AreaPrim::Sphere(r), at)?;
            }
            "cylinder" => {
                let axis = c.numbers::<3>("the cylinder's axis")?;
                let r = c.number("the cylinder's radius")?;
                area(c, &mut l, AreaPrim::Cylinder(axis, r), at)?;
            }
            "object" => {
                let inst = c.string("the emitting instance's name")?;
                area(c, &mut l, AreaPrim::Object(inst), at)?;
            }
            "user" => area(c, &mut l, AreaPrim::User, at)?,
            "visible" => l.visible = c.flag()?,
            "energy" => l.energy = Some((c.numbers::<3>("the energy's r g b")?, at)),
            "exponent" => l.exponent = Some(c.number("the exponent")?),
            "emitter" => {
                while parse_ref(c, max_len)?.is_some() {}
                l.ignored.push(("photon emitter shader".into(), at));
            }
            other => {
                // caustic/globillum photons, shadowmap ..., tag, label, data, hardware.
                c.skip_line()?;
                l.ignored.push((other.to_string(), at));
            }
        }
    }
}

/// Records an area primitive and reads its optional sample counts.
fn area(c: &mut Cursor, l: &mut MiLight, prim: AreaPrim, at: Loc) -> MiResult<()> {
    let mut counts = Vec::new();
    while c.at_number()? && counts.len() < 5 {
        counts.push(c.int("an area sample count", 0, MAX_SAMPLES)?);
    }
    let s = &mut l.samples;
    let fields = [&mut s.u, &mut s.v, &mut s.level, &mut s.low_u, &mut s.low_v];
    for (f, v) in fields.into_iter().zip(counts) {
        *f = v;
    }
    if let AreaPrim::Disc(_, r) | AreaPrim::Sphere(r) | AreaPrim::Cylinder(_, r) = &prim {
        if r.is_nan() || *r <= 0.0 {
            return Err(LxsError::new(
                LxsErrorKind::InvalidValue,
                at,
                format!("area light radius must be positive, got {r}"),
            ));
        }
    }
    l.area = Some((prim, at));
    Ok(())
}

//! `instance "name" "item" ... end instance` and `instgroup "name" "a" "b" ... end
//! instgroup`: where things are placed, and with which materials.
//!
//! ```text
//! instance block --parse_instance--> MiInstance { item, world→local matrix, material(s) }
//! instgroup block --parse_instgroup--> MiInstGroup { members }
//! ```
//!
//! mental ray writes an instance's `transform` as the 16 numbers of the matrix that takes a
//! point of the parent space (the world, for a top-level instance) to the instance's own
//! space, row by row with the translation in the last row: a point p (a row vector) maps to
//! p·M. In column-vector form that is Mᵀ, whose columns are the rows as written — so the
//! numbers read as columns give the world→local matrix directly ([`world_to_local`]); the
//! item's object→world matrix is its inverse. The .lxs twin of the sample scene agrees (see
//! `tests/mentalray_cornell.rs`). Nested instances compose parent first. `motion transform`
//! (motion blur) is read and ignored with a note.

use super::cursor::{Cursor, MiResult};
use super::lexer::Tok;
use crate::lxs::{Loc, LxsError, LxsErrorKind};
use glam::DMat4;

/// The material(s) an instance gives its item.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum InstMaterial {
    /// None: inherited from the instances above.
    #[default]
    None,
    One(String),
    /// A material array, indexed by the polygons' tags.
    Array(Vec<String>),
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct MiInstance {
    pub name: String,
    pub loc: Loc,
    pub item: String,
    pub item_loc: Loc,
    /// Parent space → instance space (column-vector convention), when written.
    pub transform: Option<DMat4>,
    pub material: InstMaterial,
    pub material_loc: Loc,
    pub hide: bool,
    /// Statements read and not used (motion, geometry shaders), with where.
    pub ignored: Vec<(String, Loc)>,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct MiInstGroup {
    pub name: String,
    pub loc: Loc,
    pub members: Vec<(String, Loc)>,
}

/// The world→local matrix of 16 numbers written row by row, translation last.
pub fn world_to_local(m: [f64; 16]) -> DMat4 {
    DMat4::from_cols_array(&m)
}

/// Reads a transform's 16 numbers, refusing a singular or non-finite matrix.
fn transform(c: &mut Cursor, at: &Loc) -> MiResult<DMat4> {
    let m = c.numbers::<16>("a transform's 16 numbers")?;
    let mat = world_to_local(m);
    let det = mat.determinant();
    if !(det.is_finite() && det.abs() > 1e-300) {
        return Err(LxsError::new(
            LxsErrorKind::InvalidValue,
            at.clone(),
            "singular transform (it cannot be inverted)",
        ));
    }
    Ok(mat)
}

/// Reads the block after `instance "name"` up to and including `end instance`.
pub fn parse_instance(
    c: &mut Cursor,
    name: String,
    loc: Loc,
    max_len: usize,
) -> MiResult<MiInstance> {
    let item_loc = c.loc()?;
    if c.at_word("geometry")? {
        return Err(c.error(
            LxsErrorKind::Unsupported,
            "instances of geometry shaders are not supported",
        ));
    }
    let item = c.string("the instanced item's name")?;
    let mut inst = MiInstance {
        name,
        loc,
        item,
        item_loc,
        ..MiInstance::default()
    };
    if c.at_punct(b'(')? {
        super::params::parse_list(c, max_len)?;
        inst.ignored
            .push(("instance parameters".into(), c.last_loc()));
    }
    loop {
        let at = c.loc()?;
        let w = match c.peek()? {
            Tok::Word(w) => *w,
            _ => return Err(c.unexpected("an instance statement or 'end instance'")),
        };
        c.next()?;
        match w {
            "end" => {
                c.expect_word("instance")?;
                return Ok(inst);
            }
            "transform" => inst.transform = Some(transform(c, &at)?),
            "motion" => {
                if c.eat_word("transform")? {
                    transform(c, &at)?;
                    inst.ignored.push(("motion transform".into(), at));
                } else {
                    c.flag()?;
                }
            }
            "material" => {
                inst.material_loc = at;
                inst.material = if c.eat_punct(b'[')? {
                    let mut names = Vec::new();
                    loop {
                        if c.eat_punct(b']')? {
                            break;
                        }
                        if names.len() >= max_len {
                            return Err(
                                c.error(LxsErrorKind::ArrayTooLong, "material array too long")
                            );
                        }
                        names.push(c.string("a material name")?);
                        if !c.eat_punct(b',')? && !c.at_punct(b']')? {
                            return Err(c.unexpected("',' or ']' in a material array"));
                        }
                    }
                    InstMaterial::Array(names)
                } else {
                    InstMaterial::One(c.string("a material name or '['")?)
                };
            }
            "hide" => inst.hide = c.flag()?,
            "override" | "geometry" => {
                return Err(LxsError::new(
                    LxsErrorKind::Unsupported,
                    at,
                    format!("instance '{w}' is not supported"),
                ))
            }
            // visible, shadow, trace, caustic, globillum, finalgather, tag, data, approximate...
            _ => c.skip_values()?,
        }
    }
}

/// Reads the block after `instgroup "name"` up to and including `end instgroup`.
pub fn parse_instgroup(
    c: &mut Cursor,
    name: String,
    loc: Loc,
    max_len: usize,
) -> MiResult<MiInstGroup> {
    let mut g = MiInstGroup {
        name,
        loc,
        members: Vec::new(),
    };
    loop {
        match c.peek()? {
            Tok::Str(_) => {
                if g.members.len() >= max_len {
                    return Err(c.error(LxsErrorKind::ArrayTooLong, "too many instgroup members"));
                }
                let at = c.loc()?;
                g.members.push((c.string("a member")?, at));
            }
            Tok::Word("end") => {
                c.next()?;
                c.expect_word("instgroup")?;
                return Ok(g);
            }
            Tok::Word(_) => {
                // tagged, merge, ... (flags of the group).
                c.next()?;
                c.skip_values()?;
            }
            _ => return Err(c.unexpected("a quoted member name or 'end instgroup'")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn rows_with_the_translation_last_map_world_to_local() {
        // mental ray: p·M with translation (−1, −2, −3) in the last row: the world point
        // (1, 2, 3) is the instance's origin.
        let m = world_to_local([
            1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., -1., -2., -3., 1.,
        ]);
        assert_eq!(m.transform_point3(DVec3::new(1., 2., 3.)), DVec3::ZERO);
        assert_eq!(
            m.inverse().transform_point3(DVec3::ZERO),
            DVec3::new(1., 2., 3.)
        );
    }

    #[test]
    fn an_instance_with_a_material_array() {
        let mut c = Cursor::new(
            "\"obj\" material [ \"a\", \"b\" ] visible on transform 2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1 end instance",
            "t.mi".into(),
        );
        let i = parse_instance(&mut c, "i".into(), Loc::default(), 100).unwrap();
        assert_eq!(i.item, "obj");
        assert_eq!(
            i.material,
            InstMaterial::Array(vec!["a".into(), "b".into()])
        );
        assert_eq!(i.transform.unwrap().determinant(), 8.0);
        let mut c = Cursor::new(
            "\"o\" transform 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1 end instance",
            "t.mi".into(),
        );
        let e = parse_instance(&mut c, "i".into(), Loc::default(), 100).unwrap_err();
        assert!(e.message.contains("singular"), "{e}");
    }
}

//! Shader parameter lists — `( "name" value, "name" value, ... )` — and shader references,
//! as `shader`, `material` and `light` statements write them.
//!
//! ```text
//! ( "color" 1 1 1 1, "diffuse" = "tex", "lights" ["l1", "l2"], "s" {"a" 1} )
//!     --parse_list--> ShaderParams [(name, MiValue, Loc)]
//! = "shader_name"  |  "shader_type" ( ... )   --parse_ref--> ShaderRef
//! ```
//!
//! A value is numbers (a scalar, colour or vector), on/off, a string, a reference to another
//! shader (`= "name"`, a shader connection), an array `[...]` or a struct `{...}`. Nesting
//! is bounded ([`MAX_NESTING`]) and so is every list (`ParseOptions::max_array_len`).

use super::cursor::{Cursor, MiResult};
use super::lexer::Tok;
use crate::lxs::{Loc, LxsErrorKind};

/// Deepest nesting of arrays and structs in a parameter value.
pub const MAX_NESTING: usize = 32;

/// A parameter value.
#[derive(Clone, Debug, PartialEq)]
pub enum MiValue {
    Numbers(Vec<f64>),
    Bool(bool),
    Str(String),
    /// `= "shader"`: the output of another shader (or `= interface "p"` of a phenomenon).
    Ref(String),
    Array(Vec<MiValue>),
    Struct(Vec<(String, MiValue)>),
}

/// A named parameter with where it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct MiParam {
    pub name: String,
    pub value: MiValue,
    pub loc: Loc,
}

/// The parameters of one shader, in written order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShaderParams(pub Vec<MiParam>);

impl ShaderParams {
    /// The last parameter of this name.
    pub fn get(&self, name: &str) -> Option<&MiParam> {
        self.0.iter().rev().find(|p| p.name == name)
    }

    /// A scalar parameter (its first number).
    pub fn scalar(&self, name: &str) -> Option<f64> {
        match &self.get(name)?.value {
            MiValue::Numbers(v) => v.first().copied(),
            MiValue::Bool(b) => Some(f64::from(u8::from(*b))),
            _ => None,
        }
    }

    /// A colour parameter: r g b (an alpha is ignored; one number is grey).
    pub fn color(&self, name: &str) -> Option<[f64; 3]> {
        match &self.get(name)?.value {
            MiValue::Numbers(v) => match v.as_slice() {
                [g] => Some([*g; 3]),
                [r, g, b, ..] => Some([*r, *g, *b]),
                _ => None,
            },
            _ => None,
        }
    }

    pub fn boolean(&self, name: &str) -> Option<bool> {
        match &self.get(name)?.value {
            MiValue::Bool(b) => Some(*b),
            MiValue::Numbers(v) => v.first().map(|x| *x != 0.0),
            _ => None,
        }
    }

    /// Whether the parameter is connected to another shader's output.
    pub fn is_connected(&self, name: &str) -> bool {
        matches!(self.get(name).map(|p| &p.value), Some(MiValue::Ref(_)))
    }
}

/// A shader as used by a material or a light: a named shader, or one defined in place.
#[derive(Clone, Debug, PartialEq)]
pub enum ShaderRef {
    Named {
        name: String,
        loc: Loc,
    },
    Inline {
        kind: String,
        params: ShaderParams,
        loc: Loc,
    },
}

impl ShaderRef {
    pub fn loc(&self) -> &Loc {
        match self {
            ShaderRef::Named { loc, .. } | ShaderRef::Inline { loc, .. } => loc,
        }
    }
}

/// Reads a shader reference if one starts here: `= "name"` or `"type" ( params )`.
pub fn parse_ref(c: &mut Cursor, max_len: usize) -> MiResult<Option<ShaderRef>> {
    let loc = c.loc()?;
    if c.eat_punct(b'=')? {
        c.eat_word("interface")?;
        let name = c.string("a shader name after '='")?;
        return Ok(Some(ShaderRef::Named { name, loc }));
    }
    if !c.at_string()? {
        return Ok(None);
    }
    let kind = c.string("a shader type")?;
    let params = parse_list(c, max_len)?;
    Ok(Some(ShaderRef::Inline { kind, params, loc }))
}

/// Reads `( "name" value, ... )`; a trailing comma is allowed.
pub fn parse_list(c: &mut Cursor, max_len: usize) -> MiResult<ShaderParams> {
    c.expect_punct(b'(')?;
    let mut out = Vec::new();
    loop {
        if c.eat_punct(b')')? {
            return Ok(ShaderParams(out));
        }
        if out.len() >= max_len {
            return Err(c.error(
                LxsErrorKind::ArrayTooLong,
                format!("more than {max_len} shader parameters"),
            ));
        }
        let loc = c.loc()?;
        let name = c.string("a quoted parameter name or ')'")?;
        let value = parse_value(c, max_len, 0)?;
        out.push(MiParam { name, value, loc });
        if !c.eat_punct(b',')? && !c.at_punct(b')')? {
            return Err(c.unexpected("',' or ')' after a parameter value"));
        }
    }
}

/// One value (see [`MiValue`]).
fn parse_value(c: &mut Cursor, max_len: usize, depth: usize) -> MiResult<MiValue> {
    if depth > MAX_NESTING {
        return Err(c.error(
            LxsErrorKind::InputTooLarge,
            format!("parameter values nested deeper than {MAX_NESTING}"),
        ));
    }
    match c.peek()? {
        Tok::Num(..) => {
            let mut v = Vec::new();
            while c.at_number()? {
                if v.len() >= max_len {
                    return Err(c.error(LxsErrorKind::ArrayTooLong, "too many numbers"));
                }
                v.push(c.number("a number")?);
            }
            Ok(MiValue::Numbers(v))
        }
        Tok::Word("on" | "true") => {
            c.next()?;
            Ok(MiValue::Bool(true))
        }
        Tok::Word("off" | "false") => {
            c.next()?;
            Ok(MiValue::Bool(false))
        }
        Tok::Str(_) => Ok(MiValue::Str(c.string("a string")?)),
        Tok::Punct(b'=') => {
            c.next()?;
            c.eat_word("interface")?;
            Ok(MiValue::Ref(c.string("a shader name after '='")?))
        }
        Tok::Punct(b'[') => {
            c.next()?;
            let mut items = Vec::new();
            loop {
                if c.eat_punct(b']')? {
                    return Ok(MiValue::Array(items));
                }
                if items.len() >= max_len {
                    return Err(c.error(LxsErrorKind::ArrayTooLong, "array too long"));
                }
                items.push(parse_value(c, max_len, depth + 1)?);
                if !c.eat_punct(b',')? && !c.at_punct(b']')? {
                    return Err(c.unexpected("',' or ']' in an array"));
                }
            }
        }
        Tok::Punct(b'{') => {
            c.next()?;
            let mut fields = Vec::new();
            loop {
                if c.eat_punct(b'}')? {
                    return Ok(MiValue::Struct(fields));
                }
                if fields.len() >= max_len {
                    return Err(c.error(LxsErrorKind::ArrayTooLong, "struct too long"));
                }
                let name = c.string("a quoted field name or '}'")?;
                fields.push((name, parse_value(c, max_len, depth + 1)?));
                if !c.eat_punct(b',')? && !c.at_punct(b'}')? {
                    return Err(c.unexpected("',' or '}' in a struct"));
                }
            }
        }
        _ => Err(c.unexpected("a parameter value")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_of_every_kind() {
        let text = r#"( "color" 1 0.5 0 1, "on" on, "tex" = "t1", "lights" ["a", "b"],
                       "s" { "x" 2, "y" off }, )"#;
        let mut c = Cursor::new(text, "t.mi".into());
        let p = parse_list(&mut c, 100).unwrap();
        assert_eq!(p.color("color"), Some([1.0, 0.5, 0.0]));
        assert_eq!(p.boolean("on"), Some(true));
        assert!(p.is_connected("tex"));
        assert_eq!(
            p.get("lights").unwrap().value,
            MiValue::Array(vec![MiValue::Str("a".into()), MiValue::Str("b".into())])
        );
        assert_eq!(p.get("s").unwrap().loc.line, 2);
        assert!(c.at_eof().unwrap());
    }

    #[test]
    fn malformed_lists_are_located() {
        for (text, col) in [
            ("( \"a\" 1 \"b\" 2 )", 9),
            ("( a 1 )", 3),
            ("( \"a\" [1, 2 )", 13),
            ("( \"a\" )", 7),
        ] {
            let mut c = Cursor::new(text, "t.mi".into());
            let e = parse_list(&mut c, 100).unwrap_err();
            assert_eq!(e.loc.col, col, "{text}: {e}");
        }
        let deep = format!("( \"a\" {} )", "[".repeat(40));
        let e = parse_list(&mut Cursor::new(&deep, "t.mi".into()), 100).unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::InputTooLarge);
    }
}

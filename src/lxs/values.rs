//! Parameter lists (`"float fov" [45] "string type" "matte" ...`) read straight from the lexer
//! into typed vectors: the declared type is known before the values, so numbers go directly
//! into `Vec<f32>`/`Vec<i32>`/`Vec<[f32; 3]>` with no intermediate token list.

use super::description::Diagnostic;
use super::error::{LxsError, LxsErrorKind, LxsResult};
use super::lexer::{parse_f32, parse_i32, Lexer, Peek};
use super::params::{Loc, Param, ParamSet, ParamType, ParamValue, SpectrumValue};
use super::suggest::nearest;

const TYPE_KEYWORDS: &[&str] = &[
    "integer", "float", "point", "vector", "normal", "color", "bool", "string", "texture",
    "spectrum",
];

/// Reads parameter lists with a limit on array length; collects warnings.
pub struct ValueReader {
    pub max_array_len: usize,
    pub warnings: Vec<Diagnostic>,
}

/// Values collected for one parameter, by declared type.
enum Acc {
    Ints(Vec<i32>, bool),
    Floats(Vec<f32>),
    Triples(Vec<[f32; 3]>, [f32; 3], usize),
    Strings(Vec<String>),
    Spectrum(Vec<f32>, Vec<String>),
}

impl Acc {
    fn new(ty: ParamType) -> Acc {
        match ty {
            ParamType::Integer => Acc::Ints(Vec::new(), false),
            ParamType::Float => Acc::Floats(Vec::new()),
            ParamType::Point | ParamType::Vector | ParamType::Normal | ParamType::Color => {
                Acc::Triples(Vec::new(), [0.0; 3], 0)
            }
            ParamType::Bool | ParamType::String | ParamType::Texture => Acc::Strings(Vec::new()),
            ParamType::Spectrum => Acc::Spectrum(Vec::new(), Vec::new()),
        }
    }

    fn wants_numbers(&self) -> bool {
        !matches!(self, Acc::Strings(_))
    }

    /// Parses one number token into the accumulator.
    #[inline]
    fn number(&mut self, lex: &mut Lexer) -> LxsResult<()> {
        match self {
            Acc::Ints(v, truncated) => {
                let (x, t) = lex.number(parse_i32)?;
                *truncated |= t;
                v.push(x);
            }
            Acc::Floats(v) | Acc::Spectrum(v, _) => v.push(lex.number(parse_f32)?),
            Acc::Triples(v, pending, k) => {
                pending[*k] = lex.number(parse_f32)?;
                *k += 1;
                if *k == 3 {
                    v.push(*pending);
                    *k = 0;
                }
            }
            Acc::Strings(_) => {}
        }
        Ok(())
    }

    /// Parses a run of numbers (the hot path for big arrays) into the accumulator.
    fn number_run(&mut self, lex: &mut Lexer) -> LxsResult<()> {
        match self {
            Acc::Ints(v, truncated) => lex.number_run(parse_i32, |(x, t)| {
                *truncated |= t;
                v.push(x);
            }),
            Acc::Floats(v) | Acc::Spectrum(v, _) => lex.number_run(parse_f32, |x| v.push(x)),
            Acc::Triples(v, pending, k) => lex.number_run(parse_f32, |x| {
                pending[*k] = x;
                *k += 1;
                if *k == 3 {
                    v.push(*pending);
                    *k = 0;
                }
            }),
            Acc::Strings(_) => Ok(()),
        }
    }

    /// Number of values collected so far.
    fn count(&self) -> usize {
        match self {
            Acc::Ints(v, _) => v.len(),
            Acc::Floats(v) => v.len(),
            Acc::Triples(v, _, k) => v.len() * 3 + k,
            Acc::Strings(v) => v.len(),
            Acc::Spectrum(v, s) => v.len() + s.len(),
        }
    }
}

impl ValueReader {
    pub fn new(max_array_len: usize) -> ValueReader {
        ValueReader {
            max_array_len,
            warnings: Vec::new(),
        }
    }

    /// Reads `"type name" values` pairs until the next token is not a string.
    pub fn param_list(&mut self, lex: &mut Lexer) -> LxsResult<ParamSet> {
        let mut ps = ParamSet::new();
        loop {
            lex.skip_ws()?;
            if lex.peek()? != Peek::Str {
                return Ok(ps);
            }
            let p = self.param(lex)?;
            ps.push(p);
        }
    }

    /// Reads one parameter: its declaration string, then a bracketed list or a single value.
    fn param(&mut self, lex: &mut Lexer) -> LxsResult<Param> {
        let loc = lex.loc();
        let decl = lex.string()?;
        let (ty, name) = parse_declaration(&decl, &loc)?;
        lex.skip_ws()?;
        let mut acc = Acc::new(ty);
        match lex.peek()? {
            Peek::LBrack => {
                let open = lex.loc();
                lex.bump();
                self.bracketed(lex, &mut acc, &decl, &loc, open)?;
            }
            Peek::Number if acc.wants_numbers() => acc.number(lex)?,
            Peek::Str => {
                let s = lex.string()?;
                return self.bare_string(ty, name, s, loc);
            }
            Peek::Number => {
                return Err(LxsError::new(
                    LxsErrorKind::WrongValueType,
                    lex.loc(),
                    format!("parameter \"{decl}\" takes strings, found a number"),
                ))
            }
            _ => {
                return Err(LxsError::new(
                    LxsErrorKind::WrongValueCount,
                    loc,
                    format!("parameter \"{decl}\" has no value"),
                ))
            }
        }
        let value = self.finish(ty, &decl, acc, &loc)?;
        Ok(Param::new(name, value, loc))
    }

    /// A single unbracketed string value. For numeric types LuxRender reads it as a texture
    /// name (with a warning), and so do we.
    fn bare_string(&mut self, ty: ParamType, name: &str, s: String, loc: Loc) -> LxsResult<Param> {
        let value = match ty {
            ParamType::String => ParamValue::String(vec![s]),
            ParamType::Texture => ParamValue::Texture(s),
            ParamType::Bool => ParamValue::Bool(vec![parse_bool(&s, name, &loc)?]),
            ParamType::Spectrum => ParamValue::Spectrum(SpectrumValue::File(s)),
            _ => {
                self.warnings.push(Diagnostic {
                    loc: loc.clone(),
                    message: format!(
                        "parameter '{name}' of type {} given the single string \"{s}\": read as a texture name, as LuxRender does",
                        ty.keyword()
                    ),
                });
                ParamValue::Texture(s)
            }
        };
        Ok(Param::new(name, value, loc))
    }

    /// Reads values up to the closing bracket.
    fn bracketed(
        &mut self,
        lex: &mut Lexer,
        acc: &mut Acc,
        decl: &str,
        loc: &Loc,
        open_loc: Loc,
    ) -> LxsResult<()> {
        loop {
            lex.skip_ws()?;
            match lex.peek()? {
                Peek::RBrack => {
                    lex.bump();
                    return Ok(());
                }
                Peek::Number if acc.wants_numbers() => acc.number_run(lex)?,
                Peek::Str => {
                    let item_loc = lex.loc();
                    let s = lex.string()?;
                    match acc {
                        Acc::Strings(v) => v.push(s),
                        Acc::Spectrum(_, names) => names.push(s),
                        _ => {
                            return Err(LxsError::new(
                                LxsErrorKind::WrongValueType,
                                item_loc,
                                format!("parameter \"{decl}\" takes numbers, found a string"),
                            ))
                        }
                    }
                }
                Peek::Number => {
                    return Err(LxsError::new(
                        LxsErrorKind::WrongValueType,
                        lex.loc(),
                        format!("parameter \"{decl}\" takes strings, found a number"),
                    ))
                }
                Peek::Eof => {
                    return Err(LxsError::new(
                        LxsErrorKind::UnterminatedArray,
                        open_loc,
                        format!(
                            "unterminated array of parameter \"{decl}\": end of input before ']'"
                        ),
                    ))
                }
                Peek::LBrack | Peek::Ident | Peek::Other(_) => {
                    return Err(LxsError::new(
                        LxsErrorKind::UnterminatedArray,
                        open_loc,
                        format!(
                            "unterminated array of parameter \"{decl}\": found {} at {} before ']'",
                            describe_peek(lex)?,
                            lex.loc()
                        ),
                    ))
                }
            }
            if acc.count() > self.max_array_len {
                return Err(LxsError::new(
                    LxsErrorKind::ArrayTooLong,
                    loc.clone(),
                    format!(
                        "parameter \"{decl}\" has more than {} values (ParseOptions::max_array_len)",
                        self.max_array_len
                    ),
                ));
            }
        }
    }

    /// Turns the collected values into a typed value, checking counts.
    fn finish(&mut self, ty: ParamType, decl: &str, acc: Acc, loc: &Loc) -> LxsResult<ParamValue> {
        let count_err = |msg: String| {
            Err(LxsError::new(
                LxsErrorKind::WrongValueCount,
                loc.clone(),
                msg,
            ))
        };
        Ok(match acc {
            Acc::Ints(v, truncated) => {
                if truncated {
                    self.warnings.push(Diagnostic {
                        loc: loc.clone(),
                        message: format!(
                            "parameter \"{decl}\": fractional values truncated to integers"
                        ),
                    });
                }
                ParamValue::Integer(v)
            }
            Acc::Floats(v) => ParamValue::Float(v),
            Acc::Triples(mut v, _, k) => {
                if k != 0 {
                    let n = v.len() * 3 + k;
                    return count_err(format!(
                        "parameter \"{decl}\" needs a multiple of 3 numbers, found {n}"
                    ));
                }
                v.shrink_to_fit();
                match ty {
                    ParamType::Point => ParamValue::Point(v),
                    ParamType::Vector => ParamValue::Vector(v),
                    ParamType::Normal => ParamValue::Normal(v),
                    _ => ParamValue::Color(v),
                }
            }
            Acc::Strings(v) => match ty {
                ParamType::Texture => {
                    if v.len() != 1 {
                        return count_err(format!(
                            "parameter \"{decl}\" takes exactly one texture name, found {}",
                            v.len()
                        ));
                    }
                    ParamValue::Texture(v.into_iter().next().unwrap_or_default())
                }
                ParamType::Bool => {
                    let name = decl.split_whitespace().nth(1).unwrap_or(decl);
                    let b = v
                        .iter()
                        .map(|s| parse_bool(s, name, loc))
                        .collect::<LxsResult<Vec<_>>>()?;
                    ParamValue::Bool(b)
                }
                _ => ParamValue::String(v),
            },
            Acc::Spectrum(nums, names) => match (nums.is_empty(), names.len()) {
                (true, 1) => ParamValue::Spectrum(SpectrumValue::File(
                    names.into_iter().next().unwrap_or_default(),
                )),
                (_, 0) => ParamValue::Spectrum(SpectrumValue::Numbers(nums)),
                _ => {
                    return Err(LxsError::new(
                        LxsErrorKind::WrongValueType,
                        loc.clone(),
                        format!("parameter \"{decl}\" takes either numbers or one file name"),
                    ))
                }
            },
        })
    }
}

/// Splits `"float fov"` into its type and name.
fn parse_declaration<'d>(decl: &'d str, loc: &Loc) -> LxsResult<(ParamType, &'d str)> {
    let mut parts = decl.split_whitespace();
    let (Some(ty), Some(name), None) = (parts.next(), parts.next(), parts.next()) else {
        return Err(LxsError::new(
            LxsErrorKind::Syntax,
            loc.clone(),
            format!("parameter declaration \"{decl}\" must be \"TYPE NAME\""),
        ));
    };
    match ParamType::from_keyword(ty) {
        Some(t) => Ok((t, name)),
        None => {
            let hint = nearest(ty, TYPE_KEYWORDS)
                .map(|s| format!(" (did you mean '{s}'?)"))
                .unwrap_or_default();
            Err(LxsError::new(
                LxsErrorKind::UnknownParamType,
                loc.clone(),
                format!("unknown parameter type '{ty}' in \"{decl}\"{hint}"),
            ))
        }
    }
}

fn parse_bool(s: &str, name: &str, loc: &Loc) -> LxsResult<bool> {
    match s {
        "true" => Ok(true),
        "false" => Ok(false),
        _ => Err(LxsError::new(
            LxsErrorKind::WrongValueType,
            loc.clone(),
            format!("bool parameter '{name}' must be \"true\" or \"false\", found \"{s}\""),
        )),
    }
}

/// A short description of the next token, for error messages.
pub fn describe_peek(lex: &mut Lexer) -> LxsResult<String> {
    Ok(match lex.peek()? {
        Peek::Eof => "end of input".into(),
        Peek::Ident => "a statement name".into(),
        Peek::Str => "a string".into(),
        Peek::Number => "a number".into(),
        Peek::LBrack => "'['".into(),
        Peek::RBrack => "']'".into(),
        Peek::Other(b) => format!("character '{}'", char::from(b).escape_default()),
    })
}

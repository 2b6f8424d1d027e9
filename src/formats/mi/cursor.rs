//! A one-token lookahead over the [`Lexer`] with the typed reads every statement parser
//! uses (a keyword, a quoted name, numbers, on/off), each failing with a located error that
//! says what was expected and what was found.
//!
//! ```text
//! Lexer --Cursor::{peek, next, name, number, int, boolean, ...}--> statement parsers
//! ```

use super::lexer::{Lexer, Tok, Token};
use crate::lxs::{Loc, LxsError, LxsErrorKind};
use std::sync::Arc;

pub struct Cursor<'a> {
    lex: Lexer<'a>,
    peeked: Option<Token<'a>>,
    /// Where the last token taken started.
    last: (u32, u32),
}

pub type MiResult<T> = Result<T, LxsError>;

impl<'a> Cursor<'a> {
    pub fn new(text: &'a str, file: Arc<str>) -> Cursor<'a> {
        Cursor {
            lex: Lexer::new(text, file),
            peeked: None,
            last: (1, 1),
        }
    }

    pub fn file(&self) -> &Arc<str> {
        self.lex.file()
    }

    fn loc_of(&self, line: u32, col: u32) -> Loc {
        Loc {
            file: self.lex.file().clone(),
            line,
            col,
        }
    }

    /// Where the last token taken started.
    pub fn last_loc(&self) -> Loc {
        self.loc_of(self.last.0, self.last.1)
    }

    /// Where the next token starts.
    pub fn loc(&mut self) -> MiResult<Loc> {
        let t = self.peek_token()?;
        let (l, c) = (t.line, t.col);
        Ok(self.loc_of(l, c))
    }

    fn peek_token(&mut self) -> MiResult<&Token<'a>> {
        if self.peeked.is_none() {
            self.peeked = Some(self.lex.next_token()?);
        }
        self.peeked
            .as_ref()
            .ok_or_else(|| self.error_at(self.last, LxsErrorKind::Syntax, "no token"))
    }

    pub fn peek(&mut self) -> MiResult<&Tok<'a>> {
        Ok(&self.peek_token()?.tok)
    }

    /// The line of the next token.
    pub fn peek_line(&mut self) -> MiResult<u32> {
        Ok(self.peek_token()?.line)
    }

    /// The next token (a fallible read, so not `Iterator::next`).
    #[allow(clippy::should_implement_trait)]
    pub fn next(&mut self) -> MiResult<Tok<'a>> {
        let t = match self.peeked.take() {
            Some(t) => t,
            None => self.lex.next_token()?,
        };
        self.last = (t.line, t.col);
        Ok(t.tok)
    }

    fn error_at(&self, at: (u32, u32), kind: LxsErrorKind, msg: impl Into<String>) -> LxsError {
        LxsError::new(kind, self.loc_of(at.0, at.1), msg)
    }

    /// An error at the next token.
    pub fn error(&mut self, kind: LxsErrorKind, msg: impl Into<String>) -> LxsError {
        let msg = msg.into();
        match self.loc() {
            Ok(loc) => LxsError::new(kind, loc, msg),
            Err(e) => e,
        }
    }

    /// An error about the next token, which is not what `what` expected.
    pub fn unexpected(&mut self, what: &str) -> LxsError {
        let found = match self.peek() {
            Ok(t) => t.describe(),
            Err(e) => return e,
        };
        let kind = if found == Tok::Eof.describe() {
            LxsErrorKind::UnclosedBlock
        } else {
            LxsErrorKind::Syntax
        };
        self.error(kind, format!("expected {what}, found {found}"))
    }

    pub fn at_word(&mut self, w: &str) -> MiResult<bool> {
        Ok(matches!(self.peek()?, Tok::Word(x) if *x == w))
    }

    pub fn at_punct(&mut self, c: u8) -> MiResult<bool> {
        Ok(matches!(self.peek()?, Tok::Punct(x) if *x == c))
    }

    pub fn at_number(&mut self) -> MiResult<bool> {
        Ok(matches!(self.peek()?, Tok::Num(..)))
    }

    pub fn at_string(&mut self) -> MiResult<bool> {
        Ok(matches!(self.peek()?, Tok::Str(_)))
    }

    pub fn at_eof(&mut self) -> MiResult<bool> {
        Ok(matches!(self.peek()?, Tok::Eof))
    }

    /// Takes the next token if it is the word `w`.
    pub fn eat_word(&mut self, w: &str) -> MiResult<bool> {
        let yes = self.at_word(w)?;
        if yes {
            self.next()?;
        }
        Ok(yes)
    }

    pub fn eat_punct(&mut self, c: u8) -> MiResult<bool> {
        let yes = self.at_punct(c)?;
        if yes {
            self.next()?;
        }
        Ok(yes)
    }

    pub fn expect_word(&mut self, w: &str) -> MiResult<()> {
        if self.eat_word(w)? {
            Ok(())
        } else {
            Err(self.unexpected(&format!("'{w}'")))
        }
    }

    pub fn expect_punct(&mut self, c: u8) -> MiResult<()> {
        if self.eat_punct(c)? {
            Ok(())
        } else {
            Err(self.unexpected(&format!("'{}'", c as char)))
        }
    }

    /// Any word (a keyword).
    pub fn word(&mut self, what: &str) -> MiResult<&'a str> {
        match self.peek()? {
            Tok::Word(w) => {
                let w = *w;
                self.next()?;
                Ok(w)
            }
            _ => Err(self.unexpected(what)),
        }
    }

    /// A quoted string (a name).
    pub fn string(&mut self, what: &str) -> MiResult<String> {
        match self.peek()? {
            Tok::Str(_) => match self.next()? {
                Tok::Str(s) => Ok(s.into_owned()),
                _ => Err(self.unexpected(what)),
            },
            _ => Err(self.unexpected(what)),
        }
    }

    /// A number.
    pub fn number(&mut self, what: &str) -> MiResult<f64> {
        match self.peek()? {
            Tok::Num(v, _) => {
                let v = *v;
                self.next()?;
                Ok(v)
            }
            _ => Err(self.unexpected(what)),
        }
    }

    /// `n` numbers.
    pub fn numbers<const N: usize>(&mut self, what: &str) -> MiResult<[f64; N]> {
        let mut out = [0.0; N];
        for v in out.iter_mut() {
            *v = self.number(what)?;
        }
        Ok(out)
    }

    /// A whole number in `[min, max]`.
    pub fn int(&mut self, what: &str, min: i64, max: i64) -> MiResult<i64> {
        let loc = self.loc()?;
        let v = self.number(what)?;
        if v.fract() != 0.0 || v < min as f64 || v > max as f64 {
            return Err(LxsError::new(
                LxsErrorKind::InvalidValue,
                loc,
                format!("{what} must be a whole number in [{min}, {max}], got {v}"),
            ));
        }
        Ok(v as i64)
    }

    /// An optional `on`/`off` (also `true`/`false`, or a number: non-zero is on) after a
    /// flag keyword; a flag alone means on.
    pub fn flag(&mut self) -> MiResult<bool> {
        match self.peek()? {
            Tok::Word("on" | "true") => {
                self.next()?;
                Ok(true)
            }
            Tok::Word("off" | "false") => {
                self.next()?;
                Ok(false)
            }
            Tok::Num(v, _) => {
                let v = *v;
                self.next()?;
                Ok(v != 0.0)
            }
            _ => Ok(true),
        }
    }

    /// Skips the value tokens (numbers, strings, on/off) that follow a keyword.
    pub fn skip_values(&mut self) -> MiResult<()> {
        while matches!(
            self.peek()?,
            Tok::Num(..) | Tok::Str(_) | Tok::Word("on" | "off" | "true" | "false")
        ) {
            self.next()?;
        }
        Ok(())
    }

    /// Skips every token up to the next line (keeping the first token of that line).
    pub fn skip_line(&mut self) -> MiResult<()> {
        let line = self.last.0;
        while !self.at_eof()? && self.peek_line()? == line {
            self.next()?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_reads_and_errors() {
        let mut c = Cursor::new("resolution 500 \"x\" on 2.5", "t.mi".into());
        c.expect_word("resolution").unwrap();
        assert_eq!(c.int("width", 1, 1000).unwrap(), 500);
        assert_eq!(c.string("name").unwrap(), "x");
        assert!(c.flag().unwrap());
        let e = c.int("count", 0, 10).unwrap_err();
        assert_eq!((e.loc.line, e.loc.col), (1, 23));
        assert!(e.message.contains("whole number"), "{e}");
        let e = c.string("a name").unwrap_err();
        assert!(e.message.contains("expected a name, found the end"), "{e}");
        assert_eq!(e.kind, LxsErrorKind::UnclosedBlock);
    }
}

//! Reading an Indigo XML file into an [`Elem`] tree whose every element knows its
//! file:line:column.
//!
//! ```text
//! bytes --clean (what Indigo accepts, strict XML does not)--> text + offset map
//!       --roxmltree--> nodes --convert (depth-limited)--> Elem tree (locations in the original)
//! ```
//!
//! Real exporters write XML that a strict parser refuses; Indigo reads it, so the cleaner
//! rewrites it first and keeps a map from every cleaned offset to the original one:
//!
//! - a byte order mark and the `<?xml ...?>` declaration are blanked (the text is decoded as
//!   UTF-8 here; bytes that are not UTF-8 become `?`, with one warning);
//! - comments, including the `<!====== ... ======>` banners some exporters write and comments
//!   holding `--`, are blanked (newlines kept, so lines do not move);
//! - a bare `&` that starts no entity becomes `&amp;`, a `<` that starts no markup becomes
//!   `&lt;` (shader code and names written without escaping).
//!
//! CDATA sections are kept as they are. A DTD is refused (no entity expansion from input).

use super::node::Elem;
use crate::lxs::{Diagnostic, Loc, LxsError, LxsErrorKind};
use std::sync::Arc;

/// Deepest element nesting accepted (real scenes nest fewer than 20 levels).
pub const MAX_DEPTH: usize = 256;

/// Maps offsets of the cleaned text back to the original bytes, and those to line:column.
struct OffsetMap {
    /// (cleaned offset, original offset) at every place the shift between the two changes.
    segments: Vec<(usize, usize)>,
    /// Byte offsets where each original line starts.
    line_starts: Vec<usize>,
}

impl OffsetMap {
    fn original(&self, cleaned: usize) -> usize {
        let i = self.segments.partition_point(|s| s.0 <= cleaned);
        match i.checked_sub(1).and_then(|k| self.segments.get(k)) {
            Some(&(c, o)) => o + (cleaned - c),
            None => cleaned,
        }
    }

    /// 1-based line and column (in bytes) of an original offset.
    fn line_col(&self, orig: usize) -> (u32, u32) {
        let line = self.line_starts.partition_point(|&s| s <= orig).max(1);
        let start = self.line_starts.get(line - 1).copied().unwrap_or(0);
        let col = orig.saturating_sub(start) + 1;
        (
            u32::try_from(line).unwrap_or(u32::MAX),
            u32::try_from(col).unwrap_or(u32::MAX),
        )
    }
}

/// The text handed to the XML parser, with the way back to the original.
struct Cleaned {
    text: String,
    map: OffsetMap,
    /// Where bytes that are not UTF-8 were replaced (the first one), if any.
    invalid_utf8_at: Option<usize>,
}

fn line_starts(bytes: &[u8]) -> Vec<usize> {
    let mut v = vec![0];
    v.extend(
        bytes
            .iter()
            .enumerate()
            .filter(|(_, &b)| b == b'\n')
            .map(|(i, _)| i + 1),
    );
    v
}

/// UTF-8 text with the same byte offsets: each byte of an invalid sequence becomes `?`.
fn decode_keeping_offsets(bytes: &[u8]) -> (String, Option<usize>) {
    let mut out = String::with_capacity(bytes.len());
    let mut first_bad = None;
    for chunk in bytes.utf8_chunks() {
        out.push_str(chunk.valid());
        if !chunk.invalid().is_empty() {
            first_bad.get_or_insert(out.len());
            out.extend(std::iter::repeat_n('?', chunk.invalid().len()));
        }
    }
    (out, first_bad)
}

/// Blank (spaces, newlines kept) `s[from..to]` into `out`.
fn blank(out: &mut String, s: &str) {
    out.extend(s.chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
}

/// Whether `s` (just after a `&`) starts an entity reference `name;` or `#123;` / `#x1f;`.
fn starts_entity(s: &str) -> bool {
    let end = s.find(';').filter(|&e| e > 0 && e <= 32);
    let Some(end) = end else { return false };
    let body = &s[..end];
    if let Some(num) = body.strip_prefix('#') {
        return match num.strip_prefix('x') {
            Some(hex) => !hex.is_empty() && hex.chars().all(|c| c.is_ascii_hexdigit()),
            None => !num.is_empty() && num.chars().all(|c| c.is_ascii_digit()),
        };
    }
    matches!(body, "amp" | "lt" | "gt" | "quot" | "apos")
}

/// Whether a `<` followed by `next` starts markup (a tag, end tag, comment, PI, CDATA).
fn starts_markup(next: Option<char>) -> bool {
    match next {
        Some(c) => c.is_alphabetic() || matches!(c, '_' | ':' | '/' | '!' | '?'),
        None => false,
    }
}

fn clean(bytes: &[u8], file: &Arc<str>) -> Result<Cleaned, LxsError> {
    let (src, invalid_utf8_at) = decode_keeping_offsets(bytes);
    let lines = line_starts(bytes);
    let mut out = String::with_capacity(src.len() + 64);
    let mut segments = vec![(0usize, 0usize)];
    let mut i = 0usize;
    // A BOM is blanked by skipping it (the map shifts by its length).
    if src.starts_with('\u{feff}') {
        i = '\u{feff}'.len_utf8();
        segments.push((0, i));
    }
    let err_at = |pos: usize, msg: &str| {
        let tmp = OffsetMap {
            segments: vec![(0, 0)],
            line_starts: lines.clone(),
        };
        let (line, col) = tmp.line_col(pos);
        LxsError::new(
            LxsErrorKind::Syntax,
            Loc {
                file: file.clone(),
                line,
                col,
            },
            msg,
        )
    };
    // Inside a start or end tag: attribute values may hold bare `&`; `<` is not expected.
    while i < src.len() {
        let rest = &src[i..];
        let Some(off) = rest.find(['<', '&']) else {
            out.push_str(rest);
            break;
        };
        out.push_str(&rest[..off]);
        i += off;
        let rest = &src[i..];
        if let Some(after) = rest.strip_prefix('&') {
            if starts_entity(after) {
                out.push('&');
            } else {
                segments.push((out.len(), i));
                out.push_str("&amp;");
                segments.push((out.len(), i + 1));
            }
            i += 1;
            continue;
        }
        // rest starts with '<'
        if let Some(body) = rest.strip_prefix("<!--") {
            let Some(end) = body.find("-->") else {
                return Err(err_at(i, "comment not closed by -->"));
            };
            let len = 4 + end + 3;
            blank(&mut out, &rest[..len]);
            i += len;
        } else if rest.starts_with("<![CDATA[") {
            let Some(end) = rest.find("]]>") else {
                return Err(err_at(i, "CDATA section not closed by ]]>"));
            };
            out.push_str(&rest[..end + 3]);
            i += end + 3;
        } else if rest.starts_with("<!DOCTYPE") {
            // Kept: the parser refuses it with its location.
            out.push_str("<!DOCTYPE");
            i += "<!DOCTYPE".len();
        } else if rest.starts_with("<!") {
            // Banner comments such as <!====== title ======>, accepted by Indigo.
            let Some(end) = rest.find('>') else {
                return Err(err_at(i, "markup declaration <! not closed by >"));
            };
            blank(&mut out, &rest[..end + 1]);
            i += end + 1;
        } else if rest.starts_with("<?xml") && rest[5..].starts_with(|c: char| c.is_whitespace()) {
            // The declaration (its encoding is not used: the text is read as UTF-8).
            let Some(end) = rest.find("?>") else {
                return Err(err_at(i, "XML declaration not closed by ?>"));
            };
            blank(&mut out, &rest[..end + 2]);
            i += end + 2;
        } else if starts_markup(rest[1..].chars().next()) {
            // A tag: copied up to its '>' with bare '&' in attribute values escaped, and quotes
            // honoured so a '>' inside a value does not end the tag.
            let mut quote: Option<char> = None;
            let mut j = 0usize;
            let mut closed = false;
            for (k, c) in rest.char_indices() {
                j = k + c.len_utf8();
                match (quote, c) {
                    (Some(q), c) if c == q => quote = None,
                    (Some(_), '&') if !starts_entity(&rest[k + 1..]) => {
                        segments.push((out.len(), i + k));
                        out.push_str("&amp;");
                        segments.push((out.len(), i + k + 1));
                        continue;
                    }
                    (Some(_), '<') => {
                        segments.push((out.len(), i + k));
                        out.push_str("&lt;");
                        segments.push((out.len(), i + k + 1));
                        continue;
                    }
                    (None, '"') | (None, '\'') => quote = Some(c),
                    (None, '>') => {
                        out.push('>');
                        closed = true;
                        break;
                    }
                    _ => {}
                }
                out.push(c);
            }
            if !closed {
                return Err(err_at(i, "tag not closed by >"));
            }
            i += j;
        } else {
            // A '<' that starts nothing: text.
            segments.push((out.len(), i));
            out.push_str("&lt;");
            segments.push((out.len(), i + 1));
            i += 1;
        }
    }
    Ok(Cleaned {
        text: out,
        map: OffsetMap {
            segments,
            line_starts: lines,
        },
        invalid_utf8_at,
    })
}

/// A parsed file: its root element and the warnings reading it produced.
#[derive(Debug)]
pub struct Parsed {
    pub root: Elem,
    pub warnings: Vec<Diagnostic>,
}

/// Parses the bytes of the XML file `file` (its name as shown in locations).
pub fn parse(bytes: &[u8], file: &Arc<str>) -> Result<Parsed, LxsError> {
    let cleaned = clean(bytes, file)?;
    let loc_of = |cleaned_off: usize| {
        let (line, col) = cleaned.map.line_col(cleaned.map.original(cleaned_off));
        Loc {
            file: file.clone(),
            line,
            col,
        }
    };
    let mut warnings = Vec::new();
    if let Some(at) = cleaned.invalid_utf8_at {
        warnings.push(Diagnostic {
            loc: loc_of(at),
            message: "bytes that are not UTF-8 read as '?' (names and paths holding them will \
                      not match)"
                .into(),
        });
    }
    let opts = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..Default::default()
    };
    let doc = roxmltree::Document::parse_with_options(&cleaned.text, opts).map_err(|e| {
        let pos = e.pos();
        let cleaned_lines = line_starts(cleaned.text.as_bytes());
        let row = (pos.row as usize).max(1);
        let start = cleaned_lines.get(row - 1).copied().unwrap_or(0);
        let line_text = cleaned.text.get(start..).unwrap_or("");
        let off = start
            + line_text
                .char_indices()
                .nth((pos.col as usize).saturating_sub(1))
                .map(|(k, _)| k)
                .unwrap_or(0);
        LxsError::new(LxsErrorKind::Syntax, loc_of(off), format!("XML: {e}"))
    })?;
    let root = convert(doc.root_element(), &loc_of, 0)?;
    Ok(Parsed { root, warnings })
}

/// Converts a roxmltree element (and its subtree) into an [`Elem`].
fn convert(
    node: roxmltree::Node,
    loc_of: &dyn Fn(usize) -> Loc,
    depth: usize,
) -> Result<Elem, LxsError> {
    let loc = loc_of(node.range().start);
    if depth > MAX_DEPTH {
        return Err(LxsError::new(
            LxsErrorKind::InputTooLarge,
            loc,
            format!("elements nested deeper than {MAX_DEPTH}"),
        ));
    }
    let mut text = String::new();
    let mut children = Vec::new();
    for c in node.children() {
        if c.is_element() {
            children.push(convert(c, loc_of, depth + 1)?);
        } else if c.is_text() {
            text.push_str(c.text().unwrap_or(""));
        }
    }
    let attrs = node
        .attributes()
        .map(|a| (a.name().to_string(), a.value().to_string()))
        .collect();
    Ok(Elem::new(
        node.tag_name().name().to_string(),
        loc,
        attrs,
        text,
        children,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file() -> Arc<str> {
        "t.igs".into()
    }

    #[test]
    fn banner_comments_and_bare_ampersands_are_accepted_with_true_locations() {
        let text = "<?xml version=\"1.0\"?>\n<scene>\n<!====== banner -- x ======>\n<!-- a -- b -->\n  <material><name>R&D < b</name></material>\n  <mesh/>\n</scene>\n";
        let p = parse(text.as_bytes(), &file()).unwrap();
        assert_eq!(p.root.name, "scene");
        let mat = &p.root.children[0];
        assert_eq!(mat.name, "material");
        assert_eq!((mat.loc.line, mat.loc.col), (5, 3));
        assert_eq!(mat.children[0].text, "R&D < b");
        let mesh = &p.root.children[1];
        assert_eq!((mesh.loc.line, mesh.loc.col), (6, 3));
    }

    #[test]
    fn attribute_values_keep_their_characters() {
        let text = "<scene><vertex pos=\"1 2 3\" name='a&b>c'/></scene>";
        let p = parse(text.as_bytes(), &file()).unwrap();
        let v = &p.root.children[0];
        assert_eq!(v.attr("name"), Some("a&b>c"));
        assert_eq!(v.attr("pos"), Some("1 2 3"));
    }

    #[test]
    fn bom_and_latin1_bytes_are_read_with_a_warning() {
        let mut bytes = vec![0xef, 0xbb, 0xbf];
        bytes.extend_from_slice(b"<scene>\n<!-- Sandr\xe9 -->\n<x>caf\xe9</x></scene>");
        let p = parse(&bytes, &file()).unwrap();
        assert_eq!(p.root.children[0].text, "caf?");
        assert_eq!(p.root.children[0].loc.line, 3);
        assert_eq!(p.warnings.len(), 1);
        assert_eq!(p.warnings[0].loc.line, 2);
    }

    #[test]
    fn malformed_xml_is_a_located_syntax_error() {
        let text = "<scene>\n  <a>\n  </b>\n</scene>";
        let e = parse(text.as_bytes(), &file()).unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::Syntax);
        assert_eq!(e.loc.line, 3, "{e}");
        for bad in [
            "<scene><!-- open",
            "<scene><a",
            "<scene><![CDATA[x",
            "",
            "<!DOCTYPE x [<!ENTITY a \"b\">]><scene>&a;</scene>",
        ] {
            assert!(parse(bad.as_bytes(), &file()).is_err(), "{bad}");
        }
    }

    #[test]
    fn nesting_is_bounded() {
        let deep = "<a>".repeat(MAX_DEPTH + 10) + &"</a>".repeat(MAX_DEPTH + 10);
        let e = parse(deep.as_bytes(), &file()).unwrap_err();
        assert_eq!(e.kind, LxsErrorKind::InputTooLarge);
    }

    #[test]
    fn cdata_is_kept_verbatim() {
        let text =
            "<scene><shader><![CDATA[def eval() real: if(a < b && c, 1, 0)]]></shader></scene>";
        let p = parse(text.as_bytes(), &file()).unwrap();
        assert_eq!(
            p.root.children[0].text,
            "def eval() real: if(a < b && c, 1, 0)"
        );
    }
}

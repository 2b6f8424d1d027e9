//! Reading an object file: recognising its IFF form and handing it to the LWO2 or LWOB reader.
//!
//! ```text
//! bytes --"FORM" size type--> LWO2 (lwo2.rs) | LWOB, LWLO (lwob.rs) | LWO3, LXOB: refused
//!       --> Model, with reader errors and warnings located in the object file
//! ```
//!
//! Errors and warnings name the object file; binary files have no lines, so the location's
//! line and column are 0 and the message gives the byte offset and the chunk.

use super::iff::{IffError, Reader};
use super::model::Model;
use super::{lwo2, lwob};
use crate::lxs::{Diagnostic, Loc, LxsError, LxsErrorKind};

fn file_loc(file: &str) -> Loc {
    Loc {
        file: file.into(),
        line: 0,
        col: 0,
    }
}

fn iff_error(file: &str, format: &str, e: IffError) -> LxsError {
    LxsError::new(
        LxsErrorKind::InvalidValue,
        file_loc(file),
        format!("malformed {format} object {e}"),
    )
}

/// Parses the object file `file` (its name is used in errors and warnings).
pub fn parse(bytes: &[u8], file: &str) -> Result<Model, LxsError> {
    let refuse = |msg: String| {
        Err(LxsError::new(
            LxsErrorKind::Unsupported,
            file_loc(file),
            msg,
        ))
    };
    if bytes.len() < 12 || &bytes[0..4] != b"FORM" {
        return refuse("not a LightWave object (no IFF FORM header)".into());
    }
    let declared = u32::from_be_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]) as usize;
    let form: [u8; 4] = [bytes[8], bytes[9], bytes[10], bytes[11]];
    if declared < 4 || declared.saturating_add(8) > bytes.len() {
        return Err(LxsError::new(
            LxsErrorKind::InvalidValue,
            file_loc(file),
            format!(
                "truncated object: the FORM declares {declared} bytes, the file holds {}",
                bytes.len().saturating_sub(8)
            ),
        ));
    }
    // The chunks, read with offsets counted from the start of the file.
    let body_reader = {
        let mut r = Reader::new(bytes);
        r.skip(12).map_err(|e| iff_error(file, "LWO", e))?;
        r.sub(declared - 4).map_err(|e| iff_error(file, "LWO", e))?
    };
    let (model, warnings) = match &form {
        b"LWO2" => lwo2::read(body_reader).map_err(|e| iff_error(file, "LWO2", e))?,
        b"LWOB" => lwob::read(body_reader, false).map_err(|e| iff_error(file, "LWOB", e))?,
        b"LWLO" => lwob::read(body_reader, true).map_err(|e| iff_error(file, "LWLO", e))?,
        b"LWO3" => {
            return refuse(
                "LWO3 objects (LightWave 2015 and later) are not supported: save the object in the LWO2 format (LightWave 9-11)"
                    .into(),
            )
        }
        b"LXOB" => {
            return refuse("modo LXO objects are not supported: export the object as LightWave LWO2".into())
        }
        other => {
            return refuse(format!(
                "unknown IFF form {} (LightWave objects are LWO2 or LWOB)",
                super::iff::id_string(*other)
            ))
        }
    };
    let mut model = model;
    model.warnings = warnings
        .into_iter()
        .map(|(offset, message)| Diagnostic {
            loc: file_loc(file),
            message: format!("byte {offset}: {message}"),
        })
        .collect();
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn form(kind: &[u8; 4], body: &[u8]) -> Vec<u8> {
        let mut v = b"FORM".to_vec();
        v.extend_from_slice(&((body.len() + 4) as u32).to_be_bytes());
        v.extend_from_slice(kind);
        v.extend_from_slice(body);
        v
    }

    #[test]
    fn newer_and_foreign_forms_are_refused_clearly() {
        let e = parse(&form(b"LWO3", b""), "a.lwo").unwrap_err();
        assert!(e.message.contains("LWO3"), "{e}");
        assert!(e.to_string().starts_with("a.lwo:0:0:"));
        let e = parse(&form(b"LXOB", b""), "a.lxo").unwrap_err();
        assert!(e.message.contains("modo"), "{e}");
        assert!(parse(b"hello world!", "a.lwo").is_err());
        let mut short = form(b"LWO2", b"");
        short[7] = 200;
        assert!(parse(&short, "a.lwo")
            .unwrap_err()
            .message
            .contains("truncated"));
    }

    #[test]
    fn chunk_errors_carry_offsets() {
        // PNTS claiming more than is there
        let body = [b"PNTS".as_slice(), &100u32.to_be_bytes(), &[0; 12]].concat();
        let e = parse(&form(b"LWO2", &body), "b.lwo").unwrap_err();
        assert!(e.message.contains("at byte 12"), "{e}");
    }

    #[test]
    fn an_empty_lwo2_is_an_empty_model() {
        let m = parse(&form(b"LWO2", b""), "c.lwo").unwrap();
        assert!(m.layers.is_empty());
        assert_eq!(m.format, "LWO2");
    }
}

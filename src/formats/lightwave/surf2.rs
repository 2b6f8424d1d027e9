//! LWO2 SURF chunks: a surface's name, the surface it derives from, and its sub-chunks.
//!
//! ```text
//! SURF body --S0 name, S0 source--> defaults (LightWave's, or the source surface's)
//!           --sub-chunks (ID4 + U2 length)--> Surface values, BLOK texture layers
//! ```
//!
//! Read sub-chunks (facts from the LWO2 specification): COLR (COL12), DIFF, LUMI, SPEC, GLOS,
//! REFL, TRAN, TRNL, BUMP, RIND, CLRH, CLRF (FP4, each followed by an envelope index that is
//! ignored: object envelopes are not animated), SMAN (ANG4), SIDE (U2: 3 = double sided), NORM
//! (S0: a custom normal map), BLOK (texture layers: an IMAP/PROC/GRAD/SHDR header with its
//! ordinal and CHAN/ENAB/OPAC/NEGA/AXIS, then TMAP, PROJ, AXIS, IMAG, WRAP, WRPW, WRPH, VMAP).
//! Anything else is skipped; texture layers that cannot be rendered are reported by the
//! material mapping, which knows which of them matter.

use super::iff::{IffResult, Reader};
use super::model::{BlockKind, Projection, Surface, TexBlock};

/// Reads one SURF body; `known` are the surfaces read before (for a source surface).
pub fn read_surface(
    b: &mut Reader,
    known: &[Surface],
) -> IffResult<(Surface, Vec<(usize, String)>)> {
    let offset = b.offset();
    let name = b.s0()?;
    let source = b.s0()?;
    let mut s = known
        .iter()
        .find(|k| !source.is_empty() && k.name == source)
        .cloned()
        .unwrap_or_else(|| Surface::default_named(&name));
    s.name = name;
    s.offset = offset;
    let mut warnings = Vec::new();
    while let Some(sub) = b.subchunk()? {
        let mut v = sub.body.clone();
        match &sub.id {
            b"COLR" => s.color = v.vec12()?,
            b"DIFF" => s.diffuse = v.f4()?,
            b"LUMI" => s.luminosity = v.f4()?,
            b"SPEC" => s.specular = v.f4()?,
            b"GLOS" => s.glossiness = v.f4()?,
            b"REFL" => s.reflection = v.f4()?,
            b"TRAN" => s.transparency = v.f4()?,
            b"TRNL" => s.translucency = v.f4()?,
            b"BUMP" => s.bump = v.f4()?,
            b"RIND" => s.index = v.f4()?,
            b"CLRH" => s.color_highlights = v.f4()?,
            b"CLRF" => s.color_filter = v.f4()?,
            b"SMAN" => s.smoothing = v.f4()?,
            b"SIDE" => s.double_sided = v.u2()? & 2 != 0,
            b"NORM" => s.normal_map = Some(v.s0()?).filter(|n| !n.is_empty()),
            b"BLOK" => {
                if let Some(block) = read_block(&mut v, &mut warnings)? {
                    s.blocks.push(block);
                }
            }
            _ => {}
        }
    }
    Ok((s, warnings))
}

/// One BLOK: its header sub-chunk, then the layer's attributes.
fn read_block(b: &mut Reader, warnings: &mut Vec<(usize, String)>) -> IffResult<Option<TexBlock>> {
    let offset = b.offset();
    let Some(header) = b.subchunk()? else {
        return Ok(None);
    };
    let kind = match &header.id {
        b"IMAP" => BlockKind::Image,
        b"PROC" => BlockKind::Procedural(String::new()),
        b"GRAD" => BlockKind::Gradient,
        b"SHDR" => BlockKind::Shader(String::new()),
        _ => {
            warnings.push((
                header.offset,
                format!("texture block {} skipped", header.id_str()),
            ));
            return Ok(None);
        }
    };
    let mut block = TexBlock::new(*b"COLR", kind, offset);
    let mut h = header.body.clone();
    let _ordinal = h.s0()?;
    while let Some(sub) = h.subchunk()? {
        let mut v = sub.body.clone();
        match &sub.id {
            b"CHAN" => block.channel = v.id4()?,
            b"ENAB" => block.enabled = v.u2()? != 0,
            b"OPAC" => {
                let _ty = v.u2()?;
                block.opacity = v.f4()?;
            }
            b"NEGA" => block.negative = v.u2()? != 0,
            b"AXIS" => block.axis = v.u2()?,
            _ => {}
        }
    }
    while let Some(sub) = b.subchunk()? {
        let mut v = sub.body.clone();
        match &sub.id {
            b"TMAP" => read_tmap(&mut v, &mut block)?,
            b"PROJ" => {
                let code = v.u2()?;
                match Projection::from_code(code) {
                    Some(p) => block.projection = p,
                    None => warnings.push((sub.offset, format!("unknown projection {code}"))),
                }
            }
            b"AXIS" => block.axis = v.u2()?,
            b"IMAG" => block.clip = Some(v.vx()?),
            b"WRAP" => block.wrap = (v.u2()?, v.u2()?),
            b"WRPW" => block.wrap_amount.0 = v.f4()?,
            b"WRPH" => block.wrap_amount.1 = v.f4()?,
            b"VMAP" => block.uv_map = Some(v.s0()?),
            b"FUNC" => {
                let name = v.s0()?;
                match &mut block.kind {
                    BlockKind::Procedural(n) | BlockKind::Shader(n) => *n = name,
                    _ => {}
                }
            }
            _ => {}
        }
    }
    Ok(Some(block))
}

/// The texture mapping sub-chunks (centre, size, rotation, coordinate system).
fn read_tmap(b: &mut Reader, block: &mut TexBlock) -> IffResult<()> {
    while let Some(sub) = b.subchunk()? {
        let mut v = sub.body.clone();
        match &sub.id {
            b"CNTR" => block.center = v.vec12()?,
            b"SIZE" => block.size = v.vec12()?,
            b"ROTA" => block.rotation = v.vec12()?,
            b"CSYS" => block.world_coords = v.u2()? == 1,
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(id: &[u8; 4], body: &[u8]) -> Vec<u8> {
        let mut v = id.to_vec();
        v.extend_from_slice(&(body.len() as u16).to_be_bytes());
        v.extend_from_slice(body);
        if body.len() % 2 == 1 {
            v.push(0);
        }
        v
    }

    fn f(x: f32) -> Vec<u8> {
        x.to_be_bytes().to_vec()
    }

    #[test]
    fn reads_values_and_an_image_block() {
        let mut data = b"Shiny\0Default\0".to_vec(); // "Shiny" + pad? lengths: 6 even, 8 even
        data.extend(sub(
            b"COLR",
            &[f(0.5), f(0.25), f(1.0), vec![0, 0]].concat(),
        ));
        data.extend(sub(b"SPEC", &[f(0.3), vec![0, 0]].concat()));
        data.extend(sub(b"SMAN", &f(1.0)));
        data.extend(sub(b"SIDE", &[0, 3]));
        let mut header = b"\x80\0".to_vec();
        header.extend(sub(b"CHAN", b"COLR"));
        header.extend(sub(b"ENAB", &[0, 1]));
        let mut blok = sub(b"IMAP", &header);
        blok.extend(sub(b"PROJ", &[0, 5]));
        blok.extend(sub(b"IMAG", &[0, 2]));
        blok.extend(sub(b"VMAP", b"uv\0\0"));
        data.extend(sub(b"BLOK", &blok));
        let mut r = Reader::new(&data);
        let (s, w) = read_surface(&mut r, &[]).unwrap();
        assert!(w.is_empty());
        assert_eq!(s.name, "Shiny");
        assert_eq!(s.color, [0.5, 0.25, 1.0]);
        assert_eq!(s.specular, 0.3);
        assert_eq!(s.smoothing, 1.0);
        assert!(s.double_sided);
        assert_eq!(s.blocks.len(), 1);
        let b = &s.blocks[0];
        assert_eq!(b.projection, Projection::Uv);
        assert_eq!(b.clip, Some(2));
        assert_eq!(b.uv_map.as_deref(), Some("uv"));
        assert_eq!(&b.channel, b"COLR");
    }

    #[test]
    fn a_truncated_sub_chunk_is_an_error() {
        let mut data = b"S\0\0\0".to_vec();
        data.extend_from_slice(b"COLR\x00\x0e\x3f\x80");
        let mut r = Reader::new(&data);
        assert!(read_surface(&mut r, &[]).is_err());
    }
}

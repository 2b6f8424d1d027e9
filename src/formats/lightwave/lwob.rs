//! The LWOB object reader (LightWave 5 and earlier; `LWLO` is its layered variant).
//!
//! ```text
//! bytes --iff::Reader--> PNTS, SRFS (surface names), POLS, SURF, LAYR (LWLO only)
//!       --> Model (surfaces converted to LWO2 units)
//! ```
//!
//! Facts from the LWOB specification: POLS stores per polygon a U2 vertex count, U2 point
//! indices and an I2 surface number counting from 1; a negative surface number means detail
//! polygons follow (an I2 count, then that many polygons of the same form), which are read as
//! ordinary polygons. SURF sub-chunks: COLR (4 × U1), FLAG (U2: 4 smoothing, 256 double
//! sided, 8 colour highlights, 16 colour filter), LUMI/DIFF/SPEC/REFL/TRAN (U2, 256 = 100%),
//! VLUM/VDIF/VSPC/VRFL/VTRN (FP4, overriding them), GLOS (U2: the Phong exponent, 16 to 1024),
//! RIND, SMAN (FP4, radians), and textures: CTEX/DTEX/STEX/RTEX/TTEX/LTEX/BTEX name a texture
//! of the colour, diffuse, specular, reflection, transparency, luminosity or bump channel,
//! and TIMG, TFLG (axis bits 1 X, 2 Y, 4 Z), TSIZ, TCTR and TWRP describe the last one named.

use super::iff::{IffError, IffResult, Reader};
use super::model::{BlockKind, Layer, Model, PolyKind, Polygon, Projection, Surface, TexBlock};

/// Reads an LWOB/LWLO body (after the FORM header). Warnings are (byte offset, message).
pub fn read(mut body: Reader, layered: bool) -> IffResult<(Model, Vec<(usize, String)>)> {
    let mut model = Model {
        format: "LWOB",
        ..Model::default()
    };
    let mut warnings: Vec<(usize, String)> = Vec::new();
    while let Some(c) = body.chunk()? {
        let mut b = c.body.clone();
        match &c.id {
            b"LAYR" if layered => {
                let number = u32::from(b.u2()?);
                let _flags = b.u2()?;
                let name = b.s0()?;
                model.layers.push(Layer {
                    number,
                    name,
                    ..Layer::default()
                });
            }
            b"PNTS" => {
                if b.remaining() % 12 != 0 {
                    return Err(b.error("PNTS length is not a multiple of 12"));
                }
                let layer = current(&mut model);
                layer.points.reserve(b.remaining() / 12);
                while !b.is_empty() {
                    let p = b.vec12()?;
                    layer.points.push(p);
                }
            }
            b"SRFS" => {
                while !b.is_empty() {
                    let s = b.s0()?;
                    model.tags.push(s);
                }
            }
            b"POLS" => polygons(&mut b, current(&mut model))?,
            b"SURF" => {
                let s = surface(&mut b, &mut warnings)?;
                model.surfaces.push(s);
            }
            b"CRVS" | b"PCHS" => {
                warnings.push((
                    c.offset,
                    format!("{} (curves, patches) are not rendered", c.id_str()),
                ));
            }
            _ => {}
        }
    }
    Ok((model, warnings))
}

fn current(model: &mut Model) -> &mut Layer {
    if model.layers.is_empty() {
        model.layers.push(Layer::default());
    }
    let last = model.layers.len() - 1;
    &mut model.layers[last]
}

fn polygons(b: &mut Reader, layer: &mut Layer) -> IffResult<()> {
    let npoints = layer.points.len();
    while !b.is_empty() {
        read_polygon(b, layer, npoints, 0)?;
    }
    Ok(())
}

/// One polygon and, when its surface number is negative, its detail polygons (one level).
fn read_polygon(b: &mut Reader, layer: &mut Layer, npoints: usize, depth: u8) -> IffResult<()> {
    let count = b.u2()?;
    let start =
        u32::try_from(layer.indices.len()).map_err(|_| b.error("too many polygon vertices"))?;
    for _ in 0..count {
        let at = b.offset();
        let v = u32::from(b.u2()?);
        if v as usize >= npoints {
            return Err(IffError {
                offset: at,
                message: format!("polygon point {v} does not exist ({npoints} points)"),
            });
        }
        layer.indices.push(v);
    }
    let surf = b.i2()?;
    let tag = u32::from(surf.unsigned_abs()).checked_sub(1);
    layer.polygons.push(Polygon {
        start,
        count,
        kind: PolyKind::Face,
        surface_tag: tag,
    });
    if surf < 0 {
        if depth > 0 {
            return Err(b.error("detail polygons inside detail polygons"));
        }
        let details = b.i2()?;
        for _ in 0..details.max(0) {
            read_polygon(b, layer, npoints, depth + 1)?;
        }
    }
    Ok(())
}

/// The channel a texture-naming sub-chunk (CTEX, DTEX...) refers to.
fn texture_channel(id: &[u8; 4]) -> Option<[u8; 4]> {
    Some(match id {
        b"CTEX" => *b"COLR",
        b"DTEX" => *b"DIFF",
        b"STEX" => *b"SPEC",
        b"RTEX" => *b"REFL",
        b"TTEX" => *b"TRAN",
        b"LTEX" => *b"LUMI",
        b"BTEX" => *b"BUMP",
        _ => return None,
    })
}

fn surface(b: &mut Reader, warnings: &mut Vec<(usize, String)>) -> IffResult<Surface> {
    let offset = b.offset();
    let name = b.s0()?;
    let mut s = Surface::default_named(&name);
    s.offset = offset;
    s.glossiness = 0.2; // exponent 16 until GLOS says otherwise
    let mut flags = 0u16;
    let mut sman = None;
    let percent = |v: &mut Reader| -> IffResult<f32> { Ok(f32::from(v.u2()?) / 256.0) };
    while let Some(sub) = b.subchunk()? {
        let mut v = sub.body.clone();
        let last = s.blocks.last_mut();
        match &sub.id {
            b"COLR" => {
                let c = [v.u1()?, v.u1()?, v.u1()?];
                s.color = c.map(|x| f32::from(x) / 255.0);
            }
            b"FLAG" => flags = v.u2()?,
            b"LUMI" => s.luminosity = percent(&mut v)?,
            b"DIFF" => s.diffuse = percent(&mut v)?,
            b"SPEC" => s.specular = percent(&mut v)?,
            b"REFL" => s.reflection = percent(&mut v)?,
            b"TRAN" => s.transparency = percent(&mut v)?,
            b"VLUM" => s.luminosity = v.f4()?,
            b"VDIF" => s.diffuse = v.f4()?,
            b"VSPC" => s.specular = v.f4()?,
            b"VRFL" => s.reflection = v.f4()?,
            b"VTRN" => s.transparency = v.f4()?,
            b"GLOS" => {
                // exponent n = 2^(10 g + 2)
                let n = f32::from(v.u2()?.max(1));
                s.glossiness = ((n.log2() - 2.0) / 10.0).clamp(0.0, 1.0);
            }
            b"RIND" => s.index = v.f4()?,
            b"SMAN" => sman = Some(v.f4()?),
            id if texture_channel(id).is_some() => {
                let channel = texture_channel(id).unwrap_or(*b"COLR");
                let kind_name = v.s0()?;
                let (kind, projection) = match kind_name.as_str() {
                    "Planar Image Map" => (BlockKind::Image, Projection::Planar),
                    "Cylindrical Image Map" => (BlockKind::Image, Projection::Cylindrical),
                    "Spherical Image Map" => (BlockKind::Image, Projection::Spherical),
                    "Cubic Image Map" => (BlockKind::Image, Projection::Cubic),
                    "Front Projection Image Map" => (BlockKind::Image, Projection::Front),
                    other => (BlockKind::Procedural(other.to_string()), Projection::Planar),
                };
                let mut block = TexBlock::new(channel, kind, sub.offset);
                block.projection = projection;
                s.blocks.push(block);
            }
            b"TIMG" => {
                let file = v.s0()?;
                if let Some(bl) = last {
                    bl.image_file = Some(file).filter(|f| !f.is_empty() && f != "(none)");
                }
            }
            b"TFLG" => {
                let f = v.u2()?;
                if let Some(bl) = last {
                    bl.axis = if f & 1 != 0 {
                        0
                    } else if f & 2 != 0 {
                        1
                    } else {
                        2
                    };
                    bl.world_coords = f & 8 != 0;
                    bl.negative = f & 16 != 0;
                }
            }
            b"TSIZ" => {
                let size = v.vec12()?;
                if let Some(bl) = last {
                    bl.size = size;
                }
            }
            b"TCTR" => {
                let c = v.vec12()?;
                if let Some(bl) = last {
                    bl.center = c;
                }
            }
            b"TWRP" => {
                let w = (v.u2()?, v.u2()?);
                if let Some(bl) = last {
                    bl.wrap = w;
                }
            }
            _ => {}
        }
    }
    s.double_sided = flags & 256 != 0;
    s.color_highlights = if flags & 8 != 0 { 1.0 } else { 0.0 };
    s.color_filter = if flags & 16 != 0 { 1.0 } else { 0.0 };
    s.smoothing = if flags & 4 != 0 {
        sman.unwrap_or(89.5f32.to_radians())
    } else {
        0.0
    };
    if flags & 512 != 0 {
        warnings.push((
            offset,
            format!(
                "surface \"{}\": additive transparency is not rendered",
                s.name
            ),
        ));
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chunk(id: &[u8; 4], body: &[u8]) -> Vec<u8> {
        let mut v = id.to_vec();
        v.extend_from_slice(&(body.len() as u32).to_be_bytes());
        v.extend_from_slice(body);
        if body.len() % 2 == 1 {
            v.push(0);
        }
        v
    }

    #[test]
    fn reads_points_polygons_and_detail_polygons() {
        let mut pts = Vec::new();
        for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for c in p {
                pts.extend_from_slice(&c.to_be_bytes());
            }
        }
        let mut data = chunk(b"PNTS", &pts);
        data.extend(chunk(b"SRFS", b"A\0B\0"));
        // polygon with detail: count 3, 0 1 2, surf -1, 1 detail: count 3, 2 1 0, surf 2
        let pols: Vec<u8> = [3u16, 0, 1, 2, (-1i16) as u16, 1, 3, 2, 1, 0, 2]
            .iter()
            .flat_map(|v| v.to_be_bytes())
            .collect();
        data.extend(chunk(b"POLS", &pols));
        let mut surf = b"A\0".to_vec();
        surf.extend_from_slice(b"FLAG\x00\x02\x01\x04");
        surf.extend_from_slice(b"DIFF\x00\x02\x00\x80");
        surf.extend_from_slice(b"GLOS\x00\x02\x00\x40");
        data.extend(chunk(b"SURF", &surf));
        let (m, w) = read(Reader::new(&data), false).unwrap();
        assert!(w.is_empty());
        let l = &m.layers[0];
        assert_eq!(l.polygons.len(), 2);
        assert_eq!(l.polygons[0].surface_tag, Some(0));
        assert_eq!(l.polygons[1].surface_tag, Some(1));
        assert_eq!(l.polygon_points(1), &[2, 1, 0]);
        let s = &m.surfaces[0];
        assert_eq!(s.diffuse, 0.5);
        assert!(s.double_sided);
        assert!((s.glossiness - 0.4).abs() < 1e-6); // exponent 64
        assert!((s.smoothing - 89.5f32.to_radians()).abs() < 1e-6);
    }

    #[test]
    fn bad_point_index_is_an_error_with_offset() {
        let mut pts = Vec::new();
        pts.extend_from_slice(&[0u8; 12]);
        let mut data = chunk(b"PNTS", &pts);
        data.extend(chunk(b"POLS", &[0, 1, 0, 5, 0, 1]));
        let e = read(Reader::new(&data), false).unwrap_err();
        assert!(e.message.contains("point 5"), "{e}");
        assert_eq!(e.offset, 20 + 10);
    }
}

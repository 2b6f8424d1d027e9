//! The LWO2 object reader (LightWave 6 and later): `FORM <size> LWO2` followed by chunks.
//!
//! ```text
//! bytes --iff::Reader--> TAGS, LAYR (starts a layer), PNTS, POLS, PTAG, VMAP, VMAD, CLIP, SURF
//!       --> Model (layers of points/polygons/maps, surfaces, clips)
//! ```
//!
//! Facts from Ernie Wright's LWO2 specification: chunks after a LAYR belong to that layer;
//! polygon and point indices in PTAG, VMAP and VMAD count from the first polygon/point of the
//! layer's latest POLS/PNTS chunk; POLS stores per polygon a U2 whose low 10 bits are the
//! vertex count (the high 6 are flags) followed by variable-length (VX) point indices; polygon
//! types FACE, PTCH and SUBD (subdivision cages) are kept, CURV, MBAL and BONE are skipped.
//! Vertex maps other than TXUV (texture coordinates) and NORM (custom normals) do not change a
//! still render (weights, morphs, selection sets) and are skipped; RGB/RGBA colour maps are
//! skipped with a warning. SURF chunks are read by [`super::surf2`].

use super::iff::{id_string, Chunk, IffError, IffResult, Reader};
use super::model::{Clip, Layer, Model, PolyKind, Polygon, VertexMap};
use super::surf2::read_surface;

/// Reads an LWO2 file's chunks (after the 12-byte FORM header, which the caller checked).
/// Warnings are returned as (byte offset, message).
pub fn read(body: Reader) -> IffResult<(Model, Vec<(usize, String)>)> {
    let mut r = Lwo2 {
        model: Model {
            format: "LWO2",
            ..Model::default()
        },
        warnings: Vec::new(),
        pts_start: 0,
        pols_start: 0,
    };
    let mut body = body;
    while let Some(chunk) = body.chunk()? {
        r.chunk(chunk)?;
    }
    Ok((r.model, r.warnings))
}

struct Lwo2 {
    model: Model,
    warnings: Vec<(usize, String)>,
    /// First point / polygon of the current layer's latest PNTS / POLS chunk.
    pts_start: u32,
    pols_start: u32,
}

impl Lwo2 {
    fn warn_once(&mut self, offset: usize, message: String) {
        if !self.warnings.iter().any(|(_, m)| *m == message) {
            self.warnings.push((offset, message));
        }
    }

    /// The layer chunks go to (a default layer 0 when the file has no LAYR before them).
    fn layer(&mut self) -> &mut Layer {
        if self.model.layers.is_empty() {
            self.model.layers.push(Layer::default());
        }
        let last = self.model.layers.len() - 1;
        &mut self.model.layers[last]
    }

    fn chunk(&mut self, c: Chunk) -> IffResult<()> {
        let mut b = c.body.clone();
        match &c.id {
            b"TAGS" => {
                while !b.is_empty() {
                    let s = b.s0()?;
                    self.model.tags.push(s);
                }
            }
            b"LAYR" => {
                let number = u32::from(b.u2()?);
                let _flags = b.u2()?;
                let pivot = b.vec12()?;
                let name = b.s0()?;
                let parent = if b.remaining() >= 2 {
                    Some(u32::from(b.u2()?))
                } else {
                    None
                };
                self.model.layers.push(Layer {
                    number,
                    name,
                    pivot,
                    parent,
                    ..Layer::default()
                });
                self.pts_start = 0;
                self.pols_start = 0;
            }
            b"PNTS" => {
                if !b.remaining().is_multiple_of(12) {
                    return Err(b.error("PNTS length is not a multiple of 12"));
                }
                let layer = self.layer();
                let start = layer.points.len();
                layer.points.reserve(b.remaining() / 12);
                while !b.is_empty() {
                    let p = b.vec12()?;
                    layer.points.push(p);
                }
                self.pts_start =
                    u32::try_from(start).map_err(|_| c.body.error("too many points"))?;
            }
            b"POLS" => self.polygons(&mut b)?,
            b"PTAG" => self.polygon_tags(&mut b)?,
            b"VMAP" | b"VMAD" => self.vertex_map(&c, &mut b)?,
            b"CLIP" => self.clip(&mut b)?,
            b"SURF" => {
                let (surface, warnings) = read_surface(&mut b, &self.model.surfaces)?;
                for (offset, m) in warnings {
                    self.warn_once(offset, m);
                }
                self.model.surfaces.push(surface);
            }
            b"BBOX" | b"VMPA" | b"ENVL" | b"DESC" | b"TEXT" | b"ICON" => {}
            _ => self.warn_once(c.offset, format!("chunk {} skipped", c.id_str())),
        }
        Ok(())
    }

    fn polygons(&mut self, b: &mut Reader) -> IffResult<()> {
        let at = b.offset();
        let kind = match &b.id4()? {
            b"FACE" => PolyKind::Face,
            b"PTCH" | b"SUBD" => {
                self.warn_once(
                    at,
                    "subdivision surfaces (PTCH/SUBD) are rendered as their cage polygons (subdivision is not implemented)"
                        .into(),
                );
                PolyKind::Patch
            }
            other => {
                let name = id_string(*other);
                self.warn_once(
                    at,
                    format!("{name} polygons (curves, metaballs or bones) are not rendered"),
                );
                return Ok(());
            }
        };
        let layer = self.layer();
        let npoints = layer.points.len();
        let first = layer.polygons.len();
        while !b.is_empty() {
            let head = b.u2()?;
            let count = head & 0x03FF;
            let start = u32::try_from(layer.indices.len())
                .map_err(|_| b.error("too many polygon vertices"))?;
            for _ in 0..count {
                let at = b.offset();
                let v = b.vx()?;
                if v as usize >= npoints {
                    return Err(IffError {
                        offset: at,
                        message: format!(
                            "polygon point {v} does not exist (the layer has {npoints} points)"
                        ),
                    });
                }
                layer.indices.push(v);
            }
            layer.polygons.push(Polygon {
                start,
                count,
                kind,
                surface_tag: None,
            });
        }
        self.pols_start = u32::try_from(first).map_err(|_| b.error("too many polygons"))?;
        Ok(())
    }

    fn polygon_tags(&mut self, b: &mut Reader) -> IffResult<()> {
        let ty = b.id4()?;
        if &ty != b"SURF" {
            return Ok(()); // PART, SMGP, COLR...: groupings without render effect
        }
        let start = self.pols_start;
        let ntags = self.model.tags.len();
        let layer = self.layer();
        while !b.is_empty() {
            let at = b.offset();
            let poly = b.vx()?;
            let tag = u32::from(b.u2()?);
            if tag as usize >= ntags {
                return Err(IffError {
                    offset: at,
                    message: format!("PTAG names tag {tag} but TAGS holds {ntags}"),
                });
            }
            let i = (start + poly) as usize;
            let p = layer.polygons.get_mut(i).ok_or_else(|| IffError {
                offset: at,
                message: format!("PTAG names polygon {poly}, which does not exist"),
            })?;
            p.surface_tag = Some(tag);
        }
        Ok(())
    }

    fn vertex_map(&mut self, c: &Chunk, b: &mut Reader) -> IffResult<()> {
        let per_poly = &c.id == b"VMAD";
        let ty = b.id4()?;
        let dim = usize::from(b.u2()?);
        let name = b.s0()?;
        let keep = match &ty {
            b"TXUV" => dim == 2,
            b"NORM" => dim == 3,
            b"RGB " | b"RGBA" => {
                self.warn_once(c.offset, "vertex colour maps are not rendered".into());
                false
            }
            _ => false,
        };
        if !keep {
            return Ok(());
        }
        let (pts_start, pols_start) = (self.pts_start, self.pols_start);
        let layer = self.layer();
        let (npoints, npolys) = (layer.points.len(), layer.polygons.len());
        let maps = if &ty == b"TXUV" {
            &mut layer.uv_maps
        } else {
            &mut layer.normal_maps
        };
        let idx = match maps.iter().position(|m| m.name == name) {
            Some(i) => i,
            None => {
                maps.push(VertexMap {
                    name,
                    ..VertexMap::default()
                });
                maps.len() - 1
            }
        };
        let map = &mut maps[idx];
        while !b.is_empty() {
            let at = b.offset();
            let point = b.vx()? + pts_start;
            let poly = if per_poly {
                Some(b.vx()? + pols_start)
            } else {
                None
            };
            let mut v = [0.0f32; 3];
            for slot in v.iter_mut().take(dim) {
                *slot = b.f4()?;
            }
            if point as usize >= npoints || poly.is_some_and(|p| p as usize >= npolys) {
                return Err(IffError {
                    offset: at,
                    message: format!(
                        "{} map entry names a point or polygon that does not exist",
                        id_string(ty)
                    ),
                });
            }
            match poly {
                Some(p) => map.per_poly.insert((point, p), v),
                None => map.values.insert(point, v),
            };
        }
        Ok(())
    }

    fn clip(&mut self, b: &mut Reader) -> IffResult<()> {
        let index = b.u4()?;
        while let Some(sub) = b.subchunk()? {
            let mut s = sub.body.clone();
            match &sub.id {
                b"STIL" => {
                    let file = s.s0()?;
                    self.model.clips.push(Clip { index, file });
                    return Ok(());
                }
                b"ISEQ" | b"ANIM" | b"XREF" | b"STCC" => {
                    self.warn_once(
                        sub.offset,
                        format!(
                            "{} clips (sequences, animations, references) are not supported",
                            sub.id_str()
                        ),
                    );
                    return Ok(());
                }
                _ => {}
            }
        }
        Ok(())
    }
}

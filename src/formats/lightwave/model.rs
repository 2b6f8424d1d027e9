//! A LightWave object as the readers produce it, whatever its file format (LWO2, LWOB/LWLO):
//! layers of points and polygons, vertex maps, surfaces with their texture layers, and clips.
//!
//! ```text
//! lwo2.rs / lwob.rs --> Model --mesh.rs--> trianglemesh parameters per (layer, surface)
//!                             --material.rs--> LuxRender materials and textures
//! ```
//!
//! Polygon vertex lists are stored flat ([`Layer::indices`]) so a large object costs one
//! allocation, not one per polygon. Surface values are LWO2's units: fractions (1.0 = 100%),
//! glossiness in [0, 1] (a Phong exponent of 2^(10·g + 2)), angles in radians.

use crate::lxs::Diagnostic;
use std::collections::HashMap;

/// What a polygon is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PolyKind {
    Face,
    /// A subdivision cage (LWO2 PTCH/SUBD), rendered as its cage.
    Patch,
}

/// One polygon: a range of [`Layer::indices`] and its surface tag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polygon {
    pub start: u32,
    pub count: u16,
    pub kind: PolyKind,
    /// Index into [`Model::tags`] (LWO2 PTAG SURF) or, for LWOB, into the surface list.
    pub surface_tag: Option<u32>,
}

/// A per-vertex map (`VMAP`): texture coordinates or normals. Two or three values per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VertexMap {
    pub name: String,
    pub values: HashMap<u32, [f32; 3]>,
    /// Discontinuous values (`VMAD`) keyed by (point, polygon).
    pub per_poly: HashMap<(u32, u32), [f32; 3]>,
}

impl VertexMap {
    /// The value at a corner: the polygon's own value when it has one, else the point's.
    pub fn at(&self, point: u32, polygon: u32) -> Option<[f32; 3]> {
        self.per_poly
            .get(&(point, polygon))
            .or_else(|| self.values.get(&point))
            .copied()
    }
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layer {
    /// The LAYR number (0-based; `LoadObjectLayer n` loads number n - 1).
    pub number: u32,
    pub name: String,
    pub pivot: [f32; 3],
    pub parent: Option<u32>,
    pub points: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
    pub polygons: Vec<Polygon>,
    /// Texture coordinate maps (TXUV), by name.
    pub uv_maps: Vec<VertexMap>,
    /// Custom normal maps (NORM), by name.
    pub normal_maps: Vec<VertexMap>,
}

impl Layer {
    /// The point indices of polygon `i`.
    pub fn polygon_points(&self, i: usize) -> &[u32] {
        let Some(p) = self.polygons.get(i) else {
            return &[];
        };
        let start = p.start as usize;
        self.indices
            .get(start..start + usize::from(p.count))
            .unwrap_or(&[])
    }

    pub fn uv_map(&self, name: &str) -> Option<&VertexMap> {
        self.uv_maps.iter().find(|m| m.name == name)
    }

    pub fn normal_map(&self, name: &str) -> Option<&VertexMap> {
        self.normal_maps.iter().find(|m| m.name == name)
    }
}

/// The texture layer kinds of a surface block.
#[derive(Clone, Debug, PartialEq)]
pub enum BlockKind {
    Image,
    Procedural(String),
    Gradient,
    Shader(String),
}

/// Image projections (LWO2 PROJ).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    Planar,
    Cylindrical,
    Spherical,
    Cubic,
    Front,
    Uv,
}

impl Projection {
    pub fn from_code(code: u16) -> Option<Projection> {
        Some(match code {
            0 => Projection::Planar,
            1 => Projection::Cylindrical,
            2 => Projection::Spherical,
            3 => Projection::Cubic,
            4 => Projection::Front,
            5 => Projection::Uv,
            _ => return None,
        })
    }
}

/// A texture layer of a surface channel (an LWO2 BLOK, or an LWOB texture).
#[derive(Clone, Debug, PartialEq)]
pub struct TexBlock {
    /// The channel it modulates: COLR, DIFF, LUMI, SPEC, GLOS, REFL, TRAN, RIND, TRNL, BUMP.
    pub channel: [u8; 4],
    pub kind: BlockKind,
    pub enabled: bool,
    pub opacity: f32,
    pub negative: bool,
    pub projection: Projection,
    /// 0 X, 1 Y, 2 Z.
    pub axis: u16,
    /// CLIP index of the image.
    pub clip: Option<u32>,
    /// An image file named directly (LWOB TIMG).
    pub image_file: Option<String>,
    /// Width and height wrap: 0 reset, 1 repeat, 2 mirror, 3 edge.
    pub wrap: (u16, u16),
    pub wrap_amount: (f32, f32),
    /// TXUV map of a UV projection.
    pub uv_map: Option<String>,
    pub center: [f32; 3],
    pub size: [f32; 3],
    pub rotation: [f32; 3],
    /// 0 object coordinates, 1 world.
    pub world_coords: bool,
    /// Where the block sits in the file (for warnings).
    pub offset: usize,
}

impl TexBlock {
    pub fn new(channel: [u8; 4], kind: BlockKind, offset: usize) -> TexBlock {
        TexBlock {
            channel,
            kind,
            enabled: true,
            opacity: 1.0,
            negative: false,
            projection: Projection::Planar,
            axis: 0,
            clip: None,
            image_file: None,
            wrap: (1, 1),
            wrap_amount: (1.0, 1.0),
            uv_map: None,
            center: [0.0; 3],
            size: [1.0; 3],
            rotation: [0.0; 3],
            world_coords: false,
            offset,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    pub name: String,
    pub color: [f32; 3],
    pub diffuse: f32,
    pub luminosity: f32,
    pub specular: f32,
    pub glossiness: f32,
    pub reflection: f32,
    pub transparency: f32,
    pub translucency: f32,
    pub index: f32,
    pub bump: f32,
    /// Smoothing angle (radians); 0 renders faceted.
    pub smoothing: f32,
    pub double_sided: bool,
    /// How much specular highlights take the surface colour (CLRH).
    pub color_highlights: f32,
    /// How much transparency is tinted by the surface colour (CLRF).
    pub color_filter: f32,
    /// A NORM vertex map holding custom normals.
    pub normal_map: Option<String>,
    pub blocks: Vec<TexBlock>,
    /// Where the SURF chunk is (for warnings).
    pub offset: usize,
}

impl Surface {
    /// LightWave's defaults for a surface with nothing set (also the surface of polygons whose
    /// tag names no SURF chunk).
    pub fn default_named(name: &str) -> Surface {
        Surface {
            name: name.to_string(),
            color: [200.0 / 255.0; 3],
            diffuse: 1.0,
            luminosity: 0.0,
            specular: 0.0,
            glossiness: 0.4,
            reflection: 0.0,
            transparency: 0.0,
            translucency: 0.0,
            index: 1.0,
            bump: 1.0,
            smoothing: 0.0,
            double_sided: false,
            color_highlights: 0.0,
            color_filter: 0.0,
            normal_map: None,
            blocks: Vec::new(),
            offset: 0,
        }
    }
}

/// An image clip (LWO2 CLIP with a still image).
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    pub index: u32,
    /// The file name as written (LightWave's platform-neutral form).
    pub file: String,
}

/// A whole object file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Model {
    /// "LWO2" or "LWOB".
    pub format: &'static str,
    pub layers: Vec<Layer>,
    /// LWO2 TAGS strings (surface names are tags); LWOB SRFS names.
    pub tags: Vec<String>,
    pub surfaces: Vec<Surface>,
    pub clips: Vec<Clip>,
    pub warnings: Vec<Diagnostic>,
}

impl Model {
    /// The surface a polygon tag names (LightWave's default surface when no SURF matches).
    pub fn surface_for_tag(&self, tag: Option<u32>) -> Option<&Surface> {
        let name = self.tags.get(tag? as usize)?;
        self.surfaces.iter().find(|s| &s.name == name)
    }

    pub fn clip(&self, index: u32) -> Option<&Clip> {
        self.clips.iter().find(|c| c.index == index)
    }

    /// The layer `LoadObjectLayer n` means: LAYR number n - 1, else the n-th layer in file
    /// order (with `fallback` set).
    pub fn layer_for_scene(&self, n: u32) -> Option<(usize, bool)> {
        let number = n.checked_sub(1)?;
        if let Some(i) = self.layers.iter().position(|l| l.number == number) {
            return Some((i, false));
        }
        let i = number as usize;
        (i < self.layers.len()).then_some((i, true))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_maps_prefer_per_polygon_values() {
        let mut m = VertexMap::default();
        m.values.insert(1, [0.5, 0.5, 0.0]);
        m.per_poly.insert((1, 7), [0.1, 0.2, 0.0]);
        assert_eq!(m.at(1, 7), Some([0.1, 0.2, 0.0]));
        assert_eq!(m.at(1, 8), Some([0.5, 0.5, 0.0]));
        assert_eq!(m.at(2, 8), None);
    }

    #[test]
    fn scene_layers_are_one_based() {
        let model = Model {
            layers: vec![
                Layer {
                    number: 3,
                    ..Layer::default()
                },
                Layer {
                    number: 0,
                    ..Layer::default()
                },
            ],
            ..Model::default()
        };
        assert_eq!(model.layer_for_scene(1), Some((1, false)));
        assert_eq!(model.layer_for_scene(4), Some((0, false)));
        assert_eq!(model.layer_for_scene(2), Some((1, true)));
        assert_eq!(model.layer_for_scene(9), None);
        assert_eq!(model.layer_for_scene(0), None);
    }
}

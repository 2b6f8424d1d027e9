//! The scene of one texture case, written twice: as LuxRender 1.x text for luxfarm and as the
//! JSON case `scripts/luxcore_textures.py` turns into LuxCore's own scene language. Both hold
//! the same camera, mesh (positions, triangles, uvs, vertex colours), texture and light, so a
//! pixel of one image shows what the same pixel of the other shows (up to LuxCore's one-row
//! camera convention, see [`crate::image_metrics`]).
//!
//! A case's textures end in one named `tex`, shown by its [`Surface`]:
//! - [`Surface::Emission`]: `tex` is the emission of a black matte seen straight on, with no
//!   other light, so the image is the texture itself. Float textures are shown through a
//!   `mix` of black and white whose amount is the texture, in both (LuxCore would otherwise
//!   emit the colour some of its blender textures also compute); a signed float (values in
//!   [-1, 1]) as 0.5 + 0.5·tex, LuxRender's `mix` of 0.5 and 1, LuxCore's `scale` by 0.5 then
//!   `add` 0.5 (LuxCore's `mix` clamps its amount to [0, 1], LuxRender's does not);
//! - [`Surface::Bump`]: a grey matte with `tex` as its bump map, lit by a distant light from the
//!   upper left, so relief shows as shading (LuxCore's `sharpdistant`: its `distant` spreads
//!   the light over a 10-degree cone whose radiance is `color`, about 1/10.5 of the
//!   irradiance of LuxRender's);
//! - [`Surface::Metal`]: a `metal2` with `tex` as its fresnel texture under a constant white
//!   infinite light, seen obliquely, so the image is the reflectance over 40-80 degrees.

use serde_json::{json, Value};
use std::fmt::Write as _;

/// How the texture `tex` is made visible.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    /// Emission of a black quad; `float` when `tex` is a float texture, `signed` when its
    /// values span [-1, 1] (shown as 0.5 + 0.5·tex, since emission is not negative).
    Emission { float: bool, signed: bool },
    /// Bump map of a grey matte under a distant light.
    Bump,
    /// Fresnel texture of a metal2 under a constant infinite light.
    Metal,
}

/// The surface's mesh: a quad in the plane z = [`PLANE_Z`], facing +z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mesh {
    /// [-1, 1]² with uvs from 0 to `uv_span` (u along x, v along y).
    Quad { uv_span: f32 },
    /// [-1, 1]² with a colour and an alpha per corner.
    VertexColours,
}

/// The plane's height: off the lattice planes of the noise functions.
pub const PLANE_Z: f32 = 0.3;
/// Material colour of the lit surfaces.
pub const KD: f32 = 0.7;
/// Direction the distant light travels (from the upper left, in front).
pub const LIGHT_DIR: [f32; 3] = [0.6, -0.5, -0.8];
/// Corner colours and alphas of [`Mesh::VertexColours`].
const CORNER_COLOURS: [[f32; 3]; 4] = [
    [0.9, 0.1, 0.1],
    [0.1, 0.8, 0.2],
    [0.1, 0.2, 0.9],
    [0.8, 0.8, 0.3],
];
const CORNER_ALPHAS: [f32; 4] = [0.1, 0.4, 0.7, 1.0];

/// One texture case.
pub struct Case {
    pub name: &'static str,
    /// What the case shows, and where LuxCore differs from LuxRender on purpose.
    pub note: &'static str,
    pub surface: Surface,
    pub mesh: Mesh,
    /// LuxCore's mesh when it differs from luxfarm's (a case comparing luxfarm at one uv scale
    /// with LuxCore at another that maps to the same texture coordinates).
    pub luxcore_mesh: Option<Mesh>,
    /// LuxRender 1.x `Texture` statements, the last one named `tex`.
    pub lxs: String,
    /// LuxCore textures in order (name, properties below `scene.textures.NAME.`), the last
    /// named `tex`.
    pub luxcore: Vec<(String, Value)>,
}

/// The camera: position, target, up, field of view in degrees.
struct Camera {
    orig: [f32; 3],
    target: [f32; 3],
    up: [f32; 3],
    fov: f32,
}

impl Surface {
    fn camera(self) -> Camera {
        match self {
            Surface::Metal => Camera {
                orig: [0.0, -1.6, PLANE_Z + 1.0],
                target: [0.0, 0.0, PLANE_Z],
                up: [0.0, 0.0, 1.0],
                fov: 40.0,
            },
            _ => Camera {
                orig: [0.0, 0.0, PLANE_Z + 2.0],
                target: [0.0, 0.0, PLANE_Z],
                up: [0.0, 1.0, 0.0],
                fov: 40.0,
            },
        }
    }
}

/// Positions, triangles, uvs, colours and alphas of a mesh.
struct MeshData {
    p: Vec<[f32; 3]>,
    tris: Vec<[u32; 3]>,
    uv: Vec<[f32; 2]>,
    cols: Option<Vec<[f32; 3]>>,
    alphas: Option<Vec<f32>>,
}

fn mesh_data(mesh: Mesh, surface: Surface) -> MeshData {
    // The metal is seen at grazing angles: its quad reaches far behind the target.
    let (x0, x1, y0, y1) = match surface {
        Surface::Metal => (-6.0, 6.0, -3.0, 12.0),
        _ => (-1.0, 1.0, -1.0, 1.0),
    };
    let p = vec![
        [x0, y0, PLANE_Z],
        [x1, y0, PLANE_Z],
        [x1, y1, PLANE_Z],
        [x0, y1, PLANE_Z],
    ];
    let s = match mesh {
        Mesh::Quad { uv_span } => uv_span,
        Mesh::VertexColours => 1.0,
    };
    let coloured = mesh == Mesh::VertexColours;
    MeshData {
        p,
        tris: vec![[0, 1, 2], [0, 2, 3]],
        uv: vec![[0.0, 0.0], [s, 0.0], [s, s], [0.0, s]],
        cols: coloured.then(|| CORNER_COLOURS.to_vec()),
        alphas: coloured.then(|| CORNER_ALPHAS.to_vec()),
    }
}

/// Numbers as LuxRender writes them in a parameter list.
fn list(v: impl IntoIterator<Item = f32>) -> String {
    v.into_iter()
        .map(|x| format!("{x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

impl Case {
    /// The scene as LuxRender 1.x text: `res`² pixels, box filter one pixel wide, the sobol
    /// sampler one sample per pixel per pass, path tracing without Russian roulette.
    pub fn lxs(&self, res: u32) -> String {
        let c = self.surface.camera();
        let m = mesh_data(self.mesh, self.surface);
        let mut s = String::new();
        let _ = writeln!(s, "# luxfarm bench luxcore-textures: {}", self.name);
        let _ = writeln!(
            s,
            "LookAt {} {} {}",
            list(c.orig),
            list(c.target),
            list(c.up)
        );
        let _ = writeln!(s, "Camera \"perspective\" \"float fov\" [{}]", c.fov);
        let _ = writeln!(
            s,
            "Film \"fleximage\" \"integer xresolution\" [{res}] \"integer yresolution\" [{res}]"
        );
        s.push_str("PixelFilter \"box\" \"float xwidth\" [0.5] \"float ywidth\" [0.5]\n");
        s.push_str("Sampler \"sobol\" \"integer pixelsamples\" [1]\n");
        s.push_str("SurfaceIntegrator \"path\" \"integer maxdepth\" [4] \"string rrstrategy\" [\"none\"]\n");
        s.push_str("WorldBegin\n");
        s.push_str(&self.lxs);
        if !self.lxs.ends_with('\n') {
            s.push('\n');
        }
        match self.surface {
            Surface::Emission { float, signed } => {
                if float {
                    let low = if signed { 0.5 } else { 0.0 };
                    let _ = writeln!(
                        s,
                        "Texture \"tex_colour\" \"color\" \"mix\" \"texture amount\" [\"tex\"] \
                         \"color tex1\" [{low} {low} {low}] \"color tex2\" [1 1 1]"
                    );
                }
                let l = if float { "tex_colour" } else { "tex" };
                s.push_str("AttributeBegin\nMaterial \"matte\" \"color Kd\" [0 0 0]\n");
                let _ = writeln!(
                    s,
                    "AreaLightSource \"area\" \"texture L\" [\"{l}\"] \"float power\" [0] \
                     \"float efficacy\" [0]"
                );
            }
            Surface::Bump => {
                let from = LIGHT_DIR.map(|x| -x);
                let _ = writeln!(
                    s,
                    "LightSource \"distant\" \"point from\" [{}] \"point to\" [0 0 0] \
                     \"color L\" [1 1 1]",
                    list(from)
                );
                s.push_str("AttributeBegin\n");
                let _ = writeln!(
                    s,
                    "Material \"matte\" \"color Kd\" [{KD} {KD} {KD}] \"texture bumpmap\" [\"tex\"]"
                );
            }
            Surface::Metal => {
                s.push_str("LightSource \"infinite\" \"color L\" [1 1 1]\nAttributeBegin\n");
                s.push_str(
                    "Material \"metal2\" \"texture fresnel\" [\"tex\"] \"float uroughness\" \
                     [0.001] \"float vroughness\" [0.001]\n",
                );
            }
        }
        let idx: Vec<String> = m.tris.iter().flatten().map(|i| i.to_string()).collect();
        let _ = write!(
            s,
            "Shape \"trianglemesh\" \"integer indices\" [{}]\n  \"point P\" [{}]\n  \"float uv\" [{}]",
            idx.join(" "),
            list(m.p.iter().flatten().copied()),
            list(m.uv.iter().flatten().copied())
        );
        if let Some(c) = &m.cols {
            let _ = write!(s, "\n  \"float C\" [{}]", list(c.iter().flatten().copied()));
        }
        if let Some(a) = &m.alphas {
            let _ = write!(s, "\n  \"float A\" [{}]", list(a.iter().copied()));
        }
        s.push_str("\nAttributeEnd\nWorldEnd\n");
        s
    }

    /// The JSON case for `scripts/luxcore_textures.py`.
    pub fn luxcore_json(&self, res: u32, spp: u32) -> Value {
        let c = self.surface.camera();
        let m = mesh_data(self.luxcore_mesh.unwrap_or(self.mesh), self.surface);
        let (material, lights) = match self.surface {
            Surface::Emission { float, .. } => (
                json!({"type": "matte", "kd": [0.0, 0.0, 0.0],
                       "emission": if float { "tex_shown" } else { "tex" },
                       "emission.power": 0.0, "emission.efficency": 0.0}),
                json!([]),
            ),
            Surface::Bump => (
                json!({"type": "matte", "kd": [KD, KD, KD], "bumptex": "tex"}),
                json!([["sun", {"type": "sharpdistant", "direction": LIGHT_DIR,
                                "color": [1.0, 1.0, 1.0]}]]),
            ),
            Surface::Metal => (
                json!({"type": "metal2", "fresnel": "tex", "uroughness": 0.001,
                       "vroughness": 0.001}),
                json!([["env", {"type": "constantinfinite", "color": [1.0, 1.0, 1.0]}]]),
            ),
        };
        let mut textures: Vec<Value> = self
            .luxcore
            .iter()
            .map(|(name, props)| json!([name, props]))
            .collect();
        match self.surface {
            Surface::Emission {
                float: true,
                signed: true,
            } => {
                textures.push(json!(["tex_half", {"type": "scale", "texture1": "tex",
                                                  "texture2": 0.5}]));
                textures.push(json!(["tex_shown", {"type": "add", "texture1": "tex_half",
                                                   "texture2": 0.5}]));
            }
            Surface::Emission { float: true, .. } => {
                textures.push(json!(["tex_shown", {"type": "mix", "amount": "tex",
                                                   "texture1": 0.0, "texture2": 1.0}]));
            }
            _ => {}
        }
        json!({
            "res": res,
            "spp": spp,
            "maxdepth": 5,
            "camera": {"orig": c.orig, "target": c.target, "up": c.up, "fov": c.fov},
            "mesh": {"points": m.p, "tris": m.tris, "uvs": m.uv, "cols": m.cols,
                     "alphas": m.alphas},
            "textures": textures,
            "material": material,
            "lights": lights,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(surface: Surface, mesh: Mesh) -> Case {
        Case {
            name: "t",
            note: "",
            surface,
            mesh,
            luxcore_mesh: None,
            lxs: "Texture \"tex\" \"float\" \"fbm\"".into(),
            luxcore: vec![("tex".into(), json!({"type": "fbm"}))],
        }
    }

    #[test]
    fn both_scenes_show_the_same_mesh_and_camera() {
        let c = case(
            Surface::Emission {
                float: true,
                signed: false,
            },
            Mesh::Quad { uv_span: 0.5 },
        );
        let text = c.lxs(32);
        assert!(text.contains("\"texture L\" [\"tex_colour\"]"), "{text}");
        assert!(
            text.contains("\"float uv\" [0 0 0.5 0 0.5 0.5 0 0.5]"),
            "{text}"
        );
        assert!(text.contains("LookAt 0 0 2.3 0 0 0.3 0 1 0"), "{text}");
        let j = c.luxcore_json(32, 8);
        assert_eq!(j["mesh"]["uvs"][2], json!([0.5, 0.5]));
        assert_eq!(j["camera"]["orig"], json!([0.0, 0.0, 2.3_f32]));
        assert_eq!(j["material"]["emission"], json!("tex_shown"));
        assert_eq!(j["textures"][1][1]["amount"], json!("tex"));
        assert_eq!(j["res"], json!(32));
    }

    #[test]
    fn signed_floats_are_shown_from_half_to_one_in_both() {
        let c = case(
            Surface::Emission {
                float: true,
                signed: true,
            },
            Mesh::Quad { uv_span: 1.0 },
        );
        assert!(c
            .lxs(8)
            .contains("\"color tex1\" [0.5 0.5 0.5] \"color tex2\" [1 1 1]"));
        let j = c.luxcore_json(8, 1);
        assert_eq!(j["material"]["emission"], json!("tex_shown"));
        assert_eq!(j["textures"][1][1]["texture2"], json!(0.5));
        assert_eq!(j["textures"][2][1]["texture1"], json!("tex_half"));
    }

    #[test]
    fn luxcore_may_get_its_own_mesh() {
        let mut c = case(Surface::Bump, Mesh::Quad { uv_span: 0.25 });
        c.luxcore_mesh = Some(Mesh::Quad { uv_span: 1.0 });
        assert!(c
            .lxs(8)
            .contains("\"float uv\" [0 0 0.25 0 0.25 0.25 0 0.25]"));
        assert_eq!(c.luxcore_json(8, 1)["mesh"]["uvs"][2], json!([1.0, 1.0]));
    }

    #[test]
    fn vertex_colours_reach_both_scenes() {
        let c = case(
            Surface::Emission {
                float: false,
                signed: false,
            },
            Mesh::VertexColours,
        );
        assert!(c.lxs(8).contains("\"float A\" [0.1 0.4 0.7 1]"));
        let j = c.luxcore_json(8, 1);
        assert_eq!(j["mesh"]["alphas"].as_array().map(Vec::len), Some(4));
        assert_eq!(j["mesh"]["cols"][0], json!([0.9_f32, 0.1_f32, 0.1_f32]));
    }
}

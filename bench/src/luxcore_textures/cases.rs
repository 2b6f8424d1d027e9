//! The texture cases of `luxfarm bench luxcore-textures`: each texture class LuxRender 1.x and
//! LuxCore share, with its parameters written in both scene languages (LuxRender's names from
//! the scene-format seed, LuxCore's from its `parsetextures.cpp`). Two reference cases come
//! first and check the set-up itself: a constant emission (the camera, film and emission
//! units) and a flat matte under the distant light (the light's units).
//!
//! Mappings: 3D textures use LuxRender's `global` coordinates with `scale` s, and LuxCore's
//! `globalmapping3d` with the matrix diag(1/s) (both map a world point p to p / s); 2D
//! textures use uv mapping with `uscale`/`vscale` (LuxCore `uvscale`). The quad sits at
//! z = 0.3 so that noise lattices are not cut at an integer plane.

use super::images::{COLOUR, HEIGHT, NORMALS};
use super::scene::{Case, Mesh, Surface};
use serde_json::{json, Map, Value};

pub(super) const QUAD: Mesh = Mesh::Quad { uv_span: 1.0 };
pub(super) const EMIT_F: Surface = Surface::Emission {
    float: true,
    signed: false,
};
const EMIT_S: Surface = Surface::Emission {
    float: true,
    signed: true,
};
const EMIT_C: Surface = Surface::Emission {
    float: false,
    signed: false,
};

/// LuxRender's 3D mapping parameters for world coordinates divided by `s`.
pub(super) fn lxs_global(s: f32) -> String {
    format!("\"string coordinates\" [\"global\"] \"vector scale\" [{s} {s} {s}]")
}

/// LuxCore's mapping properties mapping a world point p to p / s.
pub(super) fn lc_global(s: f32) -> Value {
    let i = 1.0 / s;
    json!({"mapping.type": "globalmapping3d",
           "mapping.transformation": [i, 0, 0, 0, 0, i, 0, 0, 0, 0, i, 0, 0, 0, 0, 1]})
}

/// `base` with the properties of `extra` added.
pub(super) fn with(base: Value, extra: Value) -> Value {
    let mut m: Map<String, Value> = base.as_object().cloned().unwrap_or_default();
    if let Some(e) = extra.as_object() {
        m.extend(e.iter().map(|(k, v)| (k.clone(), v.clone())));
    }
    Value::Object(m)
}

fn case(
    name: &'static str,
    surface: Surface,
    lxs: impl Into<String>,
    luxcore: Vec<(&str, Value)>,
    note: &'static str,
) -> Case {
    Case {
        name,
        note,
        surface,
        mesh: QUAD,
        luxcore_mesh: None,
        lxs: lxs.into(),
        luxcore: luxcore
            .into_iter()
            .map(|(n, v)| (n.to_string(), v))
            .collect(),
    }
}

/// A float texture over global coordinates / `s`, shown as emission.
pub(super) fn procedural(
    name: &'static str,
    surface: Surface,
    class: &str,
    lxs_params: &str,
    lc: Value,
    s: f32,
    note: &'static str,
) -> Case {
    case(
        name,
        surface,
        format!(
            "Texture \"tex\" \"float\" \"{class}\" {lxs_params} {}",
            lxs_global(s)
        ),
        vec![("tex", with(with(json!({"type": class}), lc), lc_global(s)))],
        note,
    )
}

/// The reference cases and the procedural (3D) textures.
pub(super) fn procedurals() -> Vec<Case> {
    vec![
        case(
            "reference: constant emission",
            EMIT_C,
            "Texture \"tex\" \"color\" \"constant\" \"color value\" [0.8 0.5 0.2]",
            vec![(
                "tex",
                json!({"type": "constfloat3", "value": [0.8, 0.5, 0.2]}),
            )],
            "camera, film and emission units",
        ),
        case(
            "reference: matte under the distant light",
            Surface::Bump,
            "Texture \"tex\" \"float\" \"constant\" \"float value\" [0]",
            vec![("tex", json!({"type": "constfloat1", "value": 0.0}))],
            "light units (no relief)",
        ),
        procedural(
            "fbm",
            EMIT_S,
            "fbm",
            "\"integer octaves\" [8] \"float roughness\" [0.5]",
            json!({"octaves": 8, "roughness": 0.5}),
            0.25,
            "shown as 0.5 + 0.5 fbm",
        ),
        procedural(
            "wrinkled",
            EMIT_F,
            "wrinkled",
            "\"integer octaves\" [8] \"float roughness\" [0.5]",
            json!({"octaves": 8, "roughness": 0.5}),
            0.25,
            "",
        ),
        procedural(
            "windy",
            EMIT_S,
            "windy",
            "",
            json!({}),
            0.25,
            "shown as 0.5 + 0.5 windy",
        ),
        case(
            "marble",
            EMIT_C,
            format!(
                "Texture \"tex\" \"color\" \"marble\" \"integer octaves\" [8] \"float roughness\" \
                 [0.5] \"float scale\" [1] \"float variation\" [0.2] {}",
                lxs_global(0.25)
            ),
            vec![(
                "tex",
                with(
                    json!({"type": "marble", "octaves": 8, "roughness": 0.5,
                "scale": 1.0, "variation": 0.2}),
                    lc_global(0.25),
                ),
            )],
            "",
        ),
        case(
            "checkerboard 3D",
            EMIT_C,
            format!(
                "Texture \"tex\" \"color\" \"checkerboard\" \"integer dimension\" [3] \
                 \"color tex1\" [0.9 0.2 0.1] \"color tex2\" [0.1 0.3 0.9] {}",
                lxs_global(0.25)
            ),
            vec![(
                "tex",
                with(
                    json!({"type": "checkerboard3d", "texture1": [0.9, 0.2, 0.1],
                "texture2": [0.1, 0.3, 0.9]}),
                    lc_global(0.25),
                ),
            )],
            "",
        ),
    ]
}

/// LuxRender's brick bond names and LuxCore's.
const BONDS: [(&str, &str, &str); 7] = [
    ("brick running", "running", "running"),
    ("brick stacked", "stacked", "stacked"),
    ("brick flemish", "flemish", "flemish"),
    ("brick english", "english", "english"),
    ("brick herringbone", "herringbone", "herringbone"),
    ("brick basket", "basket", "basket"),
    ("brick chain link", "chain link", "chain link"),
];

/// Bricks on the quad: LuxRender's bricks stack along texture z, so the texture space is the
/// world with y and z exchanged (a symmetric matrix, the same in either storage order), set in
/// LuxRender as the transform in force at the declaration (`TransformBegin`: an attribute
/// block would also scope the texture's name).
pub(super) fn bricks() -> Vec<Case> {
    BONDS
        .iter()
        .map(|&(name, lxs_bond, lc_bond)| {
            let lxs = format!(
                "TransformBegin\nTransform [1 0 0 0 0 0 1 0 0 1 0 0 0 0 0 1]\n\
                 Texture \"tex\" \"color\" \"brick\" \"string brickbond\" [\"{lxs_bond}\"] \
                 \"float brickwidth\" [0.4] \"float brickheight\" [0.15] \"float brickdepth\" \
                 [0.37] \"float mortarsize\" [0.02] \"float brickrun\" [0.75] \
                 \"color bricktex\" [0.7 0.3 0.2] \"color mortartex\" [0.8 0.8 0.75] \
                 \"color brickmodtex\" [1 1 1] \"string coordinates\" [\"global\"]\nTransformEnd"
            );
            let lc = json!({"type": "brick", "brickbond": lc_bond, "brickwidth": 0.4,
                "brickheight": 0.15, "brickdepth": 0.37, "mortarsize": 0.02, "brickrun": 0.75,
                "bricktex": [0.7, 0.3, 0.2], "mortartex": [0.8, 0.8, 0.75],
                "brickmodtex": [1.0, 1.0, 1.0], "brickmodbias": -1.0,
                "mapping.type": "globalmapping3d",
                "mapping.transformation": [1, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1]});
            case(
                name,
                EMIT_C,
                lxs,
                vec![("tex", lc)],
                "LuxCore given brickmodbias -1 (its default 0 mixes in brickmodtex by a per-brick \
                 noise LuxRender lacks)",
            )
        })
        .collect()
}

/// uv-mapped, vertex-colour and image textures.
pub(super) fn surfaces() -> Vec<Case> {
    let uv4 = "\"string mapping\" [\"uv\"] \"float uscale\" [4] \"float vscale\" [4]";
    let lc_uv4 = json!({"mapping.type": "uvmapping2d", "mapping.uvscale": [4.0, 4.0]});
    let coloured = |name, lxs: &str, lc: Value, float| Case {
        name,
        note: "",
        surface: Surface::Emission {
            float,
            signed: false,
        },
        mesh: Mesh::VertexColours,
        luxcore_mesh: None,
        lxs: lxs.to_string(),
        luxcore: vec![("tex".into(), lc)],
    };
    vec![
        case(
            "checkerboard 2D",
            EMIT_C,
            format!(
                "Texture \"tex\" \"color\" \"checkerboard\" \"integer dimension\" [2] \
                     \"color tex1\" [0.9 0.2 0.1] \"color tex2\" [0.1 0.3 0.9] {uv4}"
            ),
            vec![(
                "tex",
                with(
                    json!({"type": "checkerboard2d", "texture1": [0.9, 0.2, 0.1],
                "texture2": [0.1, 0.3, 0.9]}),
                    lc_uv4.clone(),
                ),
            )],
            "",
        ),
        case(
            "dots",
            EMIT_C,
            format!(
                "Texture \"tex\" \"color\" \"dots\" \"color inside\" [0.9 0.3 0.1] \
                     \"color outside\" [0.1 0.2 0.8] {uv4}"
            ),
            vec![(
                "tex",
                with(
                    json!({"type": "dots", "inside": [0.9, 0.3, 0.1],
                "outside": [0.1, 0.2, 0.8]}),
                    lc_uv4.clone(),
                ),
            )],
            "LuxRender 1.x draws `outside` in the dots (its constructor takes the pair swapped); \
             LuxCore fixed the order",
        ),
        case(
            "dots, LuxCore given inside and outside swapped",
            EMIT_C,
            format!(
                "Texture \"tex\" \"color\" \"dots\" \"color inside\" [0.9 0.3 0.1] \
                     \"color outside\" [0.1 0.2 0.8] {uv4}"
            ),
            vec![(
                "tex",
                with(
                    json!({"type": "dots", "inside": [0.1, 0.2, 0.8],
                "outside": [0.9, 0.3, 0.1]}),
                    lc_uv4.clone(),
                ),
            )],
            "the pattern itself, LuxRender's order undone",
        ),
        case(
            "bilerp",
            EMIT_C,
            "Texture \"tex\" \"color\" \"bilerp\" \"color v00\" [1 0 0] \"color v01\" [0 1 0] \
             \"color v10\" [0 0 1] \"color v11\" [1 1 1]",
            vec![(
                "tex",
                json!({"type": "bilerp", "texture00": [1.0, 0.0, 0.0],
                "texture01": [0.0, 1.0, 0.0], "texture10": [0.0, 0.0, 1.0],
                "texture11": [1.0, 1.0, 1.0]}),
            )],
            "",
        ),
        case(
            "band",
            EMIT_C,
            "Texture \"amt\" \"float\" \"bilerp\" \"float v00\" [0] \"float v01\" [0.5] \
             \"float v10\" [0.5] \"float v11\" [1]\n\
             Texture \"tex\" \"color\" \"band\" \"texture amount\" [\"amt\"] \
             \"float offsets\" [0 0.3 0.7 1] \"color tex1\" [0.1 0.1 0.6] \
             \"color tex2\" [0.9 0.2 0.1] \"color tex3\" [0.2 0.8 0.2] \"color tex4\" [1 1 1]",
            vec![
                (
                    "amt",
                    json!({"type": "bilerp", "texture00": 0.0, "texture01": 0.5,
                    "texture10": 0.5, "texture11": 1.0}),
                ),
                (
                    "tex",
                    json!({"type": "band", "amount": "amt", "interpolation": "linear",
                    "offset0": 0.0, "value0": [0.1, 0.1, 0.6], "offset1": 0.3,
                    "value1": [0.9, 0.2, 0.1], "offset2": 0.7, "value2": [0.2, 0.8, 0.2],
                    "offset3": 1.0, "value3": [1.0, 1.0, 1.0]}),
                ),
            ],
            "amount: a bilerp over uv",
        ),
        coloured(
            "hitpointcolor",
            "Texture \"tex\" \"color\" \"hitpointcolor\"",
            json!({"type": "hitpointcolor"}),
            false,
        ),
        coloured(
            "hitpointalpha",
            "Texture \"tex\" \"float\" \"hitpointalpha\"",
            json!({"type": "hitpointalpha"}),
            true,
        ),
        coloured(
            "hitpointgrey (luminance)",
            "Texture \"tex\" \"float\" \"hitpointgrey\"",
            json!({"type": "hitpointgrey"}),
            true,
        ),
        coloured(
            "hitpointgrey (green)",
            "Texture \"tex\" \"float\" \"hitpointgrey\" \"integer channel\" [1]",
            json!({"type": "hitpointgrey", "channel": 1}),
            true,
        ),
        case(
            "imagemap",
            EMIT_C,
            format!(
                "Texture \"tex\" \"color\" \"imagemap\" \"string filename\" [\"{COLOUR}\"] \
                     \"float gamma\" [2.2] \"string filtertype\" [\"bilinear\"] \
                     \"string mapping\" [\"uv\"] \"float uscale\" [1] \"float vscale\" [1]"
            ),
            vec![(
                "tex",
                json!({"type": "imagemap", "file": COLOUR, "gamma": 2.2,
                "mapping.type": "uvmapping2d", "mapping.uvscale": [1.0, 1.0]}),
            )],
            "",
        ),
    ]
}

/// Why the preset metals differ (measured at the image centre, 58 degrees, gold).
const FRESNEL_PRESET_NOTE: &str = "LuxCore fresnelpreset: LuxRender renders the n, k tables \
    spectrally; luxfarm's RGB (n, k) reflect the colour the tables reflect spectrally, within \
    0.01 RMS over the angles (gold at normal incidence 1.0, 0.786, 0.332; \
    src/spectrum/nk_rgb.rs); LuxCore turns n and k into RGB through a colour system (gold's \
    green about 0.93)";

/// Textures seen through a material: fresnel textures on metal2, bump and normal maps.
pub(super) fn materials() -> Vec<Case> {
    // luxfarm at uv span `span` and uscale `scale`; LuxCore at `lc_span` and `lc_scale`.
    let bump = |name, note, span: f32, scale: f32, lc_span: f32, lc_scale: f32| Case {
        name,
        note,
        surface: Surface::Bump,
        mesh: Mesh::Quad { uv_span: span },
        luxcore_mesh: Some(Mesh::Quad { uv_span: lc_span }),
        lxs: format!(
            "Texture \"h\" \"float\" \"imagemap\" \"string filename\" [\"{HEIGHT}\"] \
             \"float gamma\" [1] \"string mapping\" [\"uv\"] \"float uscale\" [{scale}] \
             \"float vscale\" [{scale}]\n\
             Texture \"tex\" \"float\" \"scale\" \"texture tex1\" [\"h\"] \"float tex2\" [0.1]"
        ),
        luxcore: vec![
            (
                "h".into(),
                json!({"type": "imagemap", "file": HEIGHT, "gamma": 1.0,
                "mapping.type": "uvmapping2d", "mapping.uvscale": [lc_scale, lc_scale]}),
            ),
            (
                "tex".into(),
                json!({"type": "scale", "texture1": "h", "texture2": 0.1}),
            ),
        ],
    };
    vec![
        case(
            "fresnelcolor",
            Surface::Metal,
            "Texture \"tex\" \"fresnel\" \"fresnelcolor\" \"color Kr\" [0.9 0.6 0.3]",
            vec![(
                "tex",
                json!({"type": "fresnelcolor", "kr": [0.9, 0.6, 0.3]}),
            )],
            "",
        ),
        case(
            "fresnelname gold",
            Surface::Metal,
            "Texture \"tex\" \"fresnel\" \"fresnelname\" \"string name\" [\"gold\"]",
            vec![("tex", json!({"type": "fresnelpreset", "name": "gold"}))],
            FRESNEL_PRESET_NOTE,
        ),
        case(
            "fresnelname copper",
            Surface::Metal,
            "Texture \"tex\" \"fresnel\" \"fresnelname\" \"string name\" [\"copper\"]",
            vec![("tex", json!({"type": "fresnelpreset", "name": "copper"}))],
            FRESNEL_PRESET_NOTE,
        ),
        case(
            "normalmap",
            Surface::Bump,
            format!(
                "Texture \"tex\" \"float\" \"normalmap\" \"string filename\" [\"{NORMALS}\"] \
                     \"float gamma\" [1] \"string mapping\" [\"uv\"]"
            ),
            vec![
                (
                    "nm",
                    json!({"type": "imagemap", "file": NORMALS, "gamma": 1.0,
                    "mapping.type": "uvmapping2d", "mapping.uvscale": [1.0, 1.0]}),
                ),
                (
                    "tex",
                    json!({"type": "normalmap", "texture": "nm", "scale": 1.0}),
                ),
            ],
            "",
        ),
        bump(
            "bump imagemap, uscale 1",
            "height 0.1 x the image",
            1.0,
            1.0,
            1.0,
            1.0,
        ),
        bump(
            "bump imagemap, uscale 32 on uvs spanning 1/32",
            "LuxCore's relief nearly vanishes here (its std/mean against 9 % at uscale 1); \
             LuxRender keeps the relief of uscale 1 (issue 15), see the next row",
            1.0 / 32.0,
            32.0,
            1.0 / 32.0,
            32.0,
        ),
        bump(
            "bump imagemap, uscale 32 on uvs spanning 1/32, LuxCore at uscale 1",
            "the same texture coordinates: luxfarm's uscale-32 relief against LuxCore's \
             uscale-1 relief",
            1.0 / 32.0,
            32.0,
            1.0,
            1.0,
        ),
    ]
}

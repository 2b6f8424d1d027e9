//! The `blender_*` cases of `luxfarm bench luxcore-textures` (see [`super::cases`]): each of
//! LuxRender 1.x's Blender procedurals that LuxCore also has, over world coordinates, with
//! LuxRender's parameter names (`type`, `h`, `lacu`, `octs`, `outscale`, `distamount`) and
//! LuxCore's (`woodtype`, `dimension`, `lacunarity`, `octaves`, `intensity`, `distortion`,
//! ...). All show their float value as emission; `blender_magic` also once through LuxCore's
//! colour weighted as LuxRender weighs it.

use super::cases::{lc_global, lxs_global, procedural, with, EMIT_F, QUAD};
use super::scene::Case;
use serde_json::{json, Value};

/// A blender_* texture: LuxRender's parameters and LuxCore's, over world coordinates.
fn blender(name: &'static str, lxs_params: &str, lc: Value, note: &'static str) -> Case {
    procedural(name, EMIT_F, name, lxs_params, lc, 1.0, note)
}

/// The blender_* cases, in the table's order.
pub(super) fn blenders() -> Vec<Case> {
    let basis = "\"string noisebasis\" [\"blender_original\"]";
    vec![
        blender(
            "blender_blend",
            "\"string type\" [\"lin\"]",
            json!({"progressiontype": "linear", "direction": "horizontal"}),
            "",
        ),
        blender(
            "blender_clouds",
            &format!(
                "\"string noisetype\" [\"soft_noise\"] {basis} \"float noisesize\" [0.25] \
                      \"integer noisedepth\" [2]"
            ),
            json!({"noisetype": "soft_noise", "noisebasis": "blender_original",
                   "noisesize": 0.25, "noisedepth": 2}),
            "",
        ),
        blender(
            "blender_distortednoise",
            &format!(
                "\"string type\" [\"blender_original\"] {basis} \"float noisesize\" [0.25] \
                      \"float distamount\" [1]"
            ),
            json!({"noise_distortion": "blender_original", "noisebasis": "blender_original",
                   "noisesize": 0.25, "distortion": 1.0}),
            "",
        ),
        blender(
            "blender_magic",
            "\"integer noisedepth\" [2] \"float turbulence\" [5]",
            json!({"noisedepth": 2, "turbulence": 5.0}),
            "LuxRender's float of an RGB blender texture is Blender's 0.35 r + 0.45 g + 0.2 b; \
             LuxCore's is the luminance Y",
        ),
        Case {
            name: "blender_magic, LuxCore's colour weighted as LuxRender's",
            note: "LuxCore: dotproduct of its colour with (0.35, 0.45, 0.2)",
            surface: EMIT_F,
            mesh: QUAD,
            luxcore_mesh: None,
            lxs: format!(
                "Texture \"tex\" \"float\" \"blender_magic\" \"integer noisedepth\" [2] \
                 \"float turbulence\" [5] {}",
                lxs_global(1.0)
            ),
            luxcore: vec![
                (
                    "magic".into(),
                    with(
                        json!({"type": "blender_magic", "noisedepth": 2,
                    "turbulence": 5.0}),
                        lc_global(1.0),
                    ),
                ),
                (
                    "tex".into(),
                    json!({"type": "dotproduct", "texture1": "magic",
                    "texture2": [0.35, 0.45, 0.2]}),
                ),
            ],
        },
        blender(
            "blender_marble",
            &format!(
                "\"string type\" [\"soft\"] {basis} \"string noisebasis2\" [\"sin\"] \
                      \"integer noisedepth\" [2] \"float noisesize\" [0.25] \
                      \"string noisetype\" [\"soft_noise\"] \"float turbulence\" [5]"
            ),
            json!({"marbletype": "soft", "noisebasis": "blender_original", "noisebasis2": "sin",
                   "noisedepth": 2, "noisesize": 0.25, "noisetype": "soft_noise",
                   "turbulence": 5.0}),
            "",
        ),
        blender(
            "blender_musgrave",
            &format!(
                "\"string type\" [\"multifractal\"] {basis} \"float h\" [1] \
                      \"float lacu\" [2] \"float octs\" [2] \"float noisesize\" [0.25] \
                      \"float outscale\" [1]"
            ),
            json!({"musgravetype": "multifractal", "noisebasis": "blender_original",
                   "dimension": 1.0, "lacunarity": 2.0, "octaves": 2.0, "noisesize": 0.25,
                   "intensity": 1.0}),
            "",
        ),
        blender(
            "blender_noise",
            "\"integer noisedepth\" [2]",
            json!({"noisedepth": 2}),
            "white noise: no two renders share a value per pixel (see the means)",
        ),
        blender(
            "blender_stucci",
            &format!(
                "\"string type\" [\"plastic\"] {basis} \"string noisetype\" [\"soft_noise\"] \
                      \"float noisesize\" [0.25] \"float turbulence\" [5]"
            ),
            json!({"stuccitype": "plastic", "noisebasis": "blender_original",
                   "noisetype": "soft_noise", "noisesize": 0.25, "turbulence": 5.0}),
            "",
        ),
        blender(
            "blender_voronoi",
            "\"string distmetric\" [\"actual_distance\"] \"float w1\" [1] \"float w2\" [0] \
             \"float w3\" [0] \"float w4\" [0] \"float noisesize\" [0.25] \"float outscale\" [1]",
            json!({"distmetric": "actual_distance", "w1": 1.0, "w2": 0.0, "w3": 0.0, "w4": 0.0,
                   "noisesize": 0.25, "intensity": 1.0}),
            "",
        ),
        blender(
            "blender_wood",
            &format!(
                "\"string type\" [\"bandnoise\"] {basis} \"string noisebasis2\" [\"sin\"] \
                      \"string noisetype\" [\"soft_noise\"] \"float noisesize\" [0.25] \
                      \"float turbulence\" [5]"
            ),
            json!({"woodtype": "bandnoise", "noisebasis": "blender_original",
                   "noisebasis2": "sin", "noisetype": "soft_noise", "noisesize": 0.25,
                   "turbulence": 5.0}),
            "",
        ),
    ]
}

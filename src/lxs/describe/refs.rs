//! Name-level knowledge the description builder needs: which texture namespace (float, color
//! or fresnel) a `"texture NAME"` parameter refers to, and the legacy plugin names of old
//! exporters with their modern equivalents.

use crate::lxs::description::TextureType;

/// Material, light and texture parameters that LuxRender reads as float textures.
const FLOAT_PARAMS: &[&str] = &[
    "amount",
    "bumpmap",
    "sigma",
    "index",
    "index_bf",
    "cauchyb",
    "film",
    "filmindex",
    "roughness",
    "uroughness",
    "vroughness",
    "uroughness_bf",
    "vroughness_bf",
    "d",
    "d_bf",
    "R1",
    "R2",
    "R3",
    "M1",
    "M2",
    "M3",
    "thickness",
    "p1",
    "p2",
    "p3",
    "opacity",
    "opacity1",
    "opacity2",
    "opacity3",
    "opacity4",
    "displacementmap",
    "backface_index",
    "backface_d",
    "backface_uroughness",
    "backface_vroughness",
];

/// Parameters that LuxRender reads as color textures.
const COLOR_PARAMS: &[&str] = &[
    "Kd",
    "Ks",
    "Kr",
    "Kt",
    "Ka",
    "Ks_bf",
    "Ka_bf",
    "Kt_bf",
    "Ks1",
    "Ks2",
    "Ks3",
    "n",
    "k",
    "L",
    "g",
    "Kd_bf",
    "sheen",
    "backface_Ks",
    "backface_Ka",
    "warp_Kd",
    "warp_Ks",
    "weft_Kd",
    "weft_Ks",
];

/// Parameters that LuxRender reads as fresnel textures (metal2's and the volumes' `fresnel`).
const FRESNEL_PARAMS: &[&str] = &["fresnel"];

/// Texture parameters whose namespace is the value type of the texture being defined
/// (`v00`..`v11` only for fresnel bilerp: its float and color variants take constants).
const SAME_TYPE_PARAMS: &[&str] = &[
    "tex1",
    "tex2",
    "inside",
    "outside",
    "tex",
    "bricktex",
    "mortartex",
    "brickmodtex",
    "innertex",
    "outertex",
    "v00",
    "v01",
    "v10",
    "v11",
];

/// The namespace a texture reference named `param` looks in, when known. `own` is the value
/// type of the texture being defined (None inside materials and lights).
pub fn namespace(param: &str, own: Option<TextureType>) -> Option<TextureType> {
    if let Some(t) = own {
        if SAME_TYPE_PARAMS.contains(&param) || band_input(param) {
            return Some(t);
        }
    }
    if FLOAT_PARAMS.contains(&param) {
        Some(TextureType::Float)
    } else if COLOR_PARAMS.contains(&param) {
        Some(TextureType::Color)
    } else if FRESNEL_PARAMS.contains(&param) {
        Some(TextureType::Fresnel)
    } else {
        None
    }
}

/// `tex0`, `tex1`, ... of the band texture.
fn band_input(param: &str) -> bool {
    param
        .strip_prefix("tex")
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// The statement family of a plugin name, for legacy-name lookups.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Family {
    Film,
    Material,
    Sampler,
    Light,
}

/// For a legacy plugin name written by old exporters, the modern LuxRender equivalent.
pub fn modern_equivalent(family: Family, kind: &str) -> Option<&'static str> {
    match (family, kind) {
        (Family::Film, "multiimage") => Some("fleximage"),
        (Family::Material, "plastic") | (Family::Material, "substrate") => Some("glossy"),
        (Family::Sampler, "bestcandidate") | (Family::Sampler, "stratified") => {
            Some("lowdiscrepancy")
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn namespaces() {
        assert_eq!(namespace("Kd", None), Some(TextureType::Color));
        assert_eq!(namespace("bumpmap", None), Some(TextureType::Float));
        assert_eq!(
            namespace("tex1", Some(TextureType::Float)),
            Some(TextureType::Float)
        );
        assert_eq!(
            namespace("tex3", Some(TextureType::Color)),
            Some(TextureType::Color)
        );
        assert_eq!(
            namespace("amount", Some(TextureType::Color)),
            Some(TextureType::Float)
        );
        assert_eq!(namespace("whatever", None), None);
        assert_eq!(namespace("fresnel", None), Some(TextureType::Fresnel));
        assert_eq!(
            namespace("tex2", Some(TextureType::Fresnel)),
            Some(TextureType::Fresnel)
        );
        assert_eq!(
            modern_equivalent(Family::Film, "multiimage"),
            Some("fleximage")
        );
        assert_eq!(modern_equivalent(Family::Film, "fleximage"), None);
        // LuxRender 1.x still has the Preetham sun/sky plugins beside Hosek-Wilkie's sky2.
        assert_eq!(modern_equivalent(Family::Light, "sunsky"), None);
        assert_eq!(modern_equivalent(Family::Light, "sky"), None);
    }
}

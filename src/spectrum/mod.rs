//! Colour: RGB values used by the renderer (the default, RGB unless a scene needs spectra),
//! XYZ conversion for the film, and blackbody emission.
//!
//! [`rgb_to_xyz`] reproduces LuxRender's RGB -> illuminant spectrum -> CIE XYZ chain (with its
//! 683 lm/W factor); see [`xyz`] for the derivation.

pub mod cie;
pub mod rgb;
pub mod smits;
pub mod xyz;

pub use rgb::Rgb;
pub use xyz::{blackbody, illuminant_y, rgb_to_xyz, xyz_to_rgb};

//! Colour: RGB values used by the renderer (the default, RGB unless a scene needs spectra),
//! XYZ conversion for the film, blackbody emission, and the spectral data scenes give
//! (sampled spectra in [`spd`], complex refractive indices in [`nk`]) with their RGB readings.
//!
//! [`rgb_to_xyz`] reproduces LuxRender's RGB -> spectrum -> CIE XYZ chain (Smits bases, 683 lm/W
//! factor) for reflected light under white illumination; [`illuminant_xyz`] is LuxRender's
//! value for a light colour. See [`xyz`] for the derivation.

pub mod cie;
pub mod lamp;
pub mod nk;
pub mod nk_rgb;
pub mod rgb;
pub mod smits;
pub mod spd;
pub mod xyz;

pub use rgb::Rgb;
pub use xyz::{blackbody, illuminant_xyz, illuminant_y, rgb_to_xyz, xyz_to_rgb};

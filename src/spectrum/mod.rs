//! Colour: RGB values used by the renderer (the default, RGB unless a scene needs spectra),
//! XYZ conversion for the film, and blackbody emission.

pub mod rgb;

pub use rgb::Rgb;

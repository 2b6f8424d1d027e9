//! Image outputs and inputs: PNG, TGA, OpenEXR.

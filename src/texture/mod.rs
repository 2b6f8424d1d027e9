//! Textures: constant, imagemap, scale, mix, add, subtract, checkerboard, uv, blackbody.

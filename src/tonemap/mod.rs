//! Tonemapping kernels (reinhard, linear, autolinear, contrast, maxwhite), colour spaces, gamma and clamping.

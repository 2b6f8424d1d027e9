//! Surface integrators: path and directlighting.

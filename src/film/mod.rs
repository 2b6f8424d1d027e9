//! Film buffers as LuxRender's fleximage keeps them, FLM v0 read/write, merging, comparison and convergence.

//! GPU imposter-sphere rasterizer (wgpu).

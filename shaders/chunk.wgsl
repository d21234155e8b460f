// A chunk's point records, laid out as `src/raster/chunk.rs`.

// One point: centre relative to C, and radius (metres).
struct GpuPoint {
    position: vec3<f32>,
    radius: f32,
}

// A packed base colour (`r | g << 8 | b << 16`) as 0..=255 floats.
fn unpack_color(packed: u32) -> vec3<f32> {
    return vec3<f32>(f32(packed & 0xffu), f32((packed >> 8u) & 0xffu), f32((packed >> 16u) & 0xffu));
}

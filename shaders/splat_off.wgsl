// Stand-in for splat.wgsl on devices without 64-bit atomics: every sphere is drawn.

fn try_splat(view: View, r: Rect, s: vec3<f32>, radius: f32, idx: u32) -> bool {
    return false;
}

fn try_splat_rects(view: View, rects: PixelRects, s: vec3<f32>, radius: f32, idx: u32) -> bool {
    return false;
}

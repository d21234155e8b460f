// Rays by table for the projections whose longitude depends on the column alone and
// latitude on the row alone (equirect, full or not, and cylindrical): the sines and cosines
// of every column's longitude and every row's latitude, and each row's merge factor,
// computed in f64 and rounded once (src/raster/pixel_trig.rs). A pixel's ray then costs two
// loads instead of four f32 sines and cosines and the merge profile's power, and is the ray
// tracer's ray rounded to f32. Columns first: (sin lam, cos lam, 0, 0); then rows:
// (sin phi, cos phi, merge, 0).
// Composed into the expand and imposter pipelines, after params.

@group(1) @binding(0) var<storage, read> pixel_trig: array<vec4<f32>>;

fn is_separable(kind: u32) -> bool {
    return kind == PROJ_EQUIRECT_FULL || kind == PROJ_EQUIRECT || kind == PROJ_CYLINDRICAL;
}

// The ray through the centre of pixel `px` of a separable projection.
fn table_pixel_ray(v: View, px: vec2<u32>) -> Ray {
    let t = table_pixel_trig(px);
    return ray_of_merge(v, t.trig, t.merge);
}

// Pixel `px`'s table entries: (sin lam, cos lam, sin phi, cos phi) and the merge factor.
struct PixelTrig {
    trig: vec4<f32>,
    merge: f32,
}

fn table_pixel_trig(px: vec2<u32>) -> PixelTrig {
    let column = pixel_trig[px.x];
    let row = pixel_trig[u32(params.image_size.x) + px.y];
    return PixelTrig(vec4<f32>(column.xy, row.xy), row.z);
}

// The ray through the centre of pixel `px` (integer pixel) of the image `params` draws.
fn pixel_ray(v: View, px: vec2<u32>) -> ImageRay {
    let p = projection_of(params);
    if is_separable(p.kind) {
        return ImageRay(table_pixel_ray(v, px), true);
    }
    return image_ray(v, p, params.image_size, vec2<f32>(px) + 0.5);
}

// The occlusion tiles of an eye on the keyed path: per TILE_SIDE x TILE_SIDE tile, row by
// row, !distance bits of a distance within which every pixel of the tile shows a hit (0:
// nothing known), kept with atomicMax. occlusion.wgsl records and tests them;
// tile_resolve.wgsl raises them to what the keys show.
@group(0) @binding(9) var<storage, read_write> tile_far: array<atomic<u32>>;

// Tiles per row of the image.
fn tiles_across() -> u32 {
    return (u32(params.image_size.x) + TILE_SIDE - 1u) / TILE_SIDE;
}

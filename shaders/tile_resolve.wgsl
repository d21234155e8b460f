// Raises each occlusion tile (tiles.wgsl) to the distance of its farthest pixel once every
// pixel of it shows a hit: the keys hold each pixel's nearest hit so far, so no sphere whose
// nearest possible point lies beyond that can show in the tile. Run between batches, it lets
// the spheres of later batches be hidden by the union of earlier ones, not only by a single
// large sphere. One invocation per tile, a workgroup per square of tiles; driven by
// src/raster/tile_resolve.rs.

@group(0) @binding(0) var<storage, read> params: Params;
// The eye's keys as u32 pairs (x = payload, y = !distance bits; splat_key.wgsl), read only:
// the batch's atomics are done when this runs.
@group(0) @binding(3) var<storage, read> resolve_keys: array<vec2<u32>>;

@compute @workgroup_size(RESOLVE_WORKGROUP_SIDE, RESOLVE_WORKGROUP_SIDE)
fn resolve_tiles(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = vec2<u32>(params.image_size);
    let across = tiles_across();
    if gid.x >= across || gid.y >= (size.y + TILE_SIDE - 1u) / TILE_SIDE {
        return;
    }
    let tile = gid.y * across + gid.x;
    let x0 = gid.x * TILE_SIDE;
    let y0 = gid.y * TILE_SIDE;
    let x1 = min(x0 + TILE_SIDE, size.x);
    let y1 = min(y0 + TILE_SIDE, size.y);
    // The smallest key distance bits are the farthest hit; 0, a pixel with none, ends it.
    var far = 0xffffffffu;
    for (var y = y0; y < y1 && far != 0u; y++) {
        for (var x = x0; x < x1; x++) {
            far = min(far, resolve_keys[y * size.x + x].y);
        }
    }
    if far > atomicLoad(&tile_far[tile]) {
        atomicMax(&tile_far[tile], far);
    }
}

//! How a frame's work is cut to the device: points per chunk, whether the frame takes the
//! keyed path (small spheres splatted), the vertex buffer size and the points per expand
//! batch. Pure functions of the device limits and the request.

use crate::projection::Projection;
use crate::projection::image_bounds::max_rects;
use crate::render::{Imposter, Proxy, RenderSettings};

use super::chunk::GpuPoint;
use super::constants::{MAX_DYNAMIC_LEVEL, MAX_KEY_INDEX};
use super::error::RasterError;
use super::expand::ExpandedVertex;
use super::specialisation::Specialisation;

/// Largest point buffer (bytes) one chunk binds, whatever the device allows.
const MAX_CHUNK_BYTES: u64 = 256 << 20;
/// Largest vertex buffer (bytes) a frame allocates, whatever the device allows.
const MAX_VERTEX_BYTES: u64 = 128 << 20;

/// What the device allows, as far as sizing goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeviceCaps {
    /// Largest buffer, bytes.
    pub max_buffer_size: u64,
    /// Largest storage-buffer binding, bytes.
    pub max_storage_binding: u64,
    /// Largest compute dispatch per dimension, workgroups.
    pub max_workgroups: u32,
    /// 64-bit storage atomics (the compute splat needs them).
    pub int64_atomics: bool,
}

impl DeviceCaps {
    /// The caps of a device with `limits`.
    pub fn new(limits: &wgpu::Limits, int64_atomics: bool) -> Self {
        DeviceCaps {
            max_buffer_size: limits.max_buffer_size,
            max_storage_binding: limits.max_storage_buffer_binding_size,
            max_workgroups: limits.max_compute_workgroups_per_dimension,
            int64_atomics,
        }
    }

    /// Largest buffer that can also be bound whole as storage.
    fn max_storage_buffer(&self) -> u64 {
        self.max_buffer_size.min(self.max_storage_binding)
    }
}

// A key (`shaders/splat_key.wgsl`) holds any point index of a chunk.
const _: () = assert!(
    MAX_CHUNK_BYTES / size_of::<GpuPoint>() as u64 <= MAX_KEY_INDEX as u64 + 1,
    "a chunk's point indices must fit a key"
);

/// Points one GPU chunk holds: as many as one storage binding of points allows.
pub fn points_per_chunk(caps: &DeviceCaps) -> u64 {
    (caps.max_storage_buffer().min(MAX_CHUNK_BYTES) / size_of::<GpuPoint>() as u64).max(1)
}

/// Worst-case vertices one point can emit under `proxy` in `projection`: its grid of two
/// triangles per cell, twice (the proxy and its seam copy); a bounds proxy outside the full
/// equirect, one quad per pixel rectangle.
pub fn max_vertices_per_point(proxy: Proxy, projection: &Projection) -> u64 {
    let n = match proxy {
        Proxy::Bounds => return 6 * max_rects(projection).max(2) as u64,
        Proxy::Quad => 1,
        Proxy::Static(n) => n.max(1) as u64,
        Proxy::Dynamic => MAX_DYNAMIC_LEVEL as u64,
    };
    12 * n * n
}

/// The rasterizer's own knobs that bear on sizing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Knobs {
    /// Largest sphere (pixels per side) the compute splat ray casts; 0 turns it off.
    pub splat_limit: u32,
    /// The same for the splat of an ODS pair's two eyes at once.
    pub pair_splat_limit: u32,
    /// Cap on the points per batch.
    pub batch_limit: Option<u32>,
    /// Whether a gathered frame skips pieces hidden whole (`piece_occlusion`).
    pub skip_hidden_pieces: bool,
}

/// Bytes of the keys of one `width x height` eye: one `u64` per pixel.
pub fn key_bytes(width: u32, height: u32) -> u64 {
    width as u64 * height as u64 * size_of::<u64>() as u64
}

/// Whether a frame under `settings` takes the keyed path ([`super::splat`]): ray-cast
/// imposters on analytic bounds, a device with 64-bit atomics, the splat on and one eye's
/// keys within a storage binding.
pub fn splats(caps: &DeviceCaps, knobs: &Knobs, settings: &RenderSettings) -> bool {
    caps.int64_atomics
        && knobs.splat_limit > 0
        && settings.proxy == Proxy::Bounds
        && settings.imposter == Imposter::Raycast
        && key_bytes(settings.image.width, settings.image.height) <= caps.max_storage_buffer()
}

/// How one frame is cut into GPU work.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameSizing {
    /// Largest sphere the compute splat ray casts, pixels per side of its bounds; 0 when the
    /// splat is off for this frame.
    pub splat_limit: u32,
    /// Vertices the expand pass may write per batch.
    pub vertex_capacity: u32,
    /// Points per expand dispatch.
    pub batch_points: u32,
}

/// Whether the rasterizer draws `projection` with `proxy` and `imposter`: billboard proxies
/// and sprites are equirect-only.
pub fn draws(projection: Projection, proxy: Proxy, imposter: Imposter) -> bool {
    projection.is_full_equirect() || (proxy == Proxy::Bounds && imposter == Imposter::Raycast)
}

impl FrameSizing {
    /// Sizes a frame under `settings` whose chunks hold at most `max_chunk_points` points.
    pub fn new(
        caps: &DeviceCaps,
        knobs: &Knobs,
        settings: &RenderSettings,
        max_chunk_points: u64,
    ) -> Result<Self, RasterError> {
        let projection = settings.image.projection;
        if !draws(projection, settings.proxy, settings.imposter) {
            return Err(RasterError::Settings(format!(
                "the rasterizer draws the {projection} projection with --proxy bounds \
                 --imposter raycast only (billboard proxies and sprites are equirect-only)"
            )));
        }
        if projection == Projection::Map(None) {
            return Err(RasterError::Settings(
                "the map projection needs its extent from the scene's bounds (Image::map)".into(),
            ));
        }
        let splat = splats(caps, knobs, settings);

        let vertex_bytes = size_of::<ExpandedVertex>() as u64;
        let per_point = max_vertices_per_point(settings.proxy, &projection);
        let vertex_bytes_max = caps
            .max_storage_buffer()
            .min(MAX_VERTEX_BYTES)
            // wgpu zero-fills a fresh buffer before its first use, every frame: no larger
            // than the biggest chunk needs. (Smaller still would cost more batches, and each
            // batch's submit and wait costs far more than the fill on lavapipe.)
            .min(max_chunk_points.max(1) * per_point * vertex_bytes);
        let vertex_capacity = vertex_bytes_max / vertex_bytes;
        let max_dispatch = caps.max_workgroups as u64 * super::constants::EXPAND_WORKGROUP as u64;
        let batch = (vertex_capacity / per_point)
            .min(max_dispatch)
            .min(knobs.batch_limit.map_or(u64::MAX, u64::from))
            .min(u32::MAX as u64)
            .max(1);
        let vertex_capacity = (batch * per_point).min(vertex_capacity);
        if vertex_capacity < per_point {
            return Err(RasterError::Limit {
                what: "one point's proxy vertices".into(),
                needed: per_point * vertex_bytes,
                limit: vertex_bytes_max,
            });
        }
        Ok(FrameSizing {
            splat_limit: match (splat, Specialisation::of_frame(settings).splats_pairs()) {
                (false, _) => 0,
                (true, false) => knobs.splat_limit,
                (true, true) => knobs.pair_splat_limit,
            },
            vertex_capacity: vertex_capacity as u32,
            batch_points: batch as u32,
        })
    }

    /// True when this frame splats small spheres.
    pub fn splat(&self) -> bool {
        self.splat_limit > 0
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::projection::{Camera, Image};

    /// What lavapipe (llvmpipe, Mesa 22) grants.
    const LAVAPIPE: DeviceCaps = DeviceCaps {
        max_buffer_size: (1 << 31) - 1,
        max_storage_binding: 128 << 20,
        max_workgroups: 65_535,
        int64_atomics: true,
    };

    const DEFAULT_KNOBS: Knobs = Knobs {
        splat_limit: 16,
        pair_splat_limit: 64,
        batch_limit: None,
        skip_hidden_pieces: true,
    };

    fn settings(width: u32, proxy: Proxy, imposter: Imposter) -> RenderSettings {
        let mut s = RenderSettings::new(width, Camera::new(DVec3::ZERO, 0.0));
        s.proxy = proxy;
        s.imposter = imposter;
        s
    }

    fn bounds(width: u32) -> RenderSettings {
        settings(width, Proxy::Bounds, Imposter::Raycast)
    }

    #[test]
    fn a_chunk_fills_one_storage_binding_of_points() {
        assert_eq!(points_per_chunk(&LAVAPIPE), (128 << 20) / 16);
        let big = DeviceCaps {
            max_storage_binding: 4 << 30,
            max_buffer_size: 4 << 30,
            ..LAVAPIPE
        };
        assert_eq!(points_per_chunk(&big), (256 << 20) / 16);
        let tiny = DeviceCaps {
            max_storage_binding: 4,
            ..LAVAPIPE
        };
        assert_eq!(points_per_chunk(&tiny), 1);
    }

    #[test]
    fn lavapipe_at_3840_splats_and_fills_128_mib_of_vertices() {
        let chunk = points_per_chunk(&LAVAPIPE);
        let s = FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, &bounds(3840), chunk).unwrap();
        assert_eq!(
            s,
            FrameSizing {
                splat_limit: 16,
                // 128 MiB of 16-byte vertices, 12 per point, rounded down to whole points.
                vertex_capacity: 699_050 * 12,
                batch_points: 699_050,
            }
        );
        assert!(s.splat());
    }

    #[test]
    fn an_ods_pair_in_the_full_equirect_takes_the_pair_limit() {
        let ods = RenderSettings {
            stereo: crate::projection::Stereo::DEFAULT_ODS,
            ..bounds(1024)
        };
        let limit = |s: &RenderSettings| {
            FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, s, 1000)
                .unwrap()
                .splat_limit
        };
        assert_eq!(limit(&ods), 64);
        assert_eq!(limit(&bounds(1024)), 16);
        let mut hammer = ods;
        hammer.image = Image::new(crate::projection::Projection::Hammer, 1024).unwrap();
        assert_eq!(limit(&hammer), 16);
    }

    #[test]
    fn the_splat_is_off_when_its_keys_exceed_a_binding_or_the_device_lacks_atomics() {
        // 8192 x 4096 x 8 bytes = 256 MiB > 128 MiB.
        let s = FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, &bounds(8192), 1000).unwrap();
        assert_eq!(s.splat_limit, 0);
        assert!(!s.splat());
        let no_atomics = DeviceCaps {
            int64_atomics: false,
            ..LAVAPIPE
        };
        let s = FrameSizing::new(&no_atomics, &DEFAULT_KNOBS, &bounds(512), 1000).unwrap();
        assert_eq!(s.splat_limit, 0);
        let off = Knobs {
            splat_limit: 0,
            ..DEFAULT_KNOBS
        };
        assert!(
            !FrameSizing::new(&LAVAPIPE, &off, &bounds(512), 1000)
                .unwrap()
                .splat()
        );
        for (proxy, imposter) in [
            (Proxy::Quad, Imposter::Raycast),
            (Proxy::Bounds, Imposter::Sprite),
        ] {
            let s = FrameSizing::new(
                &LAVAPIPE,
                &DEFAULT_KNOBS,
                &settings(512, proxy, imposter),
                1000,
            )
            .unwrap();
            assert!(!s.splat(), "{proxy:?} {imposter:?}");
        }
    }

    #[test]
    fn the_dynamic_proxy_sizes_for_its_worst_case_level() {
        assert_eq!(
            max_vertices_per_point(Proxy::Dynamic, &Projection::EQUIRECT),
            12 * 16 * 16
        );
        let s = settings(3840, Proxy::Dynamic, Imposter::Raycast);
        let f = FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, &s, 8 << 20).unwrap();
        // 3072 vertices of 16 bytes per point: 2730 points fit 128 MiB.
        assert_eq!(f.batch_points, 2730);
        assert_eq!(f.vertex_capacity, 2730 * 3072);
        assert_eq!(f.splat_limit, 0);
    }

    #[test]
    fn small_chunks_and_the_batch_limit_shrink_the_batch() {
        let f = FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, &bounds(512), 100).unwrap();
        assert_eq!((f.batch_points, f.vertex_capacity), (100, 1200));
        let knobs = Knobs {
            batch_limit: Some(97),
            ..DEFAULT_KNOBS
        };
        let f = FrameSizing::new(&LAVAPIPE, &knobs, &bounds(512), 1000).unwrap();
        assert_eq!((f.batch_points, f.vertex_capacity), (97, 97 * 12));
        let one_group = DeviceCaps {
            max_workgroups: 1,
            ..LAVAPIPE
        };
        let f = FrameSizing::new(&one_group, &DEFAULT_KNOBS, &bounds(512), 1 << 20).unwrap();
        assert_eq!(f.batch_points, 256);
    }

    #[test]
    fn tiny_limits_give_tiny_batches_or_a_limit_error() {
        let tiny = DeviceCaps {
            max_storage_binding: 1000,
            ..LAVAPIPE
        };
        // 1000 bytes hold 62 vertices: 5 points of 12.
        let f = FrameSizing::new(&tiny, &DEFAULT_KNOBS, &bounds(64), 1000).unwrap();
        assert_eq!((f.batch_points, f.vertex_capacity), (5, 60));
        // A dynamic proxy's worst case (49,152 bytes) does not fit 40,000.
        let small = DeviceCaps {
            max_storage_binding: 40_000,
            ..LAVAPIPE
        };
        let s = settings(64, Proxy::Dynamic, Imposter::Raycast);
        match FrameSizing::new(&small, &DEFAULT_KNOBS, &s, 1000) {
            Err(RasterError::Limit { needed, limit, .. }) => {
                assert_eq!((needed, limit), (49_152, 40_000))
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn other_projections_draw_bounds_with_one_quad_per_rectangle() {
        let mut s = bounds(384);
        s.image = Image::new(Projection::Cubemap, 384).unwrap();
        let f = FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, &s, 100).unwrap();
        // Up to six face rectangles of six vertices each.
        assert_eq!((f.batch_points, f.vertex_capacity), (100, 100 * 36));
        assert!(f.splat());
        s.image = Image::new(Projection::Hammer, 384).unwrap();
        let f = FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, &s, 100).unwrap();
        assert_eq!(f.vertex_capacity, 100 * 12);
    }

    #[test]
    fn other_projections_refuse_billboards_sprites_and_an_unresolved_map() {
        for (proxy, imposter) in [
            (Proxy::Quad, Imposter::Raycast),
            (Proxy::Dynamic, Imposter::Raycast),
            (Proxy::Bounds, Imposter::Sprite),
        ] {
            let mut s = settings(384, proxy, imposter);
            s.image = Image::new(Projection::Fisheye { fov_deg: 180.0 }, 384).unwrap();
            match FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, &s, 100) {
                Err(RasterError::Settings(m)) => {
                    assert!(m.contains("--proxy bounds --imposter raycast"), "{m}")
                }
                other => panic!("{other:?}"),
            }
        }
        let mut s = bounds(384);
        s.image.projection = Projection::Map(None);
        match FrameSizing::new(&LAVAPIPE, &DEFAULT_KNOBS, &s, 100) {
            Err(RasterError::Settings(m)) => assert!(m.contains("map"), "{m}"),
            other => panic!("{other:?}"),
        }
    }
}

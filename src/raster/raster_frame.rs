//! One frame in progress on the GPU: targets cleared once, any number of point chunks drawn
//! into them, then read back. [`Rasterizer::render_uploaded`] draws an uploaded scene's chunks
//! through it; [`super::ChunkedFrame`] draws chunks as they are decoded, so the whole cloud
//! never has to be resident.

use std::sync::Arc;

use indicatif::ProgressBar;

use crate::frame::{Frame, Rendered};
use crate::projection::View;
use crate::render::{Proxy, RenderSettings, cubemap_stereo};

use super::chunk::GpuChunk;
use super::error::RasterError;
use super::expand::{ExpandBuffers, KeyedBuffers, empty_draw_args};
use super::frame_buffers::{FrameBuffers, FrameShape, MAX_EYES, Spare};
use super::params::Params;
use super::piece_occlusion;
use super::pixel_trig;
use super::rasterizer::{Pipelines, Rasterizer};
use super::sizing::{FrameSizing, splats};
use super::specialisation::Specialisation;
use super::splat;
use super::stats::{EyeStats, RasterStats};
use super::targets::map_read;
use super::timing::{FrameClock, FrameTiming};

/// A frame being drawn: per-eye images (keys or render targets) and the expand/draw work
/// buffers, sized for chunks of up to `max_chunk_points` points.
pub struct RasterFrame<'r> {
    rasterizer: &'r Rasterizer,
    /// Compiled for the modes of `settings`.
    pipelines: Arc<Pipelines>,
    /// The pixel trigonometry of `settings`' image, bound.
    trig: wgpu::BindGroup,
    /// What is drawn: `output`, or its cube-map faces.
    settings: RenderSettings,
    /// What `finish` returns.
    output: RenderSettings,
    views: Vec<View>,
    sizing: FrameSizing,
    buffers: FrameBuffers,
    /// Whether `finish` keeps the buffers for the next frame.
    keep: bool,
    clock: FrameClock,
    batches: u64,
    /// Per eye, whether a batch was drawn this frame: its keys then hold what the next
    /// batch's tile resolve reads.
    drawn_any: [bool; MAX_EYES],
    camera_offset: [f32; 3],
}

impl Rasterizer {
    /// Starts a frame under `settings` whose chunks hold at most `max_chunk_points` points:
    /// allocates and clears the targets. [`Rasterizer::render_uploaded`] and
    /// [`super::ChunkedFrame`] draw chunks into it; [`RasterFrame::finish`] reads it back.
    pub fn begin_frame(
        &self,
        settings: &RenderSettings,
        max_chunk_points: u64,
    ) -> Result<RasterFrame<'_>, RasterError> {
        // `--stereo cubemap:N` draws its eyes' cube strips, resampled by `finish`.
        let output = *settings;
        let faces = cubemap_stereo::face_settings(&output);
        let settings = &faces.unwrap_or(output);
        let sizing = FrameSizing::new(&self.caps(), self.knobs(), settings, max_chunk_points)
            .map_err(|e| match (faces, e) {
                (Some(_), RasterError::Settings(m)) => RasterError::Settings(format!(
                    "--stereo {} draws cube-map faces: {m}",
                    output.stereo.kind()
                )),
                (_, e) => e,
            })?;
        check_settings(settings)?;
        let ctx = &self.ctx;
        let device = &ctx.device;
        let views = settings.views();
        let pipelines = self.pipelines(Specialisation::of_frame(settings), sizing.splat())?;
        if pipelines.expand.pairs() && !eyes_mirror(settings, &views) {
            return Err(RasterError::Settings(
                "the eyes of a stereo frame differ in more than their sign".into(),
            ));
        }
        // The eyes of a frame share their merge profiles: one table serves them all.
        debug_assert!(views.iter().all(|v| v.merging == views[0].merging));
        let table = pixel_trig::table(&settings.image, &views[0].merging);
        let trig = ctx.scoped("uploading the pixel trigonometry", || {
            pixel_trig::bind(device, &self.trig_layout, &table)
        })?;
        let img = settings.image;
        let shape = FrameShape::new((img.width, img.height), views.len(), &sizing);
        let (buffers, keep) = Spare::take(&self.spare, ctx, shape)?;

        let mut encoder = device.create_command_encoder(&Default::default());
        // The clears are the frame's first GPU work and are timed with it.
        let clock = FrameClock::start(ctx, &mut encoder);
        encoder.clear_buffer(&buffers.stats, 0, None);
        buffers.images.clear(&mut encoder);
        ctx.queue.submit([encoder.finish()]);

        Ok(RasterFrame {
            rasterizer: self,
            pipelines,
            trig,
            settings: *settings,
            output,
            views,
            sizing,
            buffers,
            keep,
            clock,
            batches: 0,
            drawn_any: [false; MAX_EYES],
            camera_offset: [0.0; 3],
        })
    }
}

impl Rasterizer {
    /// Compiles the pipelines a frame under `settings` draws with, ahead of the frame: a
    /// caller can do it while it reads the scene.
    pub fn prepare(&self, settings: &RenderSettings) -> Result<(), RasterError> {
        let drawn = cubemap_stereo::face_settings(settings).unwrap_or(*settings);
        let keyed = splats(&self.caps(), self.knobs(), &drawn);
        self.pipelines(Specialisation::of_frame(&drawn), keyed)
            .map(drop)
    }
}

/// Whether `views` are the two eyes of a pair whose parameters differ only in the eye (its
/// index and sign), as the pair splat (`expand_splat_pair`) takes them to.
fn eyes_mirror(settings: &RenderSettings, views: &[View]) -> bool {
    let [left, right] = views else {
        return false;
    };
    let left = Params::new(left, settings, 0, (0, 0), 0);
    let mirrored = Params {
        eye: 1,
        eye_sign: -left.eye_sign,
        ..left
    };
    Params::new(right, settings, 1, (0, 0), 0) == mirrored
}

/// Rejects settings the rasterizer cannot draw.
fn check_settings(settings: &RenderSettings) -> Result<(), RasterError> {
    let img = settings.image;
    let two_to_one = img.width == 2 * img.height || !img.projection.is_full_equirect();
    if img.width == 0 || img.height == 0 || !two_to_one {
        return Err(RasterError::Settings(format!(
            "image {}x{} is not a 2:1 equirectangular size",
            img.width, img.height
        )));
    }
    if let Proxy::Static(n) = settings.proxy
        && !(1..=64).contains(&n)
    {
        return Err(RasterError::Settings(format!(
            "static tessellation level {n} is outside 1..=64"
        )));
    }
    Ok(())
}

impl<'r> RasterFrame<'r> {
    /// The rasterizer drawing this frame.
    pub(crate) fn rasterizer(&self) -> &'r Rasterizer {
        self.rasterizer
    }

    /// Tells the frame that the chunks it will draw hold positions relative to
    /// `points_origin` (in the frame of the settings' camera centre) rather than to the
    /// camera centre itself; the shaders subtract the difference.
    pub(crate) fn set_points_origin(&mut self, points_origin: glam::DVec3) {
        let offset = self.settings.camera.center - points_origin;
        self.camera_offset = offset.as_vec3().to_array();
    }

    /// Number of views (eyes) drawn.
    pub(crate) fn eyes(&self) -> usize {
        self.views.len()
    }

    /// Expands and draws `chunk` for every eye, then merges its splatted spheres; `progress`
    /// advances by the points drawn, once per eye. Batch by batch, each eye in turn; an ODS
    /// pair's splat serves both eyes in the first eye's dispatch.
    pub(crate) fn draw(
        &mut self,
        chunk: &GpuChunk,
        progress: &ProgressBar,
    ) -> Result<(), RasterError> {
        if chunk.len == 0 {
            return Ok(());
        }
        let r = &*self.pipelines;
        let ctx = &self.rasterizer.ctx;
        let device = &ctx.device;
        let images = &self.buffers.images;
        let eyes = self.views.len();
        // Per eye: on the keyed path each eye's keys are its image.
        let bind_groups = ctx.scoped("binding a chunk", || {
            (0..eyes)
                .map(|eye| {
                    let keys = images.keys(eye);
                    // The pair splat's other eye; a mono eye binds its own again.
                    let pair = images.keys((eye + 1) % eyes);
                    let expand = r.expand.bind(
                        device,
                        &ExpandBuffers {
                            params: &self.buffers.params,
                            points: &chunk.points,
                            vertices: &self.buffers.vertices,
                            draw_args: &self.buffers.draw_args,
                            stats: &self.buffers.stats,
                            keyed: keys.zip(pair).zip(self.buffers.listed.as_ref()).map(
                                |((own, pair), (listed, listed_groups))| KeyedBuffers {
                                    keys: &own.keys,
                                    tiles: &own.tiles,
                                    pair_keys: &pair.keys,
                                    pair_tiles: &pair.tiles,
                                    colors: &chunk.colors,
                                    listed,
                                    listed_groups,
                                },
                            ),
                        },
                    );
                    let draw = r.imposter.bind(
                        device,
                        &self.buffers.params,
                        &chunk.points,
                        &chunk.colors,
                        keys.map(|eye| &eye.keys),
                    );
                    let resolve = r.resolve.as_ref().zip(keys).map(|(resolve, eye)| {
                        resolve.bind(device, &self.buffers.params, &eye.keys, &eye.tiles)
                    });
                    (expand, draw, resolve)
                })
                .collect::<Vec<_>>()
        })?;
        let pairs = r.expand.pairs();
        let img = self.settings.image;
        let mut first = 0u32;
        while first < chunk.len {
            let count = (chunk.len - first).min(self.sizing.batch_points);
            for eye in 0..eyes {
                let (expand_bg, draw_bg, _) = &bind_groups[eye];
                // The second eye of a pair: the first eye's dispatch splatted and listed its
                // spheres; it draws the listed ones.
                let listed_only = pairs && eye == 1;
                let params = self.params(eye, (first, count));
                debug_assert_eq!(Specialisation::of(&params), self.pipelines.spec);
                ctx.queue
                    .write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(&params));
                ctx.queue
                    .write_buffer(&self.buffers.draw_args, 0, empty_draw_args().as_bytes());
                if let (Some((listed, groups)), false) = (&self.buffers.listed, listed_only) {
                    ctx.queue
                        .write_buffer(listed, 0, bytemuck::bytes_of(&splat::NO_LISTED));
                    ctx.queue
                        .write_buffer(groups, 0, bytemuck::bytes_of(&splat::NO_GROUPS));
                }
                let mut encoder = device.create_command_encoder(&Default::default());
                // What earlier batches drew hides spheres of this one: the tiles of the eyes
                // this eye's splat tests.
                let splatted: &[usize] = match (listed_only, pairs) {
                    (true, _) => &[],
                    (false, true) => &[0, 1],
                    (false, false) => &[eye],
                };
                for &e in splatted {
                    if let (Some(resolve), Some(bg), true) =
                        (&r.resolve, &bind_groups[e].2, self.drawn_any[e])
                    {
                        resolve.dispatch(&mut encoder, bg, &self.trig, (img.width, img.height));
                    }
                }
                let listed_groups = self.buffers.listed.as_ref().map(|(_, groups)| groups);
                r.expand.dispatch(
                    &mut encoder,
                    expand_bg,
                    &self.trig,
                    (count, listed_groups),
                    listed_only,
                );
                {
                    let mut pass = images.begin_draw(eye, &mut encoder);
                    r.imposter.draw(
                        &mut pass,
                        draw_bg,
                        &self.trig,
                        &self.buffers.vertices,
                        &self.buffers.draw_args,
                    );
                }
                ctx.queue.submit([encoder.finish()]);
                // Keep the queue short so progress means something and memory stays flat.
                ctx.wait("drawing imposters")?;
                progress.inc(count as u64);
                self.batches += 1;
            }
            self.drawn_any[..eyes].fill(true);
            first += count;
        }
        // Lit shadings: shade each pixel's nearest hit of this chunk once (its keys index this
        // chunk's points), seen by its eye.
        for eye in 0..eyes {
            if let (Some(shade), Some(keys)) = (&r.shade, images.keys(eye).map(|e| &e.keys)) {
                let params = self.params(eye, (0, chunk.len));
                ctx.queue
                    .write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(&params));
                let bg = ctx.scoped("binding the deferred shading", || {
                    shade.bind(
                        device,
                        &self.buffers.params,
                        &chunk.points,
                        &chunk.colors,
                        keys,
                    )
                })?;
                let mut encoder = device.create_command_encoder(&Default::default());
                shade.dispatch(&mut encoder, &bg, &self.trig, (img.width, img.height));
                ctx.queue.submit([encoder.finish()]);
                ctx.wait("shading the splatted spheres")?;
            }
        }
        Ok(())
    }

    /// Whether the frame keeps occlusion tiles that [`RasterFrame::occlusion_tiles`] can read:
    /// on the keyed path, in the full equirect, without a depth map (whose spheres each have
    /// their own view).
    pub(crate) fn keeps_tiles(&self) -> bool {
        self.output == self.settings
            && self.settings.image.projection.is_full_equirect()
            && self.settings.depth_map.is_none()
            && self.buffers.images.keys(0).is_some()
    }

    /// The occlusion tiles of every eye as what is drawn so far shows them (raised to the
    /// keys first, as the next batch would); `None` where the frame keeps none.
    pub(crate) fn occlusion_tiles(
        &mut self,
    ) -> Result<Option<piece_occlusion::OcclusionTiles>, RasterError> {
        let Some(resolve) = self
            .pipelines
            .resolve
            .as_ref()
            .filter(|_| self.keeps_tiles())
        else {
            return Ok(None);
        };
        let ctx = &self.rasterizer.ctx;
        let device = &ctx.device;
        let img = self.settings.image;
        let mut eyes = Vec::with_capacity(self.views.len());
        for (eye, view) in self.views.iter().enumerate() {
            let keys = self.buffers.images.keys(eye).expect("keyed");
            let read = ctx.scoped("reading back the occlusion tiles", || {
                let read = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("occlusion tile read-back"),
                    size: keys.tiles.size(),
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                });
                let params = self.params(eye, (0, 0));
                ctx.queue
                    .write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(&params));
                let mut encoder = device.create_command_encoder(&Default::default());
                if self.drawn_any[eye] {
                    let bg = resolve.bind(device, &self.buffers.params, &keys.keys, &keys.tiles);
                    resolve.dispatch(&mut encoder, &bg, &self.trig, (img.width, img.height));
                }
                encoder.copy_buffer_to_buffer(&keys.tiles, 0, &read, 0, None);
                ctx.queue.submit([encoder.finish()]);
                read
            })?;
            let tiles = map_read(ctx, &read, "reading back the occlusion tiles")?;
            eyes.push((*view, bytemuck::pod_collect_to_vec(&tiles)));
        }
        Ok(Some(piece_occlusion::OcclusionTiles::new(
            img.width, img.height, eyes,
        )))
    }

    /// The `Params` of eye `eye` drawing the batch of `count` points from `first`.
    fn params(&self, eye: usize, (first, count): (u32, u32)) -> Params {
        Params {
            splat_limit: self.sizing.splat_limit as f32,
            camera_offset: self.camera_offset,
            ..Params::new(
                &self.views[eye],
                &self.settings,
                eye as u32,
                (first, count),
                self.sizing.vertex_capacity,
            )
        }
    }

    /// Ends the frame: reads back the images, the counts and the time the drawing took.
    pub fn finish(self) -> Result<(Rendered, RasterStats, FrameTiming), RasterError> {
        let ctx = &self.rasterizer.ctx;
        let device = &ctx.device;
        let timing = self.clock.finish(ctx, self.batches)?;

        let stats_bytes = (MAX_EYES * size_of::<EyeStats>()) as u64;
        let read = ctx.scoped("reading back statistics", || {
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stats read-back"),
                size: stats_bytes,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(&self.buffers.stats, 0, &read, 0, None);
            ctx.queue.submit([encoder.finish()]);
            read
        })?;
        let raw = map_read(ctx, &read, "reading back statistics")?;
        let per_eye: Vec<EyeStats> = bytemuck::pod_collect_to_vec(&raw);
        let stats = RasterStats::sum(&per_eye[..self.views.len()], self.batches).map_err(|n| {
            RasterError::Gpu {
                while_doing: "expanding proxies".into(),
                message: format!("{n} proxies overflowed the vertex buffer"),
            }
        })?;
        let mut buffers = self.buffers;
        let mut frames: Vec<Frame> = if self.keep {
            let frames = buffers.images.read_kept(ctx, &self.rasterizer.spare)?;
            Spare::put(&self.rasterizer.spare, buffers);
            frames
        } else {
            // The work buffers are no longer needed, and each eye's image goes as soon as its
            // frame is read back: the peak while reading stays near one eye's read-back.
            drop(buffers.vertices);
            buffers.images.read_freed(ctx)?
        };
        let rendered = if frames.len() == 2 {
            let right = frames.pop().expect("two frames");
            let left = frames.pop().expect("two frames");
            Rendered::Stereo { left, right }
        } else {
            Rendered::Mono(frames.pop().expect("one frame"))
        };
        let rendered = if self.output == self.settings {
            rendered
        } else {
            cubemap_stereo::resample(&rendered, &self.output)
        };
        Ok((rendered, stats, timing))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::projection::depth_map::DepthMap;
    use crate::projection::{Camera, OdsOffset, PoleMerge, PoleMerging, Stereo};

    #[test]
    fn the_eyes_of_every_stereo_rig_differ_only_in_their_sign() {
        let camera = Camera::new(DVec3::new(3.0, -2.0, 1.5), 37.0).with_orientation(12.0, -5.0);
        let merging = PoleMerging {
            north: PoleMerge::COMFORTABLE,
            south: PoleMerge::Off,
        };
        let rigs = [
            Stereo::DEFAULT_ODS,
            Stereo::Ods {
                ipd: 0.5,
                merging,
                offset: OdsOffset::Paper,
            },
            Stereo::Parallel { ipd: 0.064 },
        ];
        let depth_maps = [
            None,
            Some(DepthMap::new(&[(1.0, 2.0), (4.0, 3.0)]).unwrap()),
        ];
        for stereo in rigs {
            for depth_map in depth_maps {
                let settings = RenderSettings {
                    stereo,
                    depth_map,
                    ..RenderSettings::new(256, camera)
                };
                assert!(eyes_mirror(&settings, &settings.views()), "{stereo:?}");
                let mono = RenderSettings {
                    stereo: Stereo::Mono,
                    ..settings
                };
                assert!(!eyes_mirror(&mono, &mono.views()));
            }
        }
        // Eyes that differ in more than their sign do not pass.
        let settings = RenderSettings {
            stereo: Stereo::DEFAULT_ODS,
            ..RenderSettings::new(256, camera)
        };
        let mut views = settings.views();
        views[1].half_ipd *= 2.0;
        assert!(!eyes_mirror(&settings, &views));
        let mut views = settings.views();
        views[1].merging.south = PoleMerge::Off;
        assert!(!eyes_mirror(&settings, &views));
    }
}

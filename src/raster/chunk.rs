//! Points on the GPU: a chunk's point and colour buffers, in the layout of
//! `shaders/chunk.wgsl`.

use bytemuck::{Pod, Zeroable};

use crate::scene::Scene;

use super::context::GpuContext;
use super::error::RasterError;

/// One point as the shaders read it (WGSL `GpuPoint`): centre relative to the camera centre
/// (so f32 keeps sub-millimetre precision) and radius, metres.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPoint {
    /// Centre minus the camera centre.
    pub position: [f32; 3],
    /// Sphere radius.
    pub radius: f32,
}

impl GpuPoint {
    /// Point `i` of `scene` relative to the camera centre `c` (in the scene's frame).
    pub fn of(scene: &Scene, i: usize, c: glam::DVec3) -> Self {
        let p = scene.positions[i].as_dvec3() - c;
        GpuPoint {
            position: p.as_vec3().to_array(),
            radius: scene.radii.get(i),
        }
    }
}

/// A base colour as the shaders read it: `r | g << 8 | b << 16` (WGSL `unpack_color`).
pub fn pack_color(c: [u8; 3]) -> u32 {
    c[0] as u32 | (c[1] as u32) << 8 | (c[2] as u32) << 16
}

/// Points and their base colours on the GPU.
pub(crate) struct GpuChunk {
    /// One [`GpuPoint`] per point.
    pub points: wgpu::Buffer,
    /// One [`pack_color`] per point.
    pub colors: wgpu::Buffer,
    /// Points in use (the buffers may hold more).
    pub len: u32,
    /// Points the buffers can hold.
    pub capacity: u32,
}

impl GpuChunk {
    /// Allocates buffers for `capacity` points.
    pub fn new(ctx: &GpuContext, capacity: u32) -> Result<Self, RasterError> {
        let capacity = capacity.max(1);
        ctx.scoped("allocating point buffers", || {
            let make = |label, size| {
                ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    // COPY_SRC: pieces uploaded apart are gathered into one batch on the GPU.
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            };
            let n = capacity as u64;
            GpuChunk {
                points: make("chunk points", n * size_of::<GpuPoint>() as u64),
                colors: make("chunk colors", n * size_of::<u32>() as u64),
                len: 0,
                capacity,
            }
        })
    }

    /// Writes `points` and `colors` (equal lengths, at most `capacity`) to the start of the
    /// buffers.
    pub fn write(
        &mut self,
        ctx: &GpuContext,
        points: &[GpuPoint],
        colors: &[u32],
    ) -> Result<(), RasterError> {
        if points.len() != colors.len() || points.len() > self.capacity as usize {
            return Err(RasterError::Settings(format!(
                "{} points and {} colours do not fit a chunk of {}",
                points.len(),
                colors.len(),
                self.capacity
            )));
        }
        ctx.scoped("uploading points", || {
            ctx.queue
                .write_buffer(&self.points, 0, bytemuck::cast_slice(points));
            ctx.queue
                .write_buffer(&self.colors, 0, bytemuck::cast_slice(colors));
        })?;
        self.len = points.len() as u32;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::shaders::{CHUNK, compose, field_offsets, wgsl_struct_layout};
    use super::*;

    #[test]
    fn gpu_point_matches_the_wgsl_struct() {
        let rust = field_offsets!(GpuPoint: position, radius);
        let size = size_of::<GpuPoint>() as u32;
        assert_eq!(
            wgsl_struct_layout(&compose(&[CHUNK]), "GpuPoint"),
            (rust, size)
        );
    }
}

//! An eye's image read back from the device into a [`Frame`], whatever its kind.

use crate::frame::Frame;

use super::context::GpuContext;
use super::error::RasterError;

/// An eye's image that reads back into a [`Frame`]: the drawn targets or the keys.
pub trait ReadBack {
    /// Width and height of the eye.
    fn size(&self) -> (u32, u32);
    /// Reads the image back into a frame (into `reuse`'s memory when it has the eye's size:
    /// every pixel is written); `keep` keeps the read-back buffers for the next read.
    fn read(
        &mut self,
        ctx: &GpuContext,
        keep: bool,
        reuse: Option<Frame>,
    ) -> Result<Frame, RasterError>;
}

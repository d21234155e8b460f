//! What draws a sequence of frames from moving cameras: a scene kept resident
//! ([`super::Resident`]) or a level-of-detail node stream ([`super::NodeStream`]).

use indicatif::ProgressBar;

use super::anchor::Anchor;
use super::error::ResidentError;
use crate::Rendered;
use crate::render::RenderSettings;

/// Renders frames one after another for a tour or a live view.
pub trait DrawsFrames {
    /// Renders one frame; `settings.camera.center` is in the scene's local frame.
    ///
    /// # Errors
    /// Whatever the renderer reports.
    fn render_frame(
        &mut self,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<Rendered, ResidentError>;

    /// Hands a rendered frame back once written, for the next read-back to reuse its memory.
    fn recycle_frame(&self, rendered: Rendered);

    /// Where the rasterizer's points are measured from.
    fn anchor(&self) -> Anchor;

    /// Measures the points from `anchor` for the frames to come (uploading them again, or
    /// dropping the nodes held, when it moves).
    ///
    /// # Errors
    /// The upload failed.
    fn place(&mut self, anchor: Anchor) -> Result<(), ResidentError>;

    /// Frees what is on the GPU, after a failure: the next `place` or frame uploads again.
    fn release(&mut self);

    /// The device that renders: the GPU adapter's name, or the CPU.
    fn device(&self) -> &str;

    /// Widest panorama (pixels per eye) it can render; `None` when no device limits it.
    fn max_image_width(&self) -> Option<u32>;
}

impl DrawsFrames for super::Resident<'_> {
    fn render_frame(
        &mut self,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<Rendered, ResidentError> {
        self.render(settings, progress)
    }

    fn recycle_frame(&self, rendered: Rendered) {
        self.recycle(rendered);
    }

    fn anchor(&self) -> Anchor {
        super::Resident::anchor(self)
    }

    fn place(&mut self, anchor: Anchor) -> Result<(), ResidentError> {
        super::Resident::place(self, anchor)
    }

    fn release(&mut self) {
        super::Resident::release(self);
    }

    fn device(&self) -> &str {
        super::Resident::device(self)
    }

    fn max_image_width(&self) -> Option<u32> {
        super::Resident::max_image_width(self)
    }
}

#[cfg(feature = "gpu")]
impl DrawsFrames for super::NodeStream {
    fn render_frame(
        &mut self,
        settings: &RenderSettings,
        progress: &ProgressBar,
    ) -> Result<Rendered, ResidentError> {
        self.render(settings, progress)
    }

    fn recycle_frame(&self, rendered: Rendered) {
        self.rasterizer().recycle(rendered);
    }

    fn anchor(&self) -> Anchor {
        super::NodeStream::anchor(self)
    }

    fn place(&mut self, anchor: Anchor) -> Result<(), ResidentError> {
        super::NodeStream::place(self, anchor);
        Ok(())
    }

    fn release(&mut self) {
        super::NodeStream::release(self);
    }

    fn device(&self) -> &str {
        self.rasterizer().adapter_name()
    }

    fn max_image_width(&self) -> Option<u32> {
        Some(self.rasterizer().max_image_width())
    }
}

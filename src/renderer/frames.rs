//! What draws a sequence of frames from moving cameras: a scene kept resident
//! ([`super::Resident`]) or a level-of-detail node stream ([`super::NodeStream`]).

use indicatif::ProgressBar;

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
}

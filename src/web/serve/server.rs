//! `serve`'s server: a front door on the public port that takes the live stream's WebSocket
//! connections itself and passes the rest to the viewer's HTTP listener and workers; the
//! scan, and the render thread.

use std::net::SocketAddr;
use std::sync::Arc;

use crate::render::RendererKind;
use crate::web::server::{Listener, Running, Stopper};

use super::ServeError;
use super::live::StreamOptions;
use super::live::front::live_door;
use super::render_thread::RenderThread;
use super::routes::route;
use super::scan::LiveScan;

/// Requests answered at once. At most two wait on renders (the one rendering and the newest
/// waiting; older ones are answered at once), so the page and map stay responsive.
const WORKERS: usize = 6;

/// A bound live server with its render thread running, not yet serving.
pub struct LiveServer {
    listener: Listener,
    scan: Arc<LiveScan>,
    renderer: RenderThread,
    stream: StreamOptions,
}

impl LiveServer {
    /// Listens on `host:port` (port 0: any free port) and starts the render thread with the
    /// rasterizer.
    ///
    /// # Errors
    /// The address cannot be bound, or the rasterizer cannot start.
    pub fn bind(host: &str, port: u16, scan: LiveScan) -> Result<Self, ServeError> {
        Self::bind_renderer(host, port, scan, RendererKind::Raster)
    }

    /// Listens on `host:port` (port 0: any free port) and starts the render thread with
    /// `kind`.
    ///
    /// # Errors
    /// The address cannot be bound, or the renderer cannot start.
    pub fn bind_renderer(
        host: &str,
        port: u16,
        scan: LiveScan,
        kind: RendererKind,
    ) -> Result<Self, ServeError> {
        let listener = Listener::bind(host, port)?;
        let scan = Arc::new(scan);
        let renderer = RenderThread::start(scan.clone(), kind)?;
        Ok(LiveServer {
            listener,
            scan,
            renderer,
            stream: StreamOptions::default(),
        })
    }

    /// Sets how the live stream (`/api/live`) runs.
    pub fn with_stream(mut self, stream: StreamOptions) -> Self {
        self.stream = stream;
        self
    }

    /// The address it listens on (with the real port when bound to port 0).
    pub fn addr(&self) -> SocketAddr {
        self.listener.addr()
    }

    /// A handle that stops [`serve`](Self::serve).
    pub fn stopper(&self) -> Stopper {
        self.listener.stopper()
    }

    /// The render thread (its adapter and width limit).
    pub fn renderer(&self) -> &RenderThread {
        &self.renderer
    }

    /// The scan served.
    pub fn scan(&self) -> &LiveScan {
        &self.scan
    }

    /// Answers requests and streams until stopped; a bad request or a failed render gets
    /// its error reply and serving goes on.
    pub fn serve(self) {
        let shared = Arc::new(super::live::session::Shared {
            scan: self.scan.clone(),
            queue: self.renderer.queue(),
            options: self.stream,
            stop: self.listener.stop_flag(),
        });
        let (scan, renderer) = (&self.scan, &self.renderer);
        let loopback_only = self.addr().ip().is_loopback();
        self.listener.serve(
            WORKERS,
            &|method, url| route(method, url, scan, &|request| renderer.render(request)),
            Some(live_door(shared, loopback_only)),
        );
    }

    /// Serves on a background thread; the returned handle stops it and waits.
    pub fn spawn(self) -> Running {
        Running::start(self.addr(), self.stopper(), move || self.serve())
    }
}

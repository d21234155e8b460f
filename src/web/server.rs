//! The viewer's HTTP server: a front door ([`door`](super::door)) on the public port that reads
//! each request and writes its answer, and a few worker threads that make the answers with a
//! route function ([`routes::route`](super::routes::route) for `view`) until stopped.

use std::net::{SocketAddr, TcpListener};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use super::WebError;
use super::door::{self, Job, Take};
use super::host::loopback_host;
use super::panorama::Panorama;
use super::routes::{Reply, route};

/// Requests answered at once: a frame being sent does not hold up the page or the next frame.
const WORKERS: usize = 4;

/// How often an idle worker looks whether it should stop.
const STOP_POLL: Duration = Duration::from_millis(100);

/// A bound public port with its front door ([`door`](super::door)) and the stop flag: what
/// `view` and `serve` share.
pub(crate) struct Listener {
    public: TcpListener,
    addr: SocketAddr,
    stop: Arc<AtomicBool>,
}

impl Listener {
    /// Listens on `host:port` (port 0: any free port).
    pub(crate) fn bind(host: &str, port: u16) -> Result<Self, WebError> {
        let bind_err = |addr: String, reason: String| WebError::Bind { addr, reason };
        let public = TcpListener::bind((host, port))
            .map_err(|e| bind_err(format!("{host}:{port}"), e.to_string()))?;
        let addr = public
            .local_addr()
            .map_err(|e| bind_err(format!("{host}:{port}"), e.to_string()))?;
        Ok(Self {
            public,
            addr,
            stop: Arc::new(AtomicBool::new(false)),
        })
    }

    /// The address it listens on (with the real port when bound to port 0).
    pub(crate) fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Its stop flag, for threads that serve beside it.
    pub(crate) fn stop_flag(&self) -> Arc<AtomicBool> {
        self.stop.clone()
    }

    /// A handle that stops [`serve`](Self::serve).
    pub(crate) fn stopper(&self) -> Stopper {
        Stopper(self.stop.clone())
    }

    /// Answers requests with `route(method, url)` on `workers` threads until stopped, the
    /// front door offering each connection to `take` first. A bad request gets its error
    /// reply and changes nothing. The workers make the replies; each connection's own thread
    /// sends its reply, so a slow client holds no worker.
    pub(crate) fn serve(
        &self,
        workers: usize,
        route: &(dyn Fn(&str, &str) -> Reply + Sync),
        take: Option<Arc<Take>>,
    ) {
        let loopback_only = self.addr.ip().is_loopback();
        let (jobs, waiting) = mpsc::channel::<Job>();
        let waiting = Mutex::new(waiting);
        std::thread::scope(|scope| {
            scope.spawn(|| door::accept(&self.public, &self.stop, take, jobs));
            for _ in 0..workers {
                scope.spawn(|| {
                    while !self.stop.load(Ordering::SeqCst) {
                        let queue = waiting.lock().unwrap_or_else(PoisonError::into_inner);
                        let job = match queue.recv_timeout(STOP_POLL) {
                            Ok(job) => job,
                            Err(RecvTimeoutError::Timeout) => continue,
                            Err(RecvTimeoutError::Disconnected) => return,
                        };
                        drop(queue);
                        let reply = reply_to(&job.head, loopback_only, route);
                        job.answer(reply);
                    }
                });
            }
        });
    }
}

/// A bound viewer server, not yet serving.
pub struct ViewServer {
    listener: Listener,
    panorama: Arc<Panorama>,
}

/// Stops a serving server (`view`'s or `serve`'s) from another thread (a Ctrl-C handler, a
/// test).
#[derive(Clone)]
pub struct Stopper(Arc<AtomicBool>);

impl Stopper {
    /// Asks the server to stop; `serve` returns within a fraction of a second.
    pub fn stop(&self) {
        self.0.store(true, Ordering::SeqCst);
    }
}

impl ViewServer {
    /// Listens on `host:port` (port 0: any free port) for requests about `panorama`.
    pub fn bind(host: &str, port: u16, panorama: Panorama) -> Result<Self, WebError> {
        Ok(Self {
            listener: Listener::bind(host, port)?,
            panorama: Arc::new(panorama),
        })
    }

    /// The address it listens on (with the real port when bound to port 0).
    pub fn addr(&self) -> SocketAddr {
        self.listener.addr()
    }

    /// A handle that stops [`serve`](Self::serve).
    pub fn stopper(&self) -> Stopper {
        self.listener.stopper()
    }

    /// Answers requests until stopped. A bad request gets its error reply and changes nothing.
    pub fn serve(self) {
        let panorama = &self.panorama;
        self.listener
            .serve(WORKERS, &|method, url| route(method, url, panorama), None);
    }

    /// Serves on a background thread; the returned handle stops it and waits.
    pub fn spawn(self) -> Running {
        Running::start(self.addr(), self.stopper(), move || self.serve())
    }
}

/// A server serving on its own thread; dropping it stops the server.
pub struct Running {
    addr: SocketAddr,
    stopper: Stopper,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Running {
    /// Runs `serve` on a new thread; `stopper` must stop it.
    pub(crate) fn start(
        addr: SocketAddr,
        stopper: Stopper,
        serve: impl FnOnce() + Send + 'static,
    ) -> Self {
        Running {
            addr,
            stopper,
            thread: Some(std::thread::spawn(serve)),
        }
    }

    /// The address it listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stopper.stop();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The reply to `head`: a route's, or 403 for a request not addressed to this machine when
/// serving on loopback only (a page of another site cannot reach it through DNS rebinding).
fn reply_to(
    head: &door::Head,
    loopback_only: bool,
    route: &(dyn Fn(&str, &str) -> Reply + Sync),
) -> Reply {
    if loopback_only && !loopback_host(head.header("Host")) {
        return Reply::error(
            403,
            "this server answers only requests addressed to localhost or 127.0.0.1",
        );
    }
    route(&head.method, &head.target)
}

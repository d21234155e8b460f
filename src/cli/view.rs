//! `omnicloud view`: opens the panorama, starts the viewer's server, serves until Ctrl-C.

use std::net::{IpAddr, SocketAddr, UdpSocket};
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use crate::web::{Panorama, ViewServer};

/// Options of `omnicloud view`.
#[derive(Debug, Args)]
pub struct ViewerArgs {
    /// A PNG/JPEG panorama (2:1 mono, or 1:1 ODS top-bottom, left eye on top), a folder of
    /// frames (its frame_*.png/.jpg files, in name order), or an MP4 video (mono or
    /// top-bottom as its st3d box says).
    #[arg(value_name = "FILE|DIR")]
    pub path: PathBuf,
    /// Address to listen on: 127.0.0.1 keeps it on this machine; 0.0.0.0 lets a headset on
    /// the network reach it (and everyone else there).
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    /// Port to listen on (0: any free port).
    #[arg(long, default_value = "8360")]
    pub port: u16,
    /// Also open the page in the default browser.
    #[arg(long)]
    pub open: bool,
}

/// Serves `args.path` until Ctrl-C.
pub fn run(args: &ViewerArgs) -> Result<()> {
    let panorama = Panorama::open(&args.path)?;
    let summary = format!(
        "{} {}x{}, {} frame(s){}",
        match panorama.kind {
            crate::web::PanoramaKind::Mono => "mono",
            crate::web::PanoramaKind::Ods => "ODS top-bottom",
        },
        panorama.width,
        panorama.height,
        panorama.frame_count(),
        match panorama.video {
            Some(v) => format!(" of H.264 video at {} fps", v.fps),
            None => String::new(),
        }
    );
    let server = ViewServer::bind(&args.host, args.port, panorama)?;
    let addr = server.addr();
    let url = local_url(addr);
    println!("omnicloud view: {} ({summary})", args.path.display());
    println!("open {url}   (Ctrl-C stops the server)");
    if !addr.ip().is_loopback() {
        warn_exposed(addr);
    }
    let stopper = server.stopper();
    ctrlc::set_handler(move || stopper.stop()).context("installing the Ctrl-C handler")?;
    if args.open {
        open_browser(&url);
    }
    server.serve();
    println!("omnicloud view: stopped");
    Ok(())
}

/// The address a browser on this machine uses.
pub(super) fn local_url(addr: SocketAddr) -> String {
    match addr.ip() {
        IpAddr::V4(ip) if ip.is_unspecified() => format!("http://127.0.0.1:{}/", addr.port()),
        IpAddr::V6(ip) if ip.is_unspecified() => format!("http://[::1]:{}/", addr.port()),
        _ => format!("http://{addr}/"),
    }
}

pub(super) fn warn_exposed(addr: SocketAddr) {
    eprintln!(
        "warning: listening on {addr}: everyone on the network can see the served files \
         while this runs"
    );
    if addr.ip().is_unspecified()
        && let Some(ip) = lan_address()
    {
        eprintln!("  from another device: http://{ip}:{}/", addr.port());
    }
    eprintln!(
        "  browsers offer WebXR only on https:// or localhost: for \"Enter VR\" on a headset \
         over plain http, forward the port (adb reverse tcp:{0} tcp:{0}) and open \
         http://localhost:{0}/ there",
        addr.port()
    );
}

/// This machine's address on its default route (a UDP "connect" sends nothing).
fn lan_address() -> Option<IpAddr> {
    let socket = UdpSocket::bind("0.0.0.0:0").ok()?;
    socket.connect("192.0.2.1:9").ok()?;
    socket.local_addr().ok().map(|a| a.ip())
}

pub(super) fn open_browser(url: &str) {
    let (program, args): (&str, &[&str]) = if cfg!(target_os = "macos") {
        ("open", &[])
    } else if cfg!(windows) {
        ("cmd", &["/C", "start", ""])
    } else {
        ("xdg-open", &[])
    };
    if let Err(e) = std::process::Command::new(program)
        .args(args)
        .arg(url)
        .spawn()
    {
        eprintln!("warning: could not open a browser ({program}: {e}); open {url} yourself");
    }
}

//! `omnicloud serve`'s HTTP API on the sample scan, in process on a free port: a render at a
//! camera is the library's render there, pixel for pixel, and `omnicloud render`'s at the
//! camera it reports; bad values get a 400 naming the field, a failed render a 500, and the
//! server answers afterwards. Needs a GPU adapter (lavapipe will do): without one the tests
//! skip loudly, and fail under `OMNICLOUD_REQUIRE_GPU=1`.
#![cfg(all(feature = "web", feature = "gpu"))]

mod e57_common;
mod http_common;
mod serve_common;

use std::net::SocketAddr;
use std::sync::OnceLock;

use glam::{DVec2, DVec3};
use http_common::{Reply, get, send};
use indicatif::ProgressBar;
use omnicloud::Scene;
use omnicloud::prepare::placement::{EYE_HEIGHT, ground_camera_position};
use omnicloud::prepare::{EyeHeight, PrepareOptions, prepare};
use omnicloud::projection::{Camera, Image, OdsOffset, PoleMerge, PoleMerging, Stereo};
use omnicloud::raster::Rasterizer;
use omnicloud::render::{ColorMode, Imposter, Proxy, RenderSettings, Shading};
use omnicloud::web::Running;
use serve_common::{FEET_PER_METRE, UNDER_TREES, sample, start_live};

/// Panorama width of the served renders.
const WIDTH: u32 = 256;

/// The sample prepared as `serve` prepares it (camera at the centre, default radius), once.
fn scene() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| {
        prepare(
            &sample(),
            &PrepareOptions {
                camera: omnicloud::prepare::CameraChoice::Center,
                ..PrepareOptions::default()
            },
            &ProgressBar::hidden(),
        )
        .unwrap()
        .scene
    })
}

/// A live server of the sample at `width`; `None` (after the GPU rule's notice) without an
/// adapter.
fn start(width: u32) -> Option<Running> {
    start_live(scene().clone(), width)
}

/// One server at [`WIDTH`] for the tests that need no other.
fn shared() -> Option<SocketAddr> {
    static SERVER: OnceLock<Option<Running>> = OnceLock::new();
    SERVER
        .get_or_init(|| start(WIDTH))
        .as_ref()
        .map(Running::addr)
}

fn assert_still_serving(addr: SocketAddr) {
    let r = get(addr, "/api/scan");
    assert_eq!(r.status, 200, "{}", r.text());
}

fn camera_header(r: &Reply) -> DVec3 {
    let text = r.header("x-omnicloud-camera").expect("a camera header");
    let v: Vec<f64> = text.split(',').map(|c| c.parse().unwrap()).collect();
    DVec3::new(v[0], v[1], v[2])
}

#[test]
fn bad_values_get_400_naming_the_field_and_serving_goes_on() {
    let Some(addr) = shared() else { return };
    let cases = [
        (
            "/api/render?x=NaN",
            "x=\"NaN\": `NaN` is not a finite number",
        ),
        ("/api/render?y=inf", "y=\"inf\""),
        ("/api/render?y=-Infinity", "y=\"-Infinity\""),
        (
            "/api/render?x=1000000",
            "x=1000000: the camera must stand within the scan's bounds, x from 636001.760 to 637179.220",
        ),
        (
            "/api/render?y=848935",
            "y=848935: the camera must stand within",
        ),
        (
            "/api/render?ipd=11",
            "ipd=\"11\": the interocular distance must lie in 0..=10",
        ),
        ("/api/render?ipd=", "ipd=\"\""),
        (
            "/api/render?north=marrinan:10,20,3",
            "north=\"marrinan:10,20,3\": marrinan angles are measured from the pole",
        ),
        (
            "/api/render?south=sideways",
            "south=\"sideways\": unknown pole merge",
        ),
        ("/api/render?north=marrinan:45,0", "north=\"marrinan:45,0\""),
        ("/api/render?seq=-3", "seq=\"-3\""),
        (
            "/api/render?client=../x",
            "client=\"../x\": expected up to 64 letters",
        ),
        ("/api/render?zoom=2", "unknown query parameter \"zoom\""),
        ("/api/render?x=636500&x=636600", "given twice"),
        ("/map.png?size=big", "takes none"),
        ("/api/scan?verbose=1", "takes none"),
    ];
    for (target, message) in cases {
        let r = get(addr, target);
        assert_eq!(r.status, 400, "{target}: {}", r.text());
        assert!(r.text().contains(message), "{target}: {}", r.text());
        assert_still_serving(addr);
    }
    for target in [
        "/../../etc/passwd",
        "/%2e%2e/%2e%2e/etc/passwd",
        "/..%5cCargo.toml",
    ] {
        let r = get(addr, target);
        assert_eq!(r.status, 403, "{target}");
        assert!(!r.text().contains("root:"), "{target} served /etc/passwd");
    }
    for target in [
        "/etc/passwd",
        "/data/autzen_trim.laz",
        "/frames/0",
        "/api/info",
    ] {
        assert_eq!(get(addr, target).status, 404, "{target}");
    }
    let post = send(
        addr,
        b"POST /api/render HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\nConnection: close\r\n\r\n",
    );
    assert_eq!(post.status, 405);
    assert_still_serving(addr);
}

#[test]
fn a_render_is_the_library_render_at_the_camera_it_reports() {
    let Some(addr) = shared() else { return };
    let scan: serde_json::Value = serde_json::from_slice(&get(addr, "/api/scan").body).unwrap();
    assert_eq!(scan["file"], "autzen_trim.laz");
    assert_eq!(scan["points"], 110_000);
    assert_eq!(scan["width"], WIDTH);
    // 1177 m x 563 m on 256 pixels across.
    assert_eq!(scan["map"]["width"], 256);
    assert_eq!(scan["map"]["height"], 123);
    let map = get(addr, "/map.png");
    assert_eq!(map.header("content-type").unwrap(), "image/png");
    let map = image::load_from_memory(&map.body).unwrap().to_rgba8();
    assert_eq!(map.dimensions(), (256, 123));
    let covered = map.pixels().filter(|p| p[3] == 255).count();
    assert!(
        covered > 256 * 123 * 3 / 4,
        "the map covers {covered} pixels"
    );

    let (x, y) = UNDER_TREES;
    let r = get(
        addr,
        &format!("/api/render?x={x}&y={y}&ipd=0.07&north=marrinan:60,10,2&south=off&seq=5"),
    );
    assert_eq!(r.status, 200, "{}", r.text());
    assert_eq!(r.header("content-type").unwrap(), "image/png");
    assert_eq!(r.header("x-omnicloud-seq").unwrap(), "5");
    let ms: f64 = r.header("x-omnicloud-render-ms").unwrap().parse().unwrap();
    assert!(ms > 0.0);
    let camera = camera_header(&r);
    assert_eq!(
        camera.truncate(),
        DVec2::new(x, y),
        "the camera stands where asked"
    );
    // Eye height above the ground automatic placement estimates there.
    let scene = scene();
    let local = (DVec2::new(x, y) - scene.origin.truncate()).as_vec2();
    let size = |k: usize| scan["max"][k].as_f64().unwrap() - scan["min"][k].as_f64().unwrap();
    let extent = size(0).max(size(1)) as f32;
    let ground = ground_camera_position(scene, local, extent).unwrap().z - EYE_HEIGHT;
    assert!(
        (camera.z - (scene.origin.z + ground + 1.7)).abs() < 1e-6,
        "camera {camera}, ground {ground}"
    );

    let served = image::load_from_memory(&r.body).unwrap().to_rgba8();
    assert_eq!(served.dimensions(), (WIDTH, WIDTH));
    let settings = RenderSettings {
        image: Image::equirect(WIDTH),
        camera: Camera::new(camera - scene.origin, 0.0),
        stereo: Stereo::Ods {
            // The page's 0.07 m in the sample's feet.
            ipd: 0.07 * FEET_PER_METRE,
            merging: PoleMerging {
                north: PoleMerge::Marrinan {
                    start_deg: 60.0,
                    end_deg: 10.0,
                    exponent: 2.0,
                },
                south: PoleMerge::Off,
            },
            offset: OdsOffset::Exact,
        },
        color: ColorMode::Auto,
        shading: Shading::Unlit,
        proxy: Proxy::default(),
        imposter: Imposter::default(),
        depth_map: None,
    };
    let rasterizer = Rasterizer::new().unwrap();
    let (rendered, _) = rasterizer
        .render(scene, &settings, &ProgressBar::hidden())
        .unwrap();
    let library = rendered.top_bottom();
    let served_pixels: Vec<[u8; 4]> = served.pixels().map(|p| p.0).collect();
    assert_eq!(
        served_pixels, library.color,
        "served and library renders differ"
    );
    let coverage = library.coverage_count() as f64 / library.color.len() as f64;
    assert!(coverage > 0.3, "coverage {coverage}");

    #[cfg(feature = "cli")]
    same_as_the_command(camera, &served_pixels);
}

/// `omnicloud render` at the reported camera draws the same pair: its points are centred on
/// that camera in f64, the server's on the prepared one, so a few edge pixels may round the
/// other way (measured: 7 of 65536).
#[cfg(feature = "cli")]
fn same_as_the_command(camera: DVec3, served: &[[u8; 4]]) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pair.png");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .arg("render")
        .arg(sample())
        .arg("-o")
        .arg(&out)
        .args([
            "--width",
            &WIDTH.to_string(),
            "--stereo",
            "ods",
            "--ipd",
            "0.07",
        ])
        .args([
            "--pole-merge-north",
            "marrinan:60,10,2",
            "--pole-merge-south",
            "off",
        ])
        .arg(format!("--camera={},{},{}", camera.x, camera.y, camera.z))
        .arg("--quiet")
        .status()
        .unwrap();
    assert!(status.success());
    let command = image::open(&out).unwrap().to_rgba8();
    let differ = command
        .pixels()
        .zip(served)
        .filter(|(a, b)| a.0 != **b)
        .count();
    let fraction = differ as f64 / served.len() as f64;
    assert!(
        fraction < 0.001,
        "{differ} of {} pixels differ from omnicloud render",
        served.len()
    );
}

#[test]
fn a_failed_render_gets_500_with_the_reason_and_serving_goes_on() {
    // Wider than any adapter's textures: the render fails on the GPU side, not the request.
    let Some(server) = start(65_536) else { return };
    let addr = server.addr();
    for _ in 0..2 {
        let r = get(addr, "/api/render");
        assert_eq!(r.status, 500, "{}", r.text());
        assert!(
            r.text()
                .contains("the render failed: a 65536x32768 image needs 65536 but the GPU adapter allows at most"),
            "{}",
            r.text()
        );
        assert_still_serving(addr);
    }
}

/// `omnicloud serve` itself: loads the scan, prints the address (and, bound to every
/// interface, the warning), serves it, and stops on Ctrl-C (SIGINT).
#[cfg(all(unix, feature = "cli"))]
#[test]
fn the_command_prints_its_address_serves_and_stops_on_ctrl_c() {
    if shared().is_none() {
        return; // no adapter: the command would refuse to start
    }
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_omnicloud"));
    command
        .args([
            "serve", "--host", "0.0.0.0", "--port", "0", "--width", "256",
        ])
        .args(["--map-size", "128", "--height", "2.5"])
        .arg(sample());
    let server = http_common::ServerProcess::start(command);
    let (lines, addr) = (&server.before, server.addr);
    assert!(
        lines[0]
            .contains("autzen_trim.laz (110000 points, radius adaptive:8 (median 1.2154 ft), map 128x62, ODS 256x256"),
        "{lines:?}"
    );
    assert!(addr.ip().is_loopback(), "{addr}");
    let scan: serde_json::Value = serde_json::from_slice(&get(addr, "/api/scan").body).unwrap();
    // 2.5 m in the sample's feet; the page's IPD in metres.
    assert_eq!(scan["height"], 2.5 * FEET_PER_METRE);
    assert_eq!(scan["metres_per_unit"], 0.3048);
    assert_eq!(scan["ipd"], 0.064);
    let r = get(addr, "/api/render?seq=1");
    assert_eq!(r.status, 200, "{}", r.text());
    let camera = camera_header(&r);
    let start: Vec<f64> = serde_json::from_value(scan["camera"].clone()).unwrap();
    assert_eq!(
        camera.to_array().to_vec(),
        start,
        "the page starts where /api/scan says"
    );
    // Where `omnicloud render --height 2.5` stands its automatic camera.
    let render = prepare(
        &sample(),
        &PrepareOptions {
            height: EyeHeight::new(Some(2.5 * FEET_PER_METRE), FEET_PER_METRE),
            ..PrepareOptions::default()
        },
        &ProgressBar::hidden(),
    )
    .unwrap();
    assert_eq!(
        camera, render.camera_world,
        "the page starts where render stands"
    );

    let out = server.interrupt();
    let rest = String::from_utf8_lossy(&out.stdout);
    assert!(rest.contains("omnicloud serve: stopped"), "{rest}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("warning: listening on 0.0.0.0:"),
        "{stderr}"
    );
}

/// `omnicloud serve --scan 1` on a two-scan E57 survey serves that scan only: its 648
/// points (18 rows x 36 columns), not the other's 3125 as well, around that scan's bounds.
#[cfg(all(unix, feature = "cli"))]
#[test]
fn the_command_serves_only_the_scans_scan_picks() {
    if shared().is_none() {
        return; // no adapter: the command would refuse to start
    }
    let dir = tempfile::tempdir().unwrap();
    let site = dir.path().join("site.e57");
    e57_common::write_site(&site);
    let serve = |pick: &[&str]| {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_omnicloud"));
        command
            .args(["serve", "--port", "0", "--width", "64", "--map-size", "64"])
            .args(["--radius", "0.2"])
            .args(pick)
            .arg(&site);
        let server = http_common::ServerProcess::start(command);
        let scan: serde_json::Value =
            serde_json::from_slice(&get(server.addr, "/api/scan").body).unwrap();
        server.interrupt();
        scan
    };
    let south = serve(&["--scan", "1"]);
    assert_eq!(south["points"], 648, "{south}");
    // Scan 1's points lie within 3 + 1.5 + 1.7 m of its station.
    let max: Vec<f64> = serde_json::from_value(south["max"].clone()).unwrap();
    let min: Vec<f64> = serde_json::from_value(south["min"].clone()).unwrap();
    for axis in 0..2 {
        let t = e57_common::POSE1_T[axis];
        assert!(
            min[axis] > t - 6.3 && max[axis] < t + 6.3,
            "{min:?} .. {max:?}"
        );
    }
    let by_name = serve(&["--scan", "South"]);
    assert_eq!(by_name["points"], 648, "{by_name}");
    let all = serve(&[]);
    assert_eq!(all["points"], 648 + 3125, "{all}");
}

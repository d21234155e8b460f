//! The command line as clap parses it: the program and its subcommands, each command's
//! options in its own file.

use clap::{Parser, Subcommand};

use super::bench::BenchArgs;
use super::compare::CompareArgs;
use super::render_args::RenderArgs;

/// Render LiDAR scans (LAS, LAZ, PLY, E57) to 360° panoramas and omnidirectional-stereo pairs.
#[derive(Debug, Parser)]
#[command(name = "omnicloud", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
// Parsed once per run: the size of the render variant does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Command {
    /// Print a point cloud's header: format, point count, bounds, scale and offset,
    /// coordinate system, attributes (--stats: a pass over the points for histograms).
    Info(super::info::InfoArgs),
    /// Write scans (LAS, LAZ, PLY, several tiles) once as a COPC file with the sphere radii
    /// stored, so that renders read only what the view needs.
    Index(super::index::IndexArgs),
    /// Render a point cloud to an equirectangular panorama or ODS pair.
    Render(RenderArgs),
    /// Compare a test render against a reference render (EXR files with a Z channel).
    Compare(CompareArgs),
    /// Time every rasterizer mode against the ray-traced reference: tables and charts.
    Bench(BenchArgs),
    /// Look around a panorama or a tour folder in the browser (and in VR, through WebXR).
    View(super::view::ViewerArgs),
    /// Render a camera path through a scan, one frame per pose (resumable, shardable).
    Tour(super::tour::TourArgs),
    /// Render a scan live in the browser: pick camera positions on its map, tune IPD and
    /// pole merging, look around (and in VR, through WebXR).
    Serve(super::serve::ServeArgs),
    /// Encode a folder of panorama frames (a tour) into an H.264 MP4 that 360 players show
    /// as a sphere, in stereo for ODS frames.
    Video(super::video::VideoArgs),
}

impl Command {
    /// The command with `--scan` applied to its input files (each named `FILE#scan:..`), so
    /// every reader behind it reads those scans only (with `--color image`, coloured from
    /// their images: `FILE#color:image`), and `--camera station:N` turned into
    /// the station's position and heading (added to `--yaw`).
    ///
    /// # Errors
    /// A station the file does not have, or a file without stations.
    pub fn resolved(mut self) -> Result<Command, crate::tour::stations::StationError> {
        match &mut self {
            Command::Render(a) => {
                a.file = a.draw.colour_path(&a.view.scan_path(&a.file));
                for f in &mut a.more_files {
                    *f = a.draw.colour_path(&a.view.scan_path(f));
                }
                a.view.resolve_station(&a.file)?;
            }
            Command::Tour(a) => a.file = a.draw.colour_path(&a.view.scan_path(&a.file)),
            Command::Serve(a) => a.file = super::options::scan_path(a.scan.as_ref(), &a.file),
            Command::Bench(a) => {
                a.scene = a.scene.as_ref().map(|f| a.view.scan_path(f));
                if let Some(scene) = &a.scene {
                    a.view.resolve_station(scene)?;
                }
            }
            _ => {}
        }
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::Up;
    use crate::prepare::filter::ReturnFilter;
    use crate::prepare::{CameraChoice, RadiusChoice};
    use crate::projection::{OdsOffset, PoleMerge, PoleMerging, Stereo};
    use crate::render::{Background, ColorMode, Look, Proxy, RendererKind, Shading};
    use clap::CommandFactory;
    use glam::DVec3;
    use std::path::PathBuf;

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn render_parses_the_full_option_set() {
        let cli = Cli::try_parse_from([
            "omnicloud",
            "render",
            "in.laz",
            "-o",
            "out.exr",
            "--width",
            "1024",
            "--camera",
            "-637000.5,851000,12",
            "--yaw",
            "-30",
            "--stereo",
            "ods",
            "--ipd",
            "0.065",
            "--pole-merge",
            "cycles:60,75",
            "--pole-merge-south",
            "off",
            "--radius",
            "auto",
            "--color",
            "elevation",
            "--shading",
            "phong",
            "--depth",
            "d.exr",
            "--anaglyph",
            "a.png",
            "--renderer",
            "raytrace",
            "--proxy",
            "static:16",
            "--imposter",
            "sprite",
            "--ods-offset",
            "paper",
            "--quality",
            "75",
            "--quiet",
        ])
        .unwrap();
        let Command::Render(r) = cli.command else {
            panic!("not render")
        };
        assert_eq!(
            r.view.camera,
            Some(CameraChoice::At(DVec3::new(-637000.5, 851000.0, 12.0)))
        );
        assert_eq!(r.view.yaw, -30.0);
        assert_eq!(r.draw.proxy, Proxy::Static(16));
        assert_eq!(r.view.pole_merge_south, Some(PoleMerge::Off));
        assert_eq!(r.view.radius, Some(RadiusChoice::Auto));
        assert_eq!(
            r.view.stereo_mode(),
            Some(Stereo::Ods {
                ipd: 0.065,
                merging: PoleMerging {
                    north: PoleMerge::CYCLES_DEFAULT,
                    south: PoleMerge::Off
                },
                offset: OdsOffset::Paper
            })
        );
        assert_eq!(r.draw.renderer, RendererKind::Raytrace);
        assert_eq!(
            (r.draw.color, r.draw.shading),
            (ColorMode::Elevation, Shading::Phong)
        );
        assert_eq!(r.quality, 75);
        assert!(r.quiet);
        for bad in ["0", "101"] {
            let argv = [
                "omnicloud",
                "render",
                "a.laz",
                "-o",
                "a.jpg",
                "--quality",
                bad,
            ];
            assert!(Cli::try_parse_from(argv).is_err(), "--quality {bad}");
        }
    }

    #[test]
    fn bench_takes_the_shared_view_options() {
        let bench = |extra: &[&str]| {
            let argv = ["omnicloud", "bench"].iter().chain(extra);
            let Command::Bench(b) = Cli::try_parse_from(argv).unwrap().command else {
                panic!("not bench")
            };
            b
        };
        let b = bench(&[
            "s.laz",
            "--stereo",
            "ods",
            "--pole-merge-north",
            "off",
            "--ods-offset",
            "paper",
        ]);
        assert_eq!(
            b.view.stereo_mode(),
            Some(Stereo::Ods {
                ipd: 0.064,
                merging: PoleMerging {
                    north: PoleMerge::Off,
                    south: PoleMerge::COMFORTABLE
                },
                offset: OdsOffset::Paper
            })
        );
        assert_eq!(b.width, None);
        // Without --stereo the manifest (or, for a scan, mono) decides.
        assert_eq!(bench(&["--suite", "dir"]).view.stereo_mode(), None);
    }

    #[test]
    fn the_depth_map_needs_ods_stereo() {
        let view = |extra: &[&str]| {
            let argv = ["omnicloud", "render", "s.laz", "-o", "x.png"]
                .iter()
                .chain(extra);
            let Command::Render(r) = Cli::try_parse_from(argv).unwrap().command else {
                panic!("not render")
            };
            r.view
        };
        let map = view(&["--stereo", "ods", "--depth-map", "0.5=1.5,2=3"])
            .depth_map()
            .unwrap()
            .unwrap();
        assert_eq!(map.to_string(), "0.5=1.5,2=3");
        assert_eq!(view(&["--stereo", "ods"]).depth_map().unwrap(), None);
        for (extra, named) in [
            (&["--depth-map", "0.5=1.5"][..], "not none"),
            (
                &["--stereo", "parallel", "--depth-map", "0.5=1.5"],
                "not parallel",
            ),
        ] {
            let e = view(extra).depth_map().unwrap_err().to_string();
            assert!(e.contains("needs --stereo ods") && e.contains(named), "{e}");
        }
        let argv = [
            "omnicloud",
            "render",
            "s.laz",
            "-o",
            "x.png",
            "--depth-map",
            "2=1,1=3",
        ];
        let e = Cli::try_parse_from(argv).unwrap_err().to_string();
        assert!(e.contains("pair 2 `1=3`: B must be greater"), "{e}");
    }

    #[test]
    fn plain_values_are_listed_and_read_in_any_case() {
        let Command::Render(r) = Cli::try_parse_from([
            "omnicloud",
            "render",
            "a.las",
            "-o",
            "x.png",
            "--renderer",
            "RAYTRACE",
            "--up",
            "Y",
        ])
        .unwrap()
        .command
        else {
            panic!("not render")
        };
        assert_eq!(
            (r.draw.renderer, r.view.up),
            (RendererKind::Raytrace, Up::Y)
        );
        assert_eq!(r.view.stereo_mode(), None);
        let e = Cli::try_parse_from([
            "omnicloud",
            "render",
            "a.las",
            "-o",
            "x.png",
            "--shading",
            "toon",
        ])
        .unwrap_err()
        .to_string();
        assert!(e.contains("unlit, phong, normal"), "{e}");
    }

    #[test]
    fn render_takes_several_files_and_the_point_filters() {
        let Command::Render(r) = Cli::try_parse_from([
            "omnicloud",
            "render",
            "a.laz",
            "b.laz",
            "c.las",
            "-o",
            "x.png",
            "--classes",
            "2,6",
            "--drop-classes",
            "7,18",
            "--returns",
            "LAST",
            "--crop",
            "-10,5,20,-5",
            "--max-distance",
            "150",
        ])
        .unwrap()
        .command
        else {
            panic!("not render")
        };
        assert_eq!(
            r.inputs(),
            ["a.laz", "b.laz", "c.las"].map(PathBuf::from).to_vec()
        );
        assert_eq!(r.inputs_name(), "a.laz (+2 more files)");
        let f = r.view.prepare_options().filter;
        assert_eq!(f.classes.map(|c| c.codes()), Some(vec![2, 6]));
        assert_eq!(f.drop_classes.map(|c| c.codes()), Some(vec![7, 18]));
        assert_eq!(f.returns, ReturnFilter::Last);
        let crop = f.crop.unwrap();
        assert_eq!(
            (crop.min.x, crop.min.y, crop.max.x, crop.max.y),
            (-10.0, -5.0, 20.0, 5.0)
        );
        assert_eq!(f.max_distance, Some(150.0));
        for (option, bad, why) in [
            (
                "--classes",
                "2,ground",
                "'ground' is not a classification code",
            ),
            ("--crop", "1,2,3", "four numbers"),
            ("--max-distance", "0", "above 0 m"),
        ] {
            let e =
                Cli::try_parse_from(["omnicloud", "render", "a.las", "-o", "x.png", option, bad])
                    .unwrap_err()
                    .to_string();
            assert!(e.contains(why), "{option} {bad}: {e}");
        }
        let Command::Info(i) =
            Cli::try_parse_from(["omnicloud", "info", "--stats", "--json", "a.laz", "b.ply"])
                .unwrap()
                .command
        else {
            panic!("not info")
        };
        assert!(i.stats && i.json && i.files.len() == 2);
    }

    #[test]
    fn picture_options_parse_with_their_defaults() {
        let parse = |extra: &[&str]| {
            let argv = ["omnicloud", "render", "a.las", "-o", "x.png"]
                .iter()
                .chain(extra);
            match Cli::try_parse_from(argv).map(|c| c.command) {
                Ok(Command::Render(r)) => Ok(r.look()),
                Ok(_) => panic!("not render"),
                Err(e) => Err(e.to_string()),
            }
        };
        assert_eq!(
            parse(&[]).unwrap(),
            Look {
                supersample: 1,
                ..Look::default()
            }
        );
        let edl = |l: Look| l.edl.map(|e| (e.strength, e.radius));
        assert_eq!(edl(parse(&["--edl"]).unwrap()), Some((1.0, 1.4)));
        assert_eq!(
            edl(parse(&["--edl", "0.5", "--edl-radius", "2"]).unwrap()),
            Some((0.5, 2.0))
        );
        let l = parse(&["--supersample", "3", "--background", "#000000"]).unwrap();
        assert_eq!(l.supersample, 3);
        assert_eq!(l.background, Some(Background::Color([0, 0, 0])));
        for (bad, why) in [
            (&["--supersample", "9"][..], "1..=8"),
            (&["--edl=-1"], ">= 0"),
            (&["--edl-radius", "0"], "above 0"),
        ] {
            let e = parse(bad).unwrap_err();
            assert!(e.contains(why), "{bad:?}: {e}");
        }
        let e = Cli::try_parse_from(["omnicloud", "render", "--edl", "a.las", "-o", "x.png"])
            .unwrap_err()
            .to_string();
        assert!(e.contains("--edl=1"), "{e}");
    }

    #[test]
    fn bad_values_are_rejected_with_the_reason() {
        let e = Cli::try_parse_from([
            "omnicloud",
            "render",
            "a.las",
            "-o",
            "x.png",
            "--width",
            "999",
        ])
        .unwrap_err()
        .to_string();
        assert!(e.contains("even"), "{e}");
    }
}

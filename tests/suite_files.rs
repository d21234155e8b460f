//! The committed stability-suite files are exactly what the generator writes, so they cannot
//! drift from `src/suite/`; and they stay small.

use std::collections::BTreeSet;
use std::path::Path;

use omnicloud::suite;

fn committed_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/data/scenes"))
}

#[test]
fn regenerating_gives_the_committed_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    suite::write_suite(tmp.path()).unwrap();
    let names = |dir: &Path| -> BTreeSet<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".ply") || n.ends_with(".json"))
            .collect()
    };
    assert_eq!(
        names(tmp.path()),
        names(committed_dir()),
        "run `cargo run --example gen_scenes -- data/scenes`"
    );
    for name in names(tmp.path()) {
        let fresh = std::fs::read(tmp.path().join(&name)).unwrap();
        let committed = std::fs::read(committed_dir().join(&name)).unwrap();
        assert!(
            fresh == committed,
            "data/scenes/{name} differs from the generator: run `cargo run --example gen_scenes -- data/scenes`"
        );
    }
}

#[test]
fn the_suite_folder_is_small_and_every_entry_names_an_existing_file() {
    let total: u64 = std::fs::read_dir(committed_dir())
        .unwrap()
        .map(|e| e.unwrap().metadata().unwrap().len())
        .sum();
    assert!(total < 512 * 1024, "data/scenes holds {total} bytes");
    let m = suite::load_manifest(committed_dir()).unwrap();
    assert!(m.scenes.len() >= 13);
    for e in &m.scenes {
        let bytes = std::fs::read(committed_dir().join(&e.file)).unwrap();
        let header = String::from_utf8_lossy(&bytes[..bytes.len().min(400)]).into_owned();
        assert!(
            header.contains(&format!("element vertex {}\n", e.points)),
            "{}: point count",
            e.name
        );
        let end = header.find("end_header\n").unwrap() + "end_header\n".len();
        assert_eq!(bytes.len() - end, 31 * e.points, "{}: body size", e.name);
    }
}

#[test]
fn the_ply_reader_gives_back_the_generated_scenes() {
    use omnicloud::Radii;
    use omnicloud::io::{LoadOptions, load_scene};
    for s in suite::all_scenes() {
        let expected = s.to_scene();
        let options = LoadOptions {
            origin: Some(s.camera),
            ..LoadOptions::default()
        };
        let (loaded, _) = load_scene(&committed_dir().join(format!("{}.ply", s.name)), &options)
            .unwrap_or_else(|e| panic!("{}: {e}", s.name));
        assert_eq!(loaded.origin, expected.origin, "{}", s.name);
        assert_eq!(loaded.positions, expected.positions, "{}", s.name);
        assert_eq!(loaded.attributes.rgb, expected.attributes.rgb, "{}", s.name);
        let Radii::PerPoint(r) = &loaded.radii else {
            panic!("{}: per-point radius not read", s.name)
        };
        assert_eq!(Radii::PerPoint(r.clone()), expected.radii, "{}", s.name);
    }
}

//! Compresses a LAS file to LAZ with the same header and points, then reads both back and
//! checks every point record (coordinates, colour and every other field) is the same, byte
//! for byte.
//!
//! `cargo run --release --example compress_las -- IN.las OUT.laz`

use std::fs::{File, OpenOptions};
use std::io::{BufReader, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use clap::Parser;

/// Compresses a LAS file to LAZ and checks the copy point by point.
#[derive(Parser)]
struct Args {
    /// The LAS file to read.
    input: PathBuf,
    /// The LAZ file to write.
    out: PathBuf,
}

fn main() -> Result<()> {
    let Args { input, out } = Args::parse();
    ensure!(
        out.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("laz")),
        "{}: the output must end in .laz",
        out.display()
    );
    let mut reader =
        las::Reader::from_path(&input).with_context(|| format!("reading {}", input.display()))?;
    let mut writer = las::Writer::from_path(&out, reader.header().clone())
        .with_context(|| format!("writing {}", out.display()))?;
    writer.write_points(&reader.read_all()?)?;
    writer.close()?;
    drop(writer);
    copy_bounds(&input, &out)?;

    let mut original = las::Reader::from_path(&input)?;
    let mut copy = las::Reader::from_path(&out)?;
    let (a, b) = (original.header(), copy.header());
    let declared = a.number_of_points();
    ensure!(
        a.number_of_points() == b.number_of_points()
            && a.bounds() == b.bounds()
            && a.transforms() == b.transforms()
            && a.version() == b.version()
            && a.point_format().to_u8().ok() == b.point_format().to_u8().ok(),
        "the headers differ: {a:?} / {b:?}"
    );
    let (p, q) = (original.read_all()?, copy.read_all()?);
    let count = q.len() as u64;
    ensure!(
        count == declared && p.len() == q.len(),
        "read {} and {count} of {declared} points",
        p.len()
    );
    ensure!(
        p.record_len() == q.record_len() && p.raw_bytes() == q.raw_bytes(),
        "the point records differ"
    );
    eprintln!(
        "{} -> {}: {count} points, identical ({} -> {} bytes)",
        input.display(),
        out.display(),
        std::fs::metadata(&input)?.len(),
        std::fs::metadata(&out)?.len()
    );
    Ok(())
}

/// Writes the bounds `input`'s header declares into `out`'s: the writer recomputes them from
/// the points, and a file whose header bounds are not its points' extent must stay so.
fn copy_bounds(input: &Path, out: &Path) -> Result<()> {
    let source = las::raw::Header::read_from(BufReader::new(File::open(input)?))?;
    let mut file = OpenOptions::new().read(true).write(true).open(out)?;
    let mut header = las::raw::Header::read_from(&mut file)?;
    (header.min_x, header.min_y, header.min_z) = (source.min_x, source.min_y, source.min_z);
    (header.max_x, header.max_y, header.max_z) = (source.max_x, source.max_y, source.max_z);
    file.seek(SeekFrom::Start(0))?;
    header.write_to(&mut file)?;
    Ok(())
}

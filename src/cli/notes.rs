//! What a command says about its input before it renders: points dropped, the unit the
//! lengths given were taken in.

/// Says, through `say`, what the load of `file` means for the user: the points dropped for
/// NaN/inf coordinates.
pub(super) fn say_load_notes(
    file: &std::path::Path,
    report: &crate::io::LoadReport,
    say: &impl Fn(String),
) {
    if report.dropped_nonfinite > 0 {
        say(format!(
            "warning: dropped {} points with NaN/inf coordinates from {}",
            report.dropped_nonfinite,
            file.display()
        ));
    }
}

/// Says, through `say`, the unit the lengths given were taken in ([`units_line`]), when the
/// file does not count in metres.
pub(super) fn say_units(
    info: &crate::io::FileInfo,
    scale: &crate::prepare::LengthScale,
    given: &[(&str, f64)],
    say: &impl Fn(String),
) {
    if let Some(line) = units_line(info, scale, given) {
        say(line);
    }
}

/// The note of [`crate::prepare::units_note`] followed by each length `given` (option,
/// value as typed) and what it measures in the file: `--ipd 0.064 m = 0.2100 ft`. `None`
/// for a metric file (or one without a declared unit).
fn units_line(
    info: &crate::io::FileInfo,
    scale: &crate::prepare::LengthScale,
    given: &[(&str, f64)],
) -> Option<String> {
    let note = crate::prepare::units_note(info, scale)?;
    let lengths: Vec<String> = given
        .iter()
        .map(|(option, value)| {
            let symbol = scale.given_symbol();
            if scale.converts() {
                let file = if *option == "--height" {
                    scale.height(*value)
                } else {
                    scale.length(*value)
                };
                format!(
                    "{option} {value} {symbol} = {file:.4} {}",
                    scale.file_symbol
                )
            } else {
                format!("{option} {value} {symbol}")
            }
        })
        .collect();
    Some(if lengths.is_empty() {
        format!("note: {note}")
    } else {
        format!("note: {note}: {}", lengths.join(", "))
    })
}

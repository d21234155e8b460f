//! The user guide documents every option: for each subcommand `omnicloud --help` lists, the
//! chapter `docs/guide/<command>.md` has an options-table row for every long option that
//! `omnicloud <command> --help` lists, and the guide's index links the chapter.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `omnicloud ARGS` run to success; its standard output.
fn omnicloud(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_omnicloud"))
        .args(args)
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "omnicloud {} failed: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("help text is UTF-8")
}

fn guide_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide")
}

/// The lines under a help heading such as `Commands:` or `Options:`, up to the next line
/// that is not indented (the next heading).
fn section<'a>(help: &'a str, heading: &str) -> Vec<&'a str> {
    help.lines()
        .skip_while(|line| line.trim_end() != heading)
        .skip(1)
        .take_while(|line| line.is_empty() || line.starts_with(' '))
        .collect()
}

/// The subcommands of the top-level help, `help` left out.
fn subcommands(help: &str) -> Vec<String> {
    section(help, "Commands:")
        .iter()
        // A command's line is indented two spaces; a wrapped description would be indented more.
        .filter_map(|line| line.strip_prefix("  "))
        .filter(|rest| !rest.starts_with(' '))
        .filter_map(|rest| rest.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_owned)
        .collect()
}

/// The name of a long option at the start of `text` (`--pole-merge-north <P>` gives
/// `pole-merge-north`), or `None` when `text` does not start with `--` and a letter or digit.
fn long_name(text: &str) -> Option<&str> {
    let rest = text.strip_prefix("--")?;
    if !rest.starts_with(|c: char| c.is_ascii_alphanumeric()) {
        return None;
    }
    let end = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
        .unwrap_or(rest.len());
    Some(&rest[..end])
}

/// The long options of a command's help, `--help` and `--version` left out. Clap starts an
/// option's line with two spaces and either `-x, --long` or four more spaces and `--long`;
/// descriptions are indented further or follow on the same line, so an option named in a
/// description is not taken for one.
fn long_options(help: &str) -> BTreeSet<String> {
    section(help, "Options:")
        .iter()
        .filter_map(|line| line.strip_prefix("  "))
        .filter_map(|rest| {
            let bytes = rest.as_bytes();
            let short = bytes.len() > 4
                && bytes[0] == b'-'
                && bytes[1].is_ascii_alphanumeric()
                && &bytes[2..4] == b", ";
            if short {
                Some(&rest[4..])
            } else {
                rest.strip_prefix("    ")
            }
        })
        .filter_map(long_name)
        .filter(|name| *name != "help" && *name != "version")
        .map(str::to_owned)
        .collect()
}

/// The long options a chapter documents: those named in the first cell of a Markdown table
/// row (`| \`--width W\` | ... |`). Mentions in prose do not count, so removing an option's
/// row fails the check even where the text still speaks of the option.
fn documented_options(chapter: &str) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for line in chapter.lines() {
        let Some(row) = line.trim_start().strip_prefix('|') else {
            continue;
        };
        // `\|` is a pipe inside a cell (`--stereo none\|ods`), not a cell border.
        let row = row.replace("\\|", "\u{1}");
        let first_cell = row.split('|').next().unwrap_or("");
        let mut rest = first_cell;
        while let Some(at) = rest.find("--") {
            // `--` inside a longer run of dashes (a `|---|` separator) names nothing.
            let preceded_by_dash = rest[..at].ends_with('-');
            if let (false, Some(name)) = (preceded_by_dash, long_name(&rest[at..])) {
                names.insert(name.to_owned());
            }
            rest = &rest[at + 2..];
        }
    }
    names
}

#[test]
fn every_option_of_every_command_has_a_row_in_its_chapter() {
    let commands = subcommands(&omnicloud(&["--help"]));
    for expected in [
        "info", "render", "compare", "bench", "view", "tour", "serve", "video",
    ] {
        assert!(
            commands.iter().any(|c| c == expected),
            "`omnicloud --help` lists {commands:?}, without {expected}"
        );
    }
    let index = std::fs::read_to_string(guide_dir().join("README.md"))
        .expect("the guide's index docs/guide/README.md");

    let mut failures = Vec::new();
    for command in &commands {
        let options = long_options(&omnicloud(&[command, "--help"]));
        assert!(
            !options.is_empty(),
            "no options parsed from `omnicloud {command} --help`: has its layout changed?"
        );
        let chapter_name = format!("{command}.md");
        if !index.contains(&format!("({chapter_name})")) {
            failures.push(format!("docs/guide/README.md does not link {chapter_name}"));
        }
        let Ok(chapter) = std::fs::read_to_string(guide_dir().join(&chapter_name)) else {
            failures.push(format!(
                "docs/guide/{chapter_name} is missing (omnicloud {command} has {} options)",
                options.len()
            ));
            continue;
        };
        let documented = documented_options(&chapter);
        for option in options.difference(&documented) {
            failures.push(format!(
                "docs/guide/{chapter_name} has no options-table row for `omnicloud {command} --{option}`"
            ));
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn help_parsing_takes_option_lines_only() {
    let help = "\
Render things

Usage: omnicloud render [OPTIONS] --output <OUT> <FILE>

Arguments:
  <FILE>
          A file, not --an-argument

Options:
  -o, --output <OUT>
          Output image; see also --stereo, which this line only names
          
          [default: x]

      --edl [<STRENGTH>]
          Eye-dome lighting
      --pole-merge-north <P>  North pole only (overrides --pole-merge there)
  -q, --quiet
          No progress
  -h, --help
          Print help
  -V, --version  Print version
";
    let parsed: Vec<String> = long_options(help).into_iter().collect();
    assert_eq!(parsed, ["edl", "output", "pole-merge-north", "quiet"]);

    let top = "\
Usage: omnicloud <COMMAND>

Commands:
  info     Print a header
  render   Render a point cloud
  help     Print this message

Options:
  -h, --help     Print help
";
    assert_eq!(subcommands(top), ["info", "render"]);
}

#[test]
fn chapter_parsing_takes_table_rows_only() {
    let chapter = "\
# render

Prose naming `--stereo` does not document it.

| option | what | default |
|---|---|---|
| `-o`, `--output OUT` | the file | required |
| `--pole-merge P` | both poles, see `--pole-merge-north` | `comfortable` |
| `--returns all\\|first` \\| `--same-cell` | escaped pipes stay in the cell | `all` |
| `--pitch DEG` | tilt | 0 |
";
    let parsed: Vec<String> = documented_options(chapter).into_iter().collect();
    assert_eq!(
        parsed,
        ["output", "pitch", "pole-merge", "returns", "same-cell"]
    );
}

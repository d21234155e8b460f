//! Well-known text (OGC WKT1 and WKT2) of a coordinate system: the parser and the keywords
//! that name its kinds of node. [`super::info`] reads a system's name and EPSG codes from it,
//! [`super::units`] its units.

/// A parsed WKT node: `KEYWORD[arg, arg, ...]`.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct WktNode {
    pub(super) keyword: String,
    pub(super) args: Vec<WktArg>,
}

/// One argument of a WKT node: a quoted text, a bare word (a number, an enum) or a node.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum WktArg {
    Text(String),
    Word(String),
    Node(WktNode),
}

/// Parses WKT (WKT1 or WKT2): `None` when the text is not one well-formed node.
pub(super) fn parse(text: &str) -> Option<WktNode> {
    fn skip_ws(b: &[u8], i: &mut usize) {
        while *i < b.len() && b[*i].is_ascii_whitespace() {
            *i += 1;
        }
    }
    fn node(b: &[u8], i: &mut usize, depth: usize) -> Option<WktNode> {
        // Nesting is a handful of levels in any real CRS: refuse absurd depth, not overflow.
        if depth > 64 {
            return None;
        }
        skip_ws(b, i);
        let start = *i;
        while *i < b.len() && (b[*i].is_ascii_alphanumeric() || b[*i] == b'_') {
            *i += 1;
        }
        let keyword = std::str::from_utf8(&b[start..*i])
            .ok()?
            .to_ascii_uppercase();
        skip_ws(b, i);
        let close = match b.get(*i)? {
            b'[' => b']',
            b'(' => b')',
            _ => return None,
        };
        *i += 1;
        let mut args = Vec::new();
        loop {
            skip_ws(b, i);
            match *b.get(*i)? {
                c if c == close => {
                    *i += 1;
                    break;
                }
                b',' => *i += 1,
                b'"' => {
                    // A quote inside a string is written twice.
                    let mut text = Vec::new();
                    *i += 1;
                    loop {
                        match *b.get(*i)? {
                            b'"' if b.get(*i + 1) == Some(&b'"') => {
                                text.push(b'"');
                                *i += 2;
                            }
                            b'"' => {
                                *i += 1;
                                break;
                            }
                            c => {
                                text.push(c);
                                *i += 1;
                            }
                        }
                    }
                    args.push(WktArg::Text(String::from_utf8_lossy(&text).into_owned()));
                }
                _ => {
                    let start = *i;
                    while *i < b.len() && !matches!(b[*i], b',' | b']' | b')' | b'[' | b'(') {
                        *i += 1;
                    }
                    if matches!(b.get(*i), Some(b'[' | b'(')) {
                        *i = start;
                        args.push(WktArg::Node(node(b, i, depth + 1)?));
                    } else if *i == start {
                        // A closing bracket of the other kind (`]` inside `(...)`): taken as
                        // an empty word it would be met again, forever.
                        return None;
                    } else {
                        let word = std::str::from_utf8(&b[start..*i]).ok()?.trim();
                        args.push(WktArg::Word(word.to_string()));
                    }
                }
            }
        }
        Some(WktNode { keyword, args })
    }
    let b = text.as_bytes();
    let mut i = 0;
    node(b, &mut i, 0)
}

impl WktNode {
    pub(super) fn name(&self) -> Option<&str> {
        self.args.iter().find_map(|a| match a {
            WktArg::Text(t) => Some(t.as_str()),
            _ => None,
        })
    }

    pub(super) fn children(&self) -> impl Iterator<Item = &WktNode> {
        self.args.iter().filter_map(|a| match a {
            WktArg::Node(n) => Some(n),
            _ => None,
        })
    }

    /// The node's own `AUTHORITY["EPSG","2992"]` (WKT1) or `ID["EPSG",2992]` (WKT2).
    pub(super) fn epsg(&self) -> Option<u32> {
        self.children()
            .filter(|c| c.keyword == "AUTHORITY" || c.keyword == "ID")
            .find_map(|c| match c.args.as_slice() {
                [WktArg::Text(auth), code, ..] if auth.eq_ignore_ascii_case("EPSG") => match code {
                    WktArg::Text(s) | WktArg::Word(s) => s.trim().parse().ok(),
                    WktArg::Node(_) => None,
                },
                _ => None,
            })
    }
}

/// WKT keywords of compound systems, and of the vertical part inside one.
pub(super) const COMPOUND: [&str; 2] = ["COMPD_CS", "COMPOUNDCRS"];
pub(super) const VERTICAL: [&str; 3] = ["VERT_CS", "VERTCRS", "VERTICALCRS"];
/// WKT keywords of a length unit (`UNIT` in WKT1; `LENGTHUNIT` or `UNIT` in WKT2).
pub(super) const LENGTH_UNIT: [&str; 2] = ["UNIT", "LENGTHUNIT"];
/// WKT keywords of projected and geographic systems.
pub(super) const PROJECTED: [&str; 3] = ["PROJCS", "PROJCRS", "PROJECTEDCRS"];
pub(super) const GEOGRAPHIC: [&str; 5] = [
    "GEOGCS",
    "GEOGCRS",
    "GEODCRS",
    "GEOGRAPHICCRS",
    "GEODETICCRS",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_words_and_doubled_quotes_parse() {
        let root =
            parse(r#"VERT_CS["NAVD88 height ""ft""",UNIT("foot",0.3048),AXIS["Up",UP]]"#).unwrap();
        assert_eq!(root.keyword, "VERT_CS");
        assert_eq!(root.name(), Some(r#"NAVD88 height "ft""#));
        let unit = root.children().next().unwrap();
        assert_eq!(unit.keyword, "UNIT");
        assert_eq!(
            unit.args,
            [WktArg::Text("foot".into()), WktArg::Word("0.3048".into())]
        );
        assert_eq!(root.children().count(), 2);
    }

    #[test]
    fn malformed_or_absurdly_deep_text_is_none() {
        assert_eq!(parse("PROJCS[\"a\""), None);
        assert_eq!(parse("no brackets"), None);
        let deep = "A[".repeat(70) + &"]".repeat(70);
        assert_eq!(parse(&deep), None);
        let fine = "A[".repeat(60) + &"]".repeat(60);
        assert!(parse(&fine).is_some());
    }

    #[test]
    fn a_closing_bracket_of_the_other_kind_is_none_not_an_endless_loop() {
        // From a fuzzed LAS file's WKT VLR: `](` where `],` stood, so a `]` came inside
        // `(...)` and was pushed as an empty word forever (8 GB in 20 s).
        assert_eq!(
            parse(r#"DATUM["d",TOWGS84[0](AUTHORITY["EPSG","6152"]]]"#),
            None
        );
        assert_eq!(parse("A(B]"), None);
        assert_eq!(parse("A[B)"), None);
        assert!(parse("A(B)").is_some() && parse("A[B,C[1]]").is_some());
    }

    #[test]
    fn epsg_comes_from_authority_or_id() {
        let wkt1 = parse(r#"GEOGCS["x",AUTHORITY["EPSG","4326"]]"#).unwrap();
        let wkt2 = parse(r#"GEOGCRS["x",ID["EPSG",4326]]"#).unwrap();
        let other = parse(r#"GEOGCRS["x",ID["ESRI",4326]]"#).unwrap();
        assert_eq!(
            (wkt1.epsg(), wkt2.epsg(), other.epsg()),
            (Some(4326), Some(4326), None)
        );
    }
}

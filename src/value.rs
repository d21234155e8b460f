//! Numbers in option text (command line, manifests): every parser words a bad number alike.

/// A finite number; `what` names it in the message.
///
/// # Errors
/// A message quoting `s` when it is not a number or not finite.
pub fn finite(s: &str, what: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number ({what})"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("`{s}` is not a finite number ({what})"))
    }
}

/// A positive, finite length in metres.
///
/// # Errors
/// A message quoting `s` when it is not such a length.
pub fn positive_metres(s: &str) -> Result<f64, String> {
    let v = finite(s, "metres")?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(format!("expected a length > 0 in metres, got `{s}`"))
    }
}

/// One of the values of a plain enum, by its `--help` name (any case); `what` names the
/// option in the message, which lists the accepted names.
///
/// # Errors
/// A message quoting `s` and listing the names.
pub fn choice<T: clap::ValueEnum>(s: &str, what: &str) -> Result<T, String> {
    T::from_str(s.trim(), true).map_err(|_| {
        let names: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|p| p.get_name().to_string())
            .collect();
        format!("unknown {what} `{s}`: use {}", names.join(", "))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_must_be_finite_and_lengths_positive() {
        assert_eq!(finite(" 2.5 ", "x"), Ok(2.5));
        assert!(finite("inf", "x").unwrap_err().contains("finite"));
        assert!(finite("a", "angle").unwrap_err().contains("(angle)"));
        assert_eq!(positive_metres("0.3"), Ok(0.3));
        assert!(positive_metres("0").is_err() && positive_metres("-1").is_err());
    }
}

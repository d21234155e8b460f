//! Python arguments as the library's option types, parsed by the same parsers as the command
//! line's options: a string as the option takes it, or a tuple or list of numbers for the
//! options that take `A,B,C`.

use std::str::FromStr;

use omnicloud::prepare::PointFilter;
use omnicloud::prepare::filter::{ClassSet, Crop, ReturnFilter};
use pyo3::prelude::*;
use pyo3::types::PyString;

use crate::errors::value_error;

/// `value` as the command line would be given it: a string as it is, a number as Python
/// prints it (the shortest text that reads back as the same float), a sequence of numbers
/// joined by commas.
pub fn as_text(what: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(s) = value.cast::<PyString>() {
        return s.extract::<String>();
    }
    if value.is_instance_of::<pyo3::types::PyInt>()
        || value.is_instance_of::<pyo3::types::PyFloat>()
    {
        return Ok(value.str()?.to_string());
    }
    let items: Vec<Bound<'_, PyAny>> = match value.try_iter() {
        Ok(iter) => iter.collect::<PyResult<_>>()?,
        Err(_) => {
            return Err(value_error(format!(
                "{what}: expected a string or a sequence of numbers, got {}",
                value.get_type().name()?
            )));
        }
    };
    let mut parts = Vec::with_capacity(items.len());
    for item in &items {
        // numpy scalars print as plain numbers too; anything else is refused.
        let number: f64 = item.extract().map_err(|_| {
            value_error(format!(
                "{what}: expected numbers, got {}",
                item.repr().map_or_else(|_| "?".into(), |r| r.to_string())
            ))
        })?;
        if !number.is_finite() {
            return Err(value_error(format!(
                "{what}: {number} is not a finite number"
            )));
        }
        parts.push(item.str()?.to_string());
    }
    Ok(parts.join(","))
}

/// `text` parsed by the library's parser for `what`, its message in a ValueError.
pub fn parse<T: FromStr<Err = String>>(what: &str, text: &str) -> PyResult<T> {
    text.parse()
        .map_err(|e: String| value_error(format!("{what}: {e}")))
}

/// An optional argument given as text or numbers, parsed.
pub fn parse_any<T: FromStr<Err = String>>(
    what: &str,
    value: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<T>> {
    value
        .map(|v| as_text(what, v).and_then(|t| parse(what, &t)))
        .transpose()
}

/// One of a fixed set of words, as the command line's option of that name takes it.
pub fn value_enum<T: clap::ValueEnum>(what: &str, text: &str) -> PyResult<T> {
    T::from_str(text, true).map_err(|_| {
        let names: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| {
                v.to_possible_value()
                    .map(|p| format!("\"{}\"", p.get_name()))
            })
            .collect();
        value_error(format!(
            "{what}: unknown value `{text}`: use {}",
            names.join(", ")
        ))
    })
}

/// A finite number, named in the error.
pub fn finite(what: &str, value: f64) -> PyResult<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(value_error(format!(
            "{what}: {value} is not a finite number"
        )))
    }
}

/// The filters `read` and `render` take.
pub struct FilterArgs<'a, 'py> {
    pub classes: Option<&'a Bound<'py, PyAny>>,
    pub drop_classes: Option<&'a Bound<'py, PyAny>>,
    pub returns: &'a str,
    pub crop: Option<&'a Bound<'py, PyAny>>,
    /// Metres (before `per_metre` converts it).
    pub max_distance: Option<f64>,
}

impl FilterArgs<'_, '_> {
    /// The library's filter, `max_distance` converted by `per_metre` (file units per metre).
    pub fn filter(&self, per_metre: f64) -> PyResult<PointFilter> {
        let max_distance = match self.max_distance {
            Some(m) if !(m.is_finite() && m > 0.0) => {
                return Err(value_error(format!(
                    "max_distance: {m} is not a positive distance in metres"
                )));
            }
            m => m.map(|m| m * per_metre),
        };
        Ok(PointFilter {
            classes: parse_any::<ClassSet>("classes", self.classes)?,
            drop_classes: parse_any::<ClassSet>("drop_classes", self.drop_classes)?,
            returns: value_enum::<ReturnFilter>("returns", self.returns)?,
            crop: parse_any::<Crop>("crop", self.crop)?,
            max_distance,
        })
    }
}

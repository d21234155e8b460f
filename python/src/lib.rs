//! `omnicloud._native`: the compiled part of the `omnicloud` Python package. Every function
//! calls the omnicloud library (reading, filters, preparation, both renderers, outputs,
//! compare, tours); this crate only converts arguments and arrays and releases the GIL around
//! the work.

mod cloud;
mod errors;
mod image;
mod options;
mod progress;
mod render;
mod tour;
mod view;

use pyo3::prelude::*;

/// The compiled module; `omnicloud/__init__.py` re-exports it.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<cloud::PointCloud>()?;
    m.add_class::<image::Image>()?;
    m.add_function(wrap_pyfunction!(cloud::read, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(image::compare, m)?)?;
    m.add_function(wrap_pyfunction!(tour::tour, m)?)?;
    Ok(())
}

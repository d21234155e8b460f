//! The library's errors as Python exceptions, carrying the library's message: files that
//! cannot be read or written are `OSError` (`FileNotFoundError` when missing), bad arguments
//! and data that cannot be rendered `ValueError`, a missing GPU `RuntimeError`.

use omnicloud::io::LoadError;
use omnicloud::output::OutputError;
use omnicloud::prepare::PrepareError;
use omnicloud::renderer::ResidentError;
use pyo3::PyErr;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyRuntimeError, PyValueError};

/// A `ValueError` with `message`.
pub fn value_error(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// A file that could not be read.
pub fn load_error(e: LoadError) -> PyErr {
    match e {
        LoadError::NotFound { .. } => PyFileNotFoundError::new_err(e.to_string()),
        _ => PyOSError::new_err(e.to_string()),
    }
}

/// A scene that could not be prepared: reading is a file's fault, the rest the arguments'.
pub fn prepare_error(e: PrepareError) -> PyErr {
    match e {
        PrepareError::Load(e) => load_error(e),
        e => value_error(e),
    }
}

/// A render that failed: the GPU's fault, or a colour mode the points cannot give.
pub fn render_error(e: ResidentError) -> PyErr {
    match e {
        ResidentError::Color(e) => value_error(e),
        e => PyRuntimeError::new_err(e.to_string()),
    }
}

/// A file that could not be written: a name the writers do not know is a bad argument.
pub fn output_error(e: OutputError) -> PyErr {
    match e {
        OutputError::UnsupportedExtension { .. }
        | OutputError::NotStereo { .. }
        | OutputError::NotPanorama { .. } => value_error(e),
        e => PyOSError::new_err(e.to_string()),
    }
}

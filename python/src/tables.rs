//! A run's tables as numpy arrays, read from the CSV files the command line writes (the models'
//! own `write_csv`, so the columns, their order and their values are the files'). Each float was
//! written in its shortest round-trip form (`ryu`), so reading it back gives the run's f64 to the
//! bit; a column's type comes from its text: integers → int64 (uint64 above i64), `true`/`false`
//! → bool, numbers → float64 (an empty field → NaN), anything else → str.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};

/// One column as numpy array.
fn column(py: Python<'_>, values: Vec<String>) -> PyResult<Py<PyAny>> {
    if !values.is_empty() {
        if let Ok(v) = values
            .iter()
            .map(|s| s.parse::<i64>())
            .collect::<Result<Vec<_>, _>>()
        {
            return Ok(PyArray1::from_vec(py, v).into_any().unbind());
        }
        if let Ok(v) = values
            .iter()
            .map(|s| s.parse::<u64>())
            .collect::<Result<Vec<_>, _>>()
        {
            return Ok(PyArray1::from_vec(py, v).into_any().unbind());
        }
        if values.iter().all(|s| s == "true" || s == "false") {
            let v: Vec<bool> = values.iter().map(|s| s == "true").collect();
            return Ok(PyArray1::from_vec(py, v).into_any().unbind());
        }
    }
    let numbers = values.iter().any(|s| !s.is_empty())
        && values.iter().all(|s| s.is_empty() || s.parse::<f64>().is_ok());
    if numbers || values.is_empty() {
        let v: Vec<f64> = values
            .iter()
            .map(|s| s.parse::<f64>().unwrap_or(f64::NAN))
            .collect();
        return Ok(PyArray1::from_vec(py, v).into_any().unbind());
    }
    let numpy = py.import("numpy")?;
    Ok(numpy.call_method1("array", (values, "str"))?.unbind())
}

/// One CSV file as `{column: array}`, the columns in the file's order (an empty file: `{}`).
fn table(py: Python<'_>, path: &Path) -> PyResult<Py<PyDict>> {
    let err =
        |e: csv::Error| pyo3::exceptions::PyOSError::new_err(format!("reading {}: {e}", path.display()));
    let mut r = csv::Reader::from_path(path).map_err(err)?;
    let names: Vec<String> = r.headers().map_err(err)?.iter().map(String::from).collect();
    let mut cols: Vec<Vec<String>> = vec![Vec::new(); names.len()];
    for rec in r.records() {
        let rec = rec.map_err(err)?;
        for (c, f) in cols.iter_mut().zip(rec.iter()) {
            c.push(f.to_string());
        }
    }
    let d = PyDict::new(py);
    for (name, values) in names.into_iter().zip(cols) {
        d.set_item(name, column(py, values)?)?;
    }
    Ok(d.unbind())
}

/// `files` as `{file stem: {column: array}}`, in the order given.
pub(crate) fn read_tables(py: Python<'_>, files: &[PathBuf]) -> PyResult<Py<PyDict>> {
    let d = PyDict::new(py);
    for f in files {
        let stem = f
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        d.set_item(stem, table(py, f)?)?;
    }
    Ok(d.unbind())
}

/// Reads every ``.csv`` file of ``folder`` (e.g. a command line's output folder) as
/// ``{file stem: {column: numpy array}}``, by the rules a run's tables are read with; files in
/// name order.
#[pyfunction]
pub(crate) fn read_csv_folder(py: Python<'_>, folder: PathBuf) -> PyResult<Py<PyDict>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(&folder)
        .map_err(|e| pyo3::exceptions::PyOSError::new_err(format!("reading {}: {e}", folder.display())))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "csv") && p.is_file())
        .collect();
    files.sort();
    read_tables(py, &files)
}

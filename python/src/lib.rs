//! `cohesive_contact._native`: the Python extension module (PyO3) over the workspace's library
//! code. It adds no physics and no second reading of a scene: a scene is TOML text checked by
//! the same functions as the command lines (`fem::Scene::from_toml_str_in`,
//! `spectral::Scene::from_toml_str`, `compare::study::Study`), runs go through the models'
//! `run_with_progress`, and the tables a run returns are the CSV files the command lines write,
//! read back column by column. The Python package (`python/cohesive_contact/`) wraps it.
//! - [`scene`]: `Scene` and its `Table` views, attribute access to every key;
//! - [`tables`]: a folder of CSV files → `{table: {column: numpy array}}`;
//! - [`run`]: one model's run with the GIL released, progress and Ctrl-C;
//! - [`gate`]: the harness's jobs, the FE-versus-spectral comparison first.

mod gate;
mod run;
mod scene;
mod tables;

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    _native,
    SceneError,
    PyValueError,
    "A scene refused by the checks every command runs before its first step. The message is the \
     command line's; `problems` lists (key, line, message) for each problem (line is None when \
     the key is not in the text, e.g. a missing key)."
);
create_exception!(
    _native,
    BudgetError,
    PyValueError,
    "A run above its budget of steps or memory, refused before it starts; the message names the \
     estimate and the argument to raise (max_steps, max_memory_gib)."
);
create_exception!(
    _native,
    RunUnstable,
    PyRuntimeError,
    "A run that went unstable: the message says when and where; `partial` holds the result up to \
     the last good step."
);

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("BudgetError", py.get_type::<BudgetError>())?;
    m.add("RunUnstable", py.get_type::<RunUnstable>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<scene::Table>()?;
    m.add_class::<run::Run>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(gate::job, m)?)?;
    m.add_function(wrap_pyfunction!(tables::read_csv_folder, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

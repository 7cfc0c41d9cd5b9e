//! `Scene`: a scene's TOML text with attribute access to every key (`scene.fem.element_size`),
//! checked by the command lines' own functions. The text is kept as written (comments, order,
//! layout; `toml_edit`), a changed value keeps its line and its comment, so the line numbers of
//! an error point into `Scene.to_toml()`.

use crate::SceneError;
use pyo3::exceptions::{PyAttributeError, PyKeyError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::PathBuf;
use toml_edit::{Array, DocumentMut, InlineTable, Item, Value};

/// A scene: the TOML text both models and the harness read (docs/scenes.md).
///
/// Every key is an attribute, tables nest: ``scene.fem.element_size = 2e-3``,
/// ``scene.friction.friction_coeff = 0.3``, ``scene.loading.shear.final = 1.2e5``. Item access
/// works too (``scene["fem"]["element_size"]``). A table reads as a ``Table`` view into the scene,
/// a value as a Python ``float``, ``int``, ``bool``, ``str`` or ``list``. Setting a key that the
/// scene does not have adds it; ``del`` removes it. Values are checked when the scene is checked
/// (``validate()``, or a run): by the same functions and with the same messages as the command
/// lines, every problem at once, each naming its key.
#[pyclass(module = "cohesive_contact")]
pub struct Scene {
    pub(crate) doc: DocumentMut,
    /// Folder that relative paths in the scene (`fem.mesh.file`) start from.
    pub(crate) base_dir: PathBuf,
    /// Name of the scene file without its extension (`scene` for a scene from text): the
    /// comparison's default folder name.
    pub(crate) stem: String,
}

/// A table of a scene (`scene.fem`, `scene.loading.normal`): a live view, so setting a key
/// changes the scene.
#[pyclass(module = "cohesive_contact")]
pub struct Table {
    scene: Py<Scene>,
    path: Vec<String>,
}

fn parse(text: &str) -> PyResult<DocumentMut> {
    text.parse::<DocumentMut>()
        .map_err(|e| SceneError::new_err(format!("scene does not parse: {e}")))
}

fn dotted(path: &[String], key: &str) -> String {
    let mut s = path.join(".");
    if !s.is_empty() {
        s.push('.');
    }
    s.push_str(key);
    s
}

fn lookup<'a>(doc: &'a DocumentMut, path: &[String]) -> Option<&'a Item> {
    let mut item = doc.as_item();
    for key in path {
        item = item.as_table_like()?.get(key)?;
    }
    Some(item)
}

fn lookup_mut<'a>(doc: &'a mut DocumentMut, path: &[String]) -> Option<&'a mut Item> {
    let mut item = doc.as_item_mut();
    for key in path {
        item = item.as_table_like_mut()?.get_mut(key)?;
    }
    Some(item)
}

/// A TOML value as a plain Python object (inline tables as dicts).
fn value_to_py(py: Python<'_>, v: &Value) -> PyResult<Py<PyAny>> {
    Ok(match v {
        Value::String(s) => s.value().into_pyobject(py)?.into_any().unbind(),
        Value::Integer(i) => i.value().into_pyobject(py)?.into_any().unbind(),
        Value::Float(f) => f.value().into_pyobject(py)?.into_any().unbind(),
        Value::Boolean(b) => PyBool::new(py, *b.value()).to_owned().into_any().unbind(),
        Value::Datetime(d) => d.value().to_string().into_pyobject(py)?.into_any().unbind(),
        Value::Array(a) => {
            let items: Vec<Py<PyAny>> = a.iter().map(|x| value_to_py(py, x)).collect::<PyResult<_>>()?;
            PyList::new(py, items)?.into_any().unbind()
        }
        Value::InlineTable(t) => {
            let d = PyDict::new(py);
            for (k, x) in t.iter() {
                d.set_item(k, value_to_py(py, x)?)?;
            }
            d.into_any().unbind()
        }
    })
}

/// Any TOML item as a plain Python object (tables as dicts, arrays of tables as lists of dicts).
fn item_to_plain(py: Python<'_>, item: &Item) -> PyResult<Py<PyAny>> {
    match item {
        Item::Value(v) => value_to_py(py, v),
        Item::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t.iter() {
                d.set_item(k, item_to_plain(py, x)?)?;
            }
            Ok(d.into_any().unbind())
        }
        Item::ArrayOfTables(a) => {
            let items: Vec<Py<PyAny>> = a
                .iter()
                .map(|t| item_to_plain(py, &Item::Table(t.clone())))
                .collect::<PyResult<_>>()?;
            Ok(PyList::new(py, items)?.into_any().unbind())
        }
        Item::None => Ok(py.None()),
    }
}

/// A Python object as a TOML value, for the key `key` (named in the error). An `int` given where
/// the scene has a float stays a float.
fn py_to_value(obj: &Bound<'_, PyAny>, existing: Option<&Item>, key: &str) -> PyResult<Value> {
    let float_here = matches!(existing, Some(Item::Value(Value::Float(_))));
    if obj.is_instance_of::<PyBool>() {
        return Ok(Value::from(obj.extract::<bool>()?));
    }
    if obj.is_instance_of::<PyInt>() {
        let i: i64 = obj
            .extract()
            .map_err(|_| PyTypeError::new_err(format!("{key}: {obj} does not fit a 64-bit integer")))?;
        return Ok(if float_here {
            Value::from(i as f64)
        } else {
            Value::from(i)
        });
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(Value::from(obj.extract::<f64>()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(Value::from(obj.extract::<String>()?));
    }
    if let Ok(t) = obj.cast::<Table>() {
        let plain = t.borrow().to_dict(obj.py())?;
        return py_to_value(plain.bind(obj.py()), existing, key);
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut t = InlineTable::new();
        for (k, v) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("{key}: a table's keys are strings, not {k}")))?;
            let sub = dotted(&[key.to_string()], &k);
            t.insert(&k, py_to_value(&v, None, &sub)?);
        }
        return Ok(Value::InlineTable(t));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut a = Array::new();
        for (i, v) in obj.try_iter()?.enumerate() {
            a.push(py_to_value(&v?, None, &format!("{key}[{i}]"))?);
        }
        return Ok(Value::Array(a));
    }
    // numpy scalars and anything else with __index__ or __float__
    if let Ok(i) = obj.call_method0("__index__").and_then(|i| i.extract::<i64>()) {
        return Ok(if float_here {
            Value::from(i as f64)
        } else {
            Value::from(i)
        });
    }
    if let Ok(f) = obj.call_method0("__float__").and_then(|f| f.extract::<f64>()) {
        return Ok(Value::from(f));
    }
    if let Ok(seq) = obj.call_method0("tolist") {
        return py_to_value(&seq, existing, key);
    }
    Err(PyTypeError::new_err(format!(
        "{key}: a scene value is a number, a bool, a string, a list or a dict, not {}",
        obj.get_type().name()?
    )))
}

/// The kind of a scalar value (numbers are one kind: an `int` may replace a float and back);
/// `None` for arrays and tables, whose form may change.
fn scalar_kind(v: &Value) -> Option<&'static str> {
    match v {
        Value::Integer(_) | Value::Float(_) => Some("number"),
        Value::String(_) => Some("string"),
        Value::Boolean(_) => Some("bool"),
        Value::Datetime(_) => Some("date"),
        Value::Array(_) | Value::InlineTable(_) => None,
    }
}

/// Sets `key` of the table at `path` to `obj`, keeping the old value's comment and layout.
fn set_key(doc: &mut DocumentMut, path: &[String], key: &str, obj: &Bound<'_, PyAny>) -> PyResult<()> {
    let name = dotted(path, key);
    let parent = lookup_mut(doc, path)
        .and_then(Item::as_table_like_mut)
        .ok_or_else(|| PyAttributeError::new_err(format!("{}: no such table", path.join("."))))?;
    let value = py_to_value(obj, parent.get(key), &name)?;
    if let Some(Item::Value(old)) = parent.get(key)
        && let (Some(was), Some(is)) = (scalar_kind(old), scalar_kind(&value))
        && was != is
    {
        return Err(PyTypeError::new_err(format!(
            "{name}: the scene has a {was} here, not a {is} (docs/scenes.md)"
        )));
    }
    match parent.get_mut(key) {
        Some(Item::Value(old)) => {
            let decor = old.decor().clone();
            *old = value;
            *old.decor_mut() = decor;
        }
        Some(item @ Item::Table(_)) => match value {
            Value::InlineTable(t) => *item = Item::Table(t.into_table()),
            v => *item = Item::Value(v),
        },
        Some(item) => *item = Item::Value(value),
        None => {
            let at_root = path.is_empty();
            match value {
                Value::InlineTable(t) if at_root => {
                    parent.insert(key, Item::Table(t.into_table()));
                }
                v => {
                    parent.insert(key, Item::Value(v));
                }
            }
        }
    }
    Ok(())
}

fn remove_key(doc: &mut DocumentMut, path: &[String], key: &str) -> PyResult<()> {
    let parent = lookup_mut(doc, path).and_then(Item::as_table_like_mut);
    match parent.and_then(|p| p.remove(key)) {
        Some(_) => Ok(()),
        None => Err(PyAttributeError::new_err(format!(
            "{}: not in the scene",
            dotted(path, key)
        ))),
    }
}

fn keys_at(doc: &DocumentMut, path: &[String]) -> Vec<String> {
    lookup(doc, path)
        .and_then(Item::as_table_like)
        .map(|t| t.iter().map(|(k, _)| k.to_string()).collect())
        .unwrap_or_default()
}

/// The value at `path + key` for Python: a `Table` view for a table, a plain object otherwise.
fn get_key(scene: &Bound<'_, Scene>, path: &[String], key: &str) -> PyResult<Option<Py<PyAny>>> {
    let py = scene.py();
    let s = scene.borrow();
    let Some(item) = lookup(&s.doc, path)
        .and_then(Item::as_table_like)
        .and_then(|t| t.get(key))
    else {
        return Ok(None);
    };
    if item.is_table_like() && !matches!(item, Item::ArrayOfTables(_)) {
        let mut sub = path.to_vec();
        sub.push(key.to_string());
        let view = Table {
            scene: scene.clone().unbind(),
            path: sub,
        };
        return Ok(Some(Py::new(py, view)?.into_any()));
    }
    item_to_plain(py, item).map(Some)
}

fn missing(path: &[String], key: &str, keys: &[String]) -> PyErr {
    let name = dotted(path, key);
    PyAttributeError::new_err(format!(
        "{name}: not in the scene (the table has: {}; docs/scenes.md lists every key)",
        keys.join(", ")
    ))
}

/// A refusal of the scene: the command line's message and each problem.
pub(crate) struct Refusal {
    message: String,
    problems: Vec<preflight::Problem>,
}

impl From<Refusal> for PyErr {
    /// A `SceneError` with the command line's message, and `problems`: each problem as
    /// (key, line, message).
    fn from(r: Refusal) -> PyErr {
        let err = SceneError::new_err(r.message);
        Python::attach(|py| {
            let list: Vec<(String, Option<usize>, String)> = r
                .problems
                .into_iter()
                .map(|p| (p.key, p.line, p.message))
                .collect();
            let _ = err.value(py).setattr("problems", list);
        });
        err
    }
}

impl Scene {
    /// The scene's text.
    pub(crate) fn text(&self) -> String {
        self.doc.to_string()
    }

    fn has(&self, table: &str) -> bool {
        self.doc.get(table).is_some()
    }

    /// The FE model's reading of the scene (`fem` command), or its refusal.
    pub(crate) fn fem(&self) -> Result<fem::Scene, Refusal> {
        fem::Scene::from_toml_str_in(&self.text(), &self.base_dir).map_err(|e| Refusal {
            message: e.to_string(),
            problems: e.problems(),
        })
    }

    /// The spectral model's reading of the scene (`spectral` command), or its refusal.
    pub(crate) fn spectral(&self) -> Result<spectral::Scene, Refusal> {
        spectral::Scene::from_toml_str(&self.text()).map_err(|e| Refusal {
            message: e.to_string(),
            problems: e.problems(),
        })
    }

    /// The harness's reading of the scene (`compare`): both models and `[compare]`.
    pub(crate) fn study(&self) -> Result<compare::study::Study, Refusal> {
        compare::study::Study::from_toml_str_in(&self.text(), &self.stem, Some(&self.base_dir)).map_err(|e| {
            if let Some(p) = e.downcast_ref::<compare::study::Problems>() {
                return Refusal {
                    message: format!("{e:#}"),
                    problems: p.0.clone(),
                };
            }
            // refused before the values were checked (e.g. the text does not parse): the
            // problems as the models list them, for `SceneError.problems`
            let mut problems = self.fem().err().map(|r| r.problems).unwrap_or_default();
            if self.has("spectral") {
                for p in self.spectral().err().map(|r| r.problems).unwrap_or_default() {
                    if !problems.iter().any(|q| q.key == p.key) {
                        problems.push(p);
                    }
                }
            }
            Refusal {
                message: format!("{e:#}"),
                problems,
            }
        })
    }
}

#[pymethods]
impl Scene {
    /// Reads a scene file (TOML). Relative paths in it (``fem.mesh.file``) start from the file's
    /// folder. Raises ``OSError`` if the file cannot be read, ``SceneError`` if it is not TOML;
    /// the keys are checked by ``validate()`` and by every run.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Scene> {
        let text = preflight::input::Cap::scene()
            .and_then(|cap| preflight::input::read_text_capped(&path, cap))
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(format!("reading {}: {e}", path.display())))?;
        let stem = path
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        let base_dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        Ok(Scene {
            doc: parse(&text)?,
            base_dir,
            stem,
        })
    }

    /// A scene from its TOML text; relative paths in it start from ``base_dir`` (default: the
    /// working directory).
    #[staticmethod]
    #[pyo3(signature = (text, base_dir = None))]
    fn from_str(text: &str, base_dir: Option<PathBuf>) -> PyResult<Scene> {
        Ok(Scene {
            doc: parse(text)?,
            base_dir: base_dir.unwrap_or_else(|| PathBuf::from(".")),
            stem: "scene".into(),
        })
    }

    /// The scene as TOML text: the original text, comments and layout included, with every
    /// change made from Python.
    fn to_toml(&self) -> String {
        self.text()
    }

    /// Writes ``to_toml()`` to ``path``.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        std::fs::write(&path, self.text())
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(format!("writing {}: {e}", path.display())))
    }

    /// An independent copy.
    fn copy(&self) -> Scene {
        Scene {
            doc: self.doc.clone(),
            base_dir: self.base_dir.clone(),
            stem: self.stem.clone(),
        }
    }

    fn __copy__(&self) -> Scene {
        self.copy()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Scene {
        self.copy()
    }

    /// Checks the scene as the command lines do, every problem at once: the FE model's checks
    /// with ``[fem]``, the spectral model's with ``[spectral]``, and the harness's (both models
    /// and ``[compare]``) with both. Raises ``SceneError`` naming each key.
    fn validate(&self) -> PyResult<()> {
        match (self.has("fem"), self.has("spectral")) {
            (true, true) => self.study().map(|_| ())?,
            (true, false) => self.fem().map(|_| ())?,
            (false, true) => self.spectral().map(|_| ())?,
            (false, false) => Err(Refusal {
                message: "the scene has neither [fem] nor [spectral]: nothing can run it (docs/scenes.md)"
                    .into(),
                problems: vec![preflight::Problem::new("fem", "missing")],
            })?,
        }
        Ok(())
    }

    /// The FE model's warnings on this scene (printed by the ``fem`` command before its run).
    fn warnings(&self) -> PyResult<Vec<String>> {
        let mut w = Vec::new();
        if self.has("fem") {
            w.extend(self.fem()?.warnings());
        }
        if self.has("spectral") {
            w.extend(self.spectral()?.warnings());
        }
        Ok(w)
    }

    /// The whole scene as nested dicts and lists.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        item_to_plain(py, self.doc.as_item())
    }

    /// The scene's top-level keys (tables and values).
    fn keys(&self) -> Vec<String> {
        keys_at(&self.doc, &[])
    }

    /// The folder relative paths in the scene start from.
    #[getter]
    fn base_dir(&self) -> PathBuf {
        self.base_dir.clone()
    }

    fn __getattr__(slf: &Bound<'_, Self>, name: &str) -> PyResult<Py<PyAny>> {
        if name.starts_with('_') {
            return Err(PyAttributeError::new_err(name.to_string()));
        }
        get_key(slf, &[], name)?.ok_or_else(|| missing(&[], name, &slf.borrow().keys()))
    }

    fn __setattr__(&mut self, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        set_key(&mut self.doc, &[], name, value)
    }

    fn __delattr__(&mut self, name: &str) -> PyResult<()> {
        remove_key(&mut self.doc, &[], name)
    }

    fn __getitem__(slf: &Bound<'_, Self>, key: &str) -> PyResult<Py<PyAny>> {
        get_key(slf, &[], key)?.ok_or_else(|| PyKeyError::new_err(key.to_string()))
    }

    fn __setitem__(&mut self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        set_key(&mut self.doc, &[], key, value)
    }

    fn __delitem__(&mut self, key: &str) -> PyResult<()> {
        remove_key(&mut self.doc, &[], key).map_err(|_| PyKeyError::new_err(key.to_string()))
    }

    fn __contains__(&self, key: &str) -> bool {
        self.has(key)
    }

    fn __dir__(&self) -> Vec<String> {
        let mut d = self.keys();
        d.extend(
            [
                "from_file",
                "from_str",
                "to_toml",
                "save",
                "copy",
                "validate",
                "warnings",
                "to_dict",
                "keys",
                "base_dir",
            ]
            .map(String::from),
        );
        d
    }

    fn __str__(&self) -> String {
        self.text()
    }

    fn __repr__(&self) -> String {
        let name = self.doc.get("name").and_then(Item::as_str).unwrap_or(&self.stem);
        format!("Scene({name:?}: {})", self.keys().join(", "))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<Scene>()
            .is_ok_and(|o| o.borrow().text() == self.text() && o.borrow().base_dir == self.base_dir)
    }
}

impl Table {
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let s = self.scene.borrow(py);
        match lookup(&s.doc, &self.path) {
            Some(item) => item_to_plain(py, item),
            None => Err(PyAttributeError::new_err(format!(
                "{}: no longer in the scene",
                self.path.join(".")
            ))),
        }
    }

    fn keys_vec(&self, py: Python<'_>) -> Vec<String> {
        keys_at(&self.scene.borrow(py).doc, &self.path)
    }
}

#[pymethods]
impl Table {
    /// The table as a dict (a copy: changing it does not change the scene).
    #[pyo3(name = "to_dict")]
    fn py_to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.to_dict(py)
    }

    /// The table's keys.
    fn keys(&self, py: Python<'_>) -> Vec<String> {
        self.keys_vec(py)
    }

    /// The dotted name of the table (``fem.mesh``).
    #[getter]
    fn name(&self) -> String {
        self.path.join(".")
    }

    fn __getattr__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        if name.starts_with('_') {
            return Err(PyAttributeError::new_err(name.to_string()));
        }
        get_key(self.scene.bind(py), &self.path, name)?
            .ok_or_else(|| missing(&self.path, name, &self.keys_vec(py)))
    }

    fn __setattr__(&self, py: Python<'_>, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        set_key(&mut self.scene.borrow_mut(py).doc, &self.path, name, value)
    }

    fn __delattr__(&self, py: Python<'_>, name: &str) -> PyResult<()> {
        remove_key(&mut self.scene.borrow_mut(py).doc, &self.path, name)
    }

    fn __getitem__(&self, py: Python<'_>, key: &str) -> PyResult<Py<PyAny>> {
        get_key(self.scene.bind(py), &self.path, key)?.ok_or_else(|| PyKeyError::new_err(key.to_string()))
    }

    fn __setitem__(&self, py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        set_key(&mut self.scene.borrow_mut(py).doc, &self.path, key, value)
    }

    fn __delitem__(&self, py: Python<'_>, key: &str) -> PyResult<()> {
        remove_key(&mut self.scene.borrow_mut(py).doc, &self.path, key)
            .map_err(|_| PyKeyError::new_err(key.to_string()))
    }

    fn __contains__(&self, py: Python<'_>, key: &str) -> bool {
        self.keys_vec(py).iter().any(|k| k == key)
    }

    fn __iter__(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let keys = PyList::new(py, self.keys_vec(py))?;
        Ok(keys.try_iter()?.into_any().unbind())
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        self.keys_vec(py).len()
    }

    fn __dir__(&self, py: Python<'_>) -> Vec<String> {
        let mut d = self.keys_vec(py);
        d.extend(["to_dict", "keys", "name"].map(String::from));
        d
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let d = self.to_dict(py)?;
        Ok(format!("Table({}: {})", self.path.join("."), d.bind(py).repr()?))
    }

    fn __eq__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<bool> {
        let mine = self.to_dict(py)?;
        let theirs = match other.cast::<Table>() {
            Ok(t) => t.borrow().to_dict(py)?,
            Err(_) => other.clone().unbind(),
        };
        mine.bind(py).eq(theirs)
    }
}

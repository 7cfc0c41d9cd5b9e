//! Checkpoints: the complete state of a run, written into its output folder while it runs, from
//! which a killed run resumes (`--checkpoint-every SECONDS`, `--resume DIR`; docs/checkpoints.md).
//!
//! A checkpoint is one file, [`FILE`], written atomically ([`crate::save`]), so a kill during a
//! write leaves the previous checkpoint whole. It holds:
//! - a [`Header`]: which model wrote it, the scene's text as given, the size and hash of every
//!   file the scene reads (a mesh), the step and time it was taken at;
//! - the model's state and its records so far, in [`postcard`]'s serde form, whose floats are
//!   their IEEE bytes: the resumed run starts from the very bits the run had, so its output is
//!   identical, byte for byte, to the output of the run that was never stopped.
//!
//! A resumed scene must be the scene the checkpoint was written with: a changed value is refused,
//! naming each key that changed with its two values ([`changes`]); a changed input file is
//! refused, naming the file. Comments and layout may change.

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The checkpoint's file name in the output folder.
pub const FILE: &str = "checkpoint.bin";

/// The first bytes of a checkpoint, with the version of the layout that follows.
const MAGIC: &[u8] = b"cohesive-contact checkpoint 1\n";

/// What a checkpoint says about the run it belongs to, checked before a resumed run does any work.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// The command that wrote it (`fem`, `spectral`).
    pub model: String,
    /// That command's version.
    pub version: String,
    /// The scene's text, as its file held it.
    pub scene: String,
    /// Every other file the scene reads (a mesh): its path as the scene gives it, its size
    /// [bytes] and FNV-1a hash.
    pub inputs: Vec<Input>,
    /// Wall time between checkpoints [s], kept by a resumed run unless it gives its own.
    pub every_s: f64,
    /// Steps done when it was taken [-].
    pub step: u64,
    /// Simulated time when it was taken [s].
    pub time_s: f64,
    /// Steps of the whole run [-].
    pub total_steps: u64,
}

impl Header {
    /// The header of a run of `model` (its `version`) on the scene `scene` (its text) reading
    /// `inputs`, of `total_steps` steps, before its first checkpoint.
    pub fn new(model: &str, version: &str, scene: &str, inputs: Vec<Input>, total_steps: u64) -> Header {
        Header {
            model: model.to_string(),
            version: version.to_string(),
            scene: scene.to_string(),
            inputs,
            every_s: 0.0,
            step: 0,
            time_s: 0.0,
            total_steps,
        }
    }
}

/// One file a scene reads, as a checkpoint records it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Input {
    /// The path (as the scene gives it, or resolved).
    pub path: String,
    /// Size [bytes].
    pub bytes: u64,
    /// FNV-1a hash of its bytes.
    pub hash: u64,
}

impl Input {
    /// Reads `path` and records it.
    pub fn of(path: &Path) -> io::Result<Input> {
        let bytes =
            std::fs::read(path).map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
        Ok(Input {
            path: path.display().to_string(),
            bytes: bytes.len() as u64,
            hash: crate::paths::fnv1a(&bytes),
        })
    }
}

/// A checkpoint read back, its header checked against the scene to resume.
#[derive(Debug)]
pub struct Resumed {
    /// Its header.
    pub header: Header,
    /// The model's part, in postcard form ([`Resumed::state`] decodes it).
    body: Vec<u8>,
}

impl Resumed {
    /// The model's state and records, as it wrote them with [`Writer::write`].
    pub fn state<B: DeserializeOwned>(&self) -> Result<B, String> {
        postcard::from_bytes(&self.body).map_err(|e| {
            format!(
                "{FILE}: the state in it cannot be read ({e}); it was written by another version of {}",
                self.header.model
            )
        })
    }

    /// The line a resumed run starts with.
    pub fn summary(&self) -> String {
        format!(
            "resuming from the checkpoint at step {} of {}, t = {:e} s",
            self.header.step, self.header.total_steps, self.header.time_s
        )
    }
}

/// Reads the checkpoint of the run whose output folder is `dir`, and refuses it unless it was
/// written by `expected.model` for the same scene and input files (`expected`'s step, time and
/// interval are not compared). Every refusal says what to change.
pub fn read(dir: &Path, expected: &Header) -> Result<Resumed, String> {
    let path = dir.join(FILE);
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Err(format!(
                "--resume {}: no {FILE} in it; a run writes one only with --checkpoint-every, and a \
                 run that reached its end removes it",
                dir.display()
            ));
        }
        Err(e) => return Err(format!("--resume {}: {e}", path.display())),
    };
    let Some(rest) = bytes.strip_prefix(MAGIC) else {
        return Err(format!(
            "--resume {}: not a checkpoint of this version of {} (its first bytes differ)",
            path.display(),
            expected.model
        ));
    };
    let (header, body): (Header, &[u8]) = postcard::take_from_bytes(rest)
        .map_err(|e| format!("--resume {}: its header cannot be read ({e})", path.display()))?;
    if header.model != expected.model {
        return Err(format!(
            "--resume {}: written by `{}`, not `{}`",
            path.display(),
            header.model,
            expected.model
        ));
    }
    if header.version != expected.version {
        return Err(format!(
            "--resume {}: written by {} {}, this is {}; a checkpoint resumes with the version that wrote it",
            path.display(),
            header.model,
            header.version,
            expected.version
        ));
    }
    let changed = changes(&header.scene, &expected.scene)?;
    if !changed.is_empty() {
        return Err(format!(
            "--resume {}: the scene changed since the checkpoint: {}; resume with the scene it was \
             written with, or start a new run",
            dir.display(),
            changed.join("; ")
        ));
    }
    // the same scene reads the same files, in the same order (their paths may be resolved from
    // another working folder)
    if header.inputs.len() != expected.inputs.len() {
        return Err(format!(
            "--resume {}: the scene reads {} file(s) besides itself, the checkpoint knows {}",
            dir.display(),
            expected.inputs.len(),
            header.inputs.len()
        ));
    }
    for (old, new) in header.inputs.iter().zip(&expected.inputs) {
        if (old.bytes, old.hash) != (new.bytes, new.hash) {
            return Err(format!(
                "--resume {}: {} changed since the checkpoint ({} bytes, hash {:016x}; now {} \
                 bytes, hash {:016x}); resume with the file it was written with",
                dir.display(),
                new.path,
                old.bytes,
                old.hash,
                new.bytes,
                new.hash
            ));
        }
    }
    Ok(Resumed {
        header,
        body: body.to_vec(),
    })
}

/// The keys whose values differ between two scene texts, each as `key: old → new` (`added` or
/// `removed` for a key only one holds), in the order of the keys. Comments, layout and the order
/// of keys are not changes. A text that does not parse is an error.
pub fn changes(old: &str, new: &str) -> Result<Vec<String>, String> {
    let parse = |text: &str, which: &str| {
        text.parse::<toml::Table>()
            .map_err(|e| format!("the {which} scene does not parse: {e}"))
    };
    let (old, new) = (parse(old, "checkpoint's")?, parse(new, "given")?);
    let mut out = Vec::new();
    diff("", &old, &new, &mut out);
    Ok(out)
}

fn diff(prefix: &str, old: &toml::Table, new: &toml::Table, out: &mut Vec<String>) {
    let mut keys: Vec<&String> = old.keys().chain(new.keys()).collect();
    keys.sort();
    keys.dedup();
    for k in keys {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match (old.get(k), new.get(k)) {
            (Some(toml::Value::Table(a)), Some(toml::Value::Table(b))) => diff(&key, a, b, out),
            (Some(a), Some(b)) if a == b => {}
            (Some(a), Some(b)) => out.push(format!("{key}: {} → {}", short(a), short(b))),
            (Some(a), None) => out.push(format!("{key}: {} → removed", short(a))),
            (None, Some(b)) => out.push(format!("{key}: added, {}", short(b))),
            (None, None) => {}
        }
    }
}

/// A value as TOML writes it, cut to 60 characters.
fn short(v: &toml::Value) -> String {
    let mut s = String::new();
    let _ = write!(s, "{v}");
    match s.char_indices().nth(60) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s,
    }
}

/// Writes a run's checkpoints, at most one per [`Writer::every`] of wall time, and keeps their
/// cost.
#[derive(Debug)]
pub struct Writer {
    path: PathBuf,
    header: Header,
    every: Duration,
    last: Instant,
    written: u32,
    bytes: u64,
    spent: Duration,
}

impl Writer {
    /// A writer into `dir` ([`FILE`]) every `every_s` [s] of wall time, counted from now, for a
    /// run described by `header` (its step and time are set at each write).
    pub fn new(dir: &Path, every_s: f64, mut header: Header) -> Writer {
        header.every_s = every_s;
        Writer {
            path: dir.join(FILE),
            header,
            every: Duration::from_secs_f64(every_s),
            last: Instant::now(),
            written: 0,
            bytes: 0,
            spent: Duration::ZERO,
        }
    }

    /// Whether a checkpoint is due: the interval has passed since the last one (or the start).
    pub fn due(&self) -> bool {
        self.last.elapsed() >= self.every
    }

    /// Writes the checkpoint of step `step` at time `time_s` [s] with the model's `state`
    /// (atomically: the previous one stays whole until this one is). The error names the file.
    pub fn write<B: Serialize>(&mut self, step: u64, time_s: f64, state: &B) -> io::Result<()> {
        let clock = Instant::now();
        self.header.step = step;
        self.header.time_s = time_s;
        let header = &self.header;
        let bytes = crate::save::atomically(&self.path, |w| {
            let mut counted = Counted { inner: w, bytes: 0 };
            counted.write_all(MAGIC)?;
            postcard::to_io(header, &mut counted).map_err(io::Error::other)?;
            postcard::to_io(state, &mut counted).map_err(io::Error::other)?;
            Ok(counted.bytes)
        })?;
        self.written += 1;
        self.bytes = bytes;
        self.spent += clock.elapsed();
        self.last = Instant::now();
        Ok(())
    }

    /// Removes the checkpoint of a run that reached its end: there is nothing left to resume.
    pub fn remove(&self) -> io::Result<()> {
        match std::fs::remove_file(&self.path) {
            Err(e) if e.kind() != io::ErrorKind::NotFound => {
                Err(io::Error::new(e.kind(), format!("{}: {e}", self.path.display())))
            }
            _ => Ok(()),
        }
    }

    /// The line before the run: where the checkpoints go and how often.
    pub fn plan(&self) -> String {
        format!(
            "checkpoint: {} every {} s of wall time",
            self.path.display(),
            self.every.as_secs_f64()
        )
    }

    /// Checkpoints written by this process [-].
    pub fn written(&self) -> u32 {
        self.written
    }

    /// What the checkpoints cost, in one line: how many, their size, the wall time each took.
    pub fn summary(&self) -> String {
        if self.written == 0 {
            return format!(
                "no checkpoint written (one every {:.3} s of wall time)",
                self.every.as_secs_f64()
            );
        }
        format!(
            "{} checkpoint(s) of {} in {}, {:.3} s each",
            self.written,
            crate::budget::human(self.bytes),
            self.path.display(),
            self.spent.as_secs_f64() / f64::from(self.written)
        )
    }
}

/// A writer that counts the bytes through it.
struct Counted<'a, W: Write> {
    inner: &'a mut W,
    bytes: u64,
}

impl<W: Write> Write for Counted<'_, W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(scene: &str) -> Header {
        let m = Input {
            path: "m.msh".into(),
            bytes: 3,
            hash: 7,
        };
        Header::new("fem", "1.0", scene, vec![m], 100)
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("preflight-checkpoint-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// What is written is read back to the bit (NaN payloads and signed zeros included), with
    /// its step and time.
    #[test]
    fn a_state_comes_back_to_the_bit() {
        let dir = scratch("bits");
        let state: Vec<f64> = vec![0.1, -0.0, f64::from_bits(0x7ff8_0000_0000_0123), 1e-308, f64::MAX];
        let mut w = Writer::new(&dir, 1.0, header("a = 1"));
        w.write(42, 1.5e-6, &(state.clone(), 7u32)).unwrap();
        let r = read(&dir, &header("a = 1")).unwrap();
        assert_eq!(
            (r.header.step, r.header.time_s, r.header.every_s),
            (42, 1.5e-6, 1.0)
        );
        let (back, n): (Vec<f64>, u32) = r.state().unwrap();
        assert_eq!(n, 7);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&state));
        assert!(w.summary().starts_with("1 checkpoint(s) of "), "{}", w.summary());
        w.remove().unwrap();
        let gone = read(&dir, &header("a = 1")).unwrap_err();
        assert!(gone.contains("no checkpoint.bin"), "{gone}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A changed value, an added and a removed key are each named with their values; comments,
    /// layout and key order are not changes.
    #[test]
    fn a_changed_scene_is_refused_naming_each_change() {
        let old = "# run\n[fem]\nelement_size = 1e-3\nmu = 0.3\n[loading]\nshear = { initial = 1.0, final = 2.0 }\n";
        let same = "[loading]\nshear = {final = 2.0, initial = 1.0}\n[fem]\nmu = 0.3 # friction\nelement_size = 0.001\n";
        assert_eq!(changes(old, same).unwrap(), Vec::<String>::new());
        let new = "[fem]\nelement_size = 2e-3\nmodel = \"standard\"\n[loading]\nshear = { initial = 1.0, final = 3.0 }\n";
        assert_eq!(
            changes(old, new).unwrap(),
            vec![
                "fem.element_size: 0.001 → 0.002",
                "fem.model: added, \"standard\"",
                "fem.mu: 0.3 → removed",
                "loading.shear.final: 2.0 → 3.0",
            ]
        );
        let dir = scratch("changed");
        Writer::new(&dir, 1.0, header(old)).write(1, 0.0, &0u8).unwrap();
        let e = read(&dir, &header(new)).unwrap_err();
        assert!(
            e.contains("the scene changed since the checkpoint: fem.element_size: 0.001 → 0.002;"),
            "{e}"
        );
        assert!(read(&dir, &header(same)).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Another model's checkpoint, another version's, a changed mesh and a file that is not a
    /// checkpoint are each refused, named.
    #[test]
    fn a_checkpoint_of_another_run_is_refused_naming_why() {
        let dir = scratch("other");
        Writer::new(&dir, 1.0, header("a = 1"))
            .write(1, 0.0, &0u8)
            .unwrap();
        let mut other = header("a = 1");
        other.model = "spectral".into();
        assert!(
            read(&dir, &other)
                .unwrap_err()
                .contains("written by `fem`, not `spectral`")
        );
        let mut newer = header("a = 1");
        newer.version = "2.0".into();
        assert!(
            read(&dir, &newer)
                .unwrap_err()
                .contains("written by fem 1.0, this is 2.0")
        );
        let mut mesh = header("a = 1");
        mesh.inputs[0].hash = 8;
        let e = read(&dir, &mesh).unwrap_err();
        assert!(e.contains("m.msh changed since the checkpoint"), "{e}");
        std::fs::write(dir.join(FILE), b"not a checkpoint").unwrap();
        assert!(
            read(&dir, &header("a = 1"))
                .unwrap_err()
                .contains("not a checkpoint")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

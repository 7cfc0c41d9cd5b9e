//! Everything checked before a run's first time step, shared by the two models' command lines and
//! the comparison harness:
//! - [`file`]: the scene file as its user wrote it — unknown keys collected, every problem located
//!   on its line;
//! - [`input`]: scene and mesh files read through a size cap;
//! - [`budget`]: memory and step estimates against a budget, refused with the key to change;
//! - [`paths`]: output folders that stay where they are asked to be, and are writable before any
//!   work;
//! - [`save`]: files written whole or not at all, never through a symbolic link;
//! - [`checkpoint`]: a run's complete state, from which a killed run resumes;
//! - [`ended`]: how a run ended (reached T, unstable, stopped on request), in one form for both
//!   models' command lines and the harness;
//! - [`profile`]: the table of where a run's time went, printed by both models' commands;
//! - [`pool`] (feature `pool`): a run's own rayon pool, its other workers kept awake while the
//!   steps run (the FE model's runs);
//! - [`stop`], [`options`] and [`command`] (feature `cli`): Ctrl-C and SIGTERM stop a run at its
//!   next step; the command-line options every command shares; the checks and last line the two
//!   models' commands share around their run.
#![warn(missing_docs)]

pub mod budget;
pub mod checkpoint;
#[cfg(feature = "cli")]
pub mod command;
pub mod ended;
pub mod file;
pub mod input;
#[cfg(feature = "cli")]
pub mod options;
pub mod paths;
#[cfg(feature = "pool")]
pub mod pool;
pub mod profile;
pub mod save;
#[cfg(feature = "cli")]
pub mod stop;
#[cfg(feature = "testing")]
pub mod testing;

pub use budget::{Budget, Estimate, Part};
pub use ended::{RunEnded, Status};
pub use file::{Problem, Refused, SceneErrorKind, line_of, locate, parse, problems_text, read, unknown_keys};

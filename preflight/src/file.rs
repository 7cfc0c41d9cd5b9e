//! A scene file as its user wrote it. Both models and the harness read the same TOML file; each
//! takes its own sections, collects the keys it does not know instead of stopping at the first,
//! and reports every problem with the key as written and its line, so that one run of a bad file
//! lists all that is wrong with it.

use serde::de::DeserializeOwned;

/// One problem of a scene file.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Dotted key as written in the file (`fem.interface_zones[1].sigma_c`).
    pub key: String,
    /// Line of the key in the file (1-based; `None`: not in the file, e.g. a missing key).
    pub line: Option<usize>,
    /// What is wrong, with the allowed values.
    pub message: String,
}

impl Problem {
    /// A problem of `key`, not yet located in the text.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Problem {
        Problem {
            key: key.into(),
            line: None,
            message: message.into(),
        }
    }
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(l) => write!(f, "line {l}: {}", self.message),
            None => write!(f, "{}", self.message),
        }
    }
}

/// "N problems in the scene", then one problem per indented line.
pub fn problems_text(problems: &[Problem]) -> String {
    let n = problems.len();
    let mut s = format!("{n} problem{} in the scene", if n == 1 { "" } else { "s" });
    for p in problems {
        s.push_str("\n  ");
        s.push_str(&p.to_string());
    }
    s
}

/// Deserialises `text` into `T`, collecting the keys `T` does not know (as dotted keys,
/// `fem.interface_zones[1].bogus`) instead of refusing the first. Syntax errors and values of the
/// wrong type are returned as the parser words them (they carry their line), followed by the
/// unknown keys met before the error with their lines: a misspelt required key is reported as
/// missing, and its misspelling is the line that tells what to change.
pub fn parse<T: DeserializeOwned>(text: &str) -> Result<(T, Vec<String>), String> {
    let de = toml::de::Deserializer::parse(text).map_err(|e| e.to_string())?;
    let mut unknown = Vec::new();
    let value: Result<T, _> = serde_ignored::deserialize(de, |path| unknown.push(dotted(&path.to_string())));
    match value {
        Ok(value) => Ok((value, unknown)),
        Err(e) => {
            let mut message = e.to_string();
            let mut also = unknown_keys(unknown);
            locate(text, &mut also);
            for p in &also {
                message.push_str(&format!("\nalso {p}"));
            }
            Err(message)
        }
    }
}

/// One "unknown key" problem per key of `unknown`.
pub fn unknown_keys(unknown: Vec<String>) -> Vec<Problem> {
    unknown
        .into_iter()
        .map(|key| Problem {
            message: match MOVED.iter().find(|(old, _)| *old == key) {
                Some((_, why)) => format!("unknown key {key}: {why}"),
                None => format!("unknown key {key}"),
            },
            line: None,
            key,
        })
        .collect()
}

/// Keys that an earlier scene format had, each with where it went, so that an old scene is told
/// what to write instead of only that the key is unknown.
const MOVED: &[(&str, &str)] = &[(
    "fem.contact_friction",
    "moved to [friction] contact_friction, which both models read",
)];

/// Why a scene file was refused.
#[derive(Debug, Clone, PartialEq)]
pub enum Refused {
    /// The text does not parse or a value has the wrong type (the message has the line).
    Parse(String),
    /// Every problem found, unknown keys included, located on their lines and in file order.
    Invalid(Vec<Problem>),
}

/// What every model's scene error has in common: it can stand for a refused file (one that does
/// not parse, or the list of its problems), and any other of its errors is one problem of one key.
/// A model implements the four ways in; the problems and the conversion from [`Refused`] are
/// here, once.
pub trait SceneErrorKind: std::fmt::Display + Sized {
    /// The error of a file that does not parse (the parser's message, with its line).
    fn parse(message: String) -> Self;
    /// The error that lists every problem of a file.
    fn invalid(problems: Vec<Problem>) -> Self;
    /// The problems of an error made by [`SceneErrorKind::invalid`]; `None` for any other.
    fn listed(&self) -> Option<&[Problem]>;
    /// The dotted key the error is about (`None` for a file that does not parse, or a list).
    fn key(&self) -> Option<&str>;

    /// The problems this error stands for (one, or the list).
    fn problems(&self) -> Vec<Problem> {
        match self.listed() {
            Some(problems) => problems.to_vec(),
            None => vec![Problem::new(self.key().unwrap_or(""), self.to_string())],
        }
    }

    /// The error for a refused file.
    fn refused(r: Refused) -> Self {
        match r {
            Refused::Parse(m) => Self::parse(m),
            Refused::Invalid(problems) => Self::invalid(problems),
        }
    }
}

/// Reads a scene the way every model does: parses `text` into its raw form `R` collecting unknown
/// keys, validates it with `validate` (which reports what it finds through `problems`), and
/// refuses the file with every problem at once, each on its line. A file with unknown keys is
/// refused even when its values are valid.
pub fn read<R: DeserializeOwned, S, E>(
    text: &str,
    validate: impl FnOnce(R) -> Result<S, E>,
    problems: impl FnOnce(&E) -> Vec<Problem>,
) -> Result<S, Refused> {
    let (raw, unknown) = parse::<R>(text).map_err(Refused::Parse)?;
    let mut all = unknown_keys(unknown);
    match validate(raw) {
        Ok(scene) if all.is_empty() => return Ok(scene),
        Ok(_) => {}
        Err(e) => all.extend(problems(&e)),
    }
    locate(text, &mut all);
    Err(Refused::Invalid(all))
}

/// Sets each problem's line from `text` and sorts them in the order of the file (problems with no
/// line last, in the order given).
pub fn locate(text: &str, problems: &mut [Problem]) {
    for p in problems.iter_mut() {
        p.line = line_of(text, &p.key);
    }
    problems.sort_by_key(|p| p.line.unwrap_or(usize::MAX));
}

/// Line (1-based) of the dotted `key` in `text`: `fem.element_size`,
/// `fem.interface_zones[1].sigma_c`, `loading.normal.ramp_end` (inline tables too). A key the file
/// does not have gives its nearest enclosing table's line; `None` if nothing matches or the text
/// does not parse.
pub fn line_of(text: &str, key: &str) -> Option<usize> {
    let doc = toml::de::DeTable::parse(text).ok()?;
    let mut parts = key
        .split(' ')
        .next()?
        .split(['.', '['])
        .map(|p| p.trim_end_matches(']'))
        .filter(|p| !p.is_empty());
    let first = parts.next()?;
    let (_, mut node) = doc.get_ref().iter().find(|(k, _)| k.get_ref() == first)?;
    let mut span = node.span();
    for part in parts {
        let next = match part.parse::<usize>() {
            Ok(i) => node.get_ref().get(i),
            Err(_) => node.get_ref().get(part),
        };
        match next {
            Some(n) => {
                node = n;
                span = n.span();
            }
            None => break,
        }
    }
    Some(1 + text[..span.start.min(text.len())].matches('\n').count())
}

/// A path as `serde_ignored` reports it (`fem.?.interface_zones.1.bogus`) in the form errors use
/// (`fem.interface_zones[1].bogus`).
pub fn dotted(path: &str) -> String {
    let mut out = String::new();
    for part in path.split('.').filter(|p| *p != "?") {
        if part.parse::<usize>().is_ok() {
            out.push_str(&format!("[{part}]"));
        } else {
            if !out.is_empty() {
                out.push('.');
            }
            out.push_str(part);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "name = 'x'\n\n[loading]\nduration = 0.02\nnormal = { initial = 0.0, final = 1.0 }\n\n\
                        [fem]\nelement_size = 1e-3\n\n[[fem.zones]]\nsigma = 1.0\n\n[[fem.zones]]\nsigma = 2.0\n";

    #[test]
    fn keys_are_found_on_their_lines() {
        assert_eq!(line_of(TEXT, "name"), Some(1));
        assert_eq!(line_of(TEXT, "loading.duration"), Some(4));
        assert_eq!(line_of(TEXT, "loading.normal.final"), Some(5));
        assert_eq!(line_of(TEXT, "fem.element_size"), Some(8));
        assert_eq!(line_of(TEXT, "fem.zones[1].sigma"), Some(14));
        assert_eq!(
            line_of(TEXT, "fem.missing"),
            line_of(TEXT, "fem"),
            "a missing key gives its table"
        );
        assert_eq!(line_of(TEXT, "nowhere.at.all"), None);
    }

    #[test]
    fn ignored_paths_become_dotted_keys() {
        assert_eq!(
            dotted("fem.?.interface_zones.1.bogus"),
            "fem.interface_zones[1].bogus"
        );
        assert_eq!(dotted("compare.?.friction_coefs"), "compare.friction_coefs");
    }

    #[derive(serde::Deserialize)]
    #[allow(dead_code)]
    struct Fem {
        output_interval: f64,
        element_size: f64,
    }

    #[derive(serde::Deserialize)]
    #[allow(dead_code)]
    struct File {
        fem: Fem,
    }

    /// A misspelt required key: the parser stops at the missing one, and the misspelling, met
    /// before it, is reported with its line.
    #[test]
    fn a_misspelt_required_key_is_named_beside_the_missing_one() {
        let text = "[fem]\nelement_size = 1e-3\noutput_intervall = 1e-5\n";
        let e = parse::<File>(text).err().unwrap();
        assert!(e.contains("missing field `output_interval`"), "{e}");
        assert!(e.contains("also line 3: unknown key fem.output_intervall"), "{e}");
    }
}

//! What made a results file, stamped at its head, and the one check that
//! an exploratory run never silently replaces committed results made
//! differently.
//!
//! A results file that a later run could replace starts with its
//! [`Stamp`]: the format tag where its kind of file has one, the command
//! line that made it, and `made`, what
//! determines its results (a mining run's parameters, a study template and
//! its variants ...). `made` is flattened, so each kind of file keeps the
//! keys it has always had and committed files read back unchanged.
//!
//! Before a run replaces a file it builds the stamp it would write and
//! calls [`Stamp::check_replace`]: the file there is read as far as a
//! `Stamp<M>` (the rest of it is ignored), and every field of the format
//! and of `made` that differs is named in a one-line refusal. The command
//! line is not compared: the same run may be asked for with other flags.

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::Path;

use crate::{Error, Result};

/// The head of a results file (see the module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stamp<M> {
    /// The format tag, where the kind of file has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub format: Option<String>,
    /// The command line that made the file.
    pub command: String,
    /// What determines the results, under the keys the file keeps it at.
    #[serde(flatten)]
    pub made: M,
}

/// The `made` of files that keep what made them under `parameters`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameters<P> {
    pub parameters: P,
}

impl<P: Serialize + DeserializeOwned> Stamp<Parameters<P>> {
    /// The stamp of a file that keeps what made it under `parameters`.
    pub fn with_parameters(format: &str, command: &str, parameters: P) -> Self {
        Stamp::new(Some(format), command, Parameters { parameters })
    }
}

/// The `made` of a file that records only the command that made it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Nothing {}

impl<M: Serialize + DeserializeOwned> Stamp<M> {
    /// The stamp `command` writes on the results `made` determines.
    pub fn new(format: Option<&str>, command: &str, made: M) -> Self {
        Stamp {
            format: format.map(str::to_string),
            command: command.into(),
            made,
        }
    }

    /// Refuses to replace the file at `path` unless `force`, it is missing,
    /// or it was made as this stamp says (format and `made`; see the module
    /// docs). `what` names the kind of run in the message ("scan",
    /// "experiment").
    pub fn check_replace(&self, path: &Path, what: &str, force: bool) -> Result<()> {
        if force {
            return Ok(());
        }
        let Some(text) = existing(path)? else {
            return Ok(());
        };
        let refuse = |why: String| {
            Err(Error::Parameter(format!(
                "{} {why}; choose another --results, or --force to replace them",
                path.display()
            )))
        };
        let there: Stamp<M> = match serde_json::from_str(&text) {
            Ok(there) => there,
            Err(e) => return refuse(format!("does not hold {what} results ({e})")),
        };
        let differ = differences(&Compared::of(&there), &Compared::of(self));
        if differ.is_empty() {
            return Ok(());
        }
        refuse(format!(
            "holds the results of another {what} ({})",
            differ.join(", ")
        ))
    }
}

/// The text of the file at `path`, or `None` where there is no file.
pub fn existing(path: &Path) -> Result<Option<String>> {
    match std::fs::read_to_string(path) {
        Ok(text) => Ok(Some(text)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::io(path, e)),
    }
}

/// What the check compares: a stamp without its command.
#[derive(Serialize)]
struct Compared<'a, M> {
    #[serde(skip_serializing_if = "Option::is_none")]
    format: Option<&'a str>,
    #[serde(flatten)]
    made: &'a M,
}

impl<'a, M> Compared<'a, M> {
    fn of(stamp: &'a Stamp<M>) -> Self {
        Compared {
            format: stamp.format.as_deref(),
            made: &stamp.made,
        }
    }
}

/// The fields in which `there` and `asked` differ, each as `path there vs
/// asked` in the order of their paths (`parameters.seeds 2 vs 3`,
/// `template.gamma 10.0 vs 12.0`, `variants[1].runs 10 vs 40`). Objects and
/// lists of equal length are compared element by element; lists of
/// objects that differ in length give their lengths; a value missing on
/// one side shows as `none`.
pub fn differences(there: &impl Serialize, asked: &impl Serialize) -> Vec<String> {
    let there = serde_json::to_value(there).expect("results serialize");
    let asked = serde_json::to_value(asked).expect("results serialize");
    let mut out = Vec::new();
    differ("", &there, &asked, &mut out);
    out
}

/// Pretty JSON with a final newline, keys in the order the type declares them.
pub fn json<T: Serialize>(file: &T) -> String {
    serde_json::to_string_pretty(file).expect("results serialize") + "\n"
}

/// Pretty JSON with a final newline, the keys of every object sorted: the
/// layout of the files that were written through `serde_json::Value`
/// (the experiments of `compare`, `tradeoff` and `bias`), kept so that they
/// are written again byte for byte.
pub fn json_sorted<T: Serialize>(file: &T) -> String {
    let value = serde_json::to_value(file).expect("results serialize");
    serde_json::to_string_pretty(&value).expect("values serialize") + "\n"
}

fn differ(path: &str, there: &Value, asked: &Value, out: &mut Vec<String>) {
    if there == asked {
        return;
    }
    let at = |key: &str| {
        if path.is_empty() {
            key.to_string()
        } else {
            format!("{path}.{key}")
        }
    };
    let nested = |v: &[Value]| v.iter().any(|x| x.is_object() || x.is_array());
    match (there, asked) {
        (Value::Object(t), Value::Object(a)) => {
            let keys: std::collections::BTreeSet<&String> = t.keys().chain(a.keys()).collect();
            for k in keys {
                let none = Value::Null;
                differ(
                    &at(k),
                    t.get(k).unwrap_or(&none),
                    a.get(k).unwrap_or(&none),
                    out,
                );
            }
        }
        (Value::Array(t), Value::Array(a)) if t.len() == a.len() => {
            for (i, (x, y)) in t.iter().zip(a).enumerate() {
                differ(&format!("{path}[{i}]"), x, y, out);
            }
        }
        (Value::Array(t), Value::Array(a)) if nested(t) || nested(a) => {
            out.push(format!("{path} {} vs {} entries", t.len(), a.len()))
        }
        _ => out.push(format!("{path} {} vs {}", show(there), show(asked))),
    }
}

/// A value in a message: strings bare, nothing as `none`, the rest as JSON.
fn show(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Null => "none".into(),
        v => v.to_string(),
    }
}

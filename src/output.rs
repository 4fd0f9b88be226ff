//! Output files, written so that a failure never leaves half of one.
//!
//! Every file the library writes goes through [`write_atomic`] (or
//! [`replace_with`] for writers that need a path): the content goes to a
//! temporary file in the target's directory, is flushed and synced, and is
//! then renamed over the target. A full disk or a kill leaves the old file
//! (or none), never a truncated one. The only exception is the record files
//! of a threshold study, which grow one finished line at a time.
//!
//! A symbolic link is written through: the temporary file goes beside the
//! link's target and is renamed onto it, so the link stays a link.
//!
//! [`check_file`] and [`check_dir`] let a command refuse an unwritable
//! output before it does its work, [`check_outputs`] also refuses two
//! outputs that are one file (by what they name, not how they are spelt),
//! and [`csv()`] writes tables through the `csv` crate, so that a field
//! holding a comma or a quote is quoted.

use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::{Error, Result};

/// Replaces `path` by `bytes` atomically (see the module docs).
pub fn write_atomic(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    replace_with(path, |tmp| {
        std::fs::write(tmp, bytes.as_ref()).map_err(|e| Error::io(path, e))
    })
}

/// Replaces `path` by what `write` puts in the file it is given: a
/// temporary file beside `path` (beside its target, if `path` is a
/// symbolic link), with the same extension (some writers pick the format by
/// it), synced and renamed over the target once `write` succeeds and
/// removed if it fails.
pub fn replace_with(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let target = target(path);
    let tmp = temporary_beside(&target);
    let done = write(&tmp).and_then(|()| {
        std::fs::OpenOptions::new()
            .write(true)
            .open(&tmp)
            .and_then(|f| f.sync_all())
            .map_err(|e| Error::io(path, e))?;
        std::fs::rename(&tmp, &target).map_err(|e| Error::io(path, e))
    });
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

/// The file a write to `path` lands in: `path`, or the end of the chain of
/// symbolic links it starts (which need not exist yet). Renaming onto the
/// link itself would replace it by a plain file.
fn target(path: &Path) -> PathBuf {
    let mut p = path.to_path_buf();
    // The kernel's own limit on a chain of links; past it, the write fails there.
    for _ in 0..40 {
        match std::fs::read_link(&p) {
            // A relative target is relative to the link's directory.
            Ok(to) => p = p.parent().map_or_else(|| to.clone(), |dir| dir.join(&to)),
            Err(_) => break,
        }
    }
    p
}

/// A fresh hidden name in `path`'s directory ending in `path`'s file name:
/// unique per process and call, so parallel writers never share one.
fn temporary_beside(path: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let k = COUNTER.fetch_add(1, Ordering::Relaxed);
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".rgc-tmp-{}-{k}-{name}", std::process::id()))
}

/// `PREFIX.ext` beside a prefix that may hold dots of its own (a study
/// name like `g23.5`), where `Path::with_extension` would replace them.
pub fn with_extension(prefix: &Path, ext: &str) -> PathBuf {
    let mut name = prefix.as_os_str().to_owned();
    name.push(format!(".{ext}"));
    PathBuf::from(name)
}

/// Checks that a file can be written at `path`: it is not a directory, and
/// its directory exists (it is created if missing) and takes new files.
pub fn check_file(path: &Path) -> Result<()> {
    if path.is_dir() {
        return Err(Error::io(
            path,
            std::io::Error::other("is a directory, not a file"),
        ));
    }
    match path.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) => check_dir(dir),
        None => check_dir(Path::new(".")),
    }
}

/// The outputs of one command, as (flag, path), checked before the work:
/// each one writable ([`check_file`]) and no two the same file, however
/// they are spelt (`./a.csv` and `a.csv`, `d/../a.csv`, a symbolic or a
/// hard link to it), since the second write would silently replace the
/// first.
pub fn check_outputs(outputs: &[(&str, &Path)]) -> Result<()> {
    for (_, path) in outputs {
        check_file(path)?;
    }
    // After check_file, every output's directory exists and canonicalizes.
    let ids: Vec<FileId> = outputs.iter().map(|(_, p)| FileId::of(p)).collect();
    for (i, (flag, path)) in outputs.iter().enumerate() {
        if let Some(j) = ids[..i].iter().position(|id| *id == ids[i]) {
            let (other, first) = outputs[j];
            let spelt = if first == *path {
                path.display().to_string()
            } else {
                format!("{} and {}", first.display(), path.display())
            };
            return Err(Error::Parameter(format!(
                "{other} and {flag} both write {spelt}, one file: one would overwrite the other"
            )));
        }
    }
    Ok(())
}

/// Which file a path names, whatever its spelling.
#[derive(Debug, PartialEq)]
enum FileId {
    /// An existing file: its device and inode (through hard links).
    #[cfg(unix)]
    Node(u64, u64),
    /// A file to be made (or, off Unix, any file): its directory's
    /// canonical path joined with its name.
    Path(PathBuf),
}

impl FileId {
    fn of(path: &Path) -> Self {
        let target = target(path);
        #[cfg(unix)]
        if let Ok(m) = std::fs::metadata(&target) {
            use std::os::unix::fs::MetadataExt;
            return FileId::Node(m.dev(), m.ino());
        }
        let dir = target
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        match (dir.canonicalize(), target.file_name()) {
            (Ok(dir), Some(name)) => FileId::Path(dir.join(name)),
            _ => FileId::Path(std::path::absolute(&target).unwrap_or(target)),
        }
    }
}

/// Checks that files can be written into `dir`, creating it if missing: a
/// command that will write there fails now rather than after its work.
pub fn check_dir(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(Error::io(
            dir,
            std::io::Error::other("is a file, not a directory"),
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let probe = temporary_beside(&dir.join("probe"));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|e| Error::io(dir, e))?;
    std::fs::remove_file(&probe).map_err(|e| Error::io(&probe, e))
}

/// A CSV table of `rows`, headed by their field names (as the `csv` crate
/// does, from the first row: a table without rows is an empty file).
pub fn csv<T: Serialize>(rows: impl IntoIterator<Item = T>) -> Vec<u8> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for row in rows {
        w.serialize(row).expect("rows serialize as CSV");
    }
    w.into_inner().expect("writing to memory cannot fail")
}

/// A CSV table whose rows are a struct followed by a varying number of
/// further cells (one per parameter of the analysis, say): headed by the
/// struct's field names and then `more` (empty without rows, as [`csv()`]).
pub fn csv_with_more<T, M>(more: &[String], rows: impl IntoIterator<Item = (T, M)>) -> Vec<u8>
where
    T: Serialize,
    M: Serialize,
{
    let mut rows = rows.into_iter().peekable();
    let Some((first, _)) = rows.peek() else {
        return Vec::new();
    };
    let mut header = field_names(first);
    header.extend(more.iter().cloned());
    csv_headed(header, rows)
}

/// A CSV table of `rows` (tuples or sequences of cells) under `header`.
pub fn csv_headed<H, R>(
    header: impl IntoIterator<Item = H>,
    rows: impl IntoIterator<Item = R>,
) -> Vec<u8>
where
    H: AsRef<[u8]>,
    R: Serialize,
{
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.write_record(header)
        .expect("writing to memory cannot fail");
    for row in rows {
        w.serialize(row).expect("rows serialize as CSV");
    }
    w.into_inner().expect("writing to memory cannot fail")
}

/// The header the `csv` crate writes for a struct: its field names as serialized.
fn field_names<T: Serialize>(sample: &T) -> Vec<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.serialize(sample).expect("rows serialize as CSV");
    let text = w.into_inner().expect("writing to memory cannot fail");
    let mut r = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(&text[..]);
    let mut header = csv::StringRecord::new();
    r.read_record(&mut header).expect("a header was written");
    header.iter().map(String::from).collect()
}

/// Writes the CSV table of `rows` to `path` atomically.
pub fn write_csv<T: Serialize>(path: &Path, rows: impl IntoIterator<Item = T>) -> Result<()> {
    write_atomic(path, csv(rows))
}

/// How numbers appear in a CSV cell, for `#[serde(serialize_with =
/// "output::cell::fixed::<6, _>")]` and the like: the `csv` crate would
/// write `4.0` for 4 and its own shortest form otherwise, while the tables
/// have always used Rust's formatting.
pub mod cell {
    use serde::{Serialize, Serializer};
    use std::fmt::Display;

    /// A value written as Rust's `{}` where no field attribute can go (the
    /// varying cells of [`super::csv_with_more`]).
    pub struct Shown<T>(pub T);

    impl<T: Display> Serialize for Shown<T> {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            s.collect_str(&self.0)
        }
    }

    /// Rust's `{}`: `4` for 4.0, the shortest round-trip digits otherwise.
    pub fn display<T: Display, S: Serializer>(v: &T, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(v)
    }

    /// [`display`], an empty cell for `None`.
    pub fn display_opt<T: Display, S: Serializer>(v: &Option<T>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(v) => s.collect_str(v),
            None => s.serialize_none(),
        }
    }

    /// `P` digits after the point.
    pub fn fixed<const P: usize, S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(&format_args!("{v:.P$}"))
    }

    /// [`fixed`], an empty cell for `None`.
    pub fn fixed_opt<const P: usize, S: Serializer>(
        v: &Option<f64>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        match v {
            Some(v) => fixed::<P, S>(v, s),
            None => s.serialize_none(),
        }
    }

    /// Scientific notation with `P` digits after the point (`1.2526e13`).
    pub fn sci<const P: usize, S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(&format_args!("{v:.P$e}"))
    }

    /// Shortest scientific notation (`1e-1`), an empty cell for `None`.
    pub fn sci_opt<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(v) => s.collect_str(&format_args!("{v:e}")),
            None => s.serialize_none(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rgc-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_leaves_no_temporary() {
        let dir = scratch("atomic");
        let path = dir.join("table.csv");
        write_atomic(&path, "old\n").unwrap();
        let err = replace_with(&path, |tmp| {
            std::fs::write(tmp, "half a li").unwrap();
            Err(Error::io(tmp, std::io::Error::other("disk full")))
        })
        .unwrap_err();
        assert!(err.to_string().contains("disk full"), "{err}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old\n");
        assert_eq!(names(&dir), ["table.csv"]);
        write_atomic(&path, "new\n").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new\n");
        assert_eq!(names(&dir), ["table.csv"]);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn the_temporary_keeps_the_extension() {
        let tmp = temporary_beside(Path::new("out/chart.png"));
        assert_eq!(tmp.parent(), Some(Path::new("out")));
        assert_eq!(tmp.extension().unwrap(), "png");
        assert_ne!(tmp, temporary_beside(Path::new("out/chart.png")));
    }

    #[test]
    fn unwritable_outputs_are_found_before_the_work() {
        let dir = scratch("check");
        check_file(&dir.join("new/deeper/table.csv")).unwrap();
        assert!(dir.join("new/deeper").is_dir());
        check_dir(&dir.join("fresh")).unwrap();
        assert_eq!(names(&dir.join("fresh")), Vec::<String>::new());
        // A directory where a file should go, and a file where a directory should.
        let err = check_file(&dir.join("new")).unwrap_err().to_string();
        assert!(err.contains("is a directory"), "{err}");
        std::fs::write(dir.join("plain"), "").unwrap();
        let err = check_file(&dir.join("plain/table.csv")).unwrap_err();
        assert!(
            matches!(&err, Error::Io { path, .. } if path.ends_with("plain")),
            "{err}"
        );
        let err = check_dir(&dir.join("plain")).unwrap_err().to_string();
        assert!(err.ends_with("plain: is a file, not a directory"), "{err}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_is_written_through_and_stays_a_link() {
        let dir = scratch("link");
        std::fs::create_dir_all(dir.join("data")).unwrap();
        let real = dir.join("data/table.csv");
        std::fs::write(&real, "old\n").unwrap();
        // A relative link, and a link to that link.
        let link = dir.join("link.csv");
        std::os::unix::fs::symlink("data/table.csv", &link).unwrap();
        let chain = dir.join("chain.csv");
        std::os::unix::fs::symlink(&link, &chain).unwrap();
        write_atomic(&chain, "new\n").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
        assert!(std::fs::symlink_metadata(&chain).unwrap().is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new\n");
        assert_eq!(names(&dir.join("data")), ["table.csv"], "no temporary left");
        // A dangling link: the write makes its target.
        let dangling = dir.join("dangling.csv");
        std::os::unix::fs::symlink("data/fresh.csv", &dangling).unwrap();
        write_atomic(&dangling, "made\n").unwrap();
        assert!(std::fs::symlink_metadata(&dangling).unwrap().is_symlink());
        assert_eq!(
            std::fs::read_to_string(dir.join("data/fresh.csv")).unwrap(),
            "made\n"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn two_outputs_are_one_file_however_they_are_spelt() {
        let dir = scratch("same");
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let a = dir.join("a.csv");
        let refused = |x: &Path, y: &Path| {
            let err = check_outputs(&[("--one", x), ("--two", y)])
                .unwrap_err()
                .to_string();
            assert!(err.contains("--one and --two both write"), "{err}");
            assert!(err.contains("one file"), "{err}");
        };
        // Not yet made: spelt with ./ and with ../ from another folder.
        refused(&a, &dir.join("./a.csv"));
        refused(&a, &dir.join("sub/../a.csv"));
        // A symbolic link to it, made or not.
        let link = dir.join("link.csv");
        std::os::unix::fs::symlink("a.csv", &link).unwrap();
        refused(&a, &link);
        std::fs::write(&a, "").unwrap();
        refused(&link, &a);
        // A hard link.
        let hard = dir.join("sub/hard.csv");
        std::fs::hard_link(&a, &hard).unwrap();
        refused(&a, &hard);
        // Different files pass, in a folder made for them.
        check_outputs(&[
            ("--one", &a),
            ("--two", &dir.join("sub/b.csv")),
            ("--three", &dir.join("new/a.csv")),
        ])
        .unwrap();
        assert!(dir.join("new").is_dir());
        // The same spelling twice says it once.
        let err = check_outputs(&[("--one", &a), ("--two", &a)])
            .unwrap_err()
            .to_string();
        assert!(
            err.ends_with(&format!(
                "both write {}, one file: one would overwrite the other",
                a.display()
            )),
            "{err}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[derive(Serialize)]
    struct Row {
        name: String,
        #[serde(serialize_with = "cell::display")]
        x: f64,
        #[serde(serialize_with = "cell::fixed_opt::<2, _>")]
        y: Option<f64>,
        #[serde(serialize_with = "cell::sci::<1, _>")]
        z: f64,
    }

    #[test]
    fn csv_quotes_what_needs_it_and_formats_as_asked() {
        let rows = [
            Row {
                name: "results/g23, \"rigid\"".into(),
                x: 4.0,
                y: Some(0.125),
                z: 12345.0,
            },
            Row {
                name: "plain".into(),
                x: 0.1,
                y: None,
                z: 0.0,
            },
        ];
        let rows = || {
            rows.iter().map(|r| Row {
                name: r.name.clone(),
                ..*r
            })
        };
        assert_eq!(
            String::from_utf8(csv(rows())).unwrap(),
            "name,x,y,z\n\"results/g23, \"\"rigid\"\"\",4,0.12,1.2e4\nplain,0.1,,0.0e0\n"
        );
        let more = ["a".to_string(), "b".to_string()];
        let text = csv_with_more(
            &more,
            rows().map(|r| {
                let cells = [cell::Shown(r.x), cell::Shown(2.0 * r.x)];
                (r, cells)
            }),
        );
        assert_eq!(
            String::from_utf8(text).unwrap(),
            "name,x,y,z,a,b\n\"results/g23, \"\"rigid\"\"\",4,0.12,1.2e4,4,8\nplain,0.1,,0.0e0,0.1,0.2\n"
        );
    }
}

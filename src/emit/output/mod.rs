//! Writing a set of files into an output directory without ever touching a file sinedec did
//! not write (the rule is documented in README.md, "Output directory").
//!
//! A manifest, [`MANIFEST`] in the directory, lists every file sinedec wrote there, one per
//! line as `<command> <file name>` (`generate sd_core.v`). For `-o DIR`:
//!
//! - DIR does not exist: it is created (with its parents) and filled.
//! - DIR is empty: it is filled.
//! - DIR has a manifest: a file the new set would overwrite must be listed in it, else
//!   nothing is written; the listed files are replaced, the files the same command listed
//!   before and no longer produces are removed, every other file stays.
//! - DIR is not empty and has no manifest: refused unless `force`; with `force` the files are
//!   added next to the ones there, and a name that exists already is refused (sinedec never
//!   overwrites a file it did not write).
//! - DIR exists and is not a directory: refused.
//!
//! One sinedec writes DIR at a time: the write holds `flock` on DIR itself (no lock file is
//! left), and a second writer meanwhile is refused with "another sinedec is writing DIR"
//! ([`check_output_dir`] probes the lock too). A single file the user names is written
//! through [`PendingFile`] (`user_file.rs`). Every temporary file and every directory this
//! module creates is entered in [`crate::cleanup`], so SIGINT, SIGTERM or SIGHUP removes it.
//!
//! Every check runs before the first byte is written. The new files are written to unique
//! temporary names (`.sinedec-XXXXXX.tmp`, the `tempfile` crate) in DIR, synced, and only when
//! all of them are complete renamed over their targets, one rename per file: each target is
//! at every moment either its complete old or its complete new version. The manifest is
//! widened to the union of the old and new names before the first rename and narrowed after
//! the last, so an interruption leaves no sinedec file outside it. On an error the temporary
//! files are deleted (their destructor), and directories this call created are removed when
//! still empty.
use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

mod user_file;

pub use user_file::{check_target, same_file, PendingFile};

/// Name of the manifest file inside an output directory.
pub const MANIFEST: &str = ".sinedec-manifest";

/// Which command writes, and whether a foreign non-empty directory may be used.
#[derive(Clone, Debug)]
pub struct OutputOptions {
    /// The command writing the files (`generate`, `report`): a command removes only the
    /// stale files it wrote itself, so two commands can share a directory.
    pub command: String,
    /// Add the files to a non-empty directory that has no manifest (never overwriting).
    pub force: bool,
    /// Tests only: fail with an injected error once this many temporary files are written,
    /// before any rename (shows that the old files stay and the temporary files go).
    #[doc(hidden)]
    pub fail_after_temps: Option<usize>,
}

impl OutputOptions {
    /// Options for `command` without `--force`.
    pub fn new(command: &str) -> OutputOptions {
        OutputOptions {
            command: command.to_string(),
            force: false,
            fail_after_temps: None,
        }
    }
}

/// What an output directory holds before writing.
#[derive(Debug)]
enum State {
    /// It does not exist.
    Missing,
    /// It exists and is empty.
    Empty,
    /// It has a manifest: (command, file name) per line.
    Managed(Vec<(String, String)>),
    /// It is not empty, has no manifest, and `force` was given.
    Foreign,
}

fn refuse(path: &Path, message: impl Into<String>) -> Error {
    Error::Refused {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// A plain file name: no separator, not `.`/`..`, not empty, no NUL, not the manifest, at
/// most 255 bytes (the usual file-name limit).
fn plain_name(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= 255
        && name != "."
        && name != ".."
        && name != MANIFEST
        && !name.contains(['/', '\\', '\0'])
}

fn read_manifest(dir: &Path) -> Result<Option<Vec<(String, String)>>> {
    let path = dir.join(MANIFEST);
    match std::fs::symlink_metadata(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(Error::io(&path, e)),
        Ok(m) if !m.is_file() => {
            return Err(refuse(
                &path,
                "is not a regular file; sinedec writes its manifest as one",
            ))
        }
        Ok(_) => {}
    }
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let mut entries = vec![];
    for (i, line) in text.lines().enumerate() {
        let line = line.trim_end();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let entry = line.split_once(' ').filter(|(c, n)| {
            !c.is_empty() && c.chars().all(|c| c.is_ascii_lowercase()) && plain_name(n)
        });
        match entry {
            Some((c, n)) => entries.push((c.to_string(), n.to_string())),
            None => {
                return Err(refuse(
                    &path,
                    format!(
                        "line {}: not `<command> <file name>`; sinedec trusts this file to \
                         know which files it may replace, so it writes nothing until the line \
                         is fixed or removed",
                        i + 1
                    ),
                ))
            }
        }
    }
    Ok(Some(entries))
}

fn inspect(dir: &Path, opts: &OutputOptions) -> Result<State> {
    if dir.as_os_str().is_empty() {
        return Err(refuse(dir, "the output directory is an empty path"));
    }
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(State::Missing),
        Err(e) => Err(Error::io(dir, e)),
        Ok(m) if !m.is_dir() => Err(refuse(
            dir,
            "exists and is not a directory; the output is a directory of files: choose a new \
             or empty directory",
        )),
        Ok(_) => {
            if let Some(entries) = read_manifest(dir)? {
                return Ok(State::Managed(entries));
            }
            let mut it = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
            if it.next().is_none() {
                Ok(State::Empty)
            } else if opts.force {
                Ok(State::Foreign)
            } else {
                Err(refuse(
                    dir,
                    format!(
                        "the directory is not empty and has no {MANIFEST}, so sinedec did not \
                         write it; nothing was written. Choose a new or empty directory, or \
                         pass --force to add sinedec's files next to the ones there (an \
                         existing file is never overwritten)"
                    ),
                ))
            }
        }
    }
}

/// Checks, without writing, that `dir` can take a command's output under the rule above
/// (run it before a long computation). Name clashes are checked when writing.
pub fn check_output_dir(dir: &Path, opts: &OutputOptions) -> Result<()> {
    if dir.is_dir() {
        drop(lock_dir(dir)?);
    }
    inspect(dir, opts).map(|_| ())
}

/// Takes the output directory's lock (`flock` on the directory itself, so no lock file is
/// left behind): one sinedec writes a directory at a time, and the other one is told so.
/// A file system without locks is written unlocked.
fn lock_dir(dir: &Path) -> Result<Option<std::fs::File>> {
    let f = match std::fs::File::open(dir) {
        Ok(f) => f,
        Err(_) => return Ok(None),
    };
    match f.try_lock() {
        Ok(()) => Ok(Some(f)),
        Err(std::fs::TryLockError::WouldBlock) => Err(refuse(
            dir,
            format!(
                "another sinedec is writing {} now; nothing was written. Wait until it \
                 finishes, or choose another directory",
                dir.display()
            ),
        )),
        Err(std::fs::TryLockError::Error(_)) => Ok(None),
    }
}

/// The manifest text for `entries`.
fn manifest_text(entries: &[(String, String)]) -> String {
    let mut s = String::from(
        "# sinedec output manifest: the files sinedec wrote in this directory, one per line as\n\
         # \"<command> <file name>\". sinedec replaces or removes only the files listed here.\n",
    );
    for (c, n) in entries {
        s.push_str(&format!("{c} {n}\n"));
    }
    s
}

/// A temporary file of sinedec's beside its target, entered in [`crate::cleanup`] while
/// it exists (a signal removes it).
#[derive(Debug)]
struct Temp {
    file: tempfile::NamedTempFile,
    // After `file`: the file is deleted before its entry goes.
    _entry: crate::cleanup::Entry,
}

impl Temp {
    /// An empty temporary file in `dir` (`.sinedec-XXXXXX.tmp`).
    fn new(dir: &Path) -> Result<Temp> {
        let mut b = tempfile::Builder::new();
        b.prefix(".sinedec-").suffix(".tmp");
        #[cfg(unix)]
        {
            // The permissions `std::fs::write` gives (0666 less the umask), not tempfile's 0600.
            use std::os::unix::fs::PermissionsExt;
            b.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let (file, _entry) = crate::cleanup::create_file(
            || b.tempfile_in(dir),
            |t: &tempfile::NamedTempFile| t.path().to_path_buf(),
        )
        .map_err(|e| Error::io(dir, e))?;
        Ok(Temp { file, _entry })
    }

    /// Renames the file onto `path` (replacing a file there unless `noclobber`).
    fn persist(self, path: &Path, noclobber: bool) -> std::result::Result<(), std::io::Error> {
        let Temp { file, _entry } = self;
        let r = if noclobber {
            file.persist_noclobber(path)
        } else {
            file.persist(path)
        };
        r.map(|_| ()).map_err(|e| e.error)
    }
}

/// A complete temporary file in `dir` holding `bytes` (synced), not yet at its name.
/// Errors name `target`, the file the user will see.
fn temp_with(dir: &Path, target: &Path, bytes: &[u8]) -> Result<Temp> {
    let mut t = Temp::new(dir)?;
    t.file.write_all(bytes).map_err(|e| Error::io(target, e))?;
    t.file
        .as_file()
        .sync_all()
        .map_err(|e| Error::io(target, e))?;
    Ok(t)
}

fn write_manifest(dir: &Path, entries: &[(String, String)]) -> Result<()> {
    let path = dir.join(MANIFEST);
    let t = temp_with(dir, &path, manifest_text(entries).as_bytes())?;
    t.persist(&path, false).map_err(|e| Error::io(&path, e))?;
    Ok(())
}

/// Creates `dir` and its missing parents; returns the directories created, outermost first,
/// each entered in [`crate::cleanup`] (a signal removes it while empty) until the entries
/// are dropped.
fn create_dirs(dir: &Path) -> Result<(Vec<PathBuf>, Vec<crate::cleanup::Entry>)> {
    let mut missing = vec![];
    let mut p = Some(dir);
    while let Some(d) = p {
        if d.as_os_str().is_empty() || d.exists() {
            break;
        }
        missing.push(d.to_path_buf());
        p = d.parent();
    }
    missing.reverse();
    let mut created = vec![];
    let mut entries = vec![];
    for d in missing {
        let entry = crate::cleanup::created_dir(&d);
        match std::fs::create_dir(&d) {
            Ok(()) => {
                created.push(d);
                entries.push(entry);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && d.is_dir() => {}
            Err(e) => {
                remove_created(&created);
                return Err(Error::io(&d, e));
            }
        }
    }
    Ok((created, entries))
}

/// Removes directories this call created (innermost first), each only while empty.
fn remove_created(created: &[PathBuf]) {
    for d in created.iter().rev() {
        let _ = std::fs::remove_dir(d);
    }
}

/// Writes `files` (name, contents) into `dir` under the rule in the module documentation.
pub fn write_files(dir: &Path, files: &[(&str, &[u8])], opts: &OutputOptions) -> Result<()> {
    if let Some((n, _)) = files.iter().find(|(n, _)| !plain_name(n)) {
        return Err(Error::Export(format!(
            "output file name {} is not a plain file name",
            crate::error::Quoted(&crate::error::clip(n, 80))
        )));
    }
    // A missing directory is created first, so that it can be locked before it is looked at.
    let (created, _created_entries) = if dir.as_os_str().is_empty() || dir.exists() {
        (vec![], vec![])
    } else {
        inspect(dir, opts)?;
        create_dirs(dir)?
    };
    // Held until the last rename; on a refusal here the created directories stay (the
    // other sinedec writes into them).
    let _lock = lock_dir(dir)?;
    let state = match inspect(dir, opts) {
        Ok(s) => s,
        Err(e) => {
            remove_created(&created);
            return Err(e);
        }
    };
    let previous = match &state {
        State::Managed(e) => e.clone(),
        _ => vec![],
    };
    // Every clash is found before anything is written.
    if !matches!(state, State::Missing) {
        for (name, _) in files {
            let path = dir.join(name);
            match std::fs::symlink_metadata(&path) {
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => return Err(Error::io(&path, e)),
                Ok(m) => {
                    let listed = previous.iter().any(|(_, n)| n == name);
                    if !listed {
                        return Err(refuse(
                            &path,
                            format!(
                                "exists and sinedec did not write it (it is not in {MANIFEST}); \
                                 nothing was written. Move it away or choose another output \
                                 directory"
                            ),
                        ));
                    }
                    if !m.is_file() {
                        return Err(refuse(
                            &path,
                            "is listed in the manifest but is no longer a regular file; \
                             nothing was written. Move it away or choose another output \
                             directory",
                        ));
                    }
                }
            }
        }
    }
    let result = (|| {
        // 1. Every new file complete under a temporary name.
        let mut temps = Vec::with_capacity(files.len());
        for (name, bytes) in files {
            if opts.fail_after_temps == Some(temps.len()) {
                return Err(Error::Export("injected failure (test)".into()));
            }
            temps.push((*name, temp_with(dir, &dir.join(name), bytes)?));
        }
        crate::cleanup::test_pause("output-temps");
        // 2. The manifest covers the old and the new files.
        let mut union = previous.clone();
        for (name, _) in files {
            let e = (opts.command.clone(), name.to_string());
            if !union.contains(&e) {
                union.push(e);
            }
        }
        write_manifest(dir, &union)?;
        Ok::<_, Error>(temps)
    })();
    let temps = match result {
        Ok(t) => t,
        Err(e) => {
            remove_created(&created);
            return Err(e);
        }
    };
    // 3. One rename per file.
    for (name, t) in temps {
        let path = dir.join(name);
        t.persist(&path, false).map_err(|e| Error::io(&path, e))?;
    }
    // 4. Files this command wrote before and no longer produces go; the manifest narrows.
    let mut kept = vec![];
    for (c, n) in previous {
        let produced = files.iter().any(|(name, _)| *name == n);
        let path = dir.join(&n);
        if c == opts.command && !produced {
            match std::fs::symlink_metadata(&path) {
                Ok(m) if m.is_file() => {
                    std::fs::remove_file(&path).map_err(|e| Error::io(&path, e))?
                }
                _ => {}
            }
        } else if !produced && path.exists() {
            kept.push((c, n));
        }
    }
    kept.extend(
        files
            .iter()
            .map(|(n, _)| (opts.command.clone(), n.to_string())),
    );
    write_manifest(dir, &kept)
}

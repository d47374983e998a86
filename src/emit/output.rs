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
    inspect(dir, opts).map(|_| ())
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

/// A complete temporary file in `dir` holding `bytes` (synced), not yet at its name.
fn temp_with(dir: &Path, bytes: &[u8]) -> Result<tempfile::NamedTempFile> {
    let mut b = tempfile::Builder::new();
    b.prefix(".sinedec-").suffix(".tmp");
    #[cfg(unix)]
    {
        // The permissions `std::fs::write` gives (0666 less the umask), not tempfile's 0600.
        use std::os::unix::fs::PermissionsExt;
        b.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut t = b.tempfile_in(dir).map_err(|e| Error::io(dir, e))?;
    let path = t.path().to_path_buf();
    t.write_all(bytes).map_err(|e| Error::io(&path, e))?;
    t.as_file().sync_all().map_err(|e| Error::io(&path, e))?;
    Ok(t)
}

fn write_manifest(dir: &Path, entries: &[(String, String)]) -> Result<()> {
    let t = temp_with(dir, manifest_text(entries).as_bytes())?;
    let path = dir.join(MANIFEST);
    t.persist(&path).map_err(|e| Error::io(&path, e.error))?;
    Ok(())
}

/// Creates `dir` and its missing parents; returns the directories created, outermost first.
fn create_dirs(dir: &Path) -> Result<Vec<PathBuf>> {
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
    for d in missing {
        match std::fs::create_dir(&d) {
            Ok(()) => created.push(d),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && d.is_dir() => {}
            Err(e) => {
                remove_created(&created);
                return Err(Error::io(&d, e));
            }
        }
    }
    Ok(created)
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
    let state = inspect(dir, opts)?;
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
    let created = match state {
        State::Missing => create_dirs(dir)?,
        _ => vec![],
    };
    let result = (|| {
        // 1. Every new file complete under a temporary name.
        let mut temps = Vec::with_capacity(files.len());
        for (name, bytes) in files {
            if opts.fail_after_temps == Some(temps.len()) {
                return Err(Error::Export("injected failure (test)".into()));
            }
            temps.push((*name, temp_with(dir, bytes)?));
        }
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
        t.persist(&path).map_err(|e| Error::io(&path, e.error))?;
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

/// One file the user named (`init PATH`, `simulate --csv F`), checked and opened under a
/// unique temporary name beside it before the work that fills it: the temporary file is
/// deleted if the program stops with an error first, and [`PendingFile::commit`] renames it
/// onto the path in one step.
#[derive(Debug)]
pub struct PendingFile {
    path: PathBuf,
    temp: tempfile::NamedTempFile,
}

impl PendingFile {
    /// Checks that `path` can be written (not a directory, its directory exists) and opens
    /// the temporary file.
    pub fn new(path: &Path) -> Result<PendingFile> {
        if path.as_os_str().is_empty() {
            return Err(refuse(path, "an empty path"));
        }
        if path.is_dir() {
            return Err(refuse(
                path,
                "is a directory; give the path of the file to write",
            ));
        }
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if !parent.is_dir() {
            return Err(refuse(
                path,
                format!("the directory {} does not exist", parent.display()),
            ));
        }
        let temp = temp_with(&parent, b"")?;
        Ok(PendingFile {
            path: path.to_path_buf(),
            temp,
        })
    }

    /// The open temporary file, for streaming writes.
    pub fn file(&mut self) -> &mut std::fs::File {
        self.temp.as_file_mut()
    }

    /// Appends `bytes`.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<()> {
        let p = self.temp.path().to_path_buf();
        self.temp.write_all(bytes).map_err(|e| Error::io(p, e))
    }

    fn sync(&mut self) -> Result<()> {
        let p = self.temp.path().to_path_buf();
        self.temp
            .flush()
            .and_then(|_| self.temp.as_file().sync_all())
            .map_err(|e| Error::io(p, e))
    }

    /// Renames the complete file onto its path, replacing a file there; returns the path.
    pub fn commit(mut self) -> Result<PathBuf> {
        self.sync()?;
        self.temp
            .persist(&self.path)
            .map_err(|e| Error::io(&self.path, e.error))?;
        Ok(self.path)
    }

    /// As [`PendingFile::commit`], but refuses (and deletes the temporary file) when the path
    /// exists by then.
    pub fn commit_new(mut self) -> Result<PathBuf> {
        self.sync()?;
        self.temp.persist_noclobber(&self.path).map_err(|e| {
            if e.error.kind() == std::io::ErrorKind::AlreadyExists {
                refuse(&self.path, "exists; pass --force to overwrite it")
            } else {
                Error::io(&self.path, e.error)
            }
        })?;
        Ok(self.path)
    }
}

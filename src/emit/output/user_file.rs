//! A single file the user names (`init PATH`, `simulate --csv/--vcd PATH`, [`PendingFile`]):
//! it must be absent or a regular file; a device, FIFO, socket, link or directory at PATH is
//! refused and left as it is ([`check_target`]).

use super::*;

/// What a path that exists and is not a regular file is, in words, or None for a regular
/// file.
fn special_kind(m: &std::fs::Metadata) -> Option<&'static str> {
    let t = m.file_type();
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a directory");
    }
    if t.is_symlink() {
        return Some("a symbolic link");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO (named pipe)");
        }
        if t.is_socket() {
            return Some("a socket");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
    }
    Some("not a regular file")
}

/// Checks that `path`, a file the user named for sinedec to write, is absent or a regular
/// file: sinedec never replaces a device, a FIFO, a socket, a link or a directory.
pub fn check_target(path: &Path) -> Result<()> {
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::io(path, e)),
        Ok(m) if m.is_dir() => Err(refuse(
            path,
            "is a directory; give the path of the file to write",
        )),
        Ok(m) => match special_kind(&m) {
            None => Ok(()),
            Some(kind) => Err(refuse(
                path,
                format!(
                    "is {kind}; sinedec writes only regular files and never replaces anything                      else: give the path of a new or regular file"
                ),
            )),
        },
    }
}

/// Whether `a` and `b` name the same file: the same device and inode when both exist, else
/// the same absolute path (symbolic links in the directories resolved).
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    fn absolute(p: &Path) -> Option<PathBuf> {
        let parent = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        Some(std::fs::canonicalize(parent).ok()?.join(p.file_name()?))
    }
    match (absolute(a), absolute(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// One file the user named (`init PATH`, `simulate --csv F`), checked and opened under a
/// unique temporary name beside it before the work that fills it: the temporary file is
/// deleted if the program stops with an error or a signal first, and
/// [`PendingFile::commit`] renames it onto the path in one step. The path must be absent or
/// a regular file ([`check_target`]).
#[derive(Debug)]
pub struct PendingFile {
    path: PathBuf,
    temp: Temp,
}

impl PendingFile {
    /// Checks that `path` can be written (absent or a regular file, its directory exists)
    /// and opens the temporary file.
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
            let why = if parent.exists() {
                format!("{} is not a directory", parent.display())
            } else {
                format!("the directory {} does not exist", parent.display())
            };
            return Err(refuse(path, why));
        }
        check_target(path)?;
        let temp = temp_with(&parent, path, b"")?;
        Ok(PendingFile {
            path: path.to_path_buf(),
            temp,
        })
    }

    /// The path the file will have.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The open temporary file, for streaming writes.
    pub fn file(&mut self) -> &mut std::fs::File {
        self.temp.file.as_file_mut()
    }

    /// Appends `bytes`.
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<()> {
        self.temp
            .file
            .write_all(bytes)
            .map_err(|e| Error::io(&self.path, e))
    }

    fn sync(&mut self) -> Result<()> {
        self.temp
            .file
            .flush()
            .and_then(|_| self.temp.file.as_file().sync_all())
            .map_err(|e| Error::io(&self.path, e))
    }

    /// Renames the complete file onto its path, replacing a regular file there; returns the
    /// path.
    pub fn commit(mut self) -> Result<PathBuf> {
        self.sync()?;
        check_target(&self.path)?;
        self.temp
            .persist(&self.path, false)
            .map_err(|e| Error::io(&self.path, e))?;
        Ok(self.path)
    }

    /// As [`PendingFile::commit`], but refuses (and deletes the temporary file) when the path
    /// exists by then.
    pub fn commit_new(mut self) -> Result<PathBuf> {
        self.sync()?;
        check_target(&self.path)?;
        self.temp.persist(&self.path, true).map_err(|e| {
            if e.kind() == std::io::ErrorKind::AlreadyExists {
                refuse(&self.path, "exists; pass --force to overwrite it")
            } else {
                Error::io(&self.path, e)
            }
        })?;
        Ok(self.path)
    }
}

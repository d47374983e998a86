//! What a stop by SIGINT, SIGTERM or SIGHUP leaves behind: nothing. Every temporary file or
//! directory sinedec makes and every child process it starts (Yosys, nextpnr, rustc, Icarus,
//! Verilator) is entered here while it exists; [`install`] (called by the command line)
//! starts a thread that, on one of those signals, kills each child's process group, removes
//! the entries (newest first), and exits with 128 + the signal's number (130, 143, 129), as
//! a shell reports a program the signal ended. SIGKILL cannot be caught: it is the one stop
//! that can leave a temporary file or a child behind (README.md, "Output directory").
//!
//! ```text
//!  create / spawn ──(registry lock held)──► entry ──► work ──► drop: entry removed
//!                                             │
//!  SIGINT/TERM/HUP ──► handler thread ──(registry lock)──► kill groups, remove entries, exit
//! ```
//!
//! The registry lock is held while a temporary is created or a child spawned ([`create`],
//! [`spawn`]), so the handler never runs between the creation and the entry: whatever
//! exists is entered. Children run in their own process group (the terminal's Ctrl-C does
//! not reach them; the handler does, with every grandchild, such as Yosys's ABC).
use std::io;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::sync::Mutex;

/// One thing to undo on a signal.
#[derive(Debug)]
enum Item {
    /// A temporary file sinedec created (removed).
    File(PathBuf),
    /// A temporary directory sinedec created under a unique name (removed with its content).
    TempDir(PathBuf),
    /// A directory an output command created (removed only while empty).
    CreatedDir(PathBuf),
    /// A child process leading its own process group (the group is killed).
    Group(u32),
}

struct Registry {
    next: u64,
    items: Vec<(u64, Item)>,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    next: 0,
    items: Vec::new(),
});

fn registry() -> std::sync::MutexGuard<'static, Registry> {
    // A panic while holding the lock leaves a consistent list (each change is one push or
    // one removal), so a poisoned lock is used as it is.
    REGISTRY.lock().unwrap_or_else(|p| p.into_inner())
}

impl Registry {
    fn add(&mut self, item: Item) -> Entry {
        let id = self.next;
        self.next += 1;
        self.items.push((id, item));
        Entry(id)
    }
}

/// An entry of the registry; dropping it takes the entry out (the thing it names is then
/// gone or kept on purpose). Keep it in a struct after the value it guards, so the value's
/// own clean-up (a temporary file's deletion) runs first.
#[derive(Debug)]
#[must_use = "the entry is removed from the registry when dropped"]
pub struct Entry(u64);

impl Drop for Entry {
    fn drop(&mut self) {
        registry().items.retain(|(id, _)| *id != self.0);
    }
}

/// Creates a temporary file with `make` under the registry lock and enters the path
/// `path_of` gives.
pub fn create_file<T>(
    make: impl FnOnce() -> io::Result<T>,
    path_of: impl FnOnce(&T) -> PathBuf,
) -> io::Result<(T, Entry)> {
    let mut r = registry();
    let v = make()?;
    let e = r.add(Item::File(path_of(&v)));
    Ok((v, e))
}

/// As [`create_file`] for a temporary directory (removed with its content on a signal).
pub fn create_dir<T>(
    make: impl FnOnce() -> io::Result<T>,
    path_of: impl FnOnce(&T) -> PathBuf,
) -> io::Result<(T, Entry)> {
    let mut r = registry();
    let v = make()?;
    let e = r.add(Item::TempDir(path_of(&v)));
    Ok((v, e))
}

/// Enters a temporary file of a unique name sinedec is about to create.
pub fn temp_file(path: &Path) -> Entry {
    registry().add(Item::File(path.to_path_buf()))
}

/// Enters a temporary directory of a unique name sinedec is about to create.
pub fn temp_dir(path: &Path) -> Entry {
    registry().add(Item::TempDir(path.to_path_buf()))
}

/// Enters a directory an output command created; on a signal it goes when empty.
pub fn created_dir(path: &Path) -> Entry {
    registry().add(Item::CreatedDir(path.to_path_buf()))
}

/// Starts `cmd` as the leader of a new process group and enters the group: on a signal the
/// child and everything it started are killed.
pub fn spawn(cmd: &mut Command) -> io::Result<(Child, Entry)> {
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        cmd.process_group(0);
    }
    let mut r = registry();
    let child = cmd.spawn()?;
    let e = r.add(Item::Group(child.id()));
    Ok((child, e))
}

/// `cmd.output()` through [`spawn`] (stdin closed, stdout and stderr captured).
pub fn output(cmd: &mut Command) -> io::Result<std::process::Output> {
    use std::process::Stdio;
    cmd.stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let (child, entry) = spawn(cmd)?;
    let out = child.wait_with_output();
    drop(entry);
    out
}

/// Kills every entered child group and removes every entered temporary, newest first.
fn undo(items: &[(u64, Item)]) {
    for (_, item) in items.iter().rev() {
        if let Item::Group(pid) = item {
            kill_group(*pid);
        }
    }
    for (_, item) in items.iter().rev() {
        match item {
            Item::File(p) => {
                // Only a regular file (or a link) is removed: never a device or a FIFO.
                if std::fs::symlink_metadata(p).is_ok_and(|m| m.is_file()) {
                    let _ = std::fs::remove_file(p);
                }
            }
            Item::TempDir(p) => {
                let _ = std::fs::remove_dir_all(p);
            }
            Item::CreatedDir(p) => {
                let _ = std::fs::remove_dir(p);
            }
            Item::Group(_) => {}
        }
    }
}

#[cfg(unix)]
fn kill_group(pid: u32) {
    if let Ok(pid) = libc::pid_t::try_from(pid) {
        // SAFETY: kill(2) with a negative pid signals that process group; no memory involved.
        unsafe {
            libc::kill(-pid, libc::SIGKILL);
        }
    }
}

#[cfg(not(unix))]
fn kill_group(_pid: u32) {}

/// Tests only: when the environment variable `SINEDEC_TEST_PAUSE` equals `point`, says
/// `sinedec: paused at <point>` on stderr and waits there for a signal, so a test can stop
/// the program at a known moment (`output-temps`: every temporary file of an output
/// directory written, nothing renamed yet).
#[doc(hidden)]
pub fn test_pause(point: &str) {
    if std::env::var_os("SINEDEC_TEST_PAUSE").is_some_and(|v| v == point) {
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), "sinedec: paused at {point}");
        loop {
            std::thread::sleep(std::time::Duration::from_secs(1));
        }
    }
}

/// Exit status for a stop by signal `sig`: 128 + its number.
pub fn exit_status(sig: i32) -> i32 {
    128 + sig
}

/// Installs the handler of SIGINT, SIGTERM and SIGHUP (see the module documentation).
/// Called once, by the command line; the library works without it.
#[cfg(unix)]
pub fn install() -> io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::Builder::new()
        .name("sinedec-signals".into())
        .spawn(move || {
            if let Some(sig) = signals.forever().next() {
                // The lock stays held until the exit: nothing new is created meanwhile.
                let r = registry();
                undo(&r.items);
                std::process::exit(exit_status(sig));
            }
        })?;
    Ok(())
}

/// Without Unix signals there is nothing to install.
#[cfg(not(unix))]
pub fn install() -> io::Result<()> {
    Ok(())
}

//! The library's error type.

use std::path::PathBuf;

/// Everything that can go wrong in sinedec's library functions.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The TOML text does not parse or does not match the schema (unknown key, wrong type,
    /// value out of range); `line`/`column` are 1-based.
    #[error("{source_name}:{line}:{column}: {message}")]
    ConfigSyntax {
        /// File name (or `<default>` for the embedded config).
        source_name: String,
        /// 1-based line of the offending text.
        line: usize,
        /// 1-based column of the offending text.
        column: usize,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The config parses but a value or a combination of values is not supported.
    #[error("{source_name}:{location}key `{key}`: {message}")]
    ConfigValue {
        /// File name (or `<default>`).
        source_name: String,
        /// `line:column: ` of the key when it can be found in the text, else empty.
        location: String,
        /// Dotted key, e.g. `cordic.iterations`.
        key: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A command-line option of `simulate` or `report` is out of range or does not apply
    /// to the configuration; `option` is spelt as on the command line (`--angle-n`).
    #[error("`{option}` {message}")]
    InvalidOption {
        /// The option, e.g. `--noise-lsb`.
        option: String,
        /// The value given, what is wrong and what is allowed.
        message: String,
    },
    /// Reading or writing a file failed; the message is one plain sentence about the
    /// user's path ([`io_text`], or the part of the path that is not a directory), not the
    /// OS's text with its error number.
    #[error("{}: {detail}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What went wrong, in words.
        detail: String,
        /// The underlying error (kept out of the message).
        error: std::io::Error,
    },
    /// The temporary directory cannot be used.
    #[error("the temporary directory {} cannot be used ({reason}); set TMPDIR to a writable directory", path.display())]
    TempDir {
        /// The directory (`TMPDIR`, else `/tmp`).
        path: PathBuf,
        /// Why, in words.
        reason: String,
    },
    /// rust-hdl rejected the generated design (a connection or latch check failed).
    #[error("rust-hdl check of `{block}` failed: {message}")]
    HdlCheck {
        /// The block that failed.
        block: String,
        /// rust-hdl's description.
        message: String,
    },
    /// Internal consistency check of emitted Verilog (identifier clash, bad name).
    #[error("Verilog export: {0}")]
    Export(String),
    /// Serializing a JSON document failed (report, parameter file, cache entry).
    #[error("{what} JSON: {source}")]
    Json {
        /// Which document.
        what: String,
        /// serde_json's description.
        source: serde_json::Error,
    },
    /// Drawing an SVG plot failed.
    #[error("plot {what}: {message}")]
    Plot {
        /// Which plot.
        what: String,
        /// plotters' description.
        message: String,
    },
    /// The simulation could not be set up: a model rejected the configuration or the run
    /// does not apply to it.
    #[error("simulation: {0}")]
    Simulation(String),
    /// An external tool ran but its output lacks what sinedec reads from it (cell
    /// statistics, the longest path, a netlist it can analyse).
    #[error("{tool} output: {message}")]
    ToolOutput {
        /// The tool, e.g. `yosys`.
        tool: String,
        /// What is missing, and where.
        message: String,
    },
    /// A template of `rtl-templates/` failed to render (a bug in sinedec, not in the input).
    #[error("template {template}: {message}")]
    Template {
        /// The template's name, its path under `rtl-templates/`.
        template: String,
        /// minijinja's description.
        message: String,
    },
    /// An external tool (Yosys, Icarus, Verilator) is missing or failed.
    #[error(transparent)]
    Tool(#[from] crate::cosim::CosimError),
    /// sinedec refuses to write where it could lose a file it did not write (see
    /// `emit::output`); nothing was written.
    #[error("{}: {message}", path.display())]
    Refused {
        /// The directory or file concerned.
        path: PathBuf,
        /// Why, and the way out.
        message: String,
    },
    // Blocks' parameters, the board clock and the simulation models (one block, kept at
    // the end of the enum).
    /// A block's parameters are out of range or do not fit together (`adc`, `preamp`,
    /// `correction`, `monitor`, `nco`, `qep`, `biss`, `ssi`, `spi`, `parallel`, `top`): the
    /// block's constructor says why.
    #[error("{block}: {message}")]
    BlockParams {
        /// The block, as its config section is named.
        block: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The board's oscillator cannot make the system clock with the FPGA's clock
    /// synthesizer (DCM_SP, ALTPLL).
    #[error("{message}")]
    BoardClock {
        /// The ratio that was needed, the nearest one possible, and what to change.
        message: String,
    },
    /// A simulation model's parameters are out of range (the capacitive encoder).
    #[error("{model}: {message}")]
    ModelParams {
        /// The model, e.g. `capacitive encoder`.
        model: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// `sinedec datasheet` cannot characterize this config (the capacitive path).
    #[error("datasheet: {0}")]
    Datasheet(String),
}

/// `value` as echoed in a message: at most `max` characters; a longer value keeps its start
/// and end around `...(N characters left out)...`, so a 100,000-character input does not
/// flood the terminal.
pub fn clip(value: &str, max: usize) -> String {
    let n = value.chars().count();
    if n <= max {
        return value.to_string();
    }
    let head = max * 2 / 3;
    let tail = max.saturating_sub(head);
    let start: String = value.chars().take(head).collect();
    let end: String = value.chars().skip(n - tail).collect();
    format!(
        "{start}...({} characters left out)...{end}",
        n - head - tail
    )
}

/// A user's text shown in a message between double quotes, with `"`, `\` and control
/// characters escaped as in Rust string literals (`"a\tb"`), so a stray newline or quote in
/// the input cannot break the message's layout.
pub struct Quoted<'a>(pub &'a str);

impl std::fmt::Display for Quoted<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use std::fmt::Write as _;
        f.write_char('"')?;
        for c in self.0.chars() {
            match c {
                '"' | '\\' => write!(f, "\\{c}")?,
                c if c.is_control() => write!(f, "{}", c.escape_debug())?,
                c => f.write_char(c)?,
            }
        }
        f.write_char('"')
    }
}

/// When `e` at `path` comes from a part of the path that exists and is not a directory
/// (`-o notes.txt/out`, `init notes.txt/a.toml`): that part, in a sentence.
fn not_a_directory(path: &std::path::Path, e: &std::io::Error) -> Option<String> {
    use std::io::ErrorKind as K;
    if !matches!(e.kind(), K::NotADirectory | K::AlreadyExists | K::NotFound) {
        return None;
    }
    let is_file = |p: &std::path::Path| {
        !p.as_os_str().is_empty() && std::fs::symlink_metadata(p).is_ok() && !p.is_dir()
    };
    if e.kind() == K::AlreadyExists && is_file(path) {
        return Some("exists and is not a directory".into());
    }
    path.ancestors().skip(1).find(|a| is_file(a)).map(|a| {
        format!(
            "{} is a file, not a directory, so nothing can be created or found under it",
            a.display()
        )
    })
}

/// `e` in plain words, without the OS's error number or a temporary file's Debug-quoted
/// path (`tempfile` appends `at path "/x/.tmpAbCd"`): "permission denied", "the disk is
/// full", ...
pub fn io_text(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    let plain = match e.kind() {
        K::NotFound => "does not exist",
        K::PermissionDenied => "permission denied",
        K::AlreadyExists => "exists already",
        K::NotADirectory => "a part of the path is not a directory",
        K::IsADirectory => "is a directory",
        K::ReadOnlyFilesystem => "the file system is read-only",
        K::StorageFull => "the disk is full",
        K::QuotaExceeded => "the disk quota is exceeded",
        K::DirectoryNotEmpty => "the directory is not empty",
        K::InvalidFilename => "the file name is too long or not allowed",
        K::FileTooLarge => "the file is too large",
        K::CrossesDevices => "it would move a file across file systems",
        K::TooManyLinks => "too many links",
        K::Deadlock => "a file lock would deadlock",
        _ => "",
    };
    if !plain.is_empty() {
        return plain.to_string();
    }
    let t = e.to_string();
    let t = t.split(" at path ").next().unwrap_or(&t);
    let t = match t.find(" (os error ") {
        Some(i) => &t[..i],
        None => t,
    };
    let mut c = t.chars();
    match c.next() {
        Some(f) => f.to_lowercase().chain(c).collect(),
        None => "unknown error".into(),
    }
}

/// Shorthand result type.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// [`Error::InvalidOption`] for `option` (e.g. `--angle-n`).
    pub fn option(option: &str, message: impl Into<String>) -> Error {
        Error::InvalidOption {
            option: option.to_string(),
            message: message.into(),
        }
    }

    /// [`Error::BlockParams`] for `block`.
    pub fn block_params(block: &str, message: impl Into<String>) -> Error {
        Error::BlockParams {
            block: block.to_string(),
            message: message.into(),
        }
    }

    /// The message of a [`Error::BlockParams`] without the block's name, for an error that
    /// names the config key instead; any other error as displayed.
    pub fn detail(&self) -> String {
        match self {
            Error::BlockParams { message, .. } => message.clone(),
            e => e.to_string(),
        }
    }

    /// I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Error {
        let path = path.into();
        let detail = match not_a_directory(&path, &error) {
            Some(d) => d,
            None => io_text(&error),
        };
        Error::Io {
            path,
            detail,
            error,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Quoted;

    #[test]
    fn quoted_escapes_quotes_backslashes_and_control_characters() {
        assert_eq!(Quoted("sd").to_string(), "\"sd\"");
        assert_eq!(Quoted("a\"b\\c\nd\te").to_string(), r#""a\"b\\c\nd\te""#);
        // Other characters, a single quote and non-ASCII letters included, stay as they are.
        assert_eq!(Quoted("l'é").to_string(), "\"l'é\"");
    }
}

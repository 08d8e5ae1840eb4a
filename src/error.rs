//! Error types and their mapping to the exit codes of the CLI contract (DESIGN.md):
//! 2 bad input, 3 no usable adapter or a device error, 1 any other failure.

use std::fmt;

/// Bad input: names the file, the key (when there is one) and what is allowed.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    /// The file as the user named it or as it was resolved.
    pub file: String,
    /// Line and column (1-based) where known, e.g. for TOML syntax errors.
    pub location: Option<(usize, usize)>,
    /// Dotted key path, e.g. `sweep.metallic[2]`.
    pub key: Option<String>,
    pub message: String,
}

impl InputError {
    pub fn new(file: impl Into<String>, message: impl Into<String>) -> Self {
        Self { file: file.into(), location: None, key: None, message: message.into() }
    }

    pub fn at_key(file: impl Into<String>, key: impl Into<String>, message: impl Into<String>) -> Self {
        Self { file: file.into(), location: None, key: Some(key.into()), message: message.into() }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some((line, col)) = self.location {
            write!(f, ":{line}:{col}")?;
        }
        if let Some(key) = &self.key {
            write!(f, ": key `{key}`")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for InputError {}

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("bad input: {0}")]
    Input(#[from] InputError),
    #[error("no usable GPU adapter: {0}")]
    NoAdapter(String),
    #[error("GPU device error: {0}")]
    Device(String),
    #[error("{context}: {source}")]
    Io {
        context: String,
        #[source]
        source: std::io::Error,
    },
    /// Encoding or decoding a file format (EXR, PNG, JSON) failed; the library's error is kept.
    #[error("{what}: {source}")]
    Encode {
        what: String,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// A check ran and failed (thresholds, audit expectations): exit 1.
    #[error("check failed: {0}")]
    CheckFailed(String),
    #[error("{0}")]
    Other(String),
}

/// The CLI's exit codes (DESIGN.md).
pub mod exit {
    pub const OK: u8 = 0;
    /// A check failed (thresholds, audit expectations), or anything else went wrong.
    pub const FAILURE: u8 = 1;
    /// Bad input: the message names the file, the key, the value and what is allowed.
    pub const BAD_INPUT: u8 = 2;
    /// No usable adapter, or a device error.
    pub const DEVICE: u8 = 3;
}

impl Error {
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Input(_) => exit::BAD_INPUT,
            Error::NoAdapter(_) | Error::Device(_) => exit::DEVICE,
            Error::Io { .. } | Error::Other(_) | Error::CheckFailed(_) | Error::Encode { .. } => exit::FAILURE,
        }
    }

    /// An error of a library we call, with what we were doing.
    pub fn encode(what: impl Into<String>, source: impl std::error::Error + Send + Sync + 'static) -> Self {
        Error::Encode { what: what.into(), source: Box::new(source) }
    }

    pub fn io(context: impl Into<String>, source: std::io::Error) -> Self {
        Error::Io { context: context.into(), source }
    }

    pub fn io_path(action: &str, path: &std::path::Path, source: std::io::Error) -> Self {
        Error::io(format!("{action} {}", path.display()), source)
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Shown with every "no adapter" failure: how to get one on a machine without a GPU.
pub const ADAPTER_HELP: &str = "install a Vulkan driver; on a machine without a GPU install Mesa's lavapipe \
(Debian/Ubuntu: `apt-get install -y mesa-vulkan-drivers`). SHADEMATRIX_BACKEND (vulkan|gl) and \
SHADEMATRIX_ADAPTER (a substring of the adapter name) choose among adapters.";

//! The one way this tool reads a file: every input (matrices, scenes, user models, meshes, images,
//! skies), every record of a run folder and every cache entry goes through `read` here, and a test
//! (`tests/e2e/faults.rs`) fails when code elsewhere in the crate opens a file for reading.
//!
//! What it guarantees, whatever the path names:
//! - **Regular files only.** The file is opened without blocking (`O_NONBLOCK`: opening a FIFO
//!   would wait for a writer forever) and the *opened* handle is checked, so a link swapped in
//!   between a check and the open cannot lead to a FIFO or a device such as `/dev/zero`.
//! - **Bounded.** A read never takes more than its `Limit`; the size is checked before anything is
//!   allocated, and the read itself stops one byte past the limit, so a file that grows while it
//!   is read cannot take more memory than the limit either. Sizes a file *declares* (a glTF
//!   `byteLength`, an image header) are never used to allocate: `read_prefix` allocates what the
//!   file holds, not what it claims.

use std::io::Read;
use std::path::Path;

/// How much of a kind of file may be read, and its name in a message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limit {
    pub bytes: u64,
    pub what: &'static str,
}

/// A matrix, a scene, a model's declaration or WGSL, a glTF file's JSON: text a person writes.
pub const TEXT: Limit = Limit { bytes: 16 << 20, what: "a text input file" };
/// A GLB file, or a buffer a glTF file names: meshes of millions of triangles fit well.
pub const MESH: Limit = Limit { bytes: 2 << 30, what: "a mesh file" };
/// A texture, sky or glTF image file (a 16k RGBA float EXR is 1 GiB; a 16k PNG much less).
pub const IMAGE: Limit = Limit { bytes: 1 << 30, what: "an image file" };
/// A record the tool wrote (`run.json`, `cell.json`, a cache manifest).
pub const RECORD: Limit = Limit { bytes: 256 << 20, what: "a record" };
/// An image, map or data file of a run folder or cache entry.
pub const OUTPUT: Limit = Limit { bytes: 4 << 30, what: "a run's file" };

/// Why a file was not read. Its message names no path: the caller says which file and key.
#[derive(Debug)]
pub enum ReadError {
    NotFound,
    NotRegular,
    TooLarge { bytes: u64, limit: Limit },
    Io(std::io::Error),
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::NotFound => write!(f, "cannot read: no such file"),
            ReadError::NotRegular => write!(f, "not a regular file (a folder, FIFO or device is never read)"),
            ReadError::TooLarge { bytes, limit } => {
                write!(f, "{bytes} bytes: {} may have at most {}", limit.what, limit.bytes)
            }
            ReadError::Io(e) => write!(f, "cannot read: {e}"),
        }
    }
}

impl std::error::Error for ReadError {}

impl From<std::io::Error> for ReadError {
    fn from(e: std::io::Error) -> ReadError {
        match e.kind() {
            std::io::ErrorKind::NotFound => ReadError::NotFound,
            _ => ReadError::Io(e),
        }
    }
}

/// The regular file at `path`, opened, with its size.
fn open(path: &Path) -> Result<(std::fs::File, u64), ReadError> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(ReadError::NotRegular);
    }
    Ok((file, meta.len()))
}

/// Whether `path` names a regular file this reader would open (a FIFO is not opened to find out).
pub fn is_regular_file(path: &Path) -> Result<(), ReadError> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(_) => Err(ReadError::NotRegular),
        Err(e) => Err(e.into()),
    }
}

/// The whole regular file at `path`, at most `limit` bytes.
pub fn read(path: &Path, limit: Limit) -> Result<Vec<u8>, ReadError> {
    let (file, size) = open(path)?;
    if size > limit.bytes {
        return Err(ReadError::TooLarge { bytes: size, limit });
    }
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(limit.bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit.bytes {
        return Err(ReadError::TooLarge { bytes: bytes.len() as u64, limit });
    }
    Ok(bytes)
}

/// The regular file at `path` as UTF-8 text, at most `limit` bytes.
pub fn read_text(path: &Path, limit: Limit) -> Result<String, ReadError> {
    String::from_utf8(read(path, limit)?)
        .map_err(|e| ReadError::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error())))
}

/// The first `want` bytes of the regular file at `path` (fewer when it is shorter), refused past
/// `limit`: what a glTF buffer of `byteLength` reads. The allocation follows the file, never `want`.
pub fn read_prefix(path: &Path, want: u64, limit: Limit) -> Result<Vec<u8>, ReadError> {
    if want > limit.bytes {
        return Err(ReadError::TooLarge { bytes: want, limit });
    }
    let (file, size) = open(path)?;
    let mut bytes = Vec::with_capacity(size.min(want) as usize);
    file.take(want).read_to_end(&mut bytes)?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: Limit = Limit { bytes: 8, what: "a test file" };

    #[test]
    fn a_fifo_is_refused_without_blocking() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("fifo");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        assert!(matches!(read(&fifo, TEXT), Err(ReadError::NotRegular)));
        assert!(matches!(is_regular_file(&fifo), Err(ReadError::NotRegular)));
    }

    #[test]
    fn a_device_behind_a_link_and_a_folder_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("zero.wgsl");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        assert!(matches!(read(&link, TEXT), Err(ReadError::NotRegular)));
        assert!(matches!(read(dir.path(), TEXT), Err(ReadError::NotRegular)));
        assert!(matches!(read(&dir.path().join("absent"), TEXT), Err(ReadError::NotFound)));
    }

    #[test]
    fn sizes_are_checked_before_reading_and_prefixes_allocate_what_the_file_holds() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("f");
        std::fs::write(&f, b"123456789").unwrap();
        let err = read(&f, SMALL).unwrap_err();
        assert!(err.to_string().contains("9 bytes: a test file may have at most 8"), "{err}");
        assert_eq!(read_prefix(&f, 4, SMALL).unwrap(), b"1234");
        // A declared size far past the file: what the file holds, not what was claimed.
        assert_eq!(read_prefix(&f, 1 << 40, Limit { bytes: u64::MAX, what: "x" }).unwrap(), b"123456789");
        assert!(matches!(read_prefix(&f, 9, SMALL), Err(ReadError::TooLarge { .. })));
    }
}

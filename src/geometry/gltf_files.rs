//! The files a glTF document reaches, resolved exactly as the loader resolves them, and read with
//! bounds. The `gltf` crate's `import` reads any URI it is given whole — `file:///dev/zero` or a
//! relative path to a device reads without end — so buffers are read here: only regular files,
//! at most `byteLength` bytes. A scene may reach: the glTF file itself, its `data:` URIs, and
//! regular files named by relative URIs (percent-decoded with `urlencoding`, as `gltf` decodes
//! them), resolved against the glTF file's folder. Absolute (`file:`) and other schemes are
//! refused. The cell key hashes the same resolved paths (`run::cell_key`), so editing a file named
//! `my%20mesh.bin` re-renders its cells.

use std::path::{Path, PathBuf};

use crate::error::InputError;

/// The largest image file a glTF may name (a 16k RGBA PNG is well under it).
pub const MAX_IMAGE_BYTES: u64 = 512 << 20;

pub use crate::input::gltf_file::open;

/// What a buffer or image of a glTF file is read from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum External {
    /// Inside the file (a GLB's binary chunk, a `data:` URI).
    Embedded,
    /// A regular file, resolved.
    File(PathBuf),
}

/// Where `uri` (of the glTF file at `gltf_path`) leads, or why the scene may not reach it. `key`
/// names the entry in messages (`buffers[0].uri`).
pub fn resolve(gltf_path: &Path, key: &str, uri: &str) -> Result<External, InputError> {
    let shown = gltf_path.display().to_string();
    if uri.starts_with("data:") {
        return Ok(External::Embedded);
    }
    if uri.contains(':') {
        return Err(InputError::at_key(
            shown,
            key,
            format!(
                "`{uri}`: only relative file names and data: URIs may be referenced (absolute and \
                 other schemes such as file: are refused)"
            ),
        ));
    }
    let decoded = urlencoding::decode(uri)
        .map_err(|e| InputError::at_key(&shown, key, format!("`{uri}` is not a valid percent-encoded URI: {e}")))?;
    if Path::new(decoded.as_ref()).is_absolute() {
        return Err(InputError::at_key(
            shown,
            key,
            format!("`{uri}` is an absolute path; give it relative to the glTF file"),
        ));
    }
    let base = gltf_path.parent().unwrap_or(Path::new("."));
    let path = base.join(decoded.as_ref());
    match std::fs::metadata(&path) {
        Ok(m) if m.is_file() => Ok(External::File(path)),
        Ok(_) => Err(InputError::at_key(
            shown,
            key,
            format!("`{uri}` ({}) is not a regular file (a device, FIFO or folder is never read)", path.display()),
        )),
        Err(e) => Err(InputError::at_key(shown, key, format!("`{uri}` ({}) cannot be read: {e}", path.display()))),
    }
}

/// Every external file the document names (buffers, then images), each checked as `resolve` does.
pub fn external_files(gltf_path: &Path, doc: &gltf::Document) -> Result<Vec<PathBuf>, InputError> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        if let gltf::buffer::Source::Uri(uri) = b.source() {
            if let External::File(p) = resolve(gltf_path, &format!("buffers[{}].uri", b.index()), uri)? {
                out.push(p);
            }
        }
    }
    for i in doc.images() {
        if let gltf::image::Source::Uri { uri, .. } = i.source() {
            let key = format!("images[{}].uri", i.index());
            if let External::File(p) = resolve(gltf_path, &key, uri)? {
                let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
                if len > MAX_IMAGE_BYTES {
                    return Err(InputError::at_key(
                        gltf_path.display().to_string(),
                        key,
                        format!("`{uri}` is {len} bytes; an image file may have at most {MAX_IMAGE_BYTES}"),
                    ));
                }
                out.push(p);
            }
        }
    }
    Ok(out)
}

/// The document's buffers: at most `byteLength` bytes of each, from a regular file, the GLB blob
/// or a data: URI (decoded by `gltf`), padded to 4 bytes as `gltf::import` pads them.
pub fn read_buffers(
    gltf_path: &Path,
    doc: &gltf::Document,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<gltf::buffer::Data>, InputError> {
    let shown = gltf_path.display().to_string();
    let mut out = Vec::new();
    for b in doc.buffers() {
        let key = format!("buffers[{}]", b.index());
        let want = b.length();
        let mut data = match b.source() {
            gltf::buffer::Source::Uri(uri) => match resolve(gltf_path, &format!("{key}.uri"), uri)? {
                // At most `byteLength` bytes, allocated as the file holds them: a declared 2⁴⁰
                // is refused by the limit, never allocated.
                External::File(p) => crate::input::read::read_prefix(&p, want as u64, crate::input::read::MESH)
                    .map_err(|e| InputError::at_key(&shown, &key, format!("{}: {e}", p.display())))?,
                External::Embedded => {
                    gltf::buffer::Data::from_source(b.source(), None)
                        .map_err(|e| InputError::at_key(&shown, &key, format!("cannot decode the data: URI: {e}")))?
                        .0
                }
            },
            gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| InputError::at_key(&shown, &key, "names the GLB binary chunk, which the file lacks"))?,
        };
        if data.len() < want {
            return Err(InputError::at_key(
                shown,
                format!("{key}.byteLength"),
                format!("{want} bytes declared; the buffer has {}", data.len()),
            ));
        }
        while data.len() % 4 != 0 {
            data.push(0);
        }
        out.push(gltf::buffer::Data(data));
    }
    Ok(out)
}

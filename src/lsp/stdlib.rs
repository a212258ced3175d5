//! Editors open files by URI, but the stdlib is compiled into `axle`: each
//! module is written once per version to a read-only file in the temporary
//! directory, so go-to-definition on `import mcpherson_loads` opens its source.

use std::path::Path;

/// The URI of a stdlib file by its name in the source map (`stdlib/NAME.axle`),
/// writing the copy on first use; `None` when the copy cannot be written.
pub fn uri(name: &str) -> Option<lsp_types::Uri> {
    let module = name.strip_prefix("stdlib/")?.strip_suffix(".axle")?;
    let text = crate::stdlib::module(module)?;
    let dir = std::env::temp_dir().join(format!("axle-{}-stdlib", env!("CARGO_PKG_VERSION")));
    let path = dir.join(format!("{module}.axle"));
    if std::fs::read_to_string(&path).ok().as_deref() != Some(text) {
        std::fs::create_dir_all(&dir).ok()?;
        // A stale read-only copy from an earlier run must be replaced.
        let _ = std::fs::remove_file(&path);
        std::fs::write(&path, text).ok()?;
        let mut perms = std::fs::metadata(&path).ok()?.permissions();
        perms.set_readonly(true);
        std::fs::set_permissions(&path, perms).ok()?;
    }
    file_uri(&path)
}

/// `file://` URI of an absolute path, percent-encoding what a URI cannot hold.
pub fn file_uri(path: &Path) -> Option<lsp_types::Uri> {
    let mut s = String::from("file://");
    for b in path.to_string_lossy().bytes() {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            s.push(b as char);
        } else {
            s.push_str(&format!("%{b:02X}"));
        }
    }
    s.parse().ok()
}

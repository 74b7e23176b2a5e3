//! The one way gonio writes an output file: atomically, so that no file is ever half-written.
//!
//! The bytes go to a temporary file created in the destination's folder (so the rename cannot
//! cross file systems) by the `tempfile` crate, are flushed and synced, and the temporary file is
//! then renamed over the destination (`NamedTempFile::persist`). A reader sees the old file or the
//! new one, never a part; a failure or a crash leaves the old file in place and no temporary file
//! behind (`tempfile` removes it when it is dropped unpersisted). Images
//! ([`crate::image::RgbImage::write`]), tabulated BSDFs ([`crate::tabulated_io::write_tabulated`])
//! and the plots of the `gonio` binary are all written through [`write_atomically`].

use std::io::Write;
use std::path::{Path, PathBuf};

/// Writing an output file failed; names the file.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct WriteError {
    /// The destination file.
    pub path: PathBuf,
    /// The cause.
    pub source: std::io::Error,
}

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, flushed and synced,
/// then renamed over `path`. On failure the temporary file is removed and `path` is untouched.
///
/// The new file gets the permissions an ordinary `File::create` would give it (`0o666` less the
/// umask on Unix), not the owner-only `0o600` of a temporary file.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let err = |source| WriteError {
        path: path.to_owned(),
        source,
    };
    if path.file_name().is_none() {
        return Err(err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a file name",
        )));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".gonio-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // Passed to open(2) with O_CREAT, so the process umask applies as for File::create.
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(dir).map_err(err)?;
    tmp.write_all(bytes).map_err(err)?;
    tmp.as_file().sync_all().map_err(err)?;
    tmp.persist(path).map_err(|e| err(e.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmpdir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("gonio-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(d: &Path) -> Vec<std::ffi::OsString> {
        let mut v: Vec<_> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn writes_replaces_and_leaves_no_temporary() {
        let d = tmpdir("replace");
        let p = d.join("out.txt");
        write_atomically(&p, b"first").unwrap();
        write_atomically(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        assert_eq!(names(&d), vec![std::ffi::OsString::from("out.txt")]);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_failed_write_names_the_file_and_touches_nothing() {
        let d = tmpdir("fail");
        let p = d.join("keep.txt");
        write_atomically(&p, b"old").unwrap();
        // A folder in place of the destination: the rename fails after the temporary is written.
        std::fs::create_dir(d.join("sub")).unwrap();
        let e = write_atomically(&d.join("sub"), b"new").unwrap_err();
        assert!(e.to_string().contains("sub"), "{e}");
        // A folder that does not exist.
        let e = write_atomically(&d.join("no/such/dir/y.txt"), b"new").unwrap_err();
        assert!(e.to_string().contains("y.txt"), "{e}");
        // No file name at all.
        assert!(write_atomically(Path::new("/"), b"new").is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert_eq!(
            names(&d),
            vec![
                std::ffi::OsString::from("keep.txt"),
                std::ffi::OsString::from("sub")
            ]
        );
        let _ = std::fs::remove_dir_all(&d);
    }

    #[cfg(unix)]
    #[test]
    fn the_file_is_not_owner_only() {
        use std::os::unix::fs::PermissionsExt;
        let d = tmpdir("mode");
        let p = d.join("m.txt");
        write_atomically(&p, b"x").unwrap();
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        // Same as File::create under this process's umask.
        let q = d.join("ref.txt");
        std::fs::File::create(&q).unwrap();
        let expected = std::fs::metadata(&q).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, expected, "{mode:o} vs {expected:o}");
        let _ = std::fs::remove_dir_all(&d);
    }
}

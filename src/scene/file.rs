//! Reading a scene's files: only regular files are read ([`read_file`]), and a file that is not
//! UTF-8 text is reported at its first bad line ([`first_non_utf8_line`]).

use std::path::Path;

/// The bytes of the file at `path`, which must be a regular file: a folder, a device such as
/// `/dev/zero` or a pipe is refused before it is read (they may never end).
pub(crate) fn read_file(path: &Path) -> std::io::Result<Vec<u8>> {
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        let what = if metadata.is_dir() { "a folder" } else { "a device, pipe or socket" };
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("it is {what}, not a regular file"),
        ));
    }
    std::fs::read(path)
}

/// The 1-based line of `bytes` on which its first byte that is not UTF-8 lies.
pub(crate) fn first_non_utf8_line(bytes: &[u8], error: &std::str::Utf8Error) -> usize {
    1 + bytes[..error.valid_up_to()].iter().filter(|&&b| b == b'\n').count()
}

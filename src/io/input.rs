//! Reading input files safely: only regular files, and at most [`MAX_INPUT_BYTES`].
//!
//! A path naming a FIFO would block forever, `/dev/zero` would be read until memory runs
//! out, and a directory gives an unclear error: [`read_input`] refuses them all up front
//! with a message that says what the path is.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// The largest input file geosnap reads: 256 MiB. Real drawings, scripts and models are
/// far smaller (a dense 100k-point drawing is a few MB); the limit only keeps a wrong
/// path from filling memory.
pub const MAX_INPUT_BYTES: u64 = 256 * 1024 * 1024;

/// Reads a whole input file, refusing anything but a regular file no larger than
/// [`MAX_INPUT_BYTES`].
///
/// # Errors
///
/// [`io::ErrorKind::InvalidInput`] for a directory, a FIFO, a device or a socket (the
/// message says which), [`io::ErrorKind::FileTooLarge`] past the limit, and any error of
/// opening or reading the file.
pub fn read_input(path: &Path) -> io::Result<Vec<u8>> {
    read_input_with_limit(path, MAX_INPUT_BYTES)
}

/// [`read_input`] with another size limit.
///
/// # Errors
///
/// As [`read_input`].
pub fn read_input_with_limit(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    // Checked before opening: opening a FIFO for reading blocks until a writer comes.
    check_regular(&std::fs::metadata(path)?)?;
    let file = File::open(path)?;
    // Checked again on the open file, in case the path was swapped in between.
    let metadata = file.metadata()?;
    check_regular(&metadata)?;
    if metadata.len() > limit {
        return Err(too_large(limit));
    }
    let mut data = Vec::with_capacity(usize::try_from(metadata.len()).unwrap_or(0));
    // One byte more than the limit tells a file that grew while being read.
    file.take(limit + 1).read_to_end(&mut data)?;
    if data.len() as u64 > limit {
        return Err(too_large(limit));
    }
    Ok(data)
}

fn too_large(limit: u64) -> io::Error {
    io::Error::new(
        io::ErrorKind::FileTooLarge,
        format!(
            "the file is larger than {} MiB, the most geosnap reads",
            limit / (1024 * 1024)
        ),
    )
}

/// Refuses what is not a regular file, saying what it is.
fn check_regular(metadata: &std::fs::Metadata) -> io::Result<()> {
    let file_type = metadata.file_type();
    if file_type.is_file() {
        return Ok(());
    }
    let what = if file_type.is_dir() {
        "a directory"
    } else {
        special_kind(file_type)
    };
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("not a regular file but {what}; geosnap reads only regular files"),
    ))
}

#[cfg(unix)]
fn special_kind(file_type: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if file_type.is_fifo() {
        "a named pipe (FIFO)"
    } else if file_type.is_char_device() || file_type.is_block_device() {
        "a device"
    } else if file_type.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: std::fs::FileType) -> &'static str {
    "a special file"
}

#[cfg(test)]
mod tests {
    use std::io::ErrorKind;
    use std::path::Path;

    use super::{read_input, read_input_with_limit};

    #[test]
    fn a_directory_is_refused_with_a_clear_message() {
        let error = read_input(&std::env::temp_dir()).expect_err("a directory");
        assert_eq!(error.kind(), ErrorKind::InvalidInput);
        assert!(error.to_string().contains("a directory"), "{error}");
    }

    /// Issue 19, case 7: `/dev/zero` would be read until memory runs out.
    #[cfg(unix)]
    #[test]
    fn a_device_is_refused_not_read() {
        let error = read_input(Path::new("/dev/zero")).expect_err("a device");
        assert!(error.to_string().contains("a device"), "{error}");
    }

    /// Issue 19, case 7: a FIFO would block forever.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_fifo_is_refused_without_blocking() {
        let dir = std::env::temp_dir().join(format!("geosnap-input-fifo-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a temp dir");
        let fifo = dir.join("pipe.svg");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .expect("mkfifo runs");
        assert!(made.success(), "mkfifo failed");
        let error = read_input(&fifo).expect_err("a fifo");
        assert!(error.to_string().contains("named pipe"), "{error}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn files_past_the_limit_are_refused() {
        let path =
            std::env::temp_dir().join(format!("geosnap-input-limit-{}.json", std::process::id()));
        std::fs::write(&path, b"0123456789").expect("written");
        assert_eq!(
            read_input_with_limit(&path, 10).expect("fits"),
            b"0123456789"
        );
        let error = read_input_with_limit(&path, 9).expect_err("too large");
        assert_eq!(error.kind(), ErrorKind::FileTooLarge);
        let _ = std::fs::remove_file(&path);
    }
}

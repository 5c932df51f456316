//! The outputs of a command: checked before any work, written together or not at all.

use std::path::Path;

use anyhow::{bail, Context, Result};

/// The extensions a model file output takes.
pub(super) const MODEL_EXTENSIONS: &[&str] = &["json"];
/// The extensions a glTF output takes.
pub(super) const GLTF_EXTENSIONS: &[&str] = &["glb", "gltf"];
/// The extensions an overlay output takes.
pub(super) const PNG_EXTENSIONS: &[&str] = &["png"];

/// An output file of a command: its path, the option that names it, and the
/// extensions it takes.
pub(super) struct Output<'a> {
    pub(super) path: &'a Path,
    pub(super) option: &'static str,
    pub(super) extensions: &'static [&'static str],
}

/// Checks every output of a command before any work: a supported extension, a folder
/// that exists and takes files, not the same file as an input, not the same as another
/// output.
pub(super) fn check_outputs(outputs: &[Output<'_>], inputs: &[&Path]) -> Result<()> {
    for (index, output) in outputs.iter().enumerate() {
        let (option, path) = (output.option, output.path.display());
        let extension = output
            .path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if !extension
            .as_deref()
            .is_some_and(|e| output.extensions.contains(&e))
        {
            let takes: Vec<String> = output.extensions.iter().map(|e| format!(".{e}")).collect();
            bail!(
                "{option} {path}: unsupported extension; {option} takes a {} file",
                takes.join(" or ")
            );
        }
        if let Some(input) = inputs.iter().find(|i| same_file(output.path, i)) {
            bail!(
                "{option} {path} is an input of this command ({}): refusing to overwrite it; \
                 name another file",
                input.display()
            );
        }
        if let Some(other) = outputs
            .get(..index)
            .unwrap_or_default()
            .iter()
            .find(|o| same_target(o.path, output.path))
        {
            bail!(
                "{option} and {} both name {path}: give each output its own file",
                other.option
            );
        }
        crate::io::check_target(output.path)
            .with_context(|| format!("{option} {path}: cannot write there"))?;
    }
    Ok(())
}

/// Whether two existing paths are the same file (through links and `..` too).
pub(super) fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
    }
}

/// Whether two output paths (which may not exist yet) name the same file.
pub(super) fn same_target(a: &Path, b: &Path) -> bool {
    let resolved = |p: &Path| {
        let folder = match p.parent() {
            Some(f) if !f.as_os_str().is_empty() => f,
            _ => Path::new("."),
        };
        std::fs::canonicalize(folder)
            .ok()
            .zip(p.file_name())
            .map(|(folder, name)| folder.join(name))
    };
    same_file(a, b) || matches!((resolved(a), resolved(b)), (Some(x), Some(y)) if x == y)
}

/// Writes the outputs of one command together: all of them, or none.
pub(super) fn write_outputs(files: &[(&Path, Vec<u8>)]) -> Result<()> {
    let borrowed: Vec<(&Path, &[u8])> = files.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    let written = crate::io::write_all_atomic(&borrowed);
    written.map_err(|error| {
        let none = if files.len() > 1 {
            "; no output was written"
        } else {
            "; the old file, if any, is untouched"
        };
        anyhow::Error::new(error).context(format!("writing the outputs{none}"))
    })
}

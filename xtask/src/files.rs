//! Files and streams: what the command line reads and writes, and where.
//!
//! - A scene file is read only when it is a regular file of at most
//!   [`impact::study::MAX_SCENE_BYTES`];
//!   every file read is remembered, and no output ever replaces one ([`create`]).
//! - An output folder is `--out` or `target/<command>/<name>`, the name passing
//!   [`impact::study::folder_name`]; it is created and proven writable ([`OutDir::create`])
//!   before the first run, so a long study does not fail at its end.
//! - Whole files are written to a temporary name and renamed into place ([`write_atomic`]): a
//!   stopped run never leaves a half-written table under the final name.
//! - Standard output goes through [`say!`]: a closed pipe (`| head`) ends the program quietly,
//!   a full disk is one line of error, and control characters from a file are escaped.

use anyhow::{bail, Context};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The canonical paths of every file read: outputs never replace them.
static INPUTS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The text of the input file `path` ([`impact::study::read_input`]), registered as an input
/// that no output may replace.
pub(crate) fn read_input(path: &Path, what: &str) -> anyhow::Result<String> {
    let text = impact::study::read_input(path, what)?;
    if let (Ok(canonical), Ok(mut inputs)) = (path.canonicalize(), INPUTS.lock()) {
        inputs.push(canonical);
    }
    Ok(text)
}

/// Refuses `path` as an output when it is a file that was read.
pub(crate) fn refuse_input(path: &Path) -> anyhow::Result<()> {
    let Ok(canonical) = path.canonicalize() else { return Ok(()) };
    if INPUTS.lock().map(|inputs| inputs.contains(&canonical)).unwrap_or(false) {
        bail!("{} is an input of this run: an output must not replace it", path.display());
    }
    Ok(())
}

/// A new (or emptied) file at `path` for writing, never an input file.
pub(crate) fn create(path: &Path) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    refuse_input(path)?;
    let file =
        std::fs::File::create(path).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(std::io::BufWriter::new(file))
}

/// Writes `bytes` to `path` through a temporary file in the same folder renamed into place.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    refuse_input(path)?;
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("file");
    let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
    let mut f = create(&tmp)?;
    f.write_all(bytes)
        .and_then(|()| f.flush())
        .with_context(|| format!("cannot write {}", tmp.display()))?;
    drop(f);
    std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))
}

/// The output folder of `command` for a scene named `name`: `out` when given, else
/// `target/<command>/<name>` with a plain `name`.
pub(crate) fn out_dir(command: &str, name: &str, out: Option<&Path>) -> anyhow::Result<PathBuf> {
    match out {
        Some(out) => Ok(out.to_path_buf()),
        None => Ok(Path::new("target").join(command).join(impact::study::folder_name(name)?)),
    }
}

/// An output folder, created and proven writable.
#[derive(Debug, Clone)]
pub(crate) struct OutDir(PathBuf);

impl OutDir {
    /// Creates `path` (and its parents) and writes and removes a probe file in it, so that an
    /// unwritable folder is found before anything runs.
    pub(crate) fn create(path: &Path) -> anyhow::Result<Self> {
        std::fs::create_dir_all(path)
            .with_context(|| format!("cannot create the output folder {}", path.display()))?;
        let probe = path.join(format!(".write-probe-{}", std::process::id()));
        std::fs::write(&probe, b"probe")
            .with_context(|| format!("cannot write in the output folder {}", path.display()))?;
        std::fs::remove_file(&probe).ok();
        Ok(Self(path.to_path_buf()))
    }

    /// The folder.
    pub(crate) fn path(&self) -> &Path {
        &self.0
    }

    /// The path of the file `name` in it.
    pub(crate) fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

/// Writes one line (or lines) to standard output; `say!` formats it.
pub(crate) fn write_stdout(args: std::fmt::Arguments<'_>) -> anyhow::Result<()> {
    let text = escape_controls(&args.to_string());
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush())
        .context("cannot write to standard output")
}

/// `text` with control characters other than line breaks and tabs escaped.
pub(crate) fn escape_controls(text: &str) -> String {
    text.split('\n')
        .map(|line| line.split('\t').map(impact::study::printable).collect::<Vec<_>>().join("\t"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `say!("...", args)`: one line on standard output, an error when it cannot be written.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::files::write_stdout(format_args!($($arg)*))
    };
}
pub(crate) use say;

/// Whether `error` comes from a closed pipe on standard output (`| head`): not a failure of
/// the program, which ends quietly.
pub(crate) fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn special_and_large_files_are_refused_and_inputs_are_never_replaced() {
        let dir = std::env::temp_dir().join(format!("files-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = read_input(&dir, "scene file").unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
        if Path::new("/dev/zero").exists() {
            let e = read_input(Path::new("/dev/zero"), "scene file").unwrap_err().to_string();
            assert!(e.contains("not a regular file"), "{e}");
        }
        let big = dir.join("big.toml");
        std::fs::write(&big, vec![b'#'; impact::study::MAX_SCENE_BYTES as usize + 1]).unwrap();
        let e = read_input(&big, "scene file").unwrap_err().to_string();
        assert!(e.contains("allowed at most 1048576"), "{e}");
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, "name = \"x\"").unwrap();
        read_input(&scene, "scene file").unwrap();
        assert!(create(&scene).unwrap_err().to_string().contains("an input of this run"));
        assert!(write_atomic(&scene, b"x").is_err());
        assert_eq!(std::fs::read_to_string(&scene).unwrap(), "name = \"x\"");
        write_atomic(&dir.join("out.csv"), b"a,b\n").unwrap();
        assert_eq!(std::fs::read_to_string(dir.join("out.csv")).unwrap(), "a,b\n");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn output_folders_stay_under_their_command() {
        assert_eq!(
            out_dir("sweep", "paper-tip", None).unwrap(),
            Path::new("target/sweep/paper-tip")
        );
        for hostile in ["../../../../tmp/x", "/tmp/x", "..", "", "a/b/c"] {
            assert!(out_dir("compare", hostile, None).is_err(), "{hostile}");
        }
        assert_eq!(out_dir("beam", "..", Some(Path::new("mine"))).unwrap(), Path::new("mine"));
        assert_eq!(escape_controls("a\u{1b}[2J\tb\nc"), "a\\u{1b}[2J\tb\nc");
    }
}

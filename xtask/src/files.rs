//! Files and streams: what the command line reads and writes, and where.
//!
//! - A scene file is read only when it is a regular file of at most
//!   [`impact::study::MAX_SCENE_BYTES`];
//!   every file read is remembered, and no output ever replaces one ([`create`]).
//! - An output folder is `--out` or `target/<command>/<name>`, the name passing
//!   [`impact::study::folder_name`]; it is created and proven writable ([`OutDir::create`])
//!   before the first run, so a long study does not fail at its end.
//! - Every file is written to a new temporary name in its folder (never following a link there)
//!   and renamed into place only when it is whole ([`create`], [`Output::finish`],
//!   [`write_atomic`]): a run that fails or stops leaves an existing file as it was, and a
//!   symbolic link in an output folder is replaced, never written through.
//! - An input is known by its identity (device and inode) as well as its path: a hard link or
//!   another spelling of it is refused as an output, and an output folder that holds an
//!   input is refused before the run.
//! - The outputs a user names on one command line ([`claim`]) are checked against each other
//!   before the run: the same file twice, or a file inside an output folder of the same run,
//!   is refused.
//! - Standard output goes through [`say!`]: a closed pipe (`| head`) ends the program quietly,
//!   a full disk is one line of error, and control characters from a file are escaped.

use anyhow::{bail, Context};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// A file's identity: its device and inode where the platform has them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Identity(u64, u64);

/// The identity of the file at `path` (following links), if it exists.
fn identity(path: &Path) -> Option<Identity> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata(path).ok().map(|m| Identity(m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        None
    }
}

/// Every file read (canonical path, identity, and whether a user gave it rather than the
/// command keeping it in its own folder): outputs never replace them.
static INPUTS: Mutex<Vec<(PathBuf, Option<Identity>, bool)>> = Mutex::new(Vec::new());

/// The outputs named on this command line (file, or folder with `true`), each as given and
/// canonical where it exists: checked against each other before the run.
static CLAIMS: Mutex<Vec<(PathBuf, bool)>> = Mutex::new(Vec::new());

/// The text of the input file `path` ([`impact::study::read_input`]), registered as an input
/// that no output may replace.
pub(crate) fn read_input(path: &Path, what: &str) -> anyhow::Result<String> {
    read_registered(path, what, true)
}

/// [`read_input`] for a file a command keeps in its own output folder (a sweep's manifest):
/// an input all the same, but one that folder may hold.
pub(crate) fn read_own(path: &Path, what: &str) -> anyhow::Result<String> {
    read_registered(path, what, false)
}

fn read_registered(path: &Path, what: &str, user: bool) -> anyhow::Result<String> {
    let text = impact::study::read_input(path, what)?;
    if let (Ok(canonical), Ok(mut inputs)) = (path.canonicalize(), INPUTS.lock()) {
        inputs.push((canonical, identity(path), user));
    }
    Ok(text)
}

/// Refuses `path` as an output when it is a file that was read: the same path, or the same
/// file by another path (a hard link, a link).
pub(crate) fn refuse_input(path: &Path) -> anyhow::Result<()> {
    let (canonical, id) = (path.canonicalize().ok(), identity(path));
    let read = INPUTS.lock().is_ok_and(|inputs| {
        // (An identity counts while the input still has it: a deleted file's inode is reused.)
        inputs.iter().any(|(p, i, _)| {
            Some(p) == canonical.as_ref() || (id.is_some() && *i == id && identity(p) == *i)
        })
    });
    if read {
        bail!("{} is an input of this run: an output must not replace it", path.display());
    }
    Ok(())
}

/// `path` with its folder made absolute and canonical (the file itself need not exist).
fn normal(path: &Path) -> PathBuf {
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let parent = parent.canonicalize().unwrap_or(parent);
    match path.file_name() {
        Some(name) => parent.join(name),
        None => parent,
    }
}

/// Claims `path` as an output a user named on this command line (`folder` for an output
/// folder): refused when it is an input, when another claim names the same file (by path or
/// identity), or when a file lies inside a claimed folder (a figure's table would replace it).
pub(crate) fn claim(path: &Path, folder: bool, what: &str) -> anyhow::Result<()> {
    refuse_input(path)?;
    let mine = normal(path);
    let id = identity(path);
    let Ok(mut claims) = CLAIMS.lock() else { return Ok(()) };
    for (other, other_folder) in claims.iter() {
        let same = *other == mine || (id.is_some() && identity(other) == id);
        let inside = match (folder, *other_folder) {
            (false, true) => mine.starts_with(other),
            (true, false) => other.starts_with(&mine),
            _ => false,
        };
        if same || inside {
            bail!(
                "{what} {} {} {}: outputs of one run must not replace each other",
                path.display(),
                if same {
                    "is also"
                } else if folder {
                    "holds"
                } else {
                    "lies inside"
                },
                other.display()
            );
        }
    }
    claims.push((mine, folder));
    Ok(())
}

/// A file being written: a new temporary file in the destination's folder (created new, so a
/// link there is never followed), renamed over the destination by [`Output::finish`] only
/// when whole; dropped unfinished, it is removed and the destination left as it was.
#[derive(Debug)]
pub(crate) struct Output {
    path: PathBuf,
    tmp: PathBuf,
    file: Option<std::io::BufWriter<std::fs::File>>,
}

/// The temporary files being written now: removed by [`remove_unfinished_on_interrupt`]'s
/// handler when the program is stopped (a stop skips `Output`'s drop, and a stopped `simulate`
/// had left hidden files of up to 18 MB that nothing removed, a review's).
static UNFINISHED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// `tmp` written to, or no longer ([`UNFINISHED`]).
fn unfinished(tmp: &Path, live: bool) {
    let mut files = UNFINISHED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if live {
        files.push(tmp.to_path_buf());
    } else {
        files.retain(|p| p != tmp);
    }
}

/// On Ctrl-C or a termination signal (SIGINT, SIGTERM, SIGHUP): removes the temporary files
/// being written, says so on standard error and exits with 130, as the signal would have
/// (every finished output stays whole, an unfinished one as it was before the run; a sweep's
/// journal keeps its finished rows). Installed once at the start; a failure to install it is
/// ignored (the outputs are then as safe as before, only the temporaries may stay).
pub(crate) fn remove_unfinished_on_interrupt() {
    let _ = ctrlc::set_handler(|| {
        // Held to the exit: no temporary file is made or registered meanwhile.
        let files = UNFINISHED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        for tmp in files.iter() {
            std::fs::remove_file(tmp).ok();
        }
        let _ = writeln!(
            std::io::stderr(),
            "stopped{}",
            if files.is_empty() {
                String::new()
            } else {
                format!(
                    ": {} unfinished output(s) removed, the files they replace left as they were",
                    files.len()
                )
            }
        );
        std::process::exit(130);
    });
}

impl Output {
    /// Renames the whole file into place (replacing a link there, not its target).
    pub(crate) fn finish(mut self) -> anyhow::Result<()> {
        let Some(mut file) = self.file.take() else { return Ok(()) };
        // On the disk before the rename, and the rename on it after: the name never stands for
        // a file the disk does not hold whole, across a power loss too (without them a rename
        // may reach the disk before the data, a review's; 0.5 ms a file here).
        let written = file
            .flush()
            .and_then(|()| file.get_ref().sync_all())
            .with_context(|| format!("cannot write {}", self.path.display()));
        drop(file);
        // The destination is checked again: it may have become an input's name meanwhile.
        let renamed = written.and_then(|()| refuse_input(&self.path)).and_then(|()| {
            std::fs::rename(&self.tmp, &self.path)
                .with_context(|| format!("cannot write {}", self.path.display()))
        });
        match &renamed {
            Err(_) => {
                std::fs::remove_file(&self.tmp).ok();
            }
            Ok(()) => {
                let folder = self.path.parent().filter(|p| !p.as_os_str().is_empty());
                let folder = folder.unwrap_or_else(|| Path::new("."));
                std::fs::File::open(folder).and_then(|d| d.sync_all()).ok();
            }
        }
        unfinished(&self.tmp, false);
        renamed
    }
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.file {
            Some(f) => f.write(buf),
            None => Err(std::io::Error::other("output already finished")),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.as_mut().map_or(Ok(()), Write::flush)
    }
}

impl Drop for Output {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            std::fs::remove_file(&self.tmp).ok();
            unfinished(&self.tmp, false);
        }
    }
}

/// A file for writing at `path` (see [`Output`]), never an input file; its folder must exist
/// and be writable now, so a path that cannot be written fails before a run.
pub(crate) fn create(path: &Path) -> anyhow::Result<Output> {
    refuse_input(path)?;
    if path.is_dir() {
        bail!("{} is a folder: an output file must not replace it", path.display());
    }
    static COUNT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("file");
    let n = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let tmp = path.with_file_name(format!(".{name}.tmp{}-{n}", std::process::id()));
    // Registered before it exists: a stop between the two then finds nothing to remove rather
    // than missing a file.
    unfinished(&tmp, true);
    let file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .with_context(|| format!("cannot write {}", path.display()));
    let file = match file {
        Ok(file) => file,
        Err(e) => {
            unfinished(&tmp, false);
            return Err(e);
        }
    };
    Ok(Output { path: path.to_path_buf(), tmp, file: Some(std::io::BufWriter::new(file)) })
}

/// Writes `bytes` to `path` whole (see [`Output`]).
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let mut out = create(path)?;
    out.write_all(bytes).with_context(|| format!("cannot write {}", path.display()))?;
    out.finish()
}

/// Removes the output file `path` if it is there; never an input.
pub(crate) fn remove_output(path: &Path) -> anyhow::Result<()> {
    refuse_input(path)?;
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("cannot remove {}", path.display()))
        }
        _ => Ok(()),
    }
}

/// Renames the output `from` over `to`; never over an input.
pub(crate) fn rename_output(from: &Path, to: &Path) -> anyhow::Result<()> {
    refuse_input(to)?;
    std::fs::rename(from, to).with_context(|| format!("cannot write {}", to.display()))
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
    /// unwritable folder is found before anything runs; refused when it holds a file this run
    /// reads (its own tables or figures could replace it).
    pub(crate) fn create(path: &Path) -> anyhow::Result<Self> {
        std::fs::create_dir_all(path)
            .with_context(|| format!("cannot create the output folder {}", path.display()))?;
        if let (Ok(folder), Ok(inputs)) = (path.canonicalize(), INPUTS.lock()) {
            if let Some((input, ..)) =
                inputs.iter().find(|(p, _, user)| *user && p.starts_with(&folder))
            {
                bail!(
                    "the output folder {} holds {}, an input of this run: give another folder (--out)",
                    path.display(),
                    input.display()
                );
            }
        }
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

//! Studies: many runs of one scene, and what they share with every front end.
//!
//! A *study* runs variants of one scene and reads their reports together. The command line
//! (`cargo xtask sweep | accuracy | compare | reproduce`) and the Python package
//! (`python/`, `impact_beam`) share one of each piece here, and keep only argument parsing,
//! progress and files:
//!
//! - [`grid`]: a sweep's axes (`KEY=START:STOP:COUNT` or `KEY=v1,v2,...` over dotted scene
//!   keys), its lazily numbered grid with a size checked before anything is allocated
//!   ([`MAX_GRID_POINTS`]), shards, each point's validated scene, the report's scalar columns
//!   with their units, and the manifest that tells one sweep from another.
//! - [`variant`](fn@variant): the scene of one method at one resolution, with the other
//!   method's keys dropped (a modal scene's `residual_flexibility` has no place in its fe run).
//! - [`comparison`]: the runs of `compare`, both methods against a converged reference, and
//!   their table ([`comparison::summary`]).
//! - [`accuracy`]: the ladders of settings of the work-precision study, the study run one
//!   setting after another ([`accuracy::run`]), its references and the errors of every run from
//!   its method's reference.
//! - [`read_input`]: the one way a scene file is read (a regular file of at most
//!   [`MAX_SCENE_BYTES`]).
//! - [`folder_name`]: the one way a scene's `name` becomes an output folder, and
//!   [`printable`], the one way a name or value from a file is printed.
//!
//! Every comparison of two runs counts a contact as significant at
//! [`crate::SIGNIFICANT_PEAK`] of the first contact's peak force (the tolerance refinement,
//! `accuracy` and `compare` alike).
//!
//! ```
//! use impact::study::{Axis, Grid};
//! let base: toml::Table = toml::from_str(r#"
//!     name = "steel ball on a steel block"
//!     [half_space]
//!     youngs_modulus = 2.1e11
//!     poisson_ratio = 0.3
//!     [ball]
//!     radius = 0.01
//!     youngs_modulus = 2.1e11
//!     poisson_ratio = 0.3
//!     density = 7850.0
//!     [impact]
//!     speed = 1.0
//!     gravity = false
//! "#).unwrap();
//! let grid = Grid::new(vec![Axis::parse("impact.speed=0.5:2:4", &[])?])?;
//! assert_eq!(grid.len(), 4);
//! let scene = grid.scene(&base, 3)?;
//! assert_eq!(scene.impact.speed, Some(2.0));
//! # Ok::<(), impact::ImpactError>(())
//! ```

pub mod accuracy;
pub mod comparison;
pub mod grid;
mod variant;

pub use grid::{Axis, Grid, Manifest, Shard, COLUMNS, MAX_GRID_POINTS};
pub use variant::variant;

use crate::error::ImpactError;

/// The largest scene file read (bytes): a scene is a few hundred bytes; a megabyte is no
/// scene, and `/dev/zero` must not be read until memory runs out.
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// The text of the input file `path` (`what` names it in errors: "scene file"), refused at
/// once when it is not a regular file or is larger than [`MAX_SCENE_BYTES`]: the one way
/// every front end reads a scene file.
///
/// # Errors
/// `Input` naming the file and why it cannot be read.
pub fn read_input(path: &std::path::Path, what: &str) -> Result<String, ImpactError> {
    use std::io::Read;
    let shown = path.display();
    let input = |why: String| ImpactError::Input(why);
    let meta = std::fs::metadata(path)
        .map_err(|e| input(format!("cannot read the {what} {shown}: {e}")))?;
    if !meta.is_file() {
        return Err(input(format!("the {what} {shown} is not a regular file")));
    }
    if meta.len() > MAX_SCENE_BYTES {
        return Err(input(format!(
            "the {what} {shown} has {} bytes; allowed at most {MAX_SCENE_BYTES}",
            meta.len()
        )));
    }
    let mut text = String::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_SCENE_BYTES + 1).read_to_string(&mut text))
        .map_err(|e| input(format!("cannot read the {what} {shown} (as UTF-8 text): {e}")))?;
    if text.len() as u64 > MAX_SCENE_BYTES {
        return Err(input(format!(
            "the {what} {shown} grew beyond {MAX_SCENE_BYTES} bytes while read"
        )));
    }
    Ok(text)
}

/// The longest output folder name (characters): far below every file system's limit of 255
/// bytes for a name, with room for the files inside.
pub const MAX_FOLDER_NAME: usize = 100;

/// `name` as the name of an output folder: itself when it is a plain name (unicode letters
/// and digits, `-`, `_`, `.` and spaces inside; not empty, not `.` or `..`, at most
/// [`MAX_FOLDER_NAME`] characters), so that a folder made from it stays inside its parent.
///
/// # Errors
/// `Study` naming `name`, its value (printable) and what is allowed.
pub fn folder_name(name: &str) -> Result<&str, ImpactError> {
    let plain = |c: char| c.is_alphanumeric() || matches!(c, '-' | '_' | '.' | ' ');
    let count = name.chars().count();
    let problem = if name.is_empty() {
        Some("it is empty")
    } else if name == "." || name == ".." {
        Some("it names a folder above or the folder itself")
    } else if count > MAX_FOLDER_NAME {
        Some("it is too long")
    } else if name.starts_with(' ') || name.ends_with(' ') {
        Some("it starts or ends with a space")
    } else if !name.chars().all(plain) {
        Some("it holds a character other than a letter, a digit, '-', '_', '.' or a space")
    } else {
        None
    };
    match problem {
        None => Ok(name),
        Some(why) => Err(ImpactError::Study(format!(
            "name = {}: {why}; the name becomes an output folder, so it must be a plain name of \
             1 to {MAX_FOLDER_NAME} letters, digits, '-', '_', '.' and inner spaces (not '.' or \
             '..'), or give --out",
            printable(&format!("{name:?}"))
        ))),
    }
}

/// A fingerprint of `text` (16 hex digits, FNV-1a 64): a study's files carry the fingerprint
/// of what made them, so that a resumed or merged study refuses the files of another.
pub fn fingerprint(text: &str) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{hash:016x}")
}

/// `text` with every control character (escape, bell, newline, ...) written as `\u{..}`, so
/// that printing a name or a value from someone else's file cannot drive the terminal.
pub fn printable(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.push_str(&format!("\\u{{{:x}}}", u32::from(c)));
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_plain_names_become_folders() {
        for good in ["paper-tip", "mid span 2", "r10_v1.5", "Stoß", "ßeam", "a.b"] {
            assert_eq!(folder_name(good), Ok(good));
        }
        for bad in [
            "",
            ".",
            "..",
            "../../../../tmp/x",
            "/tmp/x",
            "a/b/c",
            "a\\b",
            "x\u{1b}]0;title\u{7}",
            "line\nbreak",
            " lead",
            "C:",
        ] {
            let e = folder_name(bad).expect_err(bad).to_string();
            assert!(e.starts_with("name = "), "{e}");
            assert!(!e.chars().any(char::is_control), "{e:?}");
        }
        assert!(folder_name(&"a".repeat(MAX_FOLDER_NAME)).is_ok());
        assert!(folder_name(&"a".repeat(MAX_FOLDER_NAME + 1)).is_err());
    }

    #[test]
    fn control_characters_are_escaped() {
        assert_eq!(printable("a\u{1b}[2Jb\u{7}"), "a\\u{1b}[2Jb\\u{7}");
        assert_eq!(printable("plain é"), "plain é");
    }
}

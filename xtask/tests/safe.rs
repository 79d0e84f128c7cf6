//! Safe by default, through the command line itself: hostile scene names write nothing
//! anywhere, inputs are never replaced, special and oversized files are refused, and standard
//! output that closes or fills ends cleanly.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a test stops on a broken fixture

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

const XTASK: &str = env!("CARGO_BIN_EXE_xtask");

fn validation(file: &str) -> String {
    std::fs::read_to_string(format!("{}/../validation/scenes/{file}", env!("CARGO_MANIFEST_DIR")))
        .unwrap()
}

/// A fresh scratch folder for one test.
fn scratch(test: &str) -> PathBuf {
    let root = std::env::temp_dir().join(format!("xtask-safe-{test}-{}", std::process::id()));
    std::fs::remove_dir_all(&root).ok();
    std::fs::create_dir_all(root.join("work")).unwrap();
    root
}

/// Every file and folder under `root`, relative to it, sorted.
fn tree(root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            out.push(path.strip_prefix(root).unwrap().to_path_buf());
            if path.is_dir() {
                stack.push(path);
            }
        }
    }
    out.sort();
    out
}

fn xtask(dir: &Path, args: &[&str]) -> Output {
    Command::new(XTASK).args(args).current_dir(dir).output().unwrap()
}

/// `text` with its `name = ...` line replaced by `name` (a TOML string).
fn renamed(text: &str, name: &str) -> String {
    let line = text.lines().find(|l| l.starts_with("name = ")).unwrap();
    text.replacen(line, &format!("name = {}", toml::Value::String(name.into())), 1)
}

#[test]
fn hostile_names_write_nothing_outside_the_folders_the_tool_owns() {
    let root = scratch("names");
    let work = root.join("work");
    let absolute = root.join("absolute").display().to_string();
    let hostile = [
        "../escape",
        "../../../escape",
        absolute.as_str(),
        "..",
        ".",
        "",
        "a/b/c",
        "x\u{1b}]0;t\u{7}",
    ];
    let before = tree(&root);
    for (i, name) in hostile.iter().enumerate() {
        let impact_scene = work.join(format!("impact{i}.toml"));
        std::fs::write(&impact_scene, renamed(&validation("paper-tip.toml"), name)).unwrap();
        let half = work.join(format!("half{i}.toml"));
        std::fs::write(&half, renamed(&validation("half-space-r10.toml"), name)).unwrap();
        let beam = work.join(format!("beam{i}.toml"));
        std::fs::write(&beam, renamed(&validation("beam-mattiasson-k10.toml"), name)).unwrap();
        let (s, h, b) =
            (impact_scene.to_str().unwrap(), half.to_str().unwrap(), beam.to_str().unwrap());
        for args in [
            vec!["compare", s],
            vec!["accuracy", s, "--quick"],
            vec!["sweep", h, "--set", "impact.speed=1,2"],
            vec!["beam", b],
        ] {
            let out = xtask(&work, &args);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{args:?} with name {name:?} ran");
            assert!(stderr.contains("error: name = "), "{args:?}, {name:?}: {stderr}");
            assert!(!stderr.chars().any(|c| c.is_control() && c != '\n'), "{stderr:?}");
        }
        for f in [impact_scene, half, beam] {
            std::fs::remove_file(f).unwrap();
        }
    }
    assert_eq!(tree(&root), before, "a command wrote outside its folder");
    std::fs::remove_dir_all(&root).ok();
}

#[test]
fn inputs_are_never_replaced_and_only_small_regular_files_are_read() {
    let root = scratch("inputs");
    let work = root.join("work");
    let scene = work.join("scene.toml");
    let text = validation("half-space-r10.toml");
    std::fs::write(&scene, &text).unwrap();
    let s = scene.to_str().unwrap();
    let out = xtask(&work, &["simulate", s, "--history", s]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("an input of this run"));
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), text, "the scene file was replaced");
    if Path::new("/dev/zero").exists() {
        let out = xtask(&work, &["simulate", "/dev/zero"]);
        assert!(String::from_utf8_lossy(&out.stderr).contains("not a regular file"));
    }
    let big = work.join("big.toml");
    std::fs::write(&big, format!("{text}\n{}", "#".repeat(2 << 20))).unwrap();
    let out = xtask(&work, &["simulate", big.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("allowed at most 1048576"));
    std::fs::remove_dir_all(&root).ok();
}

#[test]
fn a_closed_pipe_ends_quietly_and_a_full_disk_is_one_line() {
    let root = scratch("streams");
    let work = root.join("work");
    let scene = work.join("scene.toml");
    std::fs::write(&scene, validation("half-space-r10.toml")).unwrap();
    let s = scene.to_str().unwrap();
    // `| head -c 0`: the reader has gone before the first line.
    let mut child = Command::new(XTASK)
        .args(["simulate", s])
        .current_dir(&work)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{out:?}");
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
    if Path::new("/dev/full").exists() {
        let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        let out = Command::new(XTASK)
            .args(["simulate", s])
            .current_dir(&work)
            .stdout(full)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains("cannot write to standard output"), "{stderr}");
    }
    std::fs::remove_dir_all(&root).ok();
}

#[test]
fn help_lists_every_command() {
    let out = xtask(Path::new("."), &["--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    for command in ["reproduce", "simulate", "compare", "accuracy", "beam", "sweep", "validate"] {
        assert!(help.contains(command), "{command} missing from --help:\n{help}");
    }
}

#[test]
fn outputs_that_cannot_be_written_fail_before_the_run() {
    let root = scratch("outputs");
    let work = root.join("work");
    let scene = work.join("scene.toml");
    std::fs::write(&scene, validation("paper-tip.toml")).unwrap();
    let s = scene.to_str().unwrap();
    let blocker = work.join("a-file");
    std::fs::write(&blocker, "not a folder").unwrap();
    let inside = blocker.join("field.csv");
    for args in [
        vec!["simulate", s, "--field", inside.to_str().unwrap()],
        vec!["simulate", s, "--plots", blocker.to_str().unwrap()],
    ] {
        let out = xtask(&work, &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        // Refused before the run: no report was printed.
        assert!(out.stdout.is_empty(), "{}", String::from_utf8_lossy(&out.stdout));
        assert!(stderr.contains("cannot"), "{stderr}");
    }
    std::fs::remove_dir_all(&root).ok();
}

/// The paper's tip over 0.1 ms with 16 modes: a run of a few milliseconds.
fn quick_tip() -> String {
    validation("paper-tip.toml")
        .replace("modes = 128", "modes = 16")
        .replace("end_time = 0.005", "end_time = 0.0001")
}

#[test]
fn a_refused_run_leaves_every_existing_file_as_it_was() {
    // Before: the history file was opened (emptied) before the scene was known to run.
    let root = scratch("refused");
    let work = root.join("work");
    let bad = work.join("bad.toml");
    std::fs::write(&bad, quick_tip().replace("length = 1.15", "length = -1.0")).unwrap();
    let keep = work.join("keep.csv");
    std::fs::write(&keep, "precious\n").unwrap();
    let out = xtask(&work, &["simulate", "bad.toml", "--history", "keep.csv"]);
    assert!(!out.status.success());
    assert_eq!(std::fs::read_to_string(&keep).unwrap(), "precious\n");
    // --field on a half-space (no field): refused, nothing replaced (before: emptied).
    std::fs::write(work.join("half.toml"), validation("half-space-r10.toml")).unwrap();
    let out = xtask(&work, &["simulate", "half.toml", "--field", "keep.csv"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no field along it"));
    assert_eq!(std::fs::read_to_string(&keep).unwrap(), "precious\n");
    // No temporary file is left behind.
    assert_eq!(tree(&work).len(), 3, "{:?}", tree(&work));
    std::fs::remove_dir_all(&root).ok();
}

#[test]
fn outputs_that_collide_with_each_other_or_an_input_are_refused_before_the_run() {
    let root = scratch("collide");
    let work = root.join("work");
    std::fs::write(work.join("scene.toml"), quick_tip()).unwrap();
    std::fs::create_dir_all(work.join("pl")).unwrap();
    std::fs::write(work.join("h.csv"), "old\n").unwrap();
    std::fs::write(work.join("pl").join("mine.csv"), "old\n").unwrap();
    std::fs::hard_link(work.join("scene.toml"), work.join("alias.csv")).unwrap();
    let before = tree(&work);
    for (args, says) in [
        // The same file twice (before: exit 0 and the history gone).
        (vec!["--history", "h.csv", "--field", "./h.csv"], "is also"),
        // A history inside the plots folder (a figure's table would replace it).
        (vec!["--history", "pl/mine.csv", "--plots", "pl"], "holds"),
        // A hard link of the scene (before: the scene emptied).
        (vec!["--history", "alias.csv"], "an input of this run"),
    ] {
        let mut all = vec!["simulate", "scene.toml"];
        all.extend(&args);
        let out = xtask(&work, &all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && stderr.contains(says), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?} ran");
    }
    assert_eq!(tree(&work), before);
    assert_eq!(std::fs::read_to_string(work.join("h.csv")).unwrap(), "old\n");
    assert_eq!(std::fs::read_to_string(work.join("scene.toml")).unwrap(), quick_tip());
    // A scene kept in a sweep's output folder under the name of its table: refused, kept.
    let sweep = work.join("sw");
    std::fs::create_dir_all(&sweep).unwrap();
    std::fs::write(sweep.join("sweep.csv"), quick_tip()).unwrap();
    let out = xtask(
        &work,
        &["sweep", "sw/sweep.csv", "--set", "impact.drop_height=0.1:0.2:2", "--out", "sw"],
    );
    assert!(!out.status.success(), "{}", String::from_utf8_lossy(&out.stdout));
    assert!(String::from_utf8_lossy(&out.stderr).contains("an input of this run"));
    assert_eq!(std::fs::read_to_string(sweep.join("sweep.csv")).unwrap(), quick_tip());
    std::fs::remove_dir_all(&root).ok();
}

#[cfg(unix)]
#[test]
fn a_link_in_an_output_folder_is_replaced_not_followed() {
    // Before: --plots pl, with pl/contact_force.svg a link to a file outside pl, wrote the
    // figure into that file.
    let root = scratch("link");
    let work = root.join("work");
    std::fs::write(work.join("scene.toml"), quick_tip()).unwrap();
    let outside = root.join("outside.txt");
    std::fs::write(&outside, "keep me\n").unwrap();
    std::fs::create_dir_all(work.join("pl")).unwrap();
    for name in ["contact_force.svg", "contact_force.csv"] {
        std::os::unix::fs::symlink(&outside, work.join("pl").join(name)).unwrap();
    }
    let out = xtask(&work, &["simulate", "scene.toml", "--plots", "pl"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(std::fs::read_to_string(&outside).unwrap(), "keep me\n");
    for name in ["contact_force.svg", "contact_force.csv"] {
        let meta = std::fs::symlink_metadata(work.join("pl").join(name)).unwrap();
        assert!(meta.file_type().is_file(), "{name} is still a link");
    }
    std::fs::remove_dir_all(&root).ok();
}

#[test]
#[cfg(unix)]
fn a_stopped_run_removes_its_unfinished_files_and_leaves_the_old_ones() {
    // Ctrl-C or a kill's SIGTERM during `simulate --history` had left the hidden temporary
    // files (created before the run, up to 18 MB when stopped while writing) that nothing
    // removed (a review's). A long fe run is stopped once its temporaries exist.
    let root = scratch("stopped");
    let work = root.join("work");
    let slow = validation("paper-tip.toml")
        .replace("modes = 128", "elements = 64")
        .replace("method = \"modal\"", "method = \"fe\"")
        .replace("end_time = 0.005", "end_time = 1.0");
    std::fs::write(work.join("slow.toml"), slow).unwrap();
    std::fs::write(work.join("h.csv"), "the earlier history\n").unwrap();
    for signal in ["-INT", "-TERM"] {
        let child = Command::new(XTASK)
            .args(["simulate", "slow.toml", "--history", "h.csv"])
            .current_dir(&work)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let hidden = || tree(&work).iter().any(|p| p.to_string_lossy().starts_with(".h.csv.tmp"));
        let start = std::time::Instant::now();
        while !hidden() {
            assert!(start.elapsed().as_secs() < 60, "no temporary file appeared");
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let pid = child.id().to_string();
        assert!(Command::new("kill").args([signal, &pid]).status().unwrap().success());
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(130), "{signal}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("unfinished output(s) removed"));
        assert!(!hidden(), "{signal}: {:?}", tree(&work));
        assert_eq!(std::fs::read_to_string(work.join("h.csv")).unwrap(), "the earlier history\n");
    }
    std::fs::remove_dir_all(&root).ok();
}

#[test]
fn a_page_shows_only_its_own_run_s_figures() {
    // A beam run's plots, then a half-space's into the same folder: the half-space has no
    // stress, and its page had shown the beam run's stress figures left there (a review's).
    let root = scratch("page");
    let work = root.join("work");
    std::fs::write(work.join("tip.toml"), quick_tip()).unwrap();
    std::fs::write(work.join("block.toml"), validation("half-space-r10.toml")).unwrap();
    assert!(xtask(&work, &["simulate", "tip.toml", "--plots", "p"]).status.success());
    assert!(work.join("p/stress_map.svg").exists());
    assert!(xtask(&work, &["simulate", "block.toml", "--plots", "p"]).status.success());
    let page = std::fs::read_to_string(work.join("p/index.html")).unwrap();
    assert!(!page.contains("stress_map") && !work.join("p/stress_map.svg").exists(), "{page}");
    assert!(!work.join("p/stress_map.csv").exists() && page.contains("contact_force.svg"));
    std::fs::remove_dir_all(&root).ok();
}

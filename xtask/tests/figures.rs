//! Every figure the commands draw, checked for what a reader trips on (`check-figures`: tick
//! labels past six significant digits, "us" for microseconds, an axis without its unit, a
//! legend over a curve or a marker, two series drawn alike): `reproduce --quick`,
//! `simulate --plots`, `compare`, `accuracy --quick` and a sweep over two keys.
#![allow(clippy::unwrap_used, clippy::expect_used)] // a test stops on a broken fixture

use std::path::Path;
use std::process::Command;

const XTASK: &str = env!("CARGO_BIN_EXE_xtask");

fn scene(file: &str) -> String {
    format!("{}/../validation/scenes/{file}", env!("CARGO_MANIFEST_DIR"))
}

fn run(args: &[&str]) -> String {
    let out = Command::new(XTASK).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "xtask {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn count_svgs(dir: &Path) -> usize {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            if p.is_dir() {
                count_svgs(&p)
            } else {
                usize::from(p.extension().is_some_and(|e| e == "svg"))
            }
        })
        .sum()
}

#[test]
fn every_figure_of_every_command_reads_at_a_glance() {
    let root = std::env::temp_dir().join(format!("xtask-figures-{}", std::process::id()));
    std::fs::remove_dir_all(&root).ok();
    let out = |sub: &str| root.join(sub).display().to_string();
    let tip = scene("paper-tip.toml");
    let half_space = scene("half-space-r10.toml");
    run(&["reproduce", "--quick", "--out", &out("reproduce")]);
    run(&["simulate", &tip, "--plots", &out("simulate")]);
    run(&["compare", &tip, "--modes", "16", "--elements", "20", "--out", &out("compare")]);
    run(&["accuracy", &tip, "--quick", "--out", &out("accuracy")]);
    run(&[
        "sweep",
        &half_space,
        "--set",
        "impact.speed=0.5:2:4",
        "--set",
        "ball.radius=0.005:0.01:2",
        "--out",
        &out("sweep"),
    ]);
    // Each command drew all its figures (a figure it stopped drawing would go unchecked); the
    // half-space sweep has no beam, so no figure of the displacement at the impact point.
    let drawn: Vec<usize> = ["reproduce", "simulate", "compare", "accuracy", "sweep"]
        .iter()
        .map(|d| count_svgs(&root.join(d)))
        .collect();
    assert_eq!(drawn, [13, 6, 3, 1, 4], "figures per command");
    let report = Command::new(XTASK).args(["check-figures", &out("")]).output().unwrap();
    let said = String::from_utf8_lossy(&report.stdout);
    assert!(report.status.success(), "{said}");
    assert!(said.contains("27 figure(s) checked"), "{said}");
    std::fs::remove_dir_all(&root).ok();
}

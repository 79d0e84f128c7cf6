//! `cargo xtask sweep SCENE.toml --set KEY=START:STOP:COUNT ...`: one scene over a grid of
//! values of any of its keys, on every core, in shards for a cluster, merged back into one
//! table; stopped and resumed without losing a finished point.
//!
//! The grid, its shards, each point's scene and the table's columns are
//! [`impact::study::grid`]'s; this module runs the points and keeps the files. Before the first
//! point runs, every point's scene is validated, the output folder is created and proven
//! writable, and `sweep.json` (the [`Manifest`]: which sweep, which shard) is written. Each
//! finished point is appended to `sweep.partial.csv` and synced to disk at once, in the order the
//! points finish; when the last is done the rows are sorted into `sweep.csv` (written whole and
//! renamed into place), `sweep.svg` drawn, and the partial file removed. A folder holding
//! `sweep.partial.csv` is unfinished: `--resume` runs only its missing points.

use crate::files::{read_input, say, write_atomic, OutDir};
use crate::plot::{Chart, Series};
use anyhow::{bail, ensure, Context};
use impact::study::{Axis, Grid, Manifest, Shard};
use impact::{Report, Scene};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

const MANIFEST: &str = "sweep.json";
const PARTIAL: &str = "sweep.partial.csv";
const TABLE: &str = "sweep.csv";

/// `work` on every item in parallel (rayon), with a progress bar labelled `label` on standard
/// error; the results in the items' order. The one way the toolkit runs many scenes.
pub(crate) fn par_run<I: Sync, T: Send>(
    label: &str,
    items: &[I],
    work: impl Fn(&I) -> T + Sync,
) -> Vec<T> {
    let bar = progress_bar(label, items.len());
    let out = items
        .par_iter()
        .map(|item| {
            let result = work(item);
            bar.inc(1);
            result
        })
        .collect();
    bar.finish_and_clear();
    out
}

/// A progress bar on standard error (shown on a terminal only) for `len` items, labelled
/// `label`.
pub(crate) fn progress_bar(label: &str, len: usize) -> ProgressBar {
    let bar = ProgressBar::new(len as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix:>28} [{bar:30}] {pos}/{len} {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_prefix(label.to_owned());
    bar
}

/// The scenes of every point of the grid of `axes` over `base` (validated), in grid order.
pub(crate) fn scenes(base: &toml::Table, axes: Vec<Axis>) -> anyhow::Result<Vec<Scene>> {
    let grid = Grid::new(axes)?;
    (0..grid.len()).map(|i| Ok(grid.scene(base, i)?)).collect()
}

/// What `cargo xtask sweep SCENE` was asked.
pub(crate) struct Request<'a> {
    pub scene: &'a Path,
    pub sets: &'a [String],
    pub log: &'a [String],
    pub out: Option<&'a Path>,
    pub shard: Option<&'a str>,
    /// Complete an unfinished sweep in the output folder.
    pub resume: bool,
    /// Run at most this many points now (the rest with --resume later).
    pub limit: Option<usize>,
}

/// The sweep's runner: a scene to its report (the solver, or a stand-in in tests).
type Runner<'a> = &'a (dyn Fn(&Scene) -> anyhow::Result<Report> + Sync);

/// `cargo xtask sweep`.
pub(crate) fn run(request: &Request<'_>) -> anyhow::Result<bool> {
    run_with(request, &|s| Ok(impact::simulate(s)?.report))
}

/// `runner`'s report of one point; a panic (which the library should never raise) is that
/// point's error, not the sweep's end: a point that panicked had killed the whole sweep, and
/// its `--resume` again, so that the sweep could never finish (a review's, at one element).
fn guarded(runner: Runner<'_>, s: &Scene) -> anyhow::Result<Report> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| runner(s))) {
        Ok(report) => report,
        Err(panic) => Err(impact::ImpactError::from_panic(panic.as_ref()).into()),
    }
}

fn run_with(request: &Request<'_>, runner: Runner<'_>) -> anyhow::Result<bool> {
    let path = request.scene;
    let text = read_input(path, "scene file")?;
    let scene = Scene::from_toml(&text).with_context(|| format!("in {}", path.display()))?;
    let base: toml::Table =
        toml::from_str(&text).with_context(|| format!("in {}", path.display()))?;
    let axes =
        request.sets.iter().map(|s| Axis::parse(s, request.log)).collect::<Result<Vec<_>, _>>()?;
    for k in request.log {
        ensure!(
            axes.iter().any(|a| a.key == *k),
            "--log {}: not a swept key",
            impact::study::printable(k)
        );
    }
    let grid = Grid::new(axes)?;
    let shard = request.shard.map(Shard::parse).transpose()?.unwrap_or(Shard::WHOLE);
    let mine: Vec<usize> = shard.points(grid.len()).collect();
    let scenes = mine
        .iter()
        .map(|&i| Ok((i, grid.scene(&base, i)?)))
        .collect::<anyhow::Result<BTreeMap<usize, Scene>>>()?;
    let dir = OutDir::create(&crate::files::out_dir("sweep", &scene.name, request.out)?)?;
    let manifest = Manifest::new(&base, &grid, shard);
    let done = start(&dir, &manifest, request.resume)?;
    let clock = std::time::Instant::now();
    let todo: Vec<(usize, &Scene)> = scenes
        .iter()
        .filter(|(i, _)| !done.contains_key(i))
        .take(request.limit.unwrap_or(usize::MAX))
        .map(|(i, s)| (*i, s))
        .collect();
    let journal = Mutex::new(
        std::fs::OpenOptions::new()
            .append(true)
            .open(dir.join(PARTIAL))
            .with_context(|| format!("cannot append to {}", dir.join(PARTIAL).display()))?,
    );
    let written: Vec<anyhow::Result<()>> = par_run("sweep", &todo, |(i, scene)| {
        let result = guarded(runner, scene);
        let error = result.as_ref().err().map(|e| format!("{e:#}"));
        let cells = grid.row(*i, result.as_ref().map_err(|_| error.as_deref().unwrap_or("")));
        let line = csv_line(&cells)?;
        let mut file = journal.lock().map_err(|_| anyhow::anyhow!("a run panicked"))?;
        // One unbuffered write of the whole row: a stopped sweep keeps every row it finished,
        // and a row cut by a kill has no line end and is dropped on --resume. Synced, so that
        // a machine that stops (power, a node taken back) keeps it too (a fraction of a
        // millisecond a row, against runs of milliseconds to minutes).
        file.write_all(&line)
            .and_then(|()| file.sync_data())
            .with_context(|| format!("cannot write {}", dir.join(PARTIAL).display()))
    });
    written.into_iter().collect::<anyhow::Result<()>>()?;
    let rows = read_rows(&dir.join(PARTIAL), &manifest)?;
    let failed = rows.values().filter(|r| r.last().is_some_and(|e| !e.is_empty())).count();
    let shown = dir.path().display();
    if rows.len() < mine.len() {
        say!(
            "{} of {} points done ({} now, {failed} failed) in {:.2} s; the rows so far are in {shown}/{PARTIAL}: run again with --resume to finish",
            rows.len(),
            mine.len(),
            todo.len(),
            clock.elapsed().as_secs_f64()
        )?;
        return Ok(true);
    }
    let figure = finish(&dir, &manifest, &rows)?;
    crate::files::remove_output(&dir.join(PARTIAL))?;
    let what = match (mine.is_empty(), figure) {
        (true, _) => format!(
            "shard {}/{} holds no point of the {}-point grid: wrote a header-only {shown}/{TABLE}",
            shard.k,
            shard.n,
            grid.len()
        ),
        (false, true) => format!("{shown}/{TABLE} and sweep.svg"),
        (false, false) => format!("{shown}/{TABLE} (no figure: no finite value to draw)"),
    };
    say!(
        "{} point{} ({failed} failed; {} run now) in {:.2} s: {what}",
        rows.len(),
        if rows.len() == 1 { "" } else { "s" },
        todo.len(),
        clock.elapsed().as_secs_f64()
    )?;
    Ok(true)
}

/// Prepares `dir` for the sweep of `manifest`: a fresh start writes the manifest and the
/// partial table's header; `--resume` checks the manifest and returns the finished rows.
fn start(
    dir: &OutDir,
    manifest: &Manifest,
    resume: bool,
) -> anyhow::Result<BTreeMap<usize, Vec<String>>> {
    let partial = dir.join(PARTIAL);
    let shown = dir.path().display();
    if resume {
        let earlier = read_manifest(dir.path())?;
        ensure!(
            earlier.check_same_sweep(manifest).is_ok() && earlier.shard == manifest.shard,
            "{shown} holds another sweep (its scene, keys, values or shard differ): nothing to resume"
        );
        ensure!(
            partial.exists(),
            "{shown} holds no unfinished sweep ({PARTIAL} is missing): nothing to resume"
        );
        let rows = read_rows(&partial, manifest)?;
        // Rewritten without a row cut by a kill, so that appended rows start on a line.
        let mut text = csv_line(&manifest.header)?;
        for row in rows.values() {
            text.extend(csv_line(row)?);
        }
        write_atomic(&partial, &text)?;
        return Ok(rows);
    }
    ensure!(
        !partial.exists(),
        "{shown} holds an unfinished sweep ({PARTIAL}): add --resume to finish it, or remove the folder"
    );
    // A new sweep replaces the folder's earlier one: its table and figures go first (an
    // earlier sweep's figures had stayed beside a new table that drew none, a review's).
    clear(dir)?;
    write_atomic(&dir.join(MANIFEST), serde_json::to_string_pretty(manifest)?.as_bytes())?;
    write_atomic(&partial, &csv_line(&manifest.header)?)?;
    Ok(BTreeMap::new())
}

/// Removes a sweep's table and figures from `dir` (its manifest and journal stay).
fn clear(dir: &OutDir) -> anyhow::Result<()> {
    crate::files::remove_output(&dir.join(TABLE))?;
    crate::files::remove_output(&dir.join("sweep.svg"))?;
    for (name, ..) in DRAWN {
        crate::plot::remove_figure(dir.path(), &format!("sweep_{name}"))?;
    }
    Ok(())
}

/// One CSV record with its line end, fields quoted where needed.
fn csv_line(cells: &[String]) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(cells)?;
    Ok(w.into_inner()?)
}

fn read_manifest(dir: &Path) -> anyhow::Result<Manifest> {
    let path = dir.join(MANIFEST);
    let text = crate::files::read_own(&path, "sweep manifest")
        .with_context(|| format!("{} is no sweep's folder", dir.display()))?;
    serde_json::from_str(&text)
        .with_context(|| format!("{} is not a sweep manifest", path.display()))
}

/// The rows of a sweep table (`sweep.csv` or its partial form), by point: every row must have
/// the header's fields, numbers in the result columns, and belong to the folder's sweep (a
/// point of its grid and of its shard, with that point's swept values: `Manifest::check_row`);
/// an error names the file's line. In a partial table a last row without its line end (a run
/// stopped while writing it) is left out.
fn read_rows(path: &Path, manifest: &Manifest) -> anyhow::Result<BTreeMap<usize, Vec<String>>> {
    let header = &manifest.header;
    let shown = path.display();
    let mut text = std::fs::read(path).with_context(|| format!("cannot read {shown}"))?;
    if path.ends_with(PARTIAL) {
        let end = text.iter().rposition(|b| *b == b'\n').map_or(0, |i| i + 1);
        text.truncate(end);
    }
    let mut reader = csv::ReaderBuilder::new().flexible(true).from_reader(text.as_slice());
    let found: Vec<String> = reader
        .headers()
        .with_context(|| format!("{shown}: no header"))?
        .iter()
        .map(str::to_string)
        .collect();
    ensure!(&found == header, "{shown}: its columns are not the sweep's");
    let numbers = header.len() - 1 - impact::study::COLUMNS.len()..header.len() - 1;
    let mut rows = BTreeMap::new();
    for (row, record) in reader.records().enumerate() {
        let line =
            record.as_ref().ok().and_then(|r| r.position()).map_or(row as u64 + 2, |p| p.line());
        let at = format!("{shown}, line {line}");
        let record = record.with_context(|| at.clone())?;
        ensure!(
            record.len() == header.len(),
            "{at}: {} fields where the header has {}",
            record.len(),
            header.len()
        );
        let cells: Vec<String> = record.iter().map(str::to_string).collect();
        let point = manifest.check_row(&cells).with_context(|| at.clone())?;
        for c in numbers.clone() {
            ensure!(
                cells[c].is_empty() || cells[c].parse::<f64>().is_ok_and(f64::is_finite),
                "{at}: {} = {:?} is not a number",
                header[c],
                impact::study::printable(&cells[c])
            );
        }
        ensure!(rows.insert(point, cells).is_none(), "{at}: point {point} is there twice");
    }
    Ok(rows)
}

/// Writes the complete `sweep.csv` and `sweep.svg` of `rows`; whether the figure was drawn.
fn finish(
    dir: &OutDir,
    manifest: &Manifest,
    rows: &BTreeMap<usize, Vec<String>>,
) -> anyhow::Result<bool> {
    // The table last: a folder with it is finished (a merge stopped before it leaves none).
    let figure = chart(dir.path(), &manifest.header, rows)?;
    let mut text = csv_line(&manifest.header)?;
    for row in rows.values() {
        text.extend(csv_line(row)?);
    }
    write_atomic(&dir.join(TABLE), &text)?;
    Ok(figure)
}

/// The quantities drawn, each in a figure of its own: (column, axis label with its unit, scale
/// from the column's SI unit to the axis's).
const DRAWN: [(&str, &str, f64); 4] = [
    ("first_peak_force_n", "first contact's peak force (N)", 1.0),
    ("first_duration_s", "first contact's duration (µs)", 1e6),
    ("max_displacement_m", "largest displacement at the impact point (mm)", 1e3),
    ("restitution", "coefficient of restitution (-)", 1.0),
];

/// `sweep_<column>.svg` for each quantity of [`DRAWN`] the rows have (and that is not zero at
/// every point), against the first swept
/// key, one curve per value of the second (a sweep over two keys drawn against one would zig-zag
/// between them), and `sweep.svg`, the first of them. At most 16 values of the second key
/// get a curve (the figure's distinct styles); the table has every row.
fn chart(
    dir: &Path,
    header: &[String],
    rows: &BTreeMap<usize, Vec<String>>,
) -> anyhow::Result<bool> {
    let column = |name: &str| header.iter().position(|k| k == name);
    let keys = header.len().saturating_sub(2 + impact::study::COLUMNS.len());
    let (x_index, group_index) = (1, (keys >= 2).then_some(2));
    let number = |r: &Vec<String>, c: usize| r.get(c).and_then(|v| v.parse::<f64>().ok());
    let mut groups: Vec<String> = Vec::new();
    for r in rows.values() {
        let g = group_index.and_then(|c| r.get(c)).cloned().unwrap_or_default();
        if !groups.contains(&g) {
            groups.push(g);
        }
    }
    groups.truncate(16);
    let mut first = None;
    for (name, y_label, scale) in DRAWN {
        let Some(c) = column(name) else { continue };
        let series: Vec<Series> = groups
            .iter()
            .filter_map(|g| {
                let points: Vec<(f64, f64)> = rows
                    .values()
                    .filter(|r| group_index.and_then(|i| r.get(i)).is_none_or(|v| v == g))
                    .filter_map(|r| Some((number(r, x_index)?, number(r, c)? * scale)))
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .collect();
                let label = match group_index {
                    Some(i) => format!("{} = {g} {}", header[i], unit_of(&header[i])),
                    // One curve: the quantity as the axis says it (the column's SI name had
                    // read "first duration s" beside a µs axis, a review's).
                    None => y_label.to_string(),
                };
                (!points.is_empty()).then_some(Series { label, points })
            })
            .collect();
        // A quantity zero at every point is one the scene does not have (a half-space's beam
        // displacement): a flat line at 0 tells a reader nothing.
        if series.iter().all(|s| s.points.iter().all(|p| p.1 == 0.0)) {
            continue;
        }
        let title = format!("sweep: {y_label} against {}", header[x_index]);
        let x_label = format!("{} ({})", header[x_index], unit_of(&header[x_index]));
        let chart = Chart {
            title: &title,
            x_label: &x_label,
            y_label,
            series,
            markers: true,
            reference_first: false,
        };
        let stem = format!("sweep_{name}");
        chart.write(dir, &stem)?;
        if first.is_none() {
            // sweep.svg, the first figure again: not through the chart, which would write its
            // points as sweep.csv, the table's name (a stopped merge had left them there, a
            // review's).
            let svg = dir.join(format!("{stem}.svg"));
            let bytes =
                std::fs::read(&svg).with_context(|| format!("cannot read {}", svg.display()))?;
            write_atomic(&dir.join("sweep.svg"), &bytes)?;
            first = Some(name);
        }
    }
    if first.is_none() {
        crate::files::remove_output(&dir.join("sweep.svg"))?;
        return Ok(false);
    }
    Ok(true)
}

/// The SI unit of a scene key, from its last part (a sweep's values are as in the scene file).
fn unit_of(key: &str) -> &'static str {
    let last = key.rsplit('.').next().unwrap_or(key);
    match last {
        "speed" => "m/s",
        "drop_height" | "length" | "width" | "thickness" | "radius" | "position" | "offset"
        | "at" => "m",
        "mass" => "kg",
        "youngs_modulus" | "yield_stress" => "Pa",
        "density" => "kg/m^3",
        "end_time" | "time_step" | "output_interval" => "s",
        // Ratios and counts: no unit (a Poisson's ratio had been labelled "as in the scene
        // file", a review's).
        "poisson_ratio" | "restitution" | "tolerance" | "alpha" | "modes" | "elements"
        | "samples_per_pulse" => "-",
        _ => "as in the scene file",
    }
}

/// `cargo xtask sweep --merge DIR... --out DIR`: the shards' rows in point order, refused
/// unless the shards are finished parts of one sweep that together hold every point.
pub(crate) fn merge(dirs: &[PathBuf], out: &Path) -> anyhow::Result<bool> {
    ensure!(!dirs.is_empty(), "give the shards' folders to --merge");
    let mut first: Option<Manifest> = None;
    let mut shards: Vec<usize> = Vec::new();
    let mut rows: BTreeMap<usize, Vec<String>> = BTreeMap::new();
    for dir in dirs {
        let shown = dir.display();
        let manifest = read_manifest(dir)?;
        ensure!(
            !dir.join(PARTIAL).exists(),
            "{shown}: an unfinished shard ({PARTIAL}); finish it with --resume first"
        );
        match &first {
            None => first = Some(manifest.clone()),
            Some(m) => m.check_same_sweep(&manifest).with_context(|| format!("{shown}"))?,
        }
        ensure!(
            !shards.contains(&manifest.shard.k),
            "{shown}: shard {}/{} is given twice",
            manifest.shard.k,
            manifest.shard.n
        );
        shards.push(manifest.shard.k);
        let table = read_rows(&dir.join(TABLE), &manifest)?;
        let expected: Vec<usize> = manifest.expected_points().collect();
        for (point, row) in table {
            ensure!(
                expected.binary_search(&point).is_ok(),
                "{shown}: point {point} is not in shard {}/{}",
                manifest.shard.k,
                manifest.shard.n
            );
            ensure!(rows.insert(point, row).is_none(), "point {point} is in two shards");
        }
    }
    let Some(manifest) = first else { bail!("give the shards' folders to --merge") };
    let missing: Vec<usize> = (0..manifest.points).filter(|p| !rows.contains_key(p)).collect();
    if !missing.is_empty() {
        let absent: Vec<String> = (1..=manifest.shard.n)
            .filter(|k| !shards.contains(k))
            .map(|k| format!("{k}/{}", manifest.shard.n))
            .collect();
        let listed: Vec<String> = missing.iter().take(12).map(usize::to_string).collect();
        bail!(
            "{} of the {} points are missing ({}{}){}",
            missing.len(),
            manifest.points,
            listed.join(", "),
            if missing.len() > 12 { ", ..." } else { "" },
            if absent.is_empty() {
                String::new()
            } else {
                format!(": shard(s) {} not given", absent.join(", "))
            }
        );
    }
    let whole = Manifest { shard: Shard::WHOLE, ..manifest };
    // Before anything is removed: a merge into one of its own shards had cleared that shard's
    // table and figures and only then been refused (its rows lost), and one into a folder
    // holding an unfinished sweep had overwritten its manifest and orphaned its journal (a
    // review's).
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    if let Some(shard) = dirs.iter().find(|d| same(d, out)) {
        bail!(
            "--out {} is one of the shards given to --merge: give another folder",
            shard.display()
        );
    }
    ensure!(
        !out.join(PARTIAL).exists(),
        "{} holds an unfinished sweep ({PARTIAL}): finish it with --resume, or merge into another folder",
        out.display()
    );
    let dir = OutDir::create(out)?;
    // The earlier table and figures first, then the manifest, the table last: a stopped merge
    // into a folder that held a sweep had left the new manifest over the old rows (and a later
    // merge took them as the new sweep's), or a figure's points as sweep.csv (a review's).
    clear(&dir)?;
    write_atomic(&dir.join(MANIFEST), serde_json::to_string_pretty(&whole)?.as_bytes())?;
    finish(&dir, &whole, &rows)?;
    say!("{} rows from {} shard(s) into {}/{TABLE}", rows.len(), dirs.len(), out.display())?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    const SCENE: &str =
        concat!(env!("CARGO_MANIFEST_DIR"), "/../validation/scenes/half-space-r10.toml");

    fn scratch(name: &str) -> PathBuf {
        let root = std::env::temp_dir().join(format!("sweep-{name}-{}", std::process::id()));
        std::fs::remove_dir_all(&root).ok();
        root
    }

    /// The solver with its wall time zeroed: the one column that differs between runs.
    fn timeless(s: &Scene) -> anyhow::Result<Report> {
        let mut r = impact::simulate(s)?.report;
        r.wall_time = 0.0;
        Ok(r)
    }

    fn request<'a>(sets: &'a [String], out: &'a Path) -> Request<'a> {
        Request {
            scene: Path::new(SCENE),
            sets,
            log: &[],
            out: Some(out),
            shard: None,
            resume: false,
            limit: None,
        }
    }

    fn read(dir: &Path) -> String {
        std::fs::read_to_string(dir.join(TABLE)).unwrap()
    }

    #[test]
    fn an_interrupted_sweep_keeps_its_rows_and_resumes_to_the_whole_table() {
        let root = scratch("resume");
        let sets = ["impact.speed=0.5:2:7".to_string()];
        let whole = root.join("whole");
        run_with(&request(&sets, &whole), &timeless).unwrap();
        let parts = root.join("parts");
        // Stopped after 3 points: their rows are kept, flagged partial, no final table.
        run_with(&Request { limit: Some(3), ..request(&sets, &parts) }, &timeless).unwrap();
        let partial = std::fs::read_to_string(parts.join(PARTIAL)).unwrap();
        assert_eq!(partial.lines().count(), 4, "{partial}");
        assert!(!parts.join(TABLE).exists());
        // A rerun without --resume must not throw the finished rows away.
        let e = run_with(&request(&sets, &parts), &timeless).unwrap_err().to_string();
        assert!(e.contains("--resume"), "{e}");
        // A row cut by a kill is dropped and rerun.
        let mut cut = partial.clone();
        cut.push_str("5,1.75,1.7");
        std::fs::write(parts.join(PARTIAL), &cut).unwrap();
        // A row outside the grid in the journal is refused by its line, the journal kept.
        let row = partial.lines().nth(1).unwrap().split_once(',').unwrap().1;
        std::fs::write(parts.join(PARTIAL), format!("{partial}9,{row}\n")).unwrap();
        let e = format!(
            "{:#}",
            run_with(&Request { resume: true, ..request(&sets, &parts) }, &timeless).unwrap_err()
        );
        assert!(e.contains("line 5: point 9 is not in the grid"), "{e}");
        assert!(parts.join(PARTIAL).exists());
        std::fs::write(parts.join(PARTIAL), &cut).unwrap();
        // A resume of another sweep is refused.
        let other = ["impact.speed=0.5:2:8".to_string()];
        let e = run_with(&Request { resume: true, ..request(&other, &parts) }, &timeless)
            .unwrap_err()
            .to_string();
        assert!(e.contains("another sweep"), "{e}");
        // The runner refuses to run a finished point twice.
        let ran = Mutex::new(Vec::new());
        let counting = |s: &Scene| {
            ran.lock().unwrap().push(s.impact.speed);
            timeless(s)
        };
        run_with(&Request { resume: true, ..request(&sets, &parts) }, &counting).unwrap();
        assert_eq!(ran.lock().unwrap().len(), 4);
        assert_eq!(read(&parts), read(&whole));
        assert!(!parts.join(PARTIAL).exists());
        std::fs::remove_dir_all(&root).ok();
    }

    #[test]
    fn merged_shards_rebuild_the_whole_table_and_bad_shards_are_refused() {
        let root = scratch("merge");
        let sets = ["impact.speed=0.5:2:7".to_string()];
        run_with(&request(&sets, &root.join("whole")), &timeless).unwrap();
        let dirs: Vec<PathBuf> = (1..=3).map(|k| root.join(format!("shard{k}"))).collect();
        for (k, dir) in dirs.iter().enumerate() {
            let spec = format!("{}/3", k + 1);
            run_with(&Request { shard: Some(&spec), ..request(&sets, dir) }, &timeless).unwrap();
        }
        merge(&dirs, &root.join("merged")).unwrap();
        assert_eq!(read(&root.join("merged")), read(&root.join("whole")));
        let refused = |dirs: &[PathBuf], says: &str| {
            let e = format!("{:#}", merge(dirs, &root.join("refused")).unwrap_err());
            assert!(e.contains(says), "{says}: {e}");
        };
        refused(&[dirs[0].clone(), dirs[0].clone()], "given twice");
        // Into one of its own shards: refused before anything there is touched.
        let e = format!("{:#}", merge(&dirs, &dirs[1]).unwrap_err());
        assert!(e.contains("is one of the shards"), "{e}");
        assert!(dirs[1].join(TABLE).exists() && dirs[1].join("sweep.svg").exists());
        // Into a folder holding an unfinished sweep: refused, its journal kept.
        let unfinished = root.join("unfinished");
        run_with(&Request { limit: Some(1), ..request(&sets, &unfinished) }, &timeless).unwrap();
        let e = format!("{:#}", merge(&dirs, &unfinished).unwrap_err());
        assert!(e.contains("holds an unfinished sweep"), "{e}");
        assert!(unfinished.join(PARTIAL).exists());
        refused(&dirs[..2], "2 of the 7 points are missing (2, 5): shard(s) 3/3 not given");
        // A shard of another sweep.
        let other = root.join("other");
        let other_sets = ["impact.speed=0.5:3:7".to_string()];
        run_with(&Request { shard: Some("3/3"), ..request(&other_sets, &other) }, &timeless)
            .unwrap();
        refused(&[dirs[0].clone(), dirs[1].clone(), other], "two different sweeps");
        // Damaged tables: a missing field, a half-written number, junk, no manifest.
        let table = read(&dirs[2]);
        let damaged = |text: &str, says: &str| {
            std::fs::write(dirs[2].join(TABLE), text).unwrap();
            refused(&dirs, says);
        };
        let mut rows: Vec<&str> = table.lines().collect();
        let short = rows[1].rsplit_once(',').unwrap().0.to_string();
        rows[1] = &short;
        damaged(&(rows.join("\n") + "\n"), "fields where the header has");
        // Point 2's impact speed, 1 m/s, cut inside its number.
        let half = table.replacen("1.000000000e0,", "1.00000e,", 1);
        damaged(&half, "is not a number");
        damaged("junk", "columns are not the sweep's");
        // Rows that are not the shard's: a swept value edited (it no longer matches its
        // point), a point of another shard, a point past the grid; each named by its line.
        let edit = |line: usize, field: usize, to: &str| {
            let mut lines: Vec<String> = table.lines().map(str::to_string).collect();
            let mut cells: Vec<String> = lines[line - 1].split(',').map(str::to_string).collect();
            cells[field] = to.to_string();
            lines[line - 1] = cells.join(",");
            lines.join("\n") + "\n"
        };
        damaged(
            &edit(3, 1, "1.5"),
            "line 3: point 5 has impact.speed = 1.5, where the grid has 1.75",
        );
        damaged(&edit(2, 0, "3"), "line 2: point 3 is not in shard 3/3");
        damaged(&edit(2, 0, "8"), "line 2: point 8 is not in the grid (it has 7 points)");
        std::fs::write(dirs[2].join(TABLE), table).unwrap();
        std::fs::remove_file(dirs[2].join(MANIFEST)).unwrap();
        refused(&dirs, "no sweep's folder");
        std::fs::remove_dir_all(&root).ok();
    }

    #[test]
    fn an_empty_shard_says_so_and_a_failed_run_keeps_its_row() {
        let root = scratch("empty");
        let sets = ["impact.speed=0.5,1,2".to_string()];
        let dir = root.join("empty");
        run_with(&Request { shard: Some("5/7"), ..request(&sets, &dir) }, &timeless).unwrap();
        assert_eq!(read(&dir).lines().count(), 1);
        assert!(!dir.join("sweep.svg").exists());
        let dir = root.join("failing");
        let failing = |s: &Scene| {
            anyhow::ensure!(s.impact.speed != Some(1.0), "the solver failed\nhere, \"quoted\"");
            timeless(s)
        };
        run_with(&request(&sets, &dir), &failing).unwrap();
        let rows = read_rows(&dir.join(TABLE), &read_manifest(&dir).unwrap()).unwrap();
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[&1].last().unwrap(), "the solver failed\\u{a}here, \"quoted\"");
        assert!(rows[&0].last().unwrap().is_empty() && rows[&2].last().unwrap().is_empty());
        // A new sweep in a folder that held another: none of the earlier figures stay (one
        // with a displacement, then the half-space's, which has none to draw).
        let dir = root.join("reused");
        let moving = |s: &Scene| {
            let mut r = timeless(s)?;
            r.max_displacement = 1e-3 * s.impact.speed.unwrap_or(1.0);
            Ok(r)
        };
        run_with(&request(&sets, &dir), &moving).unwrap();
        let drawn = dir.join("sweep_max_displacement_m.svg");
        assert!(drawn.exists());
        run_with(&request(&["impact.speed=1,3".to_string()], &dir), &timeless).unwrap();
        assert!(!drawn.exists() && !dir.join("sweep_max_displacement_m.csv").exists());
        assert_eq!(read(&dir).lines().count(), 3);
        // A point whose run panics is that point's error: the sweep finishes (it had died,
        // and its --resume again, a review's).
        let dir = root.join("panicking");
        let panicking = |s: &Scene| {
            assert!(s.impact.speed != Some(2.0), "index out of bounds");
            timeless(s)
        };
        run_with(&request(&sets, &dir), &panicking).unwrap();
        let rows = read_rows(&dir.join(TABLE), &read_manifest(&dir).unwrap()).unwrap();
        assert!(rows[&2].last().unwrap().starts_with("internal error"), "{:?}", rows[&2]);
        assert!(rows[&0].last().unwrap().is_empty());
        std::fs::remove_dir_all(&root).ok();
    }
}

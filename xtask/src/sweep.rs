//! `cargo xtask sweep SCENE.toml --set KEY=START:STOP:COUNT ...`: one scene over a grid of
//! values of any of its keys, on every core, in shards for a cluster, merged back into one table.
//!
//! Every point is a scene file with the swept keys replaced, validated like one before anything
//! runs; the runs go in parallel (rayon) with a progress bar on standard error; a run that fails
//! leaves its row with the reason. `sweep.csv` has the point's number, the swept keys, then the
//! report's scalars with their units; `sweep.svg` draws the main ones against the first key.

use crate::plot::{Chart, Series};
use anyhow::{bail, ensure, Context};
use impact::{Plan, Report, Scene};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// One swept key and its values.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Axis {
    key: String,
    values: Vec<toml::Value>,
}

/// A point of the grid: its number and the value of each swept key.
type Point = (usize, Vec<(String, toml::Value)>);

impl Axis {
    /// The key `key` (dotted) over `values`.
    pub(crate) fn new(key: &str, values: impl IntoIterator<Item = toml::Value>) -> Self {
        Self { key: key.to_string(), values: values.into_iter().collect() }
    }
}

/// The scenes of every point of the grid of `axes` over `base` (validated), in grid order.
pub(crate) fn scenes(base: &toml::Table, axes: &[Axis]) -> anyhow::Result<Vec<Scene>> {
    grid(axes).iter().map(|p| point_scene(base, p)).collect()
}

/// `work` on every item in parallel (rayon), with a progress bar labelled `label` on standard
/// error; the results in the items' order. The one way the toolkit runs many scenes.
pub(crate) fn par_run<I: Sync, T: Send>(
    label: &str,
    items: &[I],
    work: impl Fn(&I) -> T + Sync,
) -> Vec<T> {
    let bar = ProgressBar::new(items.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix:>28} [{bar:30}] {pos}/{len} {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_prefix(label.to_owned());
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

/// `KEY=START:STOP:COUNT` (COUNT values, evenly spaced, or geometrically for a key in `log`)
/// or `KEY=v1,v2,...` (numbers, true/false, or names).
pub(crate) fn parse_set(spec: &str, log: &[String]) -> anyhow::Result<Axis> {
    let (key, values) = spec
        .split_once('=')
        .with_context(|| format!("--set {spec}: expected KEY=START:STOP:COUNT or KEY=v1,v2,..."))?;
    let key = key.trim().to_string();
    ensure!(!key.is_empty(), "--set {spec}: the key is empty");
    let parts: Vec<&str> = values.split(':').collect();
    let values = if parts.len() == 3 {
        let number = |s: &str, what: &str| -> anyhow::Result<f64> {
            let v: f64 = s
                .trim()
                .parse()
                .with_context(|| format!("--set {spec}: {what} = {s:?} is not a number"))?;
            ensure!(v.is_finite(), "--set {spec}: {what} = {s} is not finite");
            Ok(v)
        };
        let (start, stop) = (number(parts[0], "START")?, number(parts[1], "STOP")?);
        let count: usize = parts[2].trim().parse().with_context(|| {
            format!("--set {spec}: COUNT = {:?} is not a whole number", parts[2])
        })?;
        ensure!(
            (1..=1_000_000).contains(&count),
            "--set {spec}: COUNT = {count}: allowed 1 to 1000000"
        );
        let geometric = log.contains(&key);
        ensure!(
            !geometric || (start > 0.0 && stop > 0.0),
            "--set {spec}: a --log key needs START and STOP greater than 0"
        );
        (0..count)
            .map(|i| {
                let f = if count == 1 { 0.0 } else { i as f64 / (count - 1) as f64 };
                let v = if geometric {
                    start * (stop / start).powf(f)
                } else {
                    start + (stop - start) * f
                };
                toml::Value::Float(v)
            })
            .collect()
    } else {
        values.split(',').map(|v| value(v.trim())).collect()
    };
    Ok(Axis { key, values })
}

/// A value as written on the command line: an integer, a number, true/false, or a name.
fn value(text: &str) -> toml::Value {
    if let Ok(i) = text.parse::<i64>() {
        toml::Value::Integer(i)
    } else if let Ok(f) = text.parse::<f64>() {
        toml::Value::Float(f)
    } else if let Ok(b) = text.parse::<bool>() {
        toml::Value::Boolean(b)
    } else {
        toml::Value::String(text.to_string())
    }
}

/// Every combination of the axes' values, the first axis varying slowest, numbered from 0.
pub(crate) fn grid(axes: &[Axis]) -> Vec<Point> {
    let mut points: Vec<Vec<(String, toml::Value)>> = vec![Vec::new()];
    for axis in axes {
        points = points
            .into_iter()
            .flat_map(|p| {
                axis.values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push((axis.key.clone(), v.clone()));
                    q
                })
            })
            .collect();
    }
    points.into_iter().enumerate().collect()
}

/// The points of shard `k` of `n` (1-based): every n-th point from the k-th, so each shard
/// gets an even share of cheap and costly points.
pub(crate) fn shard(points: Vec<Point>, k: usize, n: usize) -> Vec<Point> {
    points.into_iter().filter(|(i, _)| i % n == k - 1).collect()
}

/// `K/N` with 1 <= K <= N.
pub(crate) fn parse_shard(text: &str) -> anyhow::Result<(usize, usize)> {
    let (k, n) = text.split_once('/').with_context(|| format!("--shard {text}: expected K/N"))?;
    let (k, n): (usize, usize) = (
        k.trim().parse().with_context(|| format!("--shard {text}: K is not a whole number"))?,
        n.trim().parse().with_context(|| format!("--shard {text}: N is not a whole number"))?,
    );
    ensure!(n >= 1 && (1..=n).contains(&k), "--shard {text}: allowed 1 <= K <= N");
    Ok((k, n))
}

/// The scene of one point: `base` with each swept key set.
pub(crate) fn point_scene(base: &toml::Table, point: &Point) -> anyhow::Result<Scene> {
    let mut table = base.clone();
    for (key, v) in &point.1 {
        let mut at = &mut table;
        let parts: Vec<&str> = key.split('.').collect();
        for part in &parts[..parts.len() - 1] {
            let entry = at
                .entry(part.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            at = entry.as_table_mut().with_context(|| {
                format!("point {}: {key}: {part} is not a table in the scene", point.0)
            })?;
        }
        at.insert(parts[parts.len() - 1].to_string(), v.clone());
    }
    let text = toml::to_string(&table)?;
    let scene = Scene::from_toml(&text)
        .with_context(|| format!("point {} ({})", point.0, describe(point)))?;
    Plan::new(&scene).with_context(|| format!("point {} ({})", point.0, describe(point)))?;
    Ok(scene)
}

fn describe(point: &Point) -> String {
    point.1.iter().map(|(k, v)| format!("{k} = {v}")).collect::<Vec<_>>().join(", ")
}

/// The report's scalars, with their units in the names.
const COLUMNS: [&str; 15] = [
    "impact_speed_m_s",
    "contact_count",
    "first_duration_s",
    "first_peak_force_n",
    "first_impulse_n_s",
    "first_print_radius_m",
    "restitution",
    "max_displacement_m",
    "equivalent_static_force_n",
    "energy_initial_j",
    "energy_dissipated_j",
    "energy_numerical_dissipation_j",
    "energy_balance_error_j",
    "estimated_error",
    "wall_time_s",
];

fn scalars(r: &Report) -> [Option<f64>; 15] {
    let first = r.contacts.first();
    [
        Some(r.impact_speed),
        Some(r.contact_count as f64),
        first.map(|c| c.duration),
        first.map(|c| c.peak_force),
        first.map(|c| c.impulse),
        first.map(|c| c.print_radius),
        r.restitution,
        Some(r.max_displacement),
        r.equivalent_static_force,
        Some(r.energy.initial),
        Some(r.energy.dissipated),
        Some(r.energy.numerical_dissipation),
        Some(r.energy.balance_error),
        r.estimated_error,
        Some(r.wall_time),
    ]
}

/// One row of `sweep.csv`.
fn row(point: &Point, result: &anyhow::Result<Report>) -> String {
    let mut cells = vec![point.0.to_string()];
    cells.extend(point.1.iter().map(|(_, v)| match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }));
    match result {
        Ok(r) => {
            cells
                .extend(scalars(r).iter().map(|x| x.map_or(String::new(), |v| format!("{v:.9e}"))));
            cells.push(String::new());
        }
        Err(e) => {
            cells.extend(std::iter::repeat_n(String::new(), COLUMNS.len()));
            cells.push(format!("\"{}\"", format!("{e:#}").replace('"', "'")));
        }
    }
    cells.join(",")
}

fn header(axes: &[String]) -> String {
    let mut h = vec!["point".to_string()];
    h.extend(axes.iter().cloned());
    h.extend(COLUMNS.iter().map(|c| c.to_string()));
    h.push("error".into());
    h.join(",")
}

/// Runs the points with `run` in parallel, a progress bar on standard error; the rows in point
/// order, a failed run's row saying why.
pub(crate) fn run_points(
    points: &[(Point, Scene)],
    run: impl Fn(&Scene) -> anyhow::Result<Report> + Sync,
) -> Vec<String> {
    par_run("sweep", points, |(p, scene)| row(p, &run(scene)))
}

/// Writes `sweep.csv` and `sweep.svg` into `dir`.
fn write(dir: &Path, header: &str, rows: &[String]) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let keys: Vec<&str> = header.split(',').collect();
    let column = |name: &str| keys.iter().position(|k| *k == name);
    let cells: Vec<Vec<&str>> = rows.iter().map(|r| r.split(',').collect()).collect();
    let x_index = 1;
    let series = ["first_peak_force_n", "first_duration_s", "max_displacement_m", "restitution"]
        .iter()
        .filter_map(|name| {
            let c = column(name)?;
            let points: Vec<(f64, f64)> = cells
                .iter()
                .filter_map(|r| Some((r.get(x_index)?.parse().ok()?, r.get(c)?.parse().ok()?)))
                .filter(|(x, y): &(f64, f64)| x.is_finite() && y.is_finite())
                .collect();
            let largest = points.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
            (largest > 0.0).then(|| Series {
                label: format!("{name} / {largest:.4e}"),
                points: points.iter().map(|(x, y)| (*x, y / largest)).collect(),
            })
        })
        .collect::<Vec<_>>();
    if !series.is_empty() && keys.len() > 1 {
        let title = format!("sweep over {}", keys[x_index]);
        let x_label = format!("{} (SI, as in the scene file)", keys[x_index]);
        Chart {
            title: &title,
            x_label: &x_label,
            y_label: "value / its largest (-)",
            series,
            markers: true,
        }
        .write(dir, "sweep")?;
    }
    let mut text = format!("{header}\n");
    for r in rows {
        text.push_str(r);
        text.push('\n');
    }
    let path = dir.join("sweep.csv");
    std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// `cargo xtask sweep`.
#[allow(clippy::print_stdout)]
pub(crate) fn run(
    scene_path: &Path,
    sets: &[String],
    log: &[String],
    out: Option<&Path>,
    shard_spec: Option<&str>,
) -> anyhow::Result<bool> {
    ensure!(!sets.is_empty(), "give at least one --set KEY=START:STOP:COUNT or KEY=v1,v2,...");
    let text = std::fs::read_to_string(scene_path)
        .with_context(|| format!("cannot read the scene file {}", scene_path.display()))?;
    let base: toml::Table =
        toml::from_str(&text).with_context(|| format!("in {}", scene_path.display()))?;
    let axes = sets.iter().map(|s| parse_set(s, log)).collect::<anyhow::Result<Vec<_>>>()?;
    for k in log {
        ensure!(axes.iter().any(|a| a.key == *k), "--log {k}: not a swept key");
    }
    let mut points = grid(&axes);
    if let Some(spec) = shard_spec {
        let (k, n) = parse_shard(spec)?;
        points = shard(points, k, n);
    }
    let scenes = points
        .into_iter()
        .map(|p| point_scene(&base, &p).map(|s| (p, s)))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let clock = std::time::Instant::now();
    let rows = run_points(&scenes, |s| impact::simulate(s).map(|o| o.report).map_err(Into::into));
    let name = scenes.first().map_or_else(|| "sweep".to_string(), |(_, s)| s.name.clone());
    let dir = out.map_or_else(|| Path::new("target/sweep").join(&name), Path::to_path_buf);
    let keys: Vec<String> = axes.iter().map(|a| a.key.clone()).collect();
    write(&dir, &header(&keys), &rows)?;
    let failed = rows.iter().filter(|r| !r.ends_with(',')).count();
    println!(
        "{} points ({} failed) in {:.2} s: {}/sweep.csv and sweep.svg",
        rows.len(),
        failed,
        clock.elapsed().as_secs_f64(),
        dir.display()
    );
    Ok(true)
}

/// `cargo xtask sweep --merge DIR... --out DIR`: the shards' rows in point order.
#[allow(clippy::print_stdout)]
pub(crate) fn merge(dirs: &[PathBuf], out: &Path) -> anyhow::Result<bool> {
    let mut header: Option<String> = None;
    let mut rows: Vec<(usize, String)> = Vec::new();
    for dir in dirs {
        let path = dir.join("sweep.csv");
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let mut lines = text.lines();
        let h = lines.next().with_context(|| format!("{} is empty", path.display()))?;
        match &header {
            None => header = Some(h.to_string()),
            Some(first) => {
                ensure!(first == h, "{}: its columns differ from the first shard's", path.display())
            }
        }
        for line in lines.filter(|l| !l.is_empty()) {
            let point: usize = line
                .split(',')
                .next()
                .and_then(|p| p.parse().ok())
                .with_context(|| format!("{}: a row without a point number", path.display()))?;
            rows.push((point, line.to_string()));
        }
    }
    let Some(header) = header else { bail!("give the shards' folders to --merge") };
    rows.sort_by_key(|r| r.0);
    if let Some(w) = rows.windows(2).find(|w| w[0].0 == w[1].0) {
        bail!("point {} is in two shards", w[0].0);
    }
    let rows: Vec<String> = rows.into_iter().map(|r| r.1).collect();
    write(out, &header, &rows)?;
    println!("{} rows from {} shard(s) into {}/sweep.csv", rows.len(), dirs.len(), out.display());
    Ok(true)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn sets_expand_into_a_grid_with_linear_log_and_listed_values() {
        let a = parse_set("impact.drop_height=0.1:0.5:5", &[]).unwrap();
        let heights: Vec<f64> = a.values.iter().map(|v| v.as_float().unwrap()).collect();
        for (h, want) in heights.iter().zip([0.1, 0.2, 0.3, 0.4, 0.5]) {
            assert!((h - want).abs() < 1e-15);
        }
        let b = parse_set("ball.radius=0.001:0.1:3", &["ball.radius".into()]).unwrap();
        let radii: Vec<f64> = b.values.iter().map(|v| v.as_float().unwrap()).collect();
        assert!((radii[1] - 0.01).abs() < 1e-15, "{radii:?}");
        let c = parse_set("contact.law=hertz,thornton", &[]).unwrap();
        assert_eq!(c.values[1], toml::Value::String("thornton".into()));
        let g = grid(&[a, c]);
        assert_eq!(g.len(), 10);
        assert_eq!(g[3].1[0].1.as_float(), Some(0.2));
        assert_eq!(g[3].1[1].1, toml::Value::String("thornton".into()));
        assert!(parse_set("impact.drop_height=1:2:0", &[]).is_err());
        assert!(parse_set("impact.drop_height=0:2:3", &["impact.drop_height".into()]).is_err());
        assert!(parse_set("nokey", &[]).is_err());
    }

    #[test]
    fn shards_hold_every_point_exactly_once() {
        let axis = parse_set("impact.speed=1:2:23", &[]).unwrap();
        let all = grid(&[axis]);
        let mut seen = vec![0; all.len()];
        for k in 1..=4 {
            for (i, _) in shard(all.clone(), k, 4) {
                seen[i] += 1;
            }
        }
        assert!(seen.iter().all(|n| *n == 1));
        assert!(parse_shard("0/4").is_err() && parse_shard("5/4").is_err());
        assert_eq!(parse_shard("2/4").unwrap(), (2, 4));
    }

    fn base() -> toml::Table {
        let text = std::fs::read_to_string(format!(
            "{}/../validation/scenes/half-space-r10.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap();
        toml::from_str(&text).unwrap()
    }

    #[test]
    fn a_bad_point_is_refused_before_anything_runs_and_a_failed_run_keeps_its_row() {
        // Validation names the point and the key.
        let bad = grid(&[parse_set("impact.speed=-1,1", &[]).unwrap()]);
        let message = format!("{:#}", point_scene(&base(), &bad[0]).unwrap_err());
        assert!(message.contains("point 0") && message.contains("impact.speed"), "{message}");
        // A run that fails: its row has the reason, the others their results.
        let points = grid(&[parse_set("impact.speed=0.5,1,2", &[]).unwrap()]);
        let scenes: Vec<_> =
            points.into_iter().map(|p| (p.clone(), point_scene(&base(), &p).unwrap())).collect();
        let rows = run_points(&scenes, |s| {
            anyhow::ensure!(s.impact.speed != Some(1.0), "the solver failed here");
            Ok(impact::simulate(s)?.report)
        });
        assert_eq!(rows.len(), 3);
        assert!(rows[1].contains("the solver failed here"), "{}", rows[1]);
        assert!(rows[0].ends_with(',') && rows[2].ends_with(','), "{rows:?}");
    }

    #[test]
    fn merged_shards_rebuild_the_whole_table() {
        let points = grid(&[parse_set("impact.speed=0.5:2:7", &[]).unwrap()]);
        let scenes: Vec<_> =
            points.iter().map(|p| (p.clone(), point_scene(&base(), p).unwrap())).collect();
        let report = |s: &Scene| {
            let mut r = impact::simulate(s)?.report;
            r.wall_time = 0.0; // the one column that differs between runs
            Ok(r)
        };
        let h = header(&["impact.speed".into()]);
        let root = std::env::temp_dir().join(format!("sweep-test-{}", std::process::id()));
        let whole = run_points(&scenes, report);
        write(&root.join("whole"), &h, &whole).unwrap();
        let mut dirs = Vec::new();
        for k in 1..=3 {
            let part: Vec<_> = scenes.iter().filter(|(p, _)| p.0 % 3 == k - 1).cloned().collect();
            let dir = root.join(format!("shard{k}"));
            write(&dir, &h, &run_points(&part, report)).unwrap();
            dirs.push(dir);
        }
        merge(&dirs, &root.join("merged")).unwrap();
        let read = |d: &str| std::fs::read_to_string(root.join(d).join("sweep.csv")).unwrap();
        assert_eq!(read("merged"), read("whole"));
        assert!(merge(&[dirs[0].clone(), dirs[0].clone()], &root.join("twice")).is_err());
        std::fs::remove_dir_all(&root).ok();
    }
}

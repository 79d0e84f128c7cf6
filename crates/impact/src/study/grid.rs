//! A sweep: axes of values of dotted scene keys, their grid, its shards, each point's scene,
//! the report's scalar columns, and the manifest that names one sweep.
//!
//! Points are numbered from 0 with the first axis varying slowest; point `i` is computed from
//! its number (mixed radix), so a grid of any allowed size costs nothing until its points run.
//! Shard K of N holds every N-th point from the (K-1)-th: each shard gets an even share of
//! cheap and costly points.

use crate::error::ImpactError;
use crate::outcome::Report;
use crate::plan::Plan;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};

/// The most points a grid may have: a million runs is days on a cluster already, and the
/// limit is checked before a point is made.
pub const MAX_GRID_POINTS: usize = 1_000_000;

/// Scene keys that take whole numbers: a range over one gives integers, or is refused.
const INTEGER_KEYS: [&str; 3] = ["solver.modes", "solver.elements", "solver.samples_per_pulse"];

/// The version of [`Manifest`]'s layout.
const MANIFEST_VERSION: u32 = 2;

fn study(message: String) -> ImpactError {
    ImpactError::Study(message)
}

/// One swept key and its values.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The dotted scene key, e.g. `impact.drop_height`.
    pub key: String,
    /// Its values, in order.
    pub values: Vec<toml::Value>,
}

impl Axis {
    /// The key `key` over `values` (checked as [`Axis::parse`] checks them).
    ///
    /// # Errors
    /// `Study` naming the key and the value that is not allowed.
    pub fn new(
        key: &str,
        values: impl IntoIterator<Item = toml::Value>,
    ) -> Result<Self, ImpactError> {
        let spec = format!("--set {key}");
        check_key(key, &spec)?;
        let values = values
            .into_iter()
            .map(|v| checked_value(key, v, &spec))
            .collect::<Result<Vec<_>, _>>()?;
        if values.is_empty() {
            return Err(study(format!("{spec}: no values")));
        }
        Ok(Self { key: key.to_string(), values })
    }

    /// `KEY=START:STOP:COUNT` (COUNT values from START to STOP, evenly spaced, or
    /// geometrically for a key listed in `log`) or `KEY=v1,v2,...` (numbers, true/false or
    /// names). On an integer key (`solver.modes`, `solver.elements`,
    /// `solver.samples_per_pulse`) every value must be whole.
    ///
    /// # Errors
    /// `Study` quoting the `--set` and naming what is wrong: no `=`, an empty or malformed
    /// key, `name` (it names the output, not the physics), a START or STOP that is not a
    /// finite number, COUNT not in 1 to [`MAX_GRID_POINTS`], COUNT 1 with START != STOP, a
    /// `--log` range through 0, a non-whole value on an integer key, a non-finite number, a
    /// control character in a value.
    pub fn parse(spec: &str, log: &[String]) -> Result<Self, ImpactError> {
        let shown = crate::study::printable(spec);
        let spec_name = format!("--set {shown}");
        let (key, values) = spec.split_once('=').ok_or_else(|| {
            study(format!("{spec_name}: expected KEY=START:STOP:COUNT or KEY=v1,v2,..."))
        })?;
        let key = key.trim();
        check_key(key, &spec_name)?;
        let parts: Vec<&str> = values.split(':').collect();
        let values = if parts.len() == 3 {
            range(key, &parts, log.iter().any(|k| k == key), &spec_name)?
        } else if parts.len() == 1 {
            values.split(',').map(|v| written_value(v.trim())).collect()
        } else {
            return Err(study(format!(
                "{spec_name}: a range is START:STOP:COUNT (three parts), a list v1,v2,..."
            )));
        };
        Self::new(key, values).map_err(|e| match e {
            ImpactError::Study(m) => study(m.replacen(&format!("--set {key}"), &spec_name, 1)),
            other => other,
        })
    }
}

/// A dotted key of lower-case words; not `name`.
fn check_key(key: &str, spec: &str) -> Result<(), ImpactError> {
    let word = |w: &str| {
        !w.is_empty() && w.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
    };
    if !key.split('.').all(word) {
        return Err(study(format!(
            "{spec}: the key must be a dotted scene key such as impact.drop_height (lower-case \
             words joined by '.')"
        )));
    }
    if key == "name" {
        return Err(study(format!(
            "{spec}: name is not swept: it names the output folder, not the physics"
        )));
    }
    Ok(())
}

/// The values of a range `START:STOP:COUNT`.
fn range(
    key: &str,
    parts: &[&str],
    geometric: bool,
    spec: &str,
) -> Result<Vec<toml::Value>, ImpactError> {
    let number = |s: &str, what: &str| -> Result<f64, ImpactError> {
        match s.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(study(format!("{spec}: {what} = {:?} is not a finite number", s.trim()))),
        }
    };
    let (start, stop) = (number(parts[0], "START")?, number(parts[1], "STOP")?);
    let count: usize = parts[2].trim().parse().map_err(|_| {
        study(format!("{spec}: COUNT = {:?} is not a whole number", parts[2].trim()))
    })?;
    if !(1..=MAX_GRID_POINTS).contains(&count) {
        return Err(study(format!("{spec}: COUNT = {count}: allowed 1 to {MAX_GRID_POINTS}")));
    }
    if count == 1 && start.to_bits() != stop.to_bits() {
        return Err(study(format!(
            "{spec}: COUNT = 1 with START != STOP would drop STOP; give COUNT >= 2, or the one \
             value as KEY={start}"
        )));
    }
    if geometric && !(start > 0.0 && stop > 0.0) {
        return Err(study(format!("{spec}: a --log key needs START and STOP greater than 0")));
    }
    let values = (0..count).map(|i| {
        let f = if count == 1 { 0.0 } else { i as f64 / (count - 1) as f64 };
        if geometric {
            start * (stop / start).powf(f)
        } else {
            start + (stop - start) * f
        }
    });
    if !INTEGER_KEYS.contains(&key) {
        return Ok(values.map(toml::Value::Float).collect());
    }
    values
        .map(|v| {
            let whole = v.round();
            if (v - whole).abs() <= 1e-9 * whole.abs().max(1.0) && whole.abs() < 9e15 {
                Ok(toml::Value::Integer(whole as i64))
            } else {
                Err(study(format!(
                    "{spec}: {key} takes whole numbers and this range gives {v}; list the \
                     values instead, e.g. {key}=16,32,64"
                )))
            }
        })
        .collect()
}

/// A value as written on the command line: an integer, a number, true/false, or a name.
fn written_value(text: &str) -> toml::Value {
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

/// `value` of `key`, checked: finite, whole on an integer key, no control characters.
fn checked_value(key: &str, value: toml::Value, spec: &str) -> Result<toml::Value, ImpactError> {
    match value {
        toml::Value::Float(f) if !f.is_finite() => {
            Err(study(format!("{spec}: {f} is not a finite number")))
        }
        toml::Value::Float(f) if INTEGER_KEYS.contains(&key) => {
            if f.fract() == 0.0 && f.abs() < 9e15 {
                Ok(toml::Value::Integer(f as i64))
            } else {
                Err(study(format!("{spec}: {key} takes whole numbers, not {f}")))
            }
        }
        toml::Value::String(s) if s.is_empty() || s.chars().any(char::is_control) => {
            Err(study(format!(
                "{spec}: the value {} is empty or holds a control character",
                crate::study::printable(&format!("{s:?}"))
            )))
        }
        toml::Value::Integer(_)
        | toml::Value::Float(_)
        | toml::Value::Boolean(_)
        | toml::Value::String(_) => Ok(value),
        other => Err(study(format!("{spec}: {other} is not a number, true/false or a name"))),
    }
}

/// The grid of every combination of its axes' values.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    axes: Vec<Axis>,
    len: usize,
}

impl Grid {
    /// The grid of `axes`, the first varying slowest.
    ///
    /// # Errors
    /// `Study` when there is no axis, a key is given twice, or the grid would have more than
    /// [`MAX_GRID_POINTS`] points (checked before anything is allocated).
    pub fn new(axes: Vec<Axis>) -> Result<Self, ImpactError> {
        if axes.is_empty() {
            return Err(study(
                "give at least one --set KEY=START:STOP:COUNT or KEY=v1,v2,...".into(),
            ));
        }
        for (i, a) in axes.iter().enumerate() {
            if axes[..i].iter().any(|b| b.key == a.key) {
                return Err(study(format!(
                    "--set {}: the key is given twice; give it once, with all its values",
                    a.key
                )));
            }
        }
        let len = axes.iter().try_fold(1usize, |n, a| n.checked_mul(a.values.len()));
        match len {
            Some(len) if len <= MAX_GRID_POINTS => Ok(Self { axes, len }),
            _ => Err(study(format!(
                "the grid has {} points; allowed at most {MAX_GRID_POINTS} (split the study \
                 into several sweeps)",
                axes.iter().map(|a| a.values.len().to_string()).collect::<Vec<_>>().join(" x ")
            ))),
        }
    }

    /// The number of points.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Never: a grid has at least one point.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The axes.
    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    /// The swept keys, in order.
    pub fn keys(&self) -> Vec<String> {
        self.axes.iter().map(|a| a.key.clone()).collect()
    }

    /// The value of each swept key at point `i` (`i < len`), in the axes' order.
    pub fn point(&self, i: usize) -> Vec<(&str, &toml::Value)> {
        let mut rest = i;
        let mut out: Vec<(&str, &toml::Value)> = self
            .axes
            .iter()
            .rev()
            .map(|a| {
                let n = a.values.len();
                let v = &a.values[rest % n];
                rest /= n;
                (a.key.as_str(), v)
            })
            .collect();
        out.reverse();
        out
    }

    /// `key = value, ...` of point `i`, printable.
    pub fn describe(&self, i: usize) -> String {
        let text =
            self.point(i).iter().map(|(k, v)| format!("{k} = {v}")).collect::<Vec<_>>().join(", ");
        crate::study::printable(&text)
    }

    /// The scene of point `i`: `base` (a scene file's table) with each swept key set, read
    /// and validated as a scene file is.
    ///
    /// # Errors
    /// `Study` naming the point, its values and what [`Scene`] or [`Plan::new`] refused.
    pub fn scene(&self, base: &toml::Table, i: usize) -> Result<Scene, ImpactError> {
        let at_point = |why: String| study(format!("point {i} ({}): {why}", self.describe(i)));
        let mut table = base.clone();
        for (key, v) in self.point(i) {
            let parts: Vec<&str> = key.split('.').collect();
            let mut at = &mut table;
            for part in &parts[..parts.len() - 1] {
                let entry = at
                    .entry(part.to_string())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                at = entry.as_table_mut().ok_or_else(|| {
                    at_point(format!("{key}: {part} is not a table in the scene"))
                })?;
            }
            at.insert(parts[parts.len() - 1].to_string(), v.clone());
        }
        let scene: Scene = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| at_point(e.message().to_string()))?;
        Plan::new(&scene).map_err(|e| at_point(e.to_string()))?;
        Ok(scene)
    }

    /// A fingerprint of the sweep of `base` over this grid: two sweeps with the same one ran
    /// the same points (FNV-1a over the scene's table and the axes).
    pub fn fingerprint(&self, base: &toml::Table) -> String {
        let mut text = toml::to_string(base).unwrap_or_default();
        for a in &self.axes {
            text.push_str(&format!("\n{}=", a.key));
            for v in &a.values {
                text.push_str(&format!("{v};"));
            }
        }
        crate::study::fingerprint(&text)
    }

    /// The CSV header: `point`, the swept keys, [`COLUMNS`], `error`.
    pub fn header(&self) -> Vec<String> {
        let mut h = vec!["point".to_string()];
        h.extend(self.keys());
        h.extend(COLUMNS.iter().map(|c| c.to_string()));
        h.push("error".into());
        h
    }

    /// The CSV row of point `i`: its number, its values, the report's [`scalars`] (blank where
    /// a quantity does not exist) and an empty error; or, for a failed run, blank scalars and
    /// the reason.
    pub fn row(&self, i: usize, result: Result<&Report, &str>) -> Vec<String> {
        let mut cells = vec![i.to_string()];
        cells.extend(self.point(i).iter().map(|(_, v)| cell(v)));
        match result {
            Ok(r) => {
                cells.extend(scalars(r).iter().zip(COLUMNS).map(|(x, column)| match x {
                    // A count or a flag is written as the whole number it is.
                    Some(v)
                        if matches!(
                            column,
                            "contact_count" | "warning_count" | "max_displacement_at_window_end"
                        ) =>
                    {
                        format!("{v:.0}")
                    }
                    Some(v) => format!("{v:.9e}"),
                    None => String::new(),
                }));
                cells.push(String::new());
            }
            Err(why) => {
                cells.extend(std::iter::repeat_n(String::new(), COLUMNS.len()));
                cells.push(crate::study::printable(why));
            }
        }
        cells
    }
}

/// The report's scalars in a sweep's table, with their units in the names.
pub const COLUMNS: [&str; 19] = [
    "impact_speed_m_s",
    "contact_count",
    "first_duration_s",
    "first_peak_force_n",
    "first_impulse_n_s",
    "first_print_radius_m",
    "restitution",
    "max_displacement_m",
    "equivalent_static_force_n",
    "max_bending_stress_pa",
    "max_twist_rad",
    "energy_initial_j",
    "energy_dissipated_j",
    "energy_numerical_dissipation_j",
    "energy_balance_error_j",
    "estimated_error",
    "max_displacement_at_window_end",
    "warning_count",
    "wall_time_s",
];

/// The values of [`COLUMNS`] of `r`; `None` where the quantity does not exist (no contact, a
/// first contact the window cut, whose duration was the window's and its peak 474 N of a
/// true 1750 N in a review's table, a half-space's equivalent static force);
/// `max_displacement_at_window_end` 1 where the largest displacement sits at the window's end
/// with the first swing unfinished (not yet the maximum, as the report warns), else 0;
/// `warning_count` the report's warnings (the table cannot hold their text).
pub fn scalars(r: &Report) -> [Option<f64>; COLUMNS.len()] {
    let first = r.contacts.first().filter(|c| c.complete);
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
        r.bending_stress.as_ref().map(|b| b.max),
        r.max_twist,
        Some(r.energy.initial),
        Some(r.energy.dissipated),
        Some(r.energy.numerical_dissipation),
        Some(r.energy.balance_error),
        r.estimated_error,
        Some(f64::from(u8::from(r.max_displacement_at_window_end))),
        Some(r.warnings.len() as f64),
        Some(r.wall_time),
    ]
}

/// Part K of N of a grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which part, 1 <= k <= n.
    pub k: usize,
    /// How many parts.
    pub n: usize,
}

impl Shard {
    /// The whole grid: part 1 of 1.
    pub const WHOLE: Shard = Shard { k: 1, n: 1 };

    /// `K/N` with 1 <= K <= N.
    ///
    /// # Errors
    /// `Study` quoting `--shard` and what is allowed.
    pub fn parse(text: &str) -> Result<Self, ImpactError> {
        let bad = || {
            study(format!(
                "--shard {}: expected K/N with whole numbers 1 <= K <= N",
                crate::study::printable(text)
            ))
        };
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n >= 1 && (1..=n).contains(&k) {
            Ok(Self { k, n })
        } else {
            Err(bad())
        }
    }

    /// The point numbers of this shard of a grid of `len` points.
    pub fn points(self, len: usize) -> impl Iterator<Item = usize> {
        (self.k - 1..len).step_by(self.n.max(1))
    }
}

/// A swept value as its table cell: a string as it is, anything else as TOML writes it.
fn cell(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// What a sweep's folder holds, written before its first point runs: which sweep (the
/// fingerprint of its scene and axes), its keys, its size and which shard. A merge reads it to
/// refuse shards of different sweeps and to name missing points; a resumed run reads it to
/// refuse a folder of another sweep.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Manifest {
    /// The layout's version.
    pub version: u32,
    /// [`Grid::fingerprint`].
    pub fingerprint: String,
    /// The swept keys, in order.
    pub keys: Vec<String>,
    /// The number of points of the whole grid.
    pub points: usize,
    /// Which part of the grid this folder holds.
    pub shard: Shard,
    /// The CSV header.
    pub header: Vec<String>,
    /// Each swept key's values as its cells in the table (version 2 on): what a row of the
    /// folder is checked against.
    #[serde(default)]
    pub values: Vec<Vec<String>>,
}

impl Manifest {
    /// The manifest of shard `shard` of the sweep of `base` over `grid`.
    pub fn new(base: &toml::Table, grid: &Grid, shard: Shard) -> Self {
        Self {
            version: MANIFEST_VERSION,
            fingerprint: grid.fingerprint(base),
            keys: grid.keys(),
            points: grid.len(),
            shard,
            header: grid.header(),
            values: grid.axes().iter().map(|a| a.values.iter().map(cell).collect()).collect(),
        }
    }

    /// Whether the table row `cells` belongs to this folder: its point number in the grid and
    /// in this shard, and its swept values the grid's at that point.
    ///
    /// # Errors
    /// `Study` saying which of these the row breaks.
    pub fn check_row(&self, cells: &[String]) -> Result<usize, ImpactError> {
        let point: usize = cells
            .first()
            .and_then(|c| c.parse().ok())
            .ok_or_else(|| study(format!("{:?} is no point number", cells.first())))?;
        if point >= self.points {
            return Err(study(format!(
                "point {point} is not in the grid (it has {} points)",
                self.points
            )));
        }
        if (point + 1 - self.shard.k) % self.shard.n.max(1) != 0 || point + 1 < self.shard.k {
            return Err(study(format!(
                "point {point} is not in shard {}/{}",
                self.shard.k, self.shard.n
            )));
        }
        // The point's digits, the last axis fastest (as Grid::point numbers them).
        let mut rest = point;
        let mut expected = vec![""; self.values.len()];
        for (slot, values) in expected.iter_mut().zip(&self.values).rev() {
            let n = values.len().max(1);
            *slot = values.get(rest % n).map_or("", String::as_str);
            rest /= n;
        }
        for ((key, want), got) in self.keys.iter().zip(&expected).zip(&cells[1..]) {
            if got != want {
                return Err(study(format!(
                    "point {point} has {key} = {}, where the grid has {}",
                    crate::study::printable(got),
                    crate::study::printable(want)
                )));
            }
        }
        Ok(point)
    }

    /// The point numbers this folder should hold.
    pub fn expected_points(&self) -> impl Iterator<Item = usize> {
        self.shard.points(self.points)
    }

    /// Whether `other` is a part of the same sweep.
    ///
    /// # Errors
    /// `Study` saying how they differ (version, scene or axes, keys, size, number of shards).
    pub fn check_same_sweep(&self, other: &Manifest) -> Result<(), ImpactError> {
        let differ = |what: &str| {
            Err(study(format!("the shards are of two different sweeps: their {what} differ")))
        };
        if self.version != other.version {
            return differ("manifest versions");
        }
        if self.keys != other.keys || self.header != other.header {
            return differ("swept keys");
        }
        if self.points != other.points {
            return differ("grid sizes");
        }
        if self.fingerprint != other.fingerprint {
            return differ("scenes or swept values (fingerprints)");
        }
        if self.shard.n != other.shard.n {
            return differ("numbers of shards");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::float_cmp)]
    use super::*;

    fn base() -> toml::Table {
        toml::from_str(include_str!("../../../../validation/scenes/half-space-r10.toml")).unwrap()
    }

    fn floats(a: &Axis) -> Vec<f64> {
        a.values.iter().map(|v| v.as_float().unwrap()).collect()
    }

    #[test]
    fn a_row_leaves_a_cut_contact_empty_and_flags_an_unfinished_swing() {
        // The half-space over 10 us, within its 69 us contact: the window's length is no
        // duration and 474 N no peak (a review's table had them, the true peak 1750 N).
        let column = |name: &str| COLUMNS.iter().position(|c| *c == name).unwrap();
        let mut scene = crate::Scene::from_toml(include_str!(
            "../../../../validation/scenes/half-space-r10.toml"
        ))
        .unwrap();
        scene.solver.end_time = Some(1e-5);
        let cut = crate::simulate(&scene).unwrap().report;
        let row = scalars(&cut);
        for name in ["first_duration_s", "first_peak_force_n", "first_impulse_n_s"] {
            assert_eq!(row[column(name)], None, "{name}");
        }
        assert_eq!(row[column("contact_count")], Some(1.0));
        assert_eq!(row[column("warning_count")], Some(cut.warnings.len() as f64));
        // The paper's tip over 1 ms: its displacement still rising at the window's end.
        let mut tip =
            crate::Scene::from_toml(include_str!("../../../../validation/scenes/paper-tip.toml"))
                .unwrap();
        tip.solver.modes = Some(16);
        tip.solver.end_time = Some(1e-3);
        let rising = crate::simulate(&tip).unwrap().report;
        assert!(rising.max_displacement_at_window_end);
        assert_eq!(scalars(&rising)[column("max_displacement_at_window_end")], Some(1.0));
        assert_eq!(scalars(&cut)[column("max_displacement_at_window_end")], Some(0.0));
    }

    #[test]
    fn ranges_are_linear_or_geometric_and_lists_keep_their_types() {
        let a = Axis::parse("impact.drop_height=0.1:0.5:5", &[]).unwrap();
        for (h, want) in floats(&a).iter().zip([0.1, 0.2, 0.3, 0.4, 0.5]) {
            assert!((h - want).abs() < 1e-15);
        }
        let b = Axis::parse("ball.radius=0.001:0.1:3", &["ball.radius".into()]).unwrap();
        assert!((floats(&b)[1] - 0.01).abs() < 1e-15);
        let c = Axis::parse("contact.law=hertz,thornton", &[]).unwrap();
        assert_eq!(c.values[1], toml::Value::String("thornton".into()));
        assert_eq!(Axis::parse("a.b=7", &[]).unwrap().values, [toml::Value::Integer(7)]);
        assert!(Axis::parse("impact.speed=2:2:1", &[]).is_ok());
    }

    #[test]
    fn malformed_sets_are_refused_with_the_reason() {
        let refused = |spec: &str, log: &[String], says: &str| {
            let e = Axis::parse(spec, log).unwrap_err().to_string();
            assert!(e.contains(says), "{spec}: {e}");
            assert!(!e.chars().any(char::is_control), "{e:?}");
        };
        refused("nokey", &[], "expected KEY=");
        refused("=1,2", &[], "dotted scene key");
        refused("impact/speed=1", &[], "dotted scene key");
        refused("name=a,b", &[], "name is not swept");
        refused("impact.speed=1:100:1", &[], "COUNT = 1 with START != STOP");
        refused("impact.speed=1:2:0", &[], "COUNT = 0");
        refused("impact.speed=1:2:1000001", &[], "allowed 1 to 1000000");
        refused("impact.speed=1:2:x", &[], "not a whole number");
        refused("impact.speed=nan:2:3", &[], "not a finite number");
        refused("impact.speed=1:2", &[], "three parts");
        refused("impact.speed=nan", &[], "not a finite number");
        refused("impact.speed=1,inf", &[], "not a finite number");
        refused("contact.law=a\nb", &[], "control character");
        refused("contact.law=hertz,", &[], "empty");
        refused("impact.speed=0:2:3", &["impact.speed".into()], "greater than 0");
        refused("solver.modes=16:64:6", &[], "list the values");
        refused("solver.modes=16.5", &[], "whole numbers");
    }

    #[test]
    fn a_range_on_an_integer_key_gives_integers() {
        let a = Axis::parse("solver.modes=16:64:3", &[]).unwrap();
        assert_eq!(a.values, [16, 40, 64].map(toml::Value::Integer));
        let b = Axis::parse("solver.modes=16:64:3", &["solver.modes".into()]).unwrap();
        assert_eq!(b.values, [16, 32, 64].map(toml::Value::Integer));
        assert_eq!(
            Axis::parse("solver.elements=32.0", &[]).unwrap().values,
            [toml::Value::Integer(32)]
        );
    }

    #[test]
    fn grids_number_points_refuse_twice_given_keys_and_check_their_size_first() {
        let a = Axis::parse("impact.speed=1:2:5", &[]).unwrap();
        let c = Axis::parse("contact.law=hertz,thornton", &[]).unwrap();
        let g = Grid::new(vec![a.clone(), c.clone()]).unwrap();
        assert_eq!(g.len(), 10);
        assert_eq!(g.point(3)[0].1.as_float(), Some(1.25));
        assert_eq!(g.point(3)[1].1, &toml::Value::String("thornton".into()));
        assert_eq!(g.describe(3), "impact.speed = 1.25, contact.law = \"thornton\"");
        let twice = Axis::parse("impact.speed=3:4:2", &[]).unwrap();
        let e = Grid::new(vec![a, twice]).unwrap_err().to_string();
        assert!(e.contains("impact.speed: the key is given twice"), "{e}");
        assert!(Grid::new(vec![]).is_err());
        // 1e12 points: refused at once, nothing but the two axes allocated.
        let big = Axis::parse("impact.speed=1:2:1000000", &[]).unwrap();
        let other = Axis::parse("ball.radius=0.001:0.01:1000000", &[]).unwrap();
        let e = Grid::new(vec![big, other]).unwrap_err().to_string();
        assert!(e.contains("1000000 x 1000000 points; allowed at most 1000000"), "{e}");
    }

    #[test]
    fn points_become_validated_scenes_and_integer_keys_reach_the_solver() {
        let g = Grid::new(vec![Axis::parse("impact.speed=-1,1", &[]).unwrap()]).unwrap();
        let e = g.scene(&base(), 0).unwrap_err().to_string();
        assert!(e.starts_with("point 0 (impact.speed = -1)") && e.contains("impact.speed"), "{e}");
        assert_eq!(g.scene(&base(), 1).unwrap().impact.speed, Some(1.0));
        // A key the scene does not know: named, with no line of a generated file.
        let g = Grid::new(vec![Axis::parse("impact.sped=1,2", &[]).unwrap()]).unwrap();
        let e = g.scene(&base(), 0).unwrap_err().to_string();
        assert!(e.contains("sped") && !e.contains("line"), "{e}");
        // Modes as integers on a beam scene.
        let beam: toml::Table =
            toml::from_str(include_str!("../../../../validation/scenes/paper-tip.toml")).unwrap();
        let g = Grid::new(vec![Axis::parse("solver.modes=16:64:3", &[]).unwrap()]).unwrap();
        assert_eq!(g.scene(&beam, 1).unwrap().solver.modes, Some(40));
    }

    #[test]
    fn a_row_writes_the_contact_count_as_a_whole_number_and_the_rest_with_ten_digits() {
        // The half-space strike of validation/scenes/half-space-r10.toml: one contact.
        let g = Grid::new(vec![Axis::parse("impact.speed=1", &[]).unwrap()]).unwrap();
        let report = crate::simulate(&g.scene(&base(), 0).unwrap()).unwrap().report;
        let row = g.row(0, Ok(&report));
        let header = g.header();
        let cell = |name: &str| &row[header.iter().position(|h| h == name).unwrap()];
        assert_eq!(cell("contact_count"), "1");
        assert_eq!(cell("impact_speed_m_s"), "1.000000000e0");
    }

    #[test]
    fn shards_hold_every_point_once_and_manifests_tell_sweeps_apart() {
        let mut seen = [0; 23];
        for k in 1..=4 {
            for i in (Shard { k, n: 4 }).points(23) {
                seen[i] += 1;
            }
        }
        assert!(seen.iter().all(|n| *n == 1));
        assert_eq!((Shard { k: 5, n: 7 }).points(3).count(), 0);
        for bad in ["0/4", "5/4", "1/0", "x", "1/2/3", "-1/2"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
        assert_eq!(Shard::parse("2/4").unwrap(), Shard { k: 2, n: 4 });
        let g = |spec: &str| Grid::new(vec![Axis::parse(spec, &[]).unwrap()]).unwrap();
        let one = Manifest::new(&base(), &g("impact.speed=1:2:5"), Shard { k: 1, n: 2 });
        let two = Manifest::new(&base(), &g("impact.speed=1:2:5"), Shard { k: 2, n: 2 });
        assert!(one.check_same_sweep(&two).is_ok());
        let other = Manifest::new(&base(), &g("impact.speed=1:3:5"), Shard { k: 2, n: 2 });
        assert!(one.check_same_sweep(&other).unwrap_err().to_string().contains("fingerprints"));
        let mut scene = base();
        scene.insert("name".into(), toml::Value::String("other".into()));
        let moved = Manifest::new(&scene, &g("impact.speed=1:2:5"), Shard { k: 2, n: 2 });
        assert!(one.check_same_sweep(&moved).is_err());
        assert_eq!(one.expected_points().collect::<Vec<_>>(), [0, 2, 4]);
    }
}

//! The toolkit's command line: `cargo xtask reproduce | simulate | compare | accuracy | sweep |
//! beam | check-figures | schema | validate`.

mod accuracy;
mod beam;
mod compare;
mod figures;
mod files;
#[cfg(test)]
mod links;
mod plot;
mod plots;
mod reproduce;
mod schema;
mod simulate;
mod sweep;
mod validate;

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Impact of a hard ball on a flexible beam: reproduce the paper, simulate a scene, compare
/// the methods, measure speed against error, sweep a scene, run a beam, validate.
#[derive(Parser)]
#[command(name = "cargo xtask", bin_name = "cargo xtask", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Regenerate every figure of Barrientos et al. as CSV + SVG with an index page.
    Reproduce {
        /// Output folder.
        #[arg(long, default_value = "target/reproduce")]
        out: PathBuf,
        /// A reduced version (fewer modes and sweep points) for CI.
        #[arg(long)]
        quick: bool,
    },
    /// Run one scene file and print its report.
    Simulate {
        /// Scene file (TOML, SI units).
        scene: PathBuf,
        /// Print the report as JSON on stdout instead of a summary.
        #[arg(long)]
        json: bool,
        /// Write the time history to this CSV file (never the scene file itself).
        #[arg(long)]
        history: Option<PathBuf>,
        /// Write the beam's field to this CSV file: displacement, slope, bending moment and
        /// stress along the beam at every recorded instant (long format, units in the names).
        #[arg(long)]
        field: Option<PathBuf>,
        /// Write the figures of the run into this folder: contact force, displacement at the
        /// impact point, energy ledger, bending stress at the worst point and the supports, and
        /// the space-time map of the stress (SVG + CSV).
        #[arg(long)]
        plots: Option<PathBuf>,
    },
    /// Run a beam scene with the modal and the finite-element method (and optional lists of
    /// mode and element counts) and print and plot the differences.
    Compare {
        /// Scene file (TOML, SI units) with a [beam].
        scene: PathBuf,
        /// Also run the modal method with these mode counts (comma separated).
        #[arg(long, value_delimiter = ',')]
        modes: Vec<usize>,
        /// Also run the finite-element method with these numbers of equal elements.
        #[arg(long, value_delimiter = ',')]
        elements: Vec<usize>,
        /// Output folder; default target/compare/NAME.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Speed against error: run a beam scene by each method over a ladder of resolutions,
    /// measure every run's errors from the method's converged run, and write
    /// work_precision.csv and work_precision.svg; print the table and the cheapest setting for
    /// 1e-2 and 1e-3.
    Accuracy {
        /// Scene file (TOML, SI units) with a [beam].
        scene: PathBuf,
        /// Output folder; default target/accuracy/NAME.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Shorter ladders (for CI): 16 to 128 modes and elements, references at 512.
        #[arg(long)]
        quick: bool,
        /// Finish a stopped study in the output folder: keep its finished runs
        /// (runs.partial.jsonl) and run only the missing settings.
        #[arg(long)]
        resume: bool,
        /// Run at most this many settings now (the rest later with --resume).
        #[arg(long)]
        limit: Option<usize>,
    },
    /// Run a beam under prescribed loads (no ball), static or dynamic; write the tracked node's
    /// history and the final shape as CSV (and SVG charts).
    Beam {
        /// Beam scene file (TOML, SI units); see validation/scenes/beam-*.toml.
        scene: PathBuf,
        /// Output folder; default target/beam/NAME.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also write the beam's natural modes below this angular frequency (rad/s), of the
        /// unloaded beam linearised about its undeformed shape, to modes.csv.
        #[arg(long, value_name = "OMEGA")]
        modes_below: Option<f64>,
    },
    /// Run a scene over a grid of values of its keys, in parallel: sweep.csv (one row a point,
    /// the report's scalars with units) and sweep.svg; or merge the shards of a sweep.
    Sweep {
        /// Scene file (TOML, SI units); not with --merge.
        scene: Option<PathBuf>,
        /// KEY=START:STOP:COUNT or KEY=v1,v2,... with KEY a dotted scene key such as
        /// impact.drop_height; several make a grid.
        #[arg(long)]
        set: Vec<String>,
        /// Space this swept key's range geometrically instead of evenly.
        #[arg(long)]
        log: Vec<String>,
        /// Run only the K-th of N interleaved parts of the grid (K/N, 1 <= K <= N).
        #[arg(long)]
        shard: Option<String>,
        /// Join the sweep.csv of these shard folders (in point order) into --out; refused
        /// unless they are finished shards of one sweep that together hold every point.
        #[arg(long, num_args = 1..)]
        merge: Vec<PathBuf>,
        /// Finish a stopped sweep in the output folder: keep its finished rows
        /// (sweep.partial.csv) and run only the missing points.
        #[arg(long)]
        resume: bool,
        /// Run at most this many points now (the rest later with --resume).
        #[arg(long)]
        limit: Option<usize>,
        /// Output folder; default target/sweep/NAME (or target/sweep/merged).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Check every SVG figure under a folder for what a reader would trip on (tick labels of
    /// more than six significant digits, "us" for microseconds, an axis without its unit, a
    /// legend over a curve or a marker, two series drawn alike); non-zero exit on a problem.
    CheckFigures {
        /// The folder (searched recursively).
        dir: PathBuf,
    },
    /// Write the scene files' JSON Schemas (docs/scene.schema.json,
    /// docs/beam-scene.schema.json) and their reference tables (docs/scene.md) from the types
    /// the parsers read.
    Schema {
        /// Only check that the files are current; non-zero exit if they differ.
        #[arg(long)]
        check: bool,
    },
    /// Run every case under validation/ against its reference; non-zero exit on a failure.
    Validate {
        /// Print the results as a JSON list.
        #[arg(long)]
        json: bool,
    },
}

/// mimalloc rather than the system's allocator: a run's heap grows by a few megabytes (the
/// modal stress search's kept states, the history, the tables), which glibc's malloc takes in
/// 4 kB pages, each first touched at a fault of a couple of microseconds; mimalloc's arenas
/// ask for transparent huge pages (where the system grants them on request, as Linux's
/// default `madvise` setting does). The paper's tip at 256 modes over 5 ms: 1555 page faults
/// a process against 220, 17 % faster (the same bits; with mimalloc's huge pages turned off,
/// 1710 faults and no faster than glibc's). The huge pages cost a tail: over 40 runs of the
/// final build the median 11.6 ms, the slowest 25.1 ms (2 runs past twice the median: the
/// kernel now and then stalls a huge-page fault), against 13.0 and 17.2 ms with
/// `MIMALLOC_ALLOW_THP=0` in the environment, which a user who wants steady times sets.
/// ARCHITECTURE.md, "Speed".
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    files::remove_unfinished_on_interrupt();
    let result = match cli.command {
        Command::Reproduce { out, quick } => reproduce::run(&out, quick),
        Command::Simulate { scene, json, history, field, plots } => simulate::run(
            &scene,
            &simulate::Outputs {
                json,
                history: history.as_deref(),
                field: field.as_deref(),
                plots: plots.as_deref(),
            },
        ),
        Command::Compare { scene, modes, elements, out } => {
            compare::run(&scene, &modes, &elements, out.as_deref())
        }
        Command::Accuracy { scene, out, quick, resume, limit } => {
            accuracy::run(&scene, out.as_deref(), quick, resume, limit)
        }
        Command::Beam { scene, out, modes_below } => beam::run(&scene, out.as_deref(), modes_below),
        Command::Sweep { scene, set, log, shard, merge, out, resume, limit } => {
            match (scene, merge.is_empty()) {
                (Some(scene), true) => sweep::run(&sweep::Request {
                    scene: &scene,
                    sets: &set,
                    log: &log,
                    out: out.as_deref(),
                    shard: shard.as_deref(),
                    resume,
                    limit,
                }),
                (None, false) => sweep::merge(
                    &merge,
                    out.as_deref().unwrap_or_else(|| std::path::Path::new("target/sweep/merged")),
                ),
                _ => Err(anyhow::anyhow!(
                    "give a scene file to sweep, or --merge DIR... without one"
                )),
            }
        }
        Command::CheckFigures { dir } => figures::run(&dir),
        Command::Schema { check } => schema::run(check),
        Command::Validate { json } => validate::run(json),
    };
    match result {
        Ok(true) => std::process::ExitCode::SUCCESS,
        Ok(false) => std::process::ExitCode::FAILURE,
        // A reader that stopped reading (`| head`) is no failure of the program.
        Err(e) if files::is_broken_pipe(&e) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // One line per cause, no control character from a file reaching the terminal.
            let message = files::escape_controls(&format!("error: {e:#}"));
            let _ = std::io::Write::write_all(&mut std::io::stderr(), (message + "\n").as_bytes());
            std::process::ExitCode::FAILURE
        }
    }
}

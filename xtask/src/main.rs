//! The toolkit's command line: `cargo xtask reproduce | simulate | compare | beam | validate`.

mod beam;
mod compare;
mod plot;
mod reproduce;
mod simulate;
mod validate;

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Impact of a hard ball on a flexible beam: reproduce the paper, simulate a scene, validate.
#[derive(Parser)]
#[command(name = "cargo xtask", version, about)]
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
        /// Write the time history to this CSV file.
        #[arg(long)]
        history: Option<PathBuf>,
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
    /// Run a beam under prescribed loads (no ball), static or dynamic; write the tracked node's
    /// history and the final shape as CSV (and SVG charts).
    Beam {
        /// Beam scene file (TOML, SI units); see validation/scenes/beam-*.toml.
        scene: PathBuf,
        /// Output folder; default target/beam/NAME.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Run every case under validation/ against its reference; non-zero exit on a failure.
    Validate {
        /// Print the results as a JSON list.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Reproduce { out, quick } => reproduce::run(&out, quick),
        Command::Simulate { scene, json, history } => {
            simulate::run(&scene, json, history.as_deref())
        }
        Command::Compare { scene, modes, elements, out } => {
            compare::run(&scene, &modes, &elements, out.as_deref())
        }
        Command::Beam { scene, out } => beam::run(&scene, out.as_deref()),
        Command::Validate { json } => validate::run(json),
    };
    match result {
        Ok(true) => std::process::ExitCode::SUCCESS,
        Ok(false) => std::process::ExitCode::FAILURE,
        Err(e) => {
            #[allow(clippy::print_stderr)]
            {
                eprintln!("error: {e:#}");
            }
            std::process::ExitCode::FAILURE
        }
    }
}

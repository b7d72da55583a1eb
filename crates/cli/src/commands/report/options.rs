//! The arguments of `lagrange report` and their validation, before anything runs.

use crate::args;
use crate::error::CliError;
use lagrange_scenes::Scene;
use lagrange_validation::plan::Plan;
use std::path::PathBuf;

/// Arguments of `lagrange report`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id or scene file to report, repeatable (default: every built-in scene).
    #[arg(long = "scene", value_name = "ID|FILE")]
    scenes: Vec<String>,
    /// Smaller sweeps, a 2 s horizon and one timed repetition (well under a minute for every scene).
    #[arg(long)]
    quick: bool,
    /// Output directory for report.json, report.md and the SVG plots (created if missing).
    #[arg(long, value_name = "DIR", default_value = "report")]
    out: PathBuf,
    /// Horizon (s), a multiple of 0.05 (default: 10, or 2 with --quick).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    t_end: Option<f64>,
    /// Print report.json on standard output instead of the terminal summary (files are still written).
    #[arg(long)]
    json: bool,
    /// Wall-time limit (s), checked before each scene and before the stability suite: past it
    /// the report of the scenes done is written (without the stability suite) and the command
    /// exits 1 naming the scenes left out.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    max_seconds: Option<f64>,
    /// Scenes run at once, each on its own thread [default: the number of cores]. Each timed
    /// run then shares the machine with at most N − 1 others, one per core
    /// (docs/validation.md#measurement); `--jobs 1` times every run alone.
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
}

/// Validated options.
pub struct Options {
    /// The scenes, in registry order, without repeats.
    pub scenes: Vec<&'static dyn Scene>,
    /// What runs (`--quick`, `--t-end`).
    pub plan: Plan,
    /// The output directory, which exists and is a directory.
    pub out: PathBuf,
    /// `--json`.
    pub json: bool,
    /// `--max-seconds`.
    pub max_seconds: Option<f64>,
    /// `--jobs`, or the number of cores.
    pub jobs: usize,
}

impl Options {
    /// Check the scenes and the horizon, then create the output directory, so that a bad argument
    /// fails at once and leaves nothing behind.
    ///
    /// # Errors
    /// An unknown scene, a bad horizon, or an output directory that cannot be created or written.
    pub fn new(args: &Args) -> Result<Options, CliError> {
        let plan = Plan::new(args.quick, args.t_end).map_err(CliError::Argument)?;
        // The main job has no default limit: only --max-seconds sets one.
        let max_seconds = crate::commands::long_work::max_seconds(args.max_seconds, true)?.map(|(s, _)| s);
        // The scenes asked for, in the registry's order, then files in the order given.
        let asked = args.scenes.iter().map(|id| args::scene(id)).collect::<Result<Vec<_>, _>>()?;
        let mut scenes: Vec<&'static dyn Scene> = lagrange_scenes::all()
            .iter()
            .copied()
            .filter(|s| args.scenes.is_empty() || asked.iter().any(|a| a.id() == s.id()))
            .collect();
        scenes.extend(asked.iter().filter(|a| !scenes.iter().any(|s| s.id() == a.id())).copied().collect::<Vec<_>>());
        let out = args.out.clone();
        if out.as_os_str().is_empty() {
            return Err(CliError::EmptyOut);
        }
        let failed = |what: &'static str| {
            let path = out.clone();
            move |source| CliError::OutputDirectory { path, what, source }
        };
        std::fs::create_dir_all(&out).map_err(failed("cannot create the output directory"))?;
        // A directory we cannot write into fails here, not after minutes of runs.
        let probe = out.join(".lagrange-report-write-test");
        std::fs::write(&probe, b"").map_err(failed("cannot write into it"))?;
        let _ = std::fs::remove_file(&probe);
        let jobs = args::jobs(args.jobs)?;
        Ok(Options { scenes, plan, out, json: args.json, max_seconds, jobs })
    }

    /// Whether every scene is reported (no `--scene` given).
    pub fn all_scenes(&self) -> bool {
        self.scenes.len() == lagrange_scenes::all().len()
    }
}

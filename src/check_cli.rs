//! `luamotion check`, and the check `run` makes before it starts anything (the `check`
//! crate, derived from the registry).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Result, bail};
use check::{Checker, Code, Options};

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum Format {
    /// `file:line:col: error[E101]: ...` with the line and a caret.
    Human,
    /// One JSON array of every finding.
    Json,
}

#[derive(clap::Args)]
pub struct CheckArgs {
    /// Lua files, or folders whose `.lua` files (recursively) are checked.
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// How findings are written.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    format: Format,
    /// Leave out a warning (repeat for several), e.g. `--allow W201`.
    #[arg(long, value_name = "CODE")]
    allow: Vec<String>,
}

/// Exit 1 when any error is found, 0 otherwise (warnings included).
pub fn check(args: CheckArgs) -> Result<ExitCode> {
    let mut allowed = Vec::new();
    for id in &args.allow {
        match Code::parse(id) {
            Some(code) if code.severity() == check::Severity::Warning => allowed.push(code),
            Some(code) => bail!("{} is an error, which cannot be allowed; only warnings (W...) can", code.id()),
            None => {
                let known: Vec<String> = Code::ALL.iter().map(|c| format!("  {} {}", c.id(), c.summary())).collect();
                bail!("no check code {id:?}; the codes are:\n{}", known.join("\n"))
            }
        }
    }
    let checker = Checker::new(Options { allowed });
    let checked = checker.check_paths(&args.paths)?;
    match args.format {
        Format::Human => {
            for file in &checked {
                crate::stdout::out!("{}", file.render())?;
            }
            let (errors, warnings) = counts(&checked);
            crate::stdout::outln!("{} file(s) checked: {errors} error(s), {warnings} warning(s)", checked.len())?;
        }
        Format::Json => {
            let all: Vec<&check::Diagnostic> = checked.iter().flat_map(|c| &c.diagnostics).collect();
            crate::stdout::outln!("{}", serde_json::to_string_pretty(&all)?)?;
        }
    }
    Ok(if checked.iter().any(|c| c.has_errors()) { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

fn counts(checked: &[check::Checked]) -> (usize, usize) {
    let all = checked.iter().flat_map(|c| &c.diagnostics);
    let errors = all.clone().filter(|d| d.severity == check::Severity::Error).count();
    (errors, all.count() - errors)
}

/// The check `run` makes of its programs: their errors (and warnings) on stderr, and
/// whether any error refuses the start. A program that cannot be read is left to the
/// start, which says so in its own words.
pub fn refuses_to_start(programs: impl IntoIterator<Item = PathBuf>) -> bool {
    let checker = Checker::new(Options::default());
    let mut refused = false;
    for program in programs {
        let Ok(checked) = checker.check_file(&program) else { continue };
        eprint!("{}", checked.render());
        refused |= checked.has_errors();
    }
    if refused {
        eprintln!("error: the check found errors; nothing was started (`--no-check` runs the programs anyway)");
    }
    refused
}

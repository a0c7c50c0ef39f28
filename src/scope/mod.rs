//! The scope's reader (`luamotion scope`, `luamotion run --scope`): drains the scope ring
//! of a running controller (`ipc::scope`) into rows, with decimation and a trigger with
//! pre- and post-trigger samples, and writes them as CSV, SVG or PNG by each output's
//! extension.

mod plot;

pub use plot::register_font;

use std::collections::VecDeque;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use calls::scope::Var;
use ipc::Namespace;
use ipc::scope::{CHANNELS, RowRead, ScopeRing};

/// What to record and where to, for `scope` and `run --scope`.
#[derive(clap::Args, Debug, Clone)]
pub struct ScopeOptions {
    /// Variables by the manual's names, comma-separated, at most 16: aN.pos_fb, aN.ref_pos,
    /// aN.pos_out, aN.pos_err, aN.vel_fb, aN.motion_status, gN.carte_pose_cmd[i],
    /// gN.grp_pg_vel, gpi, gpo, system_dtestN, system_user_table[N], ...
    #[arg(long = "scope-vars", value_delimiter = ',', default_value = "a0.ref_pos,a0.pos_fb,a0.pos_err,a0.vel_fb")]
    pub vars: Vec<String>,
    /// Keep one cycle in N (the cycles whose number N divides).
    #[arg(long = "scope-decimate", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub decimate: u64,
    /// Record around a trigger: VAR>LEVEL (rising through LEVEL), VAR<LEVEL (falling
    /// through it) or VAR&MASK (a rising edge of any of the bits); the variable is recorded too.
    #[arg(long = "scope-trigger")]
    pub trigger: Option<String>,
    /// With a trigger: samples kept before it.
    #[arg(long = "scope-pre", default_value_t = 100)]
    pub pre: usize,
    /// With a trigger: samples kept after it; the recording ends then.
    #[arg(long = "scope-post", default_value_t = 1000)]
    pub post: usize,
}

/// `luamotion scope`.
#[derive(clap::Args, Debug)]
pub struct ScopeArgs {
    /// Namespace of the running controller (`run` or `serve`).
    #[arg(long, default_value = "luamotion")]
    ns: String,
    /// Where to write: .csv, .svg or .png (repeat for several).
    #[arg(long, required = true)]
    out: Vec<PathBuf>,
    /// Stop after this long (else at the trigger's end, Ctrl-C or when the controller ends).
    #[arg(long)]
    duration_ms: Option<u64>,
    #[command(flatten)]
    options: ScopeOptions,
}

/// What was recorded.
pub struct Recording {
    pub vars: Vec<Var>,
    pub period_ns: u64,
    /// One cycle in this many was kept.
    pub decimate: u64,
    /// (cycle, one value per variable)
    pub rows: Vec<(u64, Vec<f64>)>,
    /// The cycle the trigger fired in.
    pub trigger: Option<u64>,
    /// Rows overwritten before they were read.
    pub lost: u64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Condition {
    Above(f64),
    Below(f64),
    Bits(u64),
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Trigger {
    var: Var,
    condition: Condition,
}

impl Trigger {
    fn parse(text: &str) -> Result<Trigger> {
        let at = text.find(['>', '<', '&']).context("a trigger is VAR>LEVEL, VAR<LEVEL or VAR&MASK")?;
        let (name, level) = (text[..at].trim(), text[at + 1..].trim());
        let var = Var::parse(name)?;
        let number = || level.parse::<f64>().with_context(|| format!("trigger level {level:?}"));
        let condition = match &text[at..at + 1] {
            ">" => Condition::Above(number()?),
            "<" => Condition::Below(number()?),
            _ => Condition::Bits(parse_mask(level)?),
        };
        Ok(Trigger { var, condition })
    }

    fn fires(&self, before: f64, now: f64) -> bool {
        match self.condition {
            Condition::Above(level) => before <= level && now > level,
            Condition::Below(level) => before >= level && now < level,
            Condition::Bits(mask) => (before as u64) & mask == 0 && (now as u64) & mask != 0,
        }
    }
}

fn parse_mask(text: &str) -> Result<u64> {
    let parsed = match text.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => text.parse(),
    };
    parsed.with_context(|| format!("trigger mask {text:?}"))
}

/// Turns ring rows into the recording: decimation, then the trigger's window.
struct Recorder {
    decimate: u64,
    trigger: Option<(Trigger, usize)>,
    pre: usize,
    post: usize,
    previous: Option<f64>,
    /// Before the trigger: the last `pre` rows.
    rows: VecDeque<(u64, Vec<f64>)>,
    fired: Option<u64>,
    after: usize,
}

impl Recorder {
    fn new(options: &ScopeOptions, vars: &[Var], trigger: Option<Trigger>) -> Recorder {
        let trigger =
            trigger.map(|t| (t, vars.iter().position(|v| *v == t.var).expect("the trigger's variable is recorded")));
        Recorder {
            decimate: options.decimate,
            trigger,
            pre: options.pre,
            post: options.post,
            previous: None,
            rows: VecDeque::new(),
            fired: None,
            after: 0,
        }
    }

    fn done(&self) -> bool {
        self.fired.is_some() && self.after >= self.post
    }

    fn feed(&mut self, cycle: u64, values: &[f64]) {
        if self.done() || !cycle.is_multiple_of(self.decimate) {
            return;
        }
        self.rows.push_back((cycle, values.to_vec()));
        let Some((trigger, column)) = self.trigger else { return };
        if self.fired.is_some() {
            self.after += 1;
            return;
        }
        let now = values[column];
        if self.previous.is_some_and(|before| trigger.fires(before, now)) {
            self.fired = Some(cycle);
        } else if self.rows.len() > self.pre {
            self.rows.pop_front();
        }
        self.previous = Some(now);
    }
}

/// The channels to ask for: the named ones, then the trigger's if it is not among them.
fn channels(options: &ScopeOptions) -> Result<(Vec<Var>, Option<Trigger>)> {
    let mut vars = options.vars.iter().map(|name| Var::parse(name.trim())).collect::<Result<Vec<_>, _>>()?;
    let trigger = options.trigger.as_deref().map(Trigger::parse).transpose()?;
    if let Some(t) = trigger
        && !vars.contains(&t.var)
    {
        vars.push(t.var);
    }
    if vars.is_empty() || vars.len() > CHANNELS {
        bail!("the scope records 1 to {CHANNELS} variables (the trigger's included), not {}", vars.len());
    }
    Ok((vars, trigger))
}

/// A reader attached to a controller's ring.
pub struct Reader {
    ring: ipc::shm::Region<ScopeRing>,
    vars: Vec<Var>,
    recorder: Recorder,
    next: u64,
    lost: u64,
}

impl Reader {
    /// Attaches to the ring of `ns`. `from_start`: the controller was started with these
    /// channels (`run --scope`), so read from its first row; otherwise ask for them and
    /// read from the cycle they are recorded in.
    pub fn attach(ns: &Namespace, options: &ScopeOptions, from_start: bool) -> Result<Reader> {
        let (vars, trigger) = channels(options)?;
        let ring = ScopeRing::open(ns).with_context(|| format!("no controller's scope in namespace {ns}"))?;
        let next = if from_start {
            0
        } else {
            let request = ring.request(&vars.iter().map(|v| v.code()).collect::<Vec<_>>());
            let since = Instant::now();
            while ring.active_request() < request {
                if since.elapsed() > Duration::from_secs(5) {
                    bail!("the controller in namespace {ns} does not take the scope's channels");
                }
                std::thread::sleep(Duration::from_millis(1));
            }
            ring.written()
        };
        let recorder = Recorder::new(options, &vars, trigger);
        Ok(Reader { ring, vars, recorder, next, lost: 0 })
    }

    /// The codes `run --scope` starts the controller with.
    pub fn codes(options: &ScopeOptions) -> Result<Vec<u32>> {
        Ok(channels(options)?.0.iter().map(|v| v.code()).collect())
    }

    /// Reads what the ring holds; true once the trigger's window is complete.
    pub fn drain(&mut self) -> bool {
        let mut values = [0.0; CHANNELS];
        let values = &mut values[..self.vars.len()];
        while !self.recorder.done() {
            match self.ring.read(self.next, values) {
                RowRead::Row(cycle) => {
                    self.recorder.feed(cycle, values);
                    self.next += 1;
                }
                RowRead::Pending => break,
                RowRead::Lost => {
                    // Skip to the oldest row still in the ring.
                    let oldest = self.ring.written().saturating_sub(ipc::scope::ROWS as u64 - 1).max(self.next + 1);
                    self.lost += oldest - self.next;
                    self.next = oldest;
                }
            }
        }
        self.recorder.done()
    }

    pub fn finish(mut self) -> Recording {
        self.drain();
        Recording {
            vars: self.vars,
            period_ns: self.ring.period_ns(),
            decimate: self.recorder.decimate,
            rows: self.recorder.rows.into(),
            trigger: self.recorder.fired,
            lost: self.lost,
        }
    }
}

impl Recording {
    /// Writes each output by its extension.
    pub fn write(&self, outputs: &[PathBuf]) -> Result<()> {
        for path in outputs {
            let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
            match extension.as_str() {
                "csv" => self.write_csv(path),
                "svg" | "png" => plot::draw(self, path),
                _ => bail!("{}: the scope writes .csv, .svg or .png", path.display()),
            }
            .with_context(|| format!("write {}", path.display()))?;
        }
        Ok(())
    }

    pub fn time_ms(&self, cycle: u64) -> f64 {
        cycle as f64 * self.period_ns as f64 / 1e6
    }

    fn write_csv(&self, path: &Path) -> Result<()> {
        let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
        write!(out, "cycle,time_ms")?;
        for var in &self.vars {
            write!(out, ",{} [{}]", var.name(), var.unit())?;
        }
        writeln!(out)?;
        for (cycle, values) in &self.rows {
            write!(out, "{cycle},{}", self.time_ms(*cycle))?;
            for value in values {
                write!(out, ",{value}")?;
            }
            writeln!(out)?;
        }
        out.flush()?;
        Ok(())
    }

    /// What the operator reads on stderr.
    pub fn summary(&self) -> String {
        let trigger = match self.trigger {
            Some(cycle) => format!(", triggered at {} ms", self.time_ms(cycle)),
            None => String::new(),
        };
        format!("scope: {} samples of {} variables{trigger}, {} lost", self.rows.len(), self.vars.len(), self.lost)
    }
}

/// `luamotion scope`: attaches, records, writes.
pub fn scope(args: ScopeArgs) -> Result<ExitCode> {
    let ns = Namespace::new(&args.ns)?;
    rt_core::signals::install();
    let mut reader = Reader::attach(&ns, &args.options, false)?;
    let since = Instant::now();
    let mut checked = Instant::now();
    loop {
        if reader.drain()
            || rt_core::signals::received().is_some()
            || args.duration_ms.is_some_and(|ms| since.elapsed() >= Duration::from_millis(ms))
        {
            break;
        }
        if checked.elapsed() > Duration::from_millis(100) {
            checked = Instant::now();
            if !ipc::controller_ready(&ns)? {
                break;
            }
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let recording = reader.finish();
    recording.write(&args.out)?;
    eprintln!("{}", recording.summary());
    Ok(ExitCode::SUCCESS)
}

/// `run --scope`: a thread that attaches once the controller is up and drains the ring
/// until `stop`, then writes the outputs.
pub fn record_run(
    ns: Namespace,
    options: ScopeOptions,
    outputs: Vec<PathBuf>,
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
) -> std::thread::JoinHandle<Result<()>> {
    use std::sync::atomic::Ordering;
    std::thread::spawn(move || {
        let since = Instant::now();
        while !ipc::controller_ready(&ns)? {
            if stop.load(Ordering::Acquire) || since.elapsed() > Duration::from_secs(10) {
                bail!("the controller did not come up: no scope recorded");
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        // The controller creates the ring just after it says it is up.
        let mut reader = loop {
            match Reader::attach(&ns, &options, true) {
                Ok(reader) => break reader,
                Err(e) if stop.load(Ordering::Acquire) || since.elapsed() > Duration::from_secs(10) => return Err(e),
                Err(_) => std::thread::sleep(Duration::from_millis(2)),
            }
        };
        while !reader.drain() && !stop.load(Ordering::Acquire) {
            std::thread::sleep(Duration::from_millis(5));
        }
        let recording = reader.finish();
        recording.write(&outputs)?;
        eprintln!("{}", recording.summary());
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(trigger: Option<&str>, decimate: u64, pre: usize, post: usize) -> ScopeOptions {
        ScopeOptions { vars: vec!["a0.pos_fb".into()], decimate, trigger: trigger.map(String::from), pre, post }
    }

    fn record(options: &ScopeOptions, values: impl Iterator<Item = (u64, f64)>) -> Recorder {
        let (vars, trigger) = channels(options).unwrap();
        let mut recorder = Recorder::new(options, &vars, trigger);
        for (cycle, value) in values {
            recorder.feed(cycle, &[value]);
        }
        recorder
    }

    #[test]
    fn the_trigger_keeps_pre_and_post_samples_around_the_crossing() {
        let ramp = (1..=1000).map(|c| (c, c as f64 * 0.1));
        let r = record(&options(Some("a0.pos_fb>50"), 1, 10, 20), ramp);
        assert_eq!(r.fired, Some(501));
        let cycles: Vec<u64> = r.rows.iter().map(|(c, _)| *c).collect();
        assert_eq!(cycles, (491..=521).collect::<Vec<_>>());
    }

    #[test]
    fn a_falling_trigger_and_decimation() {
        let ramp = (1..=1000).map(|c| (c, 100.0 - c as f64 * 0.1));
        let r = record(&options(Some("a0.pos_fb<50"), 4, 3, 2), ramp);
        assert_eq!(r.fired, Some(504));
        let cycles: Vec<u64> = r.rows.iter().map(|(c, _)| *c).collect();
        assert_eq!(cycles, vec![492, 496, 500, 504, 508, 512]);
    }

    #[test]
    fn a_bit_edge_fires_on_the_rising_edge_only() {
        let bits = [0.0, 1.0, 5.0, 4.0, 0.0, 4.0, 6.0].into_iter().enumerate().map(|(c, v)| (c as u64 + 1, v));
        let r = record(&options(Some("a0.pos_fb&0x4"), 1, 0, 0), bits);
        assert_eq!(r.fired, Some(3));
    }

    #[test]
    fn bad_triggers_are_refused() {
        for t in ["a0.pos_fb", "a0.pos_fb>x", "a9x.pos_fb>1", "a0.pos_fb&z"] {
            assert!(channels(&options(Some(t), 1, 0, 0)).is_err(), "{t}");
        }
    }
}

//! The soak report: a table on stdout, JSON, and a plot of the latency distributions.

use std::path::Path;

use anyhow::Result;
use hdrhistogram::Histogram;
use plotters::prelude::*;
use serde::Serialize;

use super::memory::Memory;
use super::metrics::CallCounts;
use crate::stdout::sayln;

/// Percentiles of one metric, µs.
#[derive(Debug, Serialize)]
pub struct Row {
    pub name: String,
    pub count: u64,
    pub p50: f64,
    pub p90: f64,
    pub p99: f64,
    pub p99_9: f64,
    pub p99_99: f64,
    pub max: f64,
    /// The floor this metric is compared with, and the ratios at p50 and p99.9.
    pub floor: Option<String>,
    pub ratio_p50: Option<f64>,
    pub ratio_p99_9: Option<f64>,
    #[serde(skip)]
    pub histogram: Histogram<u64>,
}

fn us(ns: u64) -> f64 {
    ns as f64 / 1000.0
}

impl Row {
    pub fn new(name: &str, h: &Histogram<u64>) -> Self {
        let q = |q: f64| if h.is_empty() { 0.0 } else { us(h.value_at_quantile(q)) };
        Row {
            name: name.to_string(),
            count: h.len(),
            p50: q(0.5),
            p90: q(0.9),
            p99: q(0.99),
            p99_9: q(0.999),
            p99_99: q(0.9999),
            max: if h.is_empty() { 0.0 } else { us(h.max()) },
            floor: None,
            ratio_p50: None,
            ratio_p99_9: None,
            histogram: h.clone(),
        }
    }

    /// Compares this metric with `floor`.
    pub fn beside(mut self, floor: &Row) -> Self {
        let ratio = |a: f64, b: f64| (b > 0.0).then(|| a / b);
        self.ratio_p50 = ratio(self.p50, floor.p50);
        self.ratio_p99_9 = ratio(self.p99_9, floor.p99_9);
        self.floor = Some(floor.name.clone());
        self
    }
}

#[derive(Debug, Serialize)]
pub struct Counters {
    #[serde(flatten)]
    pub calls: CallCounts,
    pub cycles: u64,
    pub overruns: u64,
    /// CPU time of the RT thread over the run's length, percent of one core...
    pub rt_cpu_percent: f64,
    /// ...of which the simulated drives' share.
    pub simulation_cpu_percent: f64,
    /// CPU time of the task waker threads (one per CPU), which make the RT thread's futex
    /// wakes when more than one task is due, percent of one core.
    pub task_waker_cpu_percent: f64,
    /// Task wakes over the run...
    pub task_wakes: u64,
    /// ...of which those that found the task asleep (woken by a futex wake of its bell).
    pub futex_wakes: u64,
    /// `--interface`: the process data frames on the wire.
    pub wire: Option<WireCounts>,
}

/// What the frames on a wire did over the run (`luamotion tasks` counts the same).
#[derive(Debug, Serialize)]
pub struct WireCounts {
    pub interface: String,
    /// Cycles whose frame came back complete.
    pub back: u64,
    /// Cycles without a frame back.
    pub missing: u64,
    /// Frames back short of the working counter.
    pub short: u64,
    /// Frames back that matched nothing sent.
    pub unmatched: u64,
    /// CPU time of the master's threads (ecat-master, ecat-mailbox, ecat-txrx) per cycle.
    pub master_cpu_us_per_cycle: f64,
}

/// The cycle against its period: execution percentiles as fractions of it, and the
/// overruns by cause (`rt_core::overrun`, docs/decisions.md "Overrun causes").
#[derive(Debug, Serialize)]
pub struct CycleReport {
    pub period_us: f64,
    /// A wake-up later than this is the OS's; work longer than the period less it, the cycle's.
    pub wake_up_allowance_us: f64,
    /// `cycle execution` (wall time) and `cycle CPU time` as fractions of the period.
    pub execution_of_period: Fractions,
    pub cpu_of_period: Fractions,
    /// Cycles whose execution exceeded its median by more than `STALL_US`: on a virtual
    /// machine mostly the host's stalls of about 135 us (README, "Huge pages").
    pub stalled: u64,
    pub cycles: u64,
    pub overruns: u64,
    pub late_wake_up: u64,
    pub long_execution: u64,
    pub both: u64,
    /// Of `long_execution` and `both`, the cycles whose own CPU time was too long.
    pub own_work: u64,
    /// The same test on the bare loop's fixed work (`floor::BareLoop::works_over_budget`),
    /// and the bare loop's periods.
    pub floor_works_over_budget: u64,
    pub floor_periods: u64,
}

/// How much longer than its median a cycle's execution must be to count as stalled, us.
pub const STALL_US: f64 = 80.0;

/// Percentiles as fractions of a period.
#[derive(Debug, Serialize)]
pub struct Fractions {
    pub p50: f64,
    pub p99: f64,
    pub p99_9: f64,
    pub p99_99: f64,
    pub max: f64,
}

impl Fractions {
    pub fn of(row: &Row, period_us: f64) -> Self {
        Fractions {
            p50: row.p50 / period_us,
            p99: row.p99 / period_us,
            p99_9: row.p99_9 / period_us,
            p99_99: row.p99_99 / period_us,
            max: row.max / period_us,
        }
    }
}

/// One script process: its wake-ups (rank = its task index, the order in which the core
/// wakes the tasks of a cycle), the CPU time it used, its memory.
#[derive(Debug, Serialize)]
pub struct ScriptRow {
    pub rank: usize,
    pub wake_ups: u64,
    pub wake_up_p50_us: f64,
    pub wake_up_p99_us: f64,
    /// CPU time per cycle of the run, and per wake-up (per command), µs.
    pub cpu_us_per_cycle: f64,
    pub cpu_us_per_wake_up: f64,
    /// At the sample of largest total PSS; `None` if the process was gone by then.
    pub memory: Option<Memory>,
}

/// Wake-up fairness: does a later rank wait longer than the scripts' own work explains?
#[derive(Debug, Serialize)]
pub struct Fairness {
    /// The CPU time all scripts together used per cycle, µs.
    pub scripts_cpu_us_per_cycle: f64,
    /// The highest rank's wake-up p50 less the first rank's, µs.
    pub p50_spread_us: f64,
    /// The first rank's wake-up p50 over the iceoryx2 one-way floor's p50...
    pub first_rank_vs_floor_p50: Option<f64>,
    /// ...and over the futex wake-up floor's (the same wake-up the core gives a task).
    pub first_rank_vs_futex_floor_p50: Option<f64>,
}

/// The controller's and the scripts' memory at the sample of largest total PSS.
#[derive(Debug, Serialize)]
pub struct MemoryReport {
    /// The soak's own process, which runs the controller.
    pub controller: Memory,
    pub scripts_measured: usize,
    pub scripts_rss_kib: u64,
    pub scripts_pss_kib: u64,
    pub total_rss_kib: u64,
    pub total_pss_kib: u64,
}

#[derive(Debug, Serialize)]
pub struct Target {
    pub target: String,
    pub measured: String,
    /// `None`: not applicable to this run's settings.
    pub met: Option<bool>,
}

#[derive(Debug, Serialize)]
pub struct RunInfo {
    pub period_us: u32,
    pub scripts: usize,
    pub axes: usize,
    pub duration_s: u64,
    pub pinned: bool,
    pub load: bool,
    pub cpus: usize,
    pub kernel: String,
    pub fifo_priority: Option<u8>,
    pub rt_cpu: Option<usize>,
    pub memory_locked: bool,
    /// Idle CPUs polled (`[rt] idle_poll`).
    pub idle_poll: bool,
    /// The controller's memory rebuilt in huge pages before the first cycle, bytes
    /// (`[rt] huge_pages`); none: not asked.
    pub huge_page_bytes: Option<usize>,
    /// The CPUs the scripts were kept to (`[rt] script_cpus`); none: every CPU.
    pub script_cpus: Option<Vec<usize>>,
}

#[derive(Debug, Serialize)]
pub struct Report {
    pub run: RunInfo,
    pub metrics: Vec<Row>,
    pub counters: Counters,
    pub cycle: CycleReport,
    pub scripts: Vec<ScriptRow>,
    pub fairness: Fairness,
    pub memory: MemoryReport,
    pub targets: Vec<Target>,
}

fn mib(kib: u64) -> f64 {
    kib as f64 / 1024.0
}

pub fn ratio(r: Option<f64>) -> String {
    r.map_or("-".to_string(), |r| format!("{r:.2}x"))
}

impl Report {
    pub fn row(&self, name: &str) -> Option<&Row> {
        self.metrics.iter().find(|r| r.name == name)
    }

    pub fn print(&self) {
        let r = &self.run;
        sayln!(
            "luamotion soak: {} scripts, {} axes, {} us cycle, {} s{}{}; {} CPUs, Linux {}",
            r.scripts,
            r.axes,
            r.period_us,
            r.duration_s,
            if r.pinned { ", pinned" } else { ", not pinned" },
            if r.load { ", background load" } else { "" },
            r.cpus,
            r.kernel
        );
        sayln!(
            "RT thread: SCHED_FIFO {}, CPU {}, memory {} and {}, idle CPUs {}; scripts on {}",
            r.fifo_priority.map_or("refused".to_string(), |p| p.to_string()),
            r.rt_cpu.map_or("not pinned".to_string(), |c| c.to_string()),
            if r.memory_locked { "locked" } else { "not locked" },
            r.huge_page_bytes.map_or("in 4 KiB pages".to_string(), |b| format!("{} MiB in huge pages", b >> 20)),
            if r.idle_poll { "poll" } else { "may halt" },
            r.script_cpus.as_ref().map_or("every CPU".to_string(), |cpus| format!("CPUs {cpus:?}"))
        );
        sayln!();
        sayln!(
            "{:<28} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}  {:>12}",
            "metric (us)",
            "count",
            "p50",
            "p90",
            "p99",
            "p99.9",
            "p99.99",
            "max",
            "x floor p50"
        );
        for row in &self.metrics {
            let ratio = row.ratio_p50.map_or(String::new(), |x| format!("{x:.2}"));
            sayln!(
                "{:<28} {:>9} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>9.1}  {:>12}",
                row.name,
                row.count,
                row.p50,
                row.p90,
                row.p99,
                row.p99_9,
                row.p99_99,
                row.max,
                ratio
            );
        }
        let c = &self.counters;
        sayln!();
        sayln!(
            "commands {}, queries {}, lost {}, duplicated {}, out of order {}, call errors {}",
            c.calls.commands,
            c.calls.queries,
            c.calls.lost,
            c.calls.duplicated,
            c.calls.out_of_order,
            c.calls.call_errors
        );
        sayln!(
            "cycles {}, overruns {}, RT thread CPU {:.1} % of a core ({:.1} % simulating the drives), task wakers {:.1} %; \
             {} task wakes, {} of them of a task asleep",
            c.cycles,
            c.overruns,
            c.rt_cpu_percent,
            c.simulation_cpu_percent,
            c.task_waker_cpu_percent,
            c.task_wakes,
            c.futex_wakes
        );
        if let Some(w) = &c.wire {
            sayln!(
                "EtherCAT on {}: {} frames back, {} missing, {} short of the working counter, {} matching nothing \
                 sent; the master's threads {:.1} us of CPU per cycle",
                w.interface,
                w.back,
                w.missing,
                w.short,
                w.unmatched,
                w.master_cpu_us_per_cycle
            );
        }
        self.print_cycle();
        self.print_scripts();
        sayln!();
        for t in &self.targets {
            let verdict = match t.met {
                Some(true) => "met",
                Some(false) => "MISSED",
                None => "n/a",
            };
            sayln!("[{verdict:>6}] {}: {}", t.target, t.measured);
        }
    }

    fn print_cycle(&self) {
        let y = &self.cycle;
        let f = |x: &Fractions| {
            format!(
                "p50 {:.3}, p99 {:.3}, p99.9 {:.3}, p99.99 {:.3}, max {:.3}",
                x.p50, x.p99, x.p99_9, x.p99_99, x.max
            )
        };
        sayln!("cycle execution / period {:.0} us: {}", y.period_us, f(&y.execution_of_period));
        sayln!("cycle CPU time / period:  {}", f(&y.cpu_of_period));
        sayln!(
            "cycles stalled (execution over its p50 + {STALL_US:.0} us): {} of {} ({:.2} %)",
            y.stalled,
            y.cycles,
            y.stalled as f64 * 100.0 / y.cycles.max(1) as f64
        );
        sayln!(
            "overruns {}: {} late wake-up (woke > {:.0} us late), {} long execution (work > {:.0} us), {} both; \
             {} of the long ones the cycle's own work (its CPU time > {:.0} us)",
            y.overruns,
            y.late_wake_up,
            y.wake_up_allowance_us,
            y.long_execution,
            y.period_us - y.wake_up_allowance_us,
            y.both,
            y.own_work,
            y.period_us - y.wake_up_allowance_us
        );
    }

    fn print_scripts(&self) {
        sayln!();
        sayln!("wake-up by script rank (rank = task index: each CPU's task waker wakes its tasks in index order)");
        sayln!(
            "{:>5} {:>9} {:>9} {:>9} {:>13} {:>12} {:>9} {:>9}",
            "rank",
            "wake-ups",
            "p50 us",
            "p99 us",
            "CPU us/cycle",
            "CPU us/wake",
            "RSS MiB",
            "PSS MiB"
        );
        for s in &self.scripts {
            let (rss, pss) = s.memory.map_or((String::from("-"), String::from("-")), |m| {
                (format!("{:.1}", mib(m.rss_kib)), format!("{:.1}", mib(m.pss_kib)))
            });
            sayln!(
                "{:>5} {:>9} {:>9.1} {:>9.1} {:>13.1} {:>12.1} {:>9} {:>9}",
                s.rank,
                s.wake_ups,
                s.wake_up_p50_us,
                s.wake_up_p99_us,
                s.cpu_us_per_cycle,
                s.cpu_us_per_wake_up,
                rss,
                pss
            );
        }
        let fair = &self.fairness;
        sayln!(
            "scripts' CPU time per cycle {:.1} us; wake-up p50 spread (highest rank less rank 0) {:.1} us; \
             rank 0 p50 {} the iceoryx2 one-way floor, {} the futex wake-up floor",
            fair.scripts_cpu_us_per_cycle,
            fair.p50_spread_us,
            ratio(fair.first_rank_vs_floor_p50),
            ratio(fair.first_rank_vs_futex_floor_p50)
        );
        let m = &self.memory;
        sayln!(
            "memory: controller RSS {:.1} MiB, PSS {:.1} MiB; {} scripts RSS {:.1} MiB, PSS {:.1} MiB; \
             total PSS {:.1} MiB (RSS {:.1} MiB)",
            mib(m.controller.rss_kib),
            mib(m.controller.pss_kib),
            m.scripts_measured,
            mib(m.scripts_rss_kib),
            mib(m.scripts_pss_kib),
            mib(m.total_pss_kib),
            mib(m.total_rss_kib)
        );
    }

    pub fn write_json(&self, path: &Path) -> Result<()> {
        std::fs::write(path, serde_json::to_vec_pretty(self)?)?;
        Ok(())
    }

    /// The latency distributions on log scales: x the percentile as 1/(1-p) (10 = p90,
    /// 1000 = p99.9), y the latency in µs.
    pub fn plot(&self, path: &Path) -> Result<()> {
        let rows: Vec<&Row> = self.metrics.iter().filter(|r| r.count > 0).collect();
        let max_us = rows.iter().map(|r| r.max).fold(1.0, f64::max) * 2.0;
        let root = SVGBackend::new(path, (1100, 700)).into_drawing_area();
        root.fill(&WHITE)?;
        let title = format!(
            "luamotion soak: {} scripts, {} axes, {} us cycle, {} s",
            self.run.scripts, self.run.axes, self.run.period_us, self.run.duration_s
        );
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((1.0f64..1e6).log_scale(), (0.1f64..max_us).log_scale())?;
        chart.configure_mesh().x_desc("percentile, as 1/(1-p): 10 = p90, 1000 = p99.9").y_desc("latency, us").draw()?;
        for (i, row) in rows.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            let points: Vec<(f64, f64)> = row
                .histogram
                .iter_quantiles(1)
                .map(|v| (1.0 / (1.0 - v.quantile_iterated_to()).max(1e-6), us(v.value_iterated_to()).max(0.1)))
                .collect();
            chart
                .draw_series(LineSeries::new(points, color.stroke_width(2)))?
                .label(row.name.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
        }
        chart.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw()?;
        root.present()?;
        Ok(())
    }
}

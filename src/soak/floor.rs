//! The machine's own floors, measured in the same run: what iceoryx2 alone costs between
//! two processes (the pong side runs as `luamotion soak-pong`), what the same ping costs
//! when the sleeper is woken as a task is (its futex word), how late a bare
//! absolute-deadline sleep loop wakes at the cycle's period and scheduling class (what
//! cyclictest measures), and how long the same fixed work takes in each of its periods
//! (what the machine adds to a cycle's execution that is not the cycle's doing).

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use config::RtConfig;
use hdrhistogram::Histogram;
use ipc::Namespace;
use ipc::clock::monotonic_ns;
use rt_core::realtime;

use super::metrics;
use super::ping_pong::{Echo, Ping, Pong, WakeBy};

pub const ONE_WAY: &str = "floor: iceoryx2 one way";
pub const PING_PONG: &str = "floor: iceoryx2 round trip";
/// From the wake of a sleeping process' futex word to its having the ping: the worker's
/// `wake-up` with nothing else going on.
pub const FUTEX_WAKE: &str = "floor: futex wake-up";
pub const BARE_LATENESS: &str = "floor: bare loop lateness";
/// The wall time of the bare loop's fixed work, a fifth of a period of CPU time.
pub const FIXED_WORK: &str = "floor: fixed work execution";
/// The CPU time the kernel charges the same work: without `CONFIG_IRQ_TIME_ACCOUNTING`
/// the interrupts served meanwhile are charged to it.
pub const FIXED_WORK_CPU: &str = "floor: fixed work CPU time";
/// The CPU time charged to the bare loop on its way out of each sleep
/// (`realtime::WokeCpuTime`).
pub const WAKE_UP_CPU: &str = "floor: wake-up CPU time";

/// The share of the period the bare loop works each period: about what a cycle of 96
/// axes and 16 tasks takes at its median.
pub const WORK_SHARE: f64 = 0.2;

/// What the bare loop measured: its wake-up lateness, its fixed work's wall and CPU time,
/// and its wake-ups' CPU time.
pub struct BareLoop {
    pub lateness: Histogram<u64>,
    pub fixed_work: Histogram<u64>,
    pub fixed_work_cpu: Histogram<u64>,
    pub wake_up_cpu: Histogram<u64>,
    /// The periods whose fixed work took more CPU time than a cycle may (the period less
    /// the wake-up allowance): the own-work test of `rt_core::overrun` passed on a work
    /// that never changes, so each is the machine's doing.
    pub works_over_budget: u64,
}

/// An absolute-deadline loop on a thread set up as the RT thread is: how late it wakes,
/// and how long a fixed amount of work then takes, each period. The work's wall time
/// beyond its median is what the machine (interrupts, the hypervisor, the kernel's
/// non-preemptible paths) adds; a cycle's execution tail cannot be shorter than it.
pub fn bare_loop(rt: &RtConfig, period_ns: u64, duration: Duration) -> Result<BareLoop> {
    let rt = rt.clone();
    let thread = std::thread::Builder::new().name("floor-loop".into()).spawn(move || {
        realtime::setup_current_thread(&rt);
        let mut work = FixedWork::calibrated((period_ns as f64 * WORK_SHARE) as u64);
        let budget = rt_core::overrun::work_budget_ns(period_ns);
        let mut works_over_budget = 0;
        let (mut lateness, mut fixed_work, mut fixed_work_cpu, mut wake_up_cpu) =
            (metrics::histogram(), metrics::histogram(), metrics::histogram(), metrics::histogram());
        let end = monotonic_ns() + duration.as_nanos() as u64;
        let mut deadline = monotonic_ns() + period_ns;
        // Read as the RT thread reads its CPU time.
        let mut cycle_cpu = realtime::CycleCpuTime::default();
        while deadline < end {
            realtime::sleep_until(deadline);
            let cpu = cycle_cpu.woke();
            let woke = monotonic_ns();
            metrics::record(&mut lateness, woke.saturating_sub(deadline));
            if let Some(cpu) = cpu {
                metrics::record(&mut fixed_work_cpu, cpu.previous_cycle_ns);
                metrics::record(&mut wake_up_cpu, cpu.wake_up_ns);
                works_over_budget += u64::from(cpu.previous_cycle_ns > budget);
            }
            work.run();
            metrics::record(&mut fixed_work, monotonic_ns() - woke);
            deadline += period_ns;
        }
        BareLoop { lateness, fixed_work, fixed_work_cpu, wake_up_cpu, works_over_budget }
    })?;
    thread.join().map_err(|_| anyhow::anyhow!("the floor loop panicked"))
}

/// Arithmetic over a table the size of a cycle's working set, repeated `rounds` times.
struct FixedWork {
    table: Vec<f64>,
    rounds: u64,
}

impl FixedWork {
    /// Work of about `cpu_ns` of CPU time: the fewest nanoseconds a round took in a few
    /// trials (the least disturbed) sets the number of rounds.
    fn calibrated(cpu_ns: u64) -> Self {
        let mut work = FixedWork { table: vec![1.0; 4096], rounds: 1 };
        let round_ns = (0..20)
            .map(|_| {
                let started = realtime::thread_cpu_ns();
                work.run();
                realtime::thread_cpu_ns() - started
            })
            .min()
            .unwrap_or(1)
            .max(1);
        work.rounds = (cpu_ns / round_ns).max(1);
        work
    }

    fn run(&mut self) {
        for round in 0..self.rounds {
            let k = 1.0 + round as f64 * 1e-9;
            for x in self.table.iter_mut() {
                *x = (*x * k).mul_add(0.999_999, 1e-6);
            }
        }
        std::hint::black_box(&self.table);
    }
}

/// `luamotion soak-pong`: echoes pings until terminated.
pub fn pong(ns: &str, futex: bool) -> Result<()> {
    let by = if futex { WakeBy::Futex } else { WakeBy::Iceoryx2Event };
    let pong = Pong::create(&Namespace::new(ns)?, by)?;
    pong.serve(rt_core::signals::termination_requested)?;
    Ok(())
}

struct PongProcess(Child);

impl Drop for PongProcess {
    fn drop(&mut self) {
        // SAFETY: asking our own child to end (iceoryx2 turns SIGTERM into a request).
        unsafe { libc::kill(self.0.id() as i32, libc::SIGTERM) };
        let _ = self.0.wait();
    }
}

/// One ping per period for `duration`, against a pong process woken by iceoryx2 events:
/// one way (the ping sent to the pong side having it) and round trip. One way is the leg
/// to the pong side, which slept a whole period as a task sleeps a cycle for its reply;
/// the way back wakes a ping side asleep only for the echo, whose CPU has not gone idle
/// yet, and is faster (30 against 50 us at p50 here, docs/decisions.md "Transport floor").
pub fn iceoryx2(ns: &str, period_ns: u64, duration: Duration) -> Result<(Histogram<u64>, Histogram<u64>)> {
    let (mut one_way, mut round_trip) = (metrics::histogram(), metrics::histogram());
    ping_pong(ns, WakeBy::Iceoryx2Event, period_ns, duration, |echo| {
        metrics::record(&mut one_way, echo.pong_received_ns - echo.sent_ns);
        metrics::record(&mut round_trip, echo.received_ns - echo.sent_ns);
    })?;
    Ok((one_way, round_trip))
}

/// One ping per period for `duration`, against a pong process that sleeps on its futex
/// word as a task does: from the wake to the pong side having the ping. (The way back is
/// not a wake-up: the ping side's watch of its word usually sees the echo come.)
pub fn futex(ns: &str, period_ns: u64, duration: Duration) -> Result<Histogram<u64>> {
    let mut wake = metrics::histogram();
    ping_pong(ns, WakeBy::Futex, period_ns, duration, |echo| {
        // A pong side that looked after a timed-out sleep may take the ping before its wake.
        if echo.pong_received_ns >= echo.notified_ns {
            metrics::record(&mut wake, echo.pong_received_ns - echo.notified_ns);
        }
    })?;
    Ok(wake)
}

fn ping_pong(ns: &str, by: WakeBy, period_ns: u64, duration: Duration, mut record: impl FnMut(&Echo)) -> Result<()> {
    let exe = std::env::current_exe()?;
    let mut pong = Command::new(exe);
    pong.args(["soak-pong", "--ns", ns]);
    if by == WakeBy::Futex {
        pong.arg("--futex");
    }
    let child = pong.stdin(Stdio::null()).spawn()?;
    let _pong = PongProcess(child);
    let namespace = Namespace::new(ns)?;
    let started = Instant::now();
    let mut ping = loop {
        match Ping::open(&namespace, by) {
            Ok(ping) => break ping,
            Err(_) if started.elapsed() < Duration::from_secs(10) => std::thread::sleep(Duration::from_millis(10)),
            Err(e) => return Err(e).context("the pong process did not come up"),
        }
    };
    let end = monotonic_ns() + duration.as_nanos() as u64;
    let mut next = monotonic_ns();
    while next < end {
        realtime::sleep_until(next);
        let echo = ping.ping()?;
        if echo.pong_received_ns < echo.sent_ns || echo.received_ns < echo.pong_sent_ns {
            bail!("the floor's clocks disagree: {echo:?}");
        }
        record(&echo);
        next += period_ns;
    }
    Ok(())
}

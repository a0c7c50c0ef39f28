//! The machine's own floors, measured in the same run: what iceoryx2 alone costs between
//! two processes (the pong side runs as `luamotion soak-pong`), and how late a bare
//! absolute-deadline sleep loop wakes at the cycle's period and scheduling class (what
//! cyclictest measures).

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use config::RtConfig;
use hdrhistogram::Histogram;
use ipc::Namespace;
use ipc::clock::monotonic_ns;
use rt_core::realtime;

use super::metrics;
use super::ping_pong::{Ping, Pong};

pub const ONE_WAY: &str = "floor: iceoryx2 one way";
pub const PING_PONG: &str = "floor: iceoryx2 round trip";
pub const BARE_LATENESS: &str = "floor: bare loop lateness";

/// The wake-up lateness of a bare absolute-deadline loop, on a thread set up as the RT
/// thread is.
pub fn bare_loop(rt: &RtConfig, period_ns: u64, duration: Duration) -> Result<Histogram<u64>> {
    let rt = rt.clone();
    let thread = std::thread::Builder::new().name("floor-loop".into()).spawn(move || {
        realtime::setup_current_thread(&rt);
        let mut lateness = metrics::histogram();
        let end = monotonic_ns() + duration.as_nanos() as u64;
        let mut deadline = monotonic_ns() + period_ns;
        while deadline < end {
            realtime::sleep_until(deadline);
            metrics::record(&mut lateness, monotonic_ns().saturating_sub(deadline));
            deadline += period_ns;
        }
        lateness
    })?;
    thread.join().map_err(|_| anyhow::anyhow!("the floor loop panicked"))
}

/// `luamotion soak-pong`: echoes pings until terminated.
pub fn pong(ns: &str) -> Result<()> {
    let pong = Pong::create(&Namespace::new(ns)?)?;
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

/// One ping per period for `duration`, against a pong process: one-way and round trip.
pub fn ping_pong(ns: &str, period_ns: u64, duration: Duration) -> Result<(Histogram<u64>, Histogram<u64>)> {
    let exe = std::env::current_exe()?;
    let child = Command::new(exe).args(["soak-pong", "--ns", ns]).stdin(Stdio::null()).spawn()?;
    let _pong = PongProcess(child);
    let namespace = Namespace::new(ns)?;
    let started = Instant::now();
    let mut ping = loop {
        match Ping::open(&namespace) {
            Ok(ping) => break ping,
            Err(_) if started.elapsed() < Duration::from_secs(10) => std::thread::sleep(Duration::from_millis(10)),
            Err(e) => return Err(e).context("the pong process did not come up"),
        }
    };
    let (mut one_way, mut round_trip) = (metrics::histogram(), metrics::histogram());
    let end = monotonic_ns() + duration.as_nanos() as u64;
    let mut next = monotonic_ns();
    while next < end {
        realtime::sleep_until(next);
        let echo = ping.ping()?;
        if echo.pong_received_ns < echo.sent_ns || echo.received_ns < echo.pong_sent_ns {
            bail!("the floor's clocks disagree: {echo:?}");
        }
        metrics::record(&mut one_way, echo.pong_received_ns - echo.sent_ns);
        metrics::record(&mut one_way, echo.received_ns - echo.pong_sent_ns);
        metrics::record(&mut round_trip, echo.received_ns - echo.sent_ns);
        next += period_ns;
    }
    Ok((one_way, round_trip))
}

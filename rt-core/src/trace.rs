//! The trace (`luamotion run --trace FILE`): every cycle's reference, feedback and status
//! words of the first axes, and for an axis with a flexible load (`[axes.plant]
//! load_frequency_hz`) where the load is, written to a CSV file by a thread of its own. The RT thread
//! only pushes a fixed-size row into a preallocated queue; a full queue drops the row and
//! counts it. Each traced axis' position-trigger pulses of the cycle are counted in its
//! `aN_pt_pulses` column, and every pulse is a row of its own in `FILE.pulses.csv` (cycle,
//! axis, the point's position, the time of its crossing in ms; HMPL ch. 12); the last
//! column, `gpo`, is the controller's outputs.

use std::io::Write;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use crossbeam::queue::ArrayQueue;
use schema::Snapshot;

use crate::config::MachineConfig;
use crate::position_trigger::{PositionTriggers, Pulse, TRACE_PULSES};
use devices::ecat::Network;
use kernel::Kernel;

/// Axes a trace row holds.
pub const TRACED_AXES: usize = 8;
/// Rows in flight: 16 s at 1 ms.
const CAPACITY: usize = 16_384;

#[derive(Clone, Copy, Debug, Default)]
pub struct TracedAxis {
    pub ref_pos: f64,
    pub pos_fb: f64,
    pub motion_status: u32,
    pub fault_status: u32,
    /// Simulation only: the flexible load's position, axis coordinates.
    pub load_pos: Option<f64>,
}

/// The wall-time columns of a row, ns: how late this cycle woke, how long the previous
/// cycle's work took, and how much CPU time the RT thread used from that cycle's wake-up to
/// its sleep (which a preempted cycle does not inflate); and the RT thread's page faults
/// and preemptions from the previous wake-up to this one (`realtime::WokeCpuTime`).
#[derive(Clone, Copy, Debug, Default)]
pub struct CycleTiming {
    pub lateness_ns: u64,
    pub previous_execution_ns: u64,
    pub previous_cpu_ns: u64,
    pub previous_faults: u64,
    pub previous_preemptions: u64,
}

#[derive(Clone, Copy, Debug, Default)]
pub struct TraceRow {
    pub cycle: u64,
    pub overruns: u64,
    pub timing: CycleTiming,
    pub axes: [TracedAxis; TRACED_AXES],
    /// Each traced axis' position-trigger pulses in this cycle.
    pub pt_counts: [u32; TRACED_AXES],
    /// This cycle's first pulses: (axis, pulse).
    pub pulses: [(u8, Pulse); TRACE_PULSES],
    pub pulse_count: usize,
    /// The controller's outputs.
    pub gpo: u32,
}

impl TraceRow {
    pub fn of(snapshot: &Snapshot, timing: CycleTiming) -> Self {
        let mut row = TraceRow {
            cycle: snapshot.cycle,
            overruns: snapshot.overruns,
            timing,
            gpo: snapshot.gpio.gpo,
            ..TraceRow::default()
        };
        for (out, axis) in row.axes.iter_mut().zip(&snapshot.axes) {
            *out = TracedAxis {
                ref_pos: axis.ref_pos,
                pos_fb: axis.pos_fb,
                motion_status: axis.motion_status,
                fault_status: axis.fault_status,
                load_pos: None,
            };
        }
        row
    }

    /// Adds each axis' flexible load, which no snapshot carries (a drive measures only its
    /// motor).
    pub fn with_loads(mut self, kernel: &Kernel, network: &Network) -> Self {
        for (out, axis) in self.axes.iter_mut().zip(kernel.axes()) {
            out.load_pos = axis.load_position(network);
        }
        self
    }

    /// Adds this cycle's position-trigger pulses.
    pub fn with_position_triggers(mut self, triggers: &PositionTriggers) -> Self {
        for axis in 0..triggers.axis_count() {
            let (pulses, count) = triggers.cycle_pulses(axis);
            if let Some(slot) = self.pt_counts.get_mut(axis) {
                *slot = count;
            }
            for &pulse in pulses {
                if let Some(slot) = self.pulses.get_mut(self.pulse_count) {
                    *slot = (axis as u8, pulse);
                    self.pulse_count += 1;
                }
            }
        }
        self
    }
}

/// The run's digest (docs/decisions.md, "Simulation clock"): FNV-1a, 64 bits, over each
/// recorded cycle's row in a fixed little-endian encoding (floats by their bits, the
/// wall-time columns left out), so the same run gives the same digest on any machine,
/// with or without a trace file.
#[derive(Clone, Copy, Debug)]
pub struct Digest {
    hash: u64,
    rows: u64,
}

impl Default for Digest {
    fn default() -> Self {
        Digest { hash: 0xcbf2_9ce4_8422_2325, rows: 0 }
    }
}

impl Digest {
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.hash = (self.hash ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }

    fn float(&mut self, x: f64) {
        self.bytes(&x.to_bits().to_le_bytes());
    }

    /// Adds one cycle's row.
    pub fn add(&mut self, row: &TraceRow) {
        self.rows += 1;
        self.bytes(&row.cycle.to_le_bytes());
        self.bytes(&row.overruns.to_le_bytes());
        for axis in &row.axes {
            self.float(axis.ref_pos);
            self.float(axis.pos_fb);
            self.bytes(&axis.motion_status.to_le_bytes());
            self.bytes(&axis.fault_status.to_le_bytes());
            self.float(axis.load_pos.unwrap_or(f64::NAN));
        }
        for count in &row.pt_counts {
            self.bytes(&count.to_le_bytes());
        }
        for (axis, pulse) in &row.pulses[..row.pulse_count] {
            self.bytes(&[*axis]);
            self.float(pulse.pos);
            self.float(pulse.time_ms);
        }
        self.bytes(&row.gpo.to_le_bytes());
    }

    /// The digest so far.
    pub fn value(&self) -> u64 {
        self.hash
    }

    /// Rows added.
    pub fn rows(&self) -> u64 {
        self.rows
    }
}

/// The RT thread's end.
pub struct TraceSender {
    queue: Arc<ArrayQueue<TraceRow>>,
    dropped: Arc<AtomicU64>,
}

impl TraceSender {
    pub fn push(&self, row: TraceRow) {
        if self.queue.push(row).is_err() {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// On the simulation clock, where the cycle may wait: a full queue waits for the writer
    /// instead of dropping the row, so the file holds every row.
    pub fn push_all(&self, mut row: TraceRow) {
        while let Err(back) = self.queue.push(row) {
            row = back;
            std::thread::sleep(Duration::from_millis(1));
        }
    }
}

/// The writer thread; `finish` writes what is left and closes the file.
pub struct TraceWriter {
    stop: Arc<AtomicBool>,
    thread: JoinHandle<std::io::Result<u64>>,
    dropped: Arc<AtomicU64>,
}

impl TraceWriter {
    /// Rows the writer could not keep up with, and the file's result.
    pub fn finish(self) -> (u64, std::io::Result<u64>) {
        self.stop.store(true, Ordering::Release);
        let written = self.thread.join().unwrap_or_else(|_| Err(std::io::Error::other("trace writer panicked")));
        (self.dropped.load(Ordering::Relaxed), written)
    }
}

/// Opens `path` and starts the writer for the axes of `config`.
pub fn start(path: &Path, config: &MachineConfig) -> std::io::Result<(TraceSender, TraceWriter)> {
    let axes = config.axes.len().min(TRACED_AXES);
    let mut loads = [false; TRACED_AXES];
    for (load, axis) in loads.iter_mut().zip(&config.axes) {
        *load = axis.plant.load_frequency_hz > 0.0;
    }
    let file = std::fs::File::create(path)?;
    let pulses = std::fs::File::create(pulses_path(path))?;
    let queue = Arc::new(ArrayQueue::new(CAPACITY));
    let dropped = Arc::new(AtomicU64::new(0));
    let stop = Arc::new(AtomicBool::new(false));
    let thread = {
        let (queue, stop) = (queue.clone(), stop.clone());
        std::thread::Builder::new()
            .name("trace".into())
            .spawn(move || write([file, pulses], &queue, &stop, &loads[..axes]))?
    };
    Ok((TraceSender { queue, dropped: dropped.clone() }, TraceWriter { stop, thread, dropped }))
}

/// `FILE.pulses.csv` beside the trace `FILE.csv`.
pub fn pulses_path(path: &Path) -> std::path::PathBuf {
    path.with_extension("pulses.csv")
}

/// One row per cycle; `loads` says, per traced axis, whether it has a load column.
fn write(
    [file, pulses]: [std::fs::File; 2],
    queue: &ArrayQueue<TraceRow>,
    stop: &AtomicBool,
    loads: &[bool],
) -> std::io::Result<u64> {
    let axes = loads.len();
    let mut out = std::io::BufWriter::new(file);
    let mut pulses_out = std::io::BufWriter::new(pulses);
    writeln!(pulses_out, "cycle,axis,position,time_ms")?;
    let mut header = String::from(
        "cycle,overruns,lateness_us,previous_execution_us,previous_cpu_us,previous_faults,previous_preemptions",
    );
    for (a, &load) in loads.iter().enumerate() {
        header += &format!(",a{a}_ref_pos,a{a}_pos_fb,a{a}_motion_status,a{a}_fault_status");
        if load {
            header += &format!(",a{a}_load_pos");
        }
    }
    for a in 0..axes {
        header += &format!(",a{a}_pt_pulses");
    }
    header += ",gpo";
    writeln!(out, "{header}")?;
    let mut rows = 0;
    loop {
        let stopping = stop.load(Ordering::Acquire);
        while let Some(row) = queue.pop() {
            let us = |ns: u64| ns as f64 / 1000.0;
            let timing = row.timing;
            let (late, execution, cpu) =
                (us(timing.lateness_ns), us(timing.previous_execution_ns), us(timing.previous_cpu_ns));
            let (faults, preemptions) = (timing.previous_faults, timing.previous_preemptions);
            write!(out, "{},{},{late},{execution},{cpu},{faults},{preemptions}", row.cycle, row.overruns)?;
            for (axis, &load) in row.axes.iter().zip(loads) {
                write!(out, ",{},{},{},{}", axis.ref_pos, axis.pos_fb, axis.motion_status, axis.fault_status)?;
                if load {
                    write!(out, ",{}", axis.load_pos.unwrap_or(f64::NAN))?;
                }
            }
            for count in &row.pt_counts[..axes] {
                write!(out, ",{count}")?;
            }
            writeln!(out, ",{}", row.gpo)?;
            for (axis, pulse) in &row.pulses[..row.pulse_count] {
                writeln!(pulses_out, "{},{axis},{},{}", row.cycle, pulse.pos, pulse.time_ms)?;
            }
            rows += 1;
        }
        if stopping {
            out.flush()?;
            pulses_out.flush()?;
            return Ok(rows);
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn digest_of(rows: &[TraceRow]) -> u64 {
        let mut digest = Digest::default();
        rows.iter().for_each(|row| digest.add(row));
        digest.value()
    }

    /// The digest is FNV-1a over a fixed encoding: the empty digest is FNV's offset basis,
    /// the wall-time columns do not count, and one bit of a position does.
    #[test]
    fn the_digest_sees_the_machine_not_the_wall() {
        assert_eq!(Digest::default().value(), 0xcbf2_9ce4_8422_2325);
        let mut row = TraceRow { cycle: 7, gpo: 3, ..TraceRow::default() };
        row.axes[0].pos_fb = 100.0;
        let base = digest_of(&[row, row]);
        assert_eq!(base, digest_of(&[row, row]));
        let timing = CycleTiming {
            lateness_ns: 12_345,
            previous_execution_ns: 678,
            previous_cpu_ns: 90,
            previous_faults: 3,
            previous_preemptions: 1,
        };
        let timed = TraceRow { timing, ..row };
        assert_eq!(digest_of(&[row, timed]), base, "wall time is left out");
        let mut moved = row;
        moved.axes[0].pos_fb = f64::from_bits(100f64.to_bits() + 1);
        assert_ne!(digest_of(&[row, moved]), base, "the last bit of a position counts");
        assert_ne!(digest_of(&[row]), base, "so does every row");
    }
}

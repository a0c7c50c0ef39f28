//! The trace (`luamotion run --trace FILE`): every cycle's reference, feedback and status
//! words of the first axes, written to a CSV file by a thread of its own. The RT thread
//! only pushes a fixed-size row into a preallocated queue; a full queue drops the row and
//! counts it. The last columns are each axis' position-trigger pulses of the cycle
//! (HMPL ch. 12): `position@time_ms` for each, `;` between them.

use std::io::Write;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use crossbeam::queue::ArrayQueue;
use ipc::messages::Snapshot;

use crate::position_trigger::{PositionTriggers, Pulse, TRACE_PULSES};

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
}

#[derive(Clone, Copy, Debug, Default)]
pub struct TraceRow {
    pub cycle: u64,
    pub overruns: u64,
    /// How late this cycle woke, and how long the previous cycle's work took, ns.
    pub lateness_ns: u64,
    pub previous_execution_ns: u64,
    pub axes: [TracedAxis; TRACED_AXES],
    pub pulses: [TracedPulses; TRACED_AXES],
}

/// An axis' position-trigger pulses in one cycle: the first `TRACE_PULSES` and the count.
#[derive(Clone, Copy, Debug, Default)]
pub struct TracedPulses {
    pub count: u32,
    pub pulses: [Pulse; TRACE_PULSES],
}

impl TraceRow {
    pub fn of(snapshot: &Snapshot, lateness_ns: u64, previous_execution_ns: u64) -> Self {
        let mut row = TraceRow {
            cycle: snapshot.cycle,
            overruns: snapshot.overruns,
            lateness_ns,
            previous_execution_ns,
            ..TraceRow::default()
        };
        for (out, axis) in row.axes.iter_mut().zip(&snapshot.axes) {
            *out = TracedAxis {
                ref_pos: axis.ref_pos,
                pos_fb: axis.pos_fb,
                motion_status: axis.motion_status,
                fault_status: axis.fault_status,
            };
        }
        row
    }

    /// Adds this cycle's position-trigger pulses.
    pub fn with_position_triggers(mut self, triggers: &PositionTriggers) -> Self {
        for (axis, out) in self.pulses.iter_mut().enumerate() {
            let (pulses, count) = triggers.cycle_pulses(axis);
            out.count = count;
            out.pulses[..pulses.len()].copy_from_slice(pulses);
        }
        self
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

/// Opens `path` and starts the writer for `axes` axes.
pub fn start(path: &Path, axes: usize) -> std::io::Result<(TraceSender, TraceWriter)> {
    let file = std::fs::File::create(path)?;
    let queue = Arc::new(ArrayQueue::new(CAPACITY));
    let dropped = Arc::new(AtomicU64::new(0));
    let stop = Arc::new(AtomicBool::new(false));
    let axes = axes.min(TRACED_AXES);
    let thread = {
        let (queue, stop) = (queue.clone(), stop.clone());
        std::thread::Builder::new().name("trace".into()).spawn(move || write(file, &queue, &stop, axes))?
    };
    Ok((TraceSender { queue, dropped: dropped.clone() }, TraceWriter { stop, thread, dropped }))
}

fn write(file: std::fs::File, queue: &ArrayQueue<TraceRow>, stop: &AtomicBool, axes: usize) -> std::io::Result<u64> {
    let mut out = std::io::BufWriter::new(file);
    let mut header = String::from("cycle,overruns,lateness_us,previous_execution_us");
    for a in 0..axes {
        header += &format!(",a{a}_ref_pos,a{a}_pos_fb,a{a}_motion_status,a{a}_fault_status");
    }
    for a in 0..axes {
        header += &format!(",a{a}_pt_pulses");
    }
    writeln!(out, "{header}")?;
    let mut rows = 0;
    loop {
        let stopping = stop.load(Ordering::Acquire);
        while let Some(row) = queue.pop() {
            let us = |ns: u64| ns as f64 / 1000.0;
            write!(out, "{},{},{},{}", row.cycle, row.overruns, us(row.lateness_ns), us(row.previous_execution_ns))?;
            for axis in &row.axes[..axes] {
                write!(out, ",{},{},{},{}", axis.ref_pos, axis.pos_fb, axis.motion_status, axis.fault_status)?;
            }
            for traced in &row.pulses[..axes] {
                write!(out, ",")?;
                let shown = (traced.count as usize).min(TRACE_PULSES);
                for (i, pulse) in traced.pulses[..shown].iter().enumerate() {
                    let separator = if i == 0 { "" } else { ";" };
                    write!(out, "{separator}{}@{}", pulse.pos, pulse.time_ms)?;
                }
                if traced.count as usize > shown {
                    write!(out, ";+{}", traced.count as usize - shown)?;
                }
            }
            writeln!(out)?;
            rows += 1;
        }
        if stopping {
            out.flush()?;
            return Ok(rows);
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

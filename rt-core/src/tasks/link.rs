//! The RT thread and the supervisor talk through two bounded lock-free queues: the core
//! orders (start a process, kill one, publish an alarm), the supervisor reports what the
//! processes did. Neither side ever waits for the other; the supervisor sleeps until an
//! order rings its bell or one of its processes ends.

use std::os::fd::{AsFd, AsRawFd, BorrowedFd, FromRawFd, OwnedFd};
use std::sync::Arc;

use crossbeam::queue::ArrayQueue;

/// Orders and reports in flight; far more than 64 tasks produce between two polls.
const CAPACITY: usize = 512;

/// The longest function name `StartTaskFunc` takes.
pub const ENTRY_BYTES: usize = 63;

/// Where a task's program starts: its top level, or a function of it (`StartTaskFunc`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    len: u8,
    name: [u8; ENTRY_BYTES],
}

impl Entry {
    /// The program's top level (`StartTask`).
    pub const TOP_LEVEL: Entry = Entry { len: 0, name: [0; ENTRY_BYTES] };

    /// A function entry; `None` when the name is empty or too long.
    pub fn function(name: &[u8]) -> Option<Self> {
        if name.is_empty() || name.len() > ENTRY_BYTES {
            return None;
        }
        let mut entry = Entry { len: name.len() as u8, name: [0; ENTRY_BYTES] };
        entry.name[..name.len()].copy_from_slice(name);
        Some(entry)
    }

    /// The function's name as bytes, empty for the top level.
    pub fn name(&self) -> &[u8] {
        &self.name[..self.len as usize]
    }

    /// The function's name, or `None` for the top level.
    pub fn function_name(&self) -> Option<String> {
        (self.len > 0).then(|| String::from_utf8_lossy(&self.name[..self.len as usize]).into_owned())
    }
}

/// An alarm for the supervisor to log and publish on the event stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AlarmReport {
    /// The alarm's code (`api::alarms`).
    pub alarm: u32,
    /// The task it concerns.
    pub task: u8,
    /// The cycle it was raised in.
    pub cycle: u64,
    /// The Lua line the task was at, when known (0: unknown).
    pub line: u32,
    /// What the alarm concerns besides the task: the axis of a 0x001F, the signal that
    /// ended a process, the ms without progress of a watchdog.
    pub detail: i64,
}

/// What the RT thread asks of the supervisor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// Start the task's script process.
    Start {
        /// The task.
        task: u8,
        /// Where its program starts.
        entry: Entry,
    },
    /// The core handed the task to the pool's waiting process `pid` on place `place` of
    /// the board: forward its output and reap it (or, when it died first, start one).
    Handed {
        /// The task.
        task: u8,
        /// Where its program starts.
        entry: Entry,
        /// The board place the process waits on.
        place: usize,
        /// The waiting process.
        pid: u32,
    },
    /// End the task's process at once (SIGKILL).
    Kill {
        /// The task.
        task: u8,
        /// Its process, so that a process started since is spared.
        pid: u32,
    },
    /// Log an alarm and publish it on the event stream.
    Alarm(AlarmReport),
}

/// How a script process ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exit {
    /// Exit status 0: the program ran to its end.
    Finished,
    /// The program failed; `end_code` is what it wrote into its slot (an HMPL code or an
    /// `ipc::task_table::EndCode`; 0 when it could not say).
    Failed {
        /// What the program wrote into its slot.
        end_code: u32,
    },
    /// Killed by a signal.
    Signal(i32),
}

/// What the supervisor tells the RT thread about the script processes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Report {
    /// The task's process started.
    Spawned {
        /// The task.
        task: u8,
        /// Its process.
        pid: u32,
    },
    /// The task's process could not be started.
    SpawnFailed {
        /// The task.
        task: u8,
    },
    /// The task's process ended.
    Exited {
        /// The task.
        task: u8,
        /// The process that ended.
        pid: u32,
        /// How it ended.
        exit: Exit,
    },
}

/// The RT thread's end.
pub struct CoreLink {
    orders: Arc<ArrayQueue<Order>>,
    reports: Arc<ArrayQueue<Report>>,
    bell: Arc<OrderBell>,
}

/// The supervisor's end.
pub struct SupervisorEnd {
    orders: Arc<ArrayQueue<Order>>,
    reports: Arc<ArrayQueue<Report>>,
    bell: Arc<OrderBell>,
}

/// What the RT thread rings with each order, so that the supervisor sleeps until there
/// is one instead of looking every millisecond: an eventfd, whose write takes a spinlock
/// and never sleeps, so the RT thread never blocks on it.
struct OrderBell(OwnedFd);

impl OrderBell {
    fn new() -> std::io::Result<Self> {
        // SAFETY: eventfd with constant flags; the descriptor is checked before it is owned.
        let fd = unsafe { libc::eventfd(0, libc::EFD_NONBLOCK | libc::EFD_CLOEXEC) };
        if fd < 0 {
            return Err(std::io::Error::last_os_error());
        }
        // SAFETY: a fresh descriptor nothing else owns.
        Ok(OrderBell(unsafe { OwnedFd::from_raw_fd(fd) }))
    }

    fn ring(&self) {
        let one = 1u64;
        // SAFETY: an 8-byte write from a live u64 to the eventfd; a full counter (EAGAIN)
        // still leaves it readable, so a failure loses no wake-up.
        unsafe { libc::write(self.0.as_raw_fd(), (&raw const one).cast(), 8) };
    }

    /// Takes the rings so far: the bell reads quiet again.
    fn clear(&self) {
        let mut rings = 0u64;
        // SAFETY: an 8-byte read into a live u64 from the non-blocking eventfd.
        unsafe { libc::read(self.0.as_raw_fd(), (&raw mut rings).cast(), 8) };
    }
}

/// The two ends; an error when the OS refuses the bell (no file descriptor left).
pub fn link() -> std::io::Result<(CoreLink, SupervisorEnd)> {
    let orders = Arc::new(ArrayQueue::new(CAPACITY));
    let reports = Arc::new(ArrayQueue::new(CAPACITY));
    let bell = Arc::new(OrderBell::new()?);
    Ok((
        CoreLink { orders: orders.clone(), reports: reports.clone(), bell: bell.clone() },
        SupervisorEnd { orders, reports, bell },
    ))
}

impl CoreLink {
    /// Never blocks; an order that finds the queue full is dropped.
    pub fn order(&mut self, order: Order) {
        if self.orders.push(order).is_ok() {
            self.bell.ring();
        }
    }

    pub(crate) fn next_report(&self) -> Option<Report> {
        self.reports.pop()
    }
}

impl SupervisorEnd {
    pub(crate) fn next_order(&self) -> Option<Order> {
        self.orders.pop()
    }

    /// The bell the RT thread rings with each order, to wait on (`poll`: readable once
    /// rung).
    pub fn bell(&self) -> BorrowedFd<'_> {
        self.bell.0.as_fd()
    }

    /// Before the orders are taken: a ring from now on wakes the next wait.
    pub fn clear_bell(&self) {
        self.bell.clear();
    }

    /// Reports never get lost: a full queue is retried until the RT thread drains it.
    pub fn report(&self, mut report: Report) {
        while let Err(back) = self.reports.push(report) {
            report = back;
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }
}

//! SCHED_FIFO for the threads that stand in for hardware or drive the wire: an ESC answers
//! a frame in microseconds whatever else the machine does, and a master's frames leave on
//! its cycle. As plain threads on a loaded machine they wait behind any busy process for
//! longer than a frame may take. The core's RT thread and task wakers ask through it too
//! (`rt-core/src/realtime.rs`): one request of the OS, in the lowest crate that needs it.

use std::io;

/// The calling thread at SCHED_FIFO `priority` (1..99); 0 leaves it a plain thread.
pub fn fifo(priority: u8) -> io::Result<()> {
    if priority == 0 {
        return Ok(());
    }
    let param = libc::sched_param { sched_priority: i32::from(priority) };
    // SAFETY: `param` is valid for the call; 0 is the calling thread.
    if unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) } == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

/// `fifo`, a refusal logged: the thread then runs as a plain one (a container, a laptop).
pub fn fifo_or_plain(priority: u8, thread: &str) {
    if let Err(error) = fifo(priority) {
        tracing::warn!("SCHED_FIFO priority {priority} refused to {thread} ({error}); it runs as a plain thread");
    }
}

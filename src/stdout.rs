//! Everything the CLI prints to stdout goes through `write`, so that a reader that goes
//! away (`luamotion tasks | head -1`: EPIPE, as Rust ignores SIGPIPE) never ends a command
//! with a panic. What a closed stdout does depends on the command:
//!
//! - a command that hosts a controller (`run`, `serve`, `test`, `soak`) goes on
//!   (`sayln!`): the line is dropped, as the scripts' forwarded output is, and said once
//!   on stderr. A log reader that dies must not stop a machine; SIGPIPE's default action
//!   would kill the process without stopping its axes or removing its shared memory;
//! - any other command ends (`outln!`, `out!`): the write returns `StdoutClosed`, the
//!   command returns it, its resources are dropped in order, and `main` exits quietly
//!   with 141, what the shell shows for a writer that SIGPIPE ended.

use std::fmt;
use std::io::{self, ErrorKind, Write};
use std::sync::atomic::{AtomicBool, Ordering};

/// The reader of stdout is gone (EPIPE): inside the `io::Error` `write` returns.
#[derive(Debug)]
pub struct StdoutClosed;

impl fmt::Display for StdoutClosed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("stdout is closed")
    }
}

impl std::error::Error for StdoutClosed {}

/// Writes to stdout at once (flushed, so a closed pipe is seen at this write).
pub fn write(args: fmt::Arguments) -> io::Result<()> {
    let mut out = io::stdout().lock();
    match out.write_fmt(args).and_then(|()| out.flush()) {
        Err(e) if e.kind() == ErrorKind::BrokenPipe => Err(io::Error::new(ErrorKind::BrokenPipe, StdoutClosed)),
        result => result,
    }
}

/// Whether a command ended because stdout's reader is gone: nothing to report.
pub fn closed(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        cause.downcast_ref::<io::Error>().and_then(|e| e.get_ref()).is_some_and(|inner| inner.is::<StdoutClosed>())
    })
}

/// Set once a hosting command's line could not be written.
static DROPPING: AtomicBool = AtomicBool::new(false);

/// `write` for a command that hosts a controller: a line that cannot be written is
/// dropped, the first time with a word on stderr, and the command goes on.
pub fn write_or_drop(args: fmt::Arguments) {
    if let Err(e) = write(args)
        && !DROPPING.swap(true, Ordering::Relaxed)
    {
        tracing::warn!("{e}: what the controller prints there is dropped from now on; it runs on");
    }
}

/// A line on stdout for a command that does not host a controller: `io::Result`, whose
/// `StdoutClosed` the command returns.
macro_rules! outln {
    () => {
        $crate::stdout::write(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::stdout::write(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `outln!` without the newline.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::stdout::write(format_args!($($arg)*))
    };
}

/// A line on stdout for a command that hosts a controller (`write_or_drop`).
macro_rules! sayln {
    () => {
        $crate::stdout::write_or_drop(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::stdout::write_or_drop(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `sayln!` without the newline.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::stdout::write_or_drop(format_args!($($arg)*))
    };
}

pub(crate) use {out, outln, say, sayln};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_stdouts_own_broken_pipe_counts_as_closed() {
        let closed = anyhow::Error::new(io::Error::new(ErrorKind::BrokenPipe, StdoutClosed)).context("print a task");
        assert!(super::closed(&closed));
        let socket = anyhow::Error::new(io::Error::from(ErrorKind::BrokenPipe)).context("write to the controller");
        assert!(!super::closed(&socket), "a broken socket is an error to report");
    }
}

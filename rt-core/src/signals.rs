//! The stop signals a controller obeys: SIGINT (Ctrl-C), SIGTERM (`kill`, GNU `timeout`,
//! systemd), SIGHUP (the terminal went away) and SIGQUIT. Each one sets a flag that stays
//! set, whatever arrives after it: `timeout` and systemd send SIGCONT right behind SIGTERM,
//! and a "last signal" word (iceoryx2's) would forget the SIGTERM.

use std::sync::Arc;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicUsize, Ordering};

const STOP_SIGNALS: [i32; 4] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP, libc::SIGQUIT];

/// The number of the stop signal received last, 0 while none.
static RECEIVED: OnceLock<Arc<AtomicUsize>> = OnceLock::new();

/// Starts catching the stop signals in this process (once; later calls do nothing).
pub fn install() {
    RECEIVED.get_or_init(|| {
        // iceoryx2 installs its own handler the first time one of its parts asks for
        // signals; have it do so now, so that it cannot later replace ours (ours chains to it).
        let _ = iceoryx2_bb_posix::signal::SignalHandler::last_signal();
        let received = Arc::new(AtomicUsize::new(0));
        for signal in STOP_SIGNALS {
            if let Err(e) = signal_hook::flag::register_usize(signal, received.clone(), signal as usize) {
                tracing::warn!("cannot catch signal {signal}: {e}");
            }
        }
        received
    });
}

/// The stop signal this process received last, if any.
pub fn received() -> Option<i32> {
    install();
    match RECEIVED.get().map_or(0, |r| r.load(Ordering::Acquire)) {
        0 => None,
        signal => Some(signal as i32),
    }
}

/// Whether a stop signal has arrived.
pub fn termination_requested() -> bool {
    received().is_some()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SIGTERM then SIGCONT and SIGCHLD (as `timeout` and a dying child send them): the
    /// SIGTERM is still seen.
    #[test]
    fn a_stop_signal_is_not_forgotten() {
        install();
        assert_eq!(received(), None);
        // SAFETY: raising signals at our own process; the stop signal is caught by `install`.
        unsafe {
            libc::raise(libc::SIGTERM);
            libc::raise(libc::SIGCONT);
            libc::raise(libc::SIGCHLD);
        }
        assert_eq!(received(), Some(libc::SIGTERM));
        assert!(termination_requested());
        // A second stop signal keeps the request standing.
        unsafe { libc::raise(libc::SIGHUP) };
        assert!(termination_requested());
    }
}

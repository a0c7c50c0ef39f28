//! The processes of a namespace: whether one lives, and the signals a script process
//! takes back from iceoryx2.

/// Whether process `pid` exists (signal 0: nothing is sent); one of another user exists too.
pub fn process_alive(pid: u32) -> bool {
    // SAFETY: signal 0 only checks that the process exists.
    unsafe { libc::kill(pid as libc::pid_t, 0) == 0 || *libc::__errno_location() == libc::EPERM }
}

/// Pins the calling thread to `cpu`; whether it could.
#[cfg(test)]
pub(crate) fn pin_current_thread(cpu: usize) -> bool {
    // SAFETY: a zeroed cpu_set_t with one bit set, for the calling thread.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(cpu, &mut set);
        libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &set) == 0
    }
}

/// Gives the process the default action again for the signals iceoryx2 (and Rust's
/// runtime) catch: SIGINT and SIGTERM end it, and a crash (SIGSEGV, SIGBUS, SIGILL,
/// SIGFPE, SIGABRT) kills it, whether the fault is real or the signal was sent. Script
/// processes use it, so that the controller can stop them and sees their crashes.
pub fn restore_default_signals() {
    // Creating iceoryx2's handler first: it is installed once, so it cannot replace ours later.
    let _ = iceoryx2_bb_posix::signal::SignalHandler::last_signal();
    for signal in [libc::SIGTERM, libc::SIGINT, libc::SIGSEGV, libc::SIGBUS, libc::SIGILL, libc::SIGFPE, libc::SIGABRT]
    {
        // SAFETY: resetting a signal to its default action.
        unsafe { libc::signal(signal, libc::SIG_DFL) };
    }
}

//! What the RT thread asks of the OS: SCHED_FIFO, a CPU of its own, locked memory, idle
//! CPUs that poll, and absolute-deadline sleeps. Each request the OS refuses is logged and skipped, so that
//! the controller also runs as a plain thread (in a container, on a laptop).

use crate::config::{RtConfig, ScriptCpus};

/// What the OS granted, for the logs and the soak report.
#[derive(Clone, Copy, Debug, Default)]
pub struct Granted {
    /// The SCHED_FIFO priority; `None`: refused, or not asked for.
    pub fifo_priority: Option<u8>,
    /// The CPU the thread is pinned to; `None`: refused, or not asked for.
    pub cpu: Option<usize>,
    /// The process' memory is locked (mlockall).
    pub memory_locked: bool,
    /// Idle CPUs poll (`IdlePoll` held).
    pub idle_poll: bool,
}

/// Applies `config` to the calling thread.
pub fn setup_current_thread(config: &RtConfig) -> Granted {
    let mut granted = Granted::default();
    if config.lock_memory {
        // SAFETY: plain syscall with constant flags.
        if unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) } == 0 {
            granted.memory_locked = true;
        } else {
            tracing::warn!("mlockall refused ({}); page faults may delay cycles", errno());
        }
    }
    if let Some(cpu) = config.cpu {
        if pin_current_thread(cpu) {
            granted.cpu = Some(cpu);
        } else {
            tracing::warn!("cannot pin the RT thread to CPU {cpu} ({}); it floats", errno());
        }
    }
    if config.priority > 0 {
        match subdevice::realtime::fifo(config.priority) {
            Ok(()) => granted.fifo_priority = Some(config.priority),
            Err(error) => tracing::warn!(
                "SCHED_FIFO priority {} refused ({error}); the RT thread runs as a plain thread",
                config.priority
            ),
        }
    }
    granted
}

/// Idle CPUs poll instead of halting for as long as the value lives: a Linux PM QoS CPU
/// latency limit of 0 us, which holds while `/dev/cpu_dma_latency` stays open. On a
/// virtual machine a halted vCPU is woken through the host: there a one-script soak's
/// wake-up took 19-23 us with halting CPUs and 4-6 us with polling ones (README, "Soak test").
pub struct IdlePoll {
    _file: std::fs::File,
}

impl IdlePoll {
    /// Holds the limit if `config.idle_poll`; a refusal (no such device, not root) is
    /// logged and skipped like the RT thread's other requests.
    pub fn hold(config: &RtConfig) -> Option<Self> {
        use std::io::Write;
        if !config.idle_poll {
            return None;
        }
        let opened = std::fs::OpenOptions::new().write(true).open(CPU_LATENCY_DEVICE);
        match opened.and_then(|mut file| file.write_all(&0i32.to_ne_bytes()).map(|()| file)) {
            Ok(file) => Some(IdlePoll { _file: file }),
            Err(e) => {
                tracing::warn!("idle CPU polling refused ({CPU_LATENCY_DEVICE}: {e}); idle CPUs may halt");
                None
            }
        }
    }
}

const CPU_LATENCY_DEVICE: &str = "/dev/cpu_dma_latency";

/// Pins the calling thread to `cpu`; whether the OS agreed.
fn pin_current_thread(cpu: usize) -> bool {
    confine_current_thread(&[cpu])
}

/// Has the calling thread, and every thread and process it starts from now on, run only
/// on `cpus`; whether the OS agreed (an empty set or a CPU past the set's size: no).
pub fn confine_current_thread(cpus: &[usize]) -> bool {
    if cpus.is_empty() || cpus.iter().any(|&cpu| cpu >= libc::CPU_SETSIZE as usize) {
        return false;
    }
    // SAFETY: the set is zeroed then filled with CPU indices checked against its size.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        for &cpu in cpus {
            libc::CPU_SET(cpu, &mut set);
        }
        libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &set) == 0
    }
}

/// The CPUs the calling thread may run on; none when the OS does not say.
fn allowed_cpus() -> Option<Vec<usize>> {
    // SAFETY: `set` is valid for the call, which only writes it; CPU_ISSET reads it.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        (libc::sched_getaffinity(0, size_of::<libc::cpu_set_t>(), &mut set) == 0)
            .then(|| (0..libc::CPU_SETSIZE as usize).filter(|&c| libc::CPU_ISSET(c, &set)).collect())
    }
}

/// The CPUs the script processes are kept to (`[rt] script_cpus`), of those the calling
/// thread may run on; none: they run wherever the controller may.
pub fn script_cpus(config: &RtConfig) -> Option<Vec<usize>> {
    script_cpus_among(config.script_cpus, config.cpu, &allowed_cpus()?)
}

/// `script_cpus` with the RT thread on `rt_cpu` among the controller's `allowed` CPUs:
/// kept off the RT thread's CPU when asked (`Others`, where another CPU is left) or by
/// default (`Auto`) where two or more are left: on a machine of two CPUs the scripts
/// would otherwise have one between them.
fn script_cpus_among(choice: ScriptCpus, rt_cpu: Option<usize>, allowed: &[usize]) -> Option<Vec<usize>> {
    let rt = rt_cpu.filter(|cpu| allowed.contains(cpu))?;
    let others: Vec<usize> = allowed.iter().copied().filter(|&cpu| cpu != rt).collect();
    let keep_off = match choice {
        ScriptCpus::All => false,
        ScriptCpus::Others => !others.is_empty(),
        ScriptCpus::Auto => others.len() >= 2,
    };
    keep_off.then_some(others)
}

/// The CPUs the calling thread may run on, and so the script processes: one task waker
/// each (`CoreEndpoint::hand_wakes_to_threads`). The RT thread's CPU comes first, whose
/// waker rings the others and takes the tasks of a CPU not listed (with the scripts kept
/// off its CPU, it only rings).
pub fn task_cpus(config: &RtConfig) -> Vec<usize> {
    // Never empty: the wakers need one CPU to start on.
    let Some(mut cpus) = allowed_cpus().filter(|cpus| !cpus.is_empty()) else {
        return vec![config.cpu.unwrap_or(0)];
    };
    if let Some(rt) = config.cpu.filter(|rt| cpus.contains(rt)) {
        cpus.retain(|&c| c != rt);
        cpus.insert(0, rt);
    }
    cpus
}

/// A task waker (`CoreEndpoint::hand_wakes_to_threads`): pinned to `cpu`, one SCHED_FIFO
/// priority below the RT thread, so it wakes its CPU's tasks as soon as the RT thread hands
/// them over (or, on the RT thread's CPU, once the cycle's work is done).
pub fn setup_waker_thread(config: &RtConfig, cpu: usize) {
    if !pin_current_thread(cpu) {
        tracing::warn!("cannot pin the task waker of CPU {cpu} there ({})", errno());
    }
    if config.priority > 1 {
        subdevice::realtime::fifo_or_plain(config.priority - 1, "the task waker");
    }
}

fn errno() -> std::io::Error {
    std::io::Error::last_os_error()
}

/// Sleeps until the absolute CLOCK_MONOTONIC time `deadline_ns`.
pub fn sleep_until(deadline_ns: u64) {
    let ts = libc::timespec {
        tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
    };
    // SAFETY: `ts` is valid; EINTR is retried with the same absolute deadline.
    while unsafe { libc::clock_nanosleep(libc::CLOCK_MONOTONIC, libc::TIMER_ABSTIME, &ts, std::ptr::null_mut()) }
        == libc::EINTR
    {}
}

/// CPU time the calling thread has used, ns (CLOCK_THREAD_CPUTIME_ID). For a running
/// thread Linux brings the count up to date under its run queue's lock
/// (`task_sched_runtime`); on a VM a lock held by a vCPU the host has descheduled stalls the
/// reader for milliseconds, and the stall counts as its CPU time.
pub fn thread_cpu_ns() -> u64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is valid for the call.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// CPU time the calling thread had used when the kernel last accounted it, ns, to the
/// microsecond (getrusage RUSAGE_THREAD), without any run-queue lock: as of its last sleep,
/// or of a scheduler tick since. Read right after a wake-up it is the CPU time up to the
/// sleep before.
pub fn thread_cpu_ns_at_last_sleep() -> u64 {
    thread_usage().cpu_ns
}

/// What getrusage(RUSAGE_THREAD) tells of the calling thread: its CPU time as of its last
/// accounting, and the exact counts of its page faults and of the times it was preempted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct ThreadUsage {
    cpu_ns: u64,
    /// Minor and major page faults.
    faults: u64,
    /// Involuntary context switches: another thread (or the host's vCPU scheduler, where it
    /// tells the guest) took the CPU from this one.
    preemptions: u64,
}

fn thread_usage() -> ThreadUsage {
    // SAFETY: an all-zero `rusage` is valid, and the call only writes it.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(libc::RUSAGE_THREAD, &mut usage) };
    let us = |t: libc::timeval| t.tv_sec as u64 * 1_000_000 + t.tv_usec as u64;
    ThreadUsage {
        cpu_ns: (us(usage.ru_utime) + us(usage.ru_stime)) * 1_000,
        faults: (usage.ru_minflt + usage.ru_majflt) as u64,
        preemptions: usage.ru_nivcsw as u64,
    }
}

/// The CPU time of a thread that sleeps once a cycle, from each wake-up to the next sleep,
/// with one read under the run-queue lock a cycle.
///
/// At the wake-up the exact count is read before the caller reads the wall time: a wait for
/// the lock there, or a stall of the VM on the way out of the sleep (both charged to the
/// thread as CPU time), fall into the wake-up's lateness, not into the work. The cycle's
/// end is read at the next wake-up from the lock-free count the kernel brought up to date
/// as the thread went to sleep (`thread_cpu_ns_at_last_sleep`).
#[derive(Debug, Default)]
pub struct CycleCpuTime {
    woke_ns: Option<u64>,
    /// The page faults and preemptions counted at the last wake-up.
    woke_usage: ThreadUsage,
}

/// What a wake-up learns of the CPU time (`CycleCpuTime::woke`), ns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WokeCpuTime {
    /// The previous cycle's, from its wake-up to its sleep.
    pub previous_cycle_ns: u64,
    /// This wake-up's, from the end of the sleep to now: the way out of the sleep (a few
    /// microseconds) and whatever stall of the VM the kernel charged to the thread there.
    pub wake_up_ns: u64,
    /// Page faults from the previous wake-up to this one. A cycle that touched memory it
    /// had not touched before (a first allocation, a page the kernel took away) counts
    /// them; one that only stalled does not.
    pub previous_faults: u64,
    /// Preemptions from the previous wake-up to this one.
    pub previous_preemptions: u64,
}

impl CycleCpuTime {
    /// Called first thing after each wake-up (none for the first).
    pub fn woke(&mut self) -> Option<WokeCpuTime> {
        // Before the exact read, which brings the lock-free count up to date as well.
        let at_sleep = thread_usage();
        let now_ns = thread_cpu_ns();
        let before = std::mem::replace(&mut self.woke_usage, at_sleep);
        let woke_ns = self.woke_ns.replace(now_ns)?;
        Some(WokeCpuTime {
            previous_cycle_ns: at_sleep.cpu_ns.saturating_sub(woke_ns),
            wake_up_ns: now_ns.saturating_sub(at_sleep.cpu_ns),
            previous_faults: at_sleep.faults - before.faults,
            previous_preemptions: at_sleep.preemptions - before.preemptions,
        })
    }

    /// The CPU time since the last wake-up, read now: for a last cycle, which ends without
    /// a sleep.
    pub fn since_woke(&self) -> u64 {
        self.woke_ns.map_or(0, |woke_ns| thread_cpu_ns().saturating_sub(woke_ns))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One waker per CPU the controller may use, the RT thread's first; an RT CPU the
    /// controller may not use changes nothing.
    #[test]
    fn the_task_cpus_put_the_rt_cpu_first() {
        let floating = task_cpus(&RtConfig { cpu: None, ..RtConfig::default() });
        assert!(!floating.is_empty() && floating.is_sorted(), "{floating:?}");
        assert!(floating.windows(2).all(|w| w[0] != w[1]), "{floating:?}");
        let last = *floating.last().unwrap();
        let pinned = task_cpus(&RtConfig { cpu: Some(last), ..RtConfig::default() });
        let expected: Vec<usize> =
            std::iter::once(last).chain(floating.iter().copied().filter(|&c| c != last)).collect();
        assert_eq!(pinned, expected);
        let elsewhere = task_cpus(&RtConfig { cpu: Some(libc::CPU_SETSIZE as usize + 1), ..RtConfig::default() });
        assert_eq!(elsewhere, floating);
    }

    /// `[rt] script_cpus` on machines of 1 to 4 CPUs with the RT thread on the last (one
    /// row per case): the scripts keep off its CPU when asked and another is left, or by
    /// default when two are; an RT thread not pinned, or pinned outside, keeps nothing.
    #[test]
    fn the_scripts_keep_off_the_rt_cpu_as_asked() {
        use ScriptCpus::{All, Auto, Others};
        // (asked, the RT thread's CPU, the controller's CPUs, the scripts' CPUs)
        type Row = (ScriptCpus, Option<usize>, &'static [usize], Option<&'static [usize]>);
        let rows: [Row; 11] = [
            (Auto, Some(3), &[0, 1, 2, 3], Some(&[0, 1, 2])),
            (Auto, Some(2), &[0, 1, 2], Some(&[0, 1])),
            (Auto, Some(1), &[0, 1], None),
            (Auto, Some(0), &[0], None),
            (Others, Some(1), &[0, 1], Some(&[0])),
            (Others, Some(0), &[0], None),
            (All, Some(3), &[0, 1, 2, 3], None),
            (Auto, None, &[0, 1, 2, 3], None),
            (Others, None, &[0, 1], None),
            (Others, Some(7), &[0, 1], None),
            (Others, Some(2), &[1, 2, 5], Some(&[1, 5])),
        ];
        for (choice, rt, allowed, expected) in rows {
            let got = script_cpus_among(choice, rt, allowed);
            assert_eq!(got.as_deref(), expected, "{choice:?} with the RT thread on {rt:?} of {allowed:?}");
        }
    }

    /// A thread confined to a CPU starts its processes there (a process inherits its
    /// starter's mask); an empty set is refused and changes nothing.
    #[test]
    fn a_confined_thread_starts_its_processes_on_its_cpus() {
        let cpu = *allowed_cpus().expect("this thread's CPUs").last().expect("a CPU");
        let listed = std::thread::spawn(move || {
            assert!(!confine_current_thread(&[]), "an empty set is refused");
            assert!(confine_current_thread(&[cpu]), "confined to CPU {cpu}");
            assert_eq!(allowed_cpus(), Some(vec![cpu]));
            let mut child = std::process::Command::new("sleep").arg("5").spawn().expect("start sleep");
            let status = std::fs::read_to_string(format!("/proc/{}/status", child.id())).expect("its status");
            let _ = child.kill();
            let _ = child.wait();
            status.lines().find_map(|l| l.strip_prefix("Cpus_allowed_list:")).map(|l| l.trim().to_string())
        })
        .join()
        .unwrap();
        assert_eq!(listed, Some(cpu.to_string()), "the child may run on CPU {cpu} only");
    }

    /// Held, the limit is the device's value (its read gives the lowest limit held); not
    /// asked for, nothing is held.
    #[test]
    fn idle_poll_holds_a_zero_latency_limit() {
        let off = RtConfig { idle_poll: false, ..RtConfig::default() };
        assert!(IdlePoll::hold(&off).is_none());
        let Some(held) = IdlePoll::hold(&RtConfig::default()) else {
            return eprintln!("{CPU_LATENCY_DEVICE} refused here: nothing to check");
        };
        let limit = std::fs::read(CPU_LATENCY_DEVICE).expect("the device reads while held");
        assert_eq!(limit, 0i32.to_ne_bytes(), "0 us while held");
        drop(held);
    }

    /// A cycle that touches memory it never touched counts its page faults, one per page;
    /// one that only computes counts none: what tells a cycle's own work on memory from a
    /// stall charged to it.
    #[test]
    fn a_cycle_counts_the_pages_it_touched_first() {
        std::thread::spawn(|| {
            const PAGES: usize = 256;
            let mut cycle = CycleCpuTime::default();
            cycle.woke();
            let mut x = 1.0f64;
            for _ in 0..100_000 {
                x = std::hint::black_box(x * 1.000_001);
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
            let computed = cycle.woke().expect("a cycle ended");
            let len = PAGES * 4096;
            // SAFETY: a fresh private anonymous mapping, written inside its length and unmapped.
            unsafe {
                let flags = libc::MAP_PRIVATE | libc::MAP_ANONYMOUS;
                let area = libc::mmap(std::ptr::null_mut(), len, libc::PROT_READ | libc::PROT_WRITE, flags, -1, 0);
                assert_ne!(area, libc::MAP_FAILED);
                libc::madvise(area, len, libc::MADV_NOHUGEPAGE);
                for page in 0..PAGES {
                    (area as *mut u8).add(page * 4096).write_volatile(1);
                }
                libc::munmap(area, len);
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
            let touched = cycle.woke().expect("a cycle ended");
            assert!(touched.previous_faults >= PAGES as u64, "{touched:?}");
            assert!(computed.previous_faults < 8, "{computed:?}");
        })
        .join()
        .unwrap();
    }

    /// Right after a sleep the lock-free count is the thread's CPU time up to that sleep
    /// (without the sleep's update it lags by up to a scheduler tick, 4 ms here), and a
    /// cycle's CPU time is its work's.
    #[test]
    fn a_cycle_counts_its_work_up_to_its_sleep() {
        use std::time::{Duration, Instant};
        std::thread::spawn(|| {
            let mut cycle = CycleCpuTime::default();
            assert_eq!(cycle.woke(), None, "no cycle before the first wake-up");
            for work in [20, 3].map(Duration::from_millis) {
                // Work without reading the CPU time, which would bring the count up to date.
                let started = Instant::now();
                let mut x = 1.0f64;
                while started.elapsed() < work {
                    x = std::hint::black_box(x * 1.000_001);
                }
                std::thread::sleep(Duration::from_millis(5));
                let at_sleep = thread_cpu_ns_at_last_sleep();
                let now = thread_cpu_ns();
                assert!(now - at_sleep < 100_000, "{now} ns used, {at_sleep} ns counted at the sleep");
                let WokeCpuTime { previous_cycle_ns: cpu, wake_up_ns, .. } = cycle.woke().expect("a cycle ended");
                // Preemption may take some of the work's wall time; nothing adds to it but
                // the way into the sleep (the scheduler's, which on a busy machine may
                // balance the CPU's load then), never the sleep itself.
                assert!(cpu > 0 && cpu < work.as_nanos() as u64 + 2_000_000, "{cpu} ns for {work:?} of work");
                assert!(wake_up_ns < 2_000_000, "{wake_up_ns} ns for the way out of the sleep");
            }
        })
        .join()
        .unwrap();
    }
}

//! The task wakers: threads that make the futex wakes of a cycle's due tasks for the RT
//! thread, one thread per CPU the tasks run on.
//!
//! A futex wake costs the waker the kernel's `try_to_wake_up` of the woken process: on this
//! project's 2-vCPU VM about 0.6-0.7 us when the process last slept on the waker's own CPU
//! and 1.5-1.7 us when it slept on another one, whose run queue has to be locked and
//! interrupted from afar (docs/decisions.md, "The task wakers"). So each task notes the
//! CPU it goes to sleep on (`TaskSlot::sleep_cpu`), and its wake goes to the waker of that
//! CPU, which wakes all of a cycle's tasks asleep on one of that CPU's bells in one futex
//! call (`TaskTable::wake_sleepers`). The RT thread wakes only the first waker, on its own
//! CPU; that one wakes the others: with the wakes handed over, the RT thread does not
//! reach into another CPU's run queue, whose lock a vCPU the host has descheduled may hold.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

use crate::error::IpcError;
use crate::futex;
use crate::namespace::Namespace;
use crate::shm::Region;
use crate::task_table::TaskTable;

/// The futex wakes handed to one waker thread.
#[derive(Default)]
struct WakeHandoff {
    /// Bit t: task t is to be woken.
    pending: AtomicU64,
    /// Bumped with each hand-off; the waker sleeps on it.
    word: AtomicU32,
    stop: AtomicBool,
    /// Of the wakes handed over, those that found the task asleep (woken through its bell).
    futex_wakes: AtomicU64,
}

impl WakeHandoff {
    /// Adds `tasks` to what the waker is to wake, without waking it (`ring`).
    fn give(&self, tasks: u64) {
        self.pending.fetch_or(tasks, Ordering::Release);
    }

    /// Wakes the waker. The word is the controller's own: a private futex (`futex::wake_private`).
    fn ring(&self) {
        self.word.fetch_add(1, Ordering::Release);
        futex::wake_private(&self.word);
    }

    fn stop(&self) {
        self.stop.store(true, Ordering::Release);
        self.ring();
    }

    /// The waker thread: wakes the tasks handed to it until stopped, and first the
    /// `others` wakers that were given some.
    fn serve(&self, table: &TaskTable, others: &[Arc<WakeHandoff>]) {
        while !self.stop.load(Ordering::Acquire) {
            let seen = self.word.load(Ordering::Acquire);
            for other in others.iter().filter(|o| o.pending.load(Ordering::Acquire) != 0) {
                other.ring();
            }
            let pending = self.pending.swap(0, Ordering::AcqRel);
            self.futex_wakes.fetch_add(table.wake_sleepers(pending), Ordering::Relaxed);
            futex::wait_private(&self.word, seen, std::time::Duration::from_millis(100));
        }
    }
}

/// One waker thread and what it is handed.
struct TaskWaker {
    handoff: Arc<WakeHandoff>,
    thread: Option<std::thread::JoinHandle<()>>,
    /// The tasks this cycle hands it, gathered by `TaskWakers::hand`.
    batch: u64,
}

impl TaskWaker {
    /// Starts the thread of `cpu`'s waker, which also wakes the `others`; `setup` runs on
    /// it first (e.g. pins it there).
    fn start(
        ns: &Namespace,
        cpu: usize,
        others: Vec<Arc<WakeHandoff>>,
        setup: impl FnOnce(usize) + Send + 'static,
    ) -> Result<Self, IpcError> {
        let handoff = Arc::new(WakeHandoff::default());
        let (served, ns) = (handoff.clone(), ns.clone());
        let (opened_tx, opened) = std::sync::mpsc::channel();
        let thread = std::thread::Builder::new()
            .name(format!("task-waker{cpu}"))
            .spawn(move || {
                // The table's mapping is the thread's own (a region stays in its thread).
                let table = match Region::<TaskTable>::open(&ns, "tasks") {
                    Ok(table) => table,
                    Err(e) => return drop(opened_tx.send(Err(e))),
                };
                setup(cpu);
                let _ = opened_tx.send(Ok(()));
                served.serve(&table, &others);
            })
            .map_err(IpcError::TaskWakerThread)?;
        let waker = TaskWaker { handoff, thread: Some(thread), batch: 0 };
        opened.recv().map_err(|_| IpcError::TaskWakerEnded)??;
        Ok(waker)
    }

    /// The thread's CPU time so far, ns (0 when it cannot be read).
    fn cpu_ns(&self) -> u64 {
        use std::os::unix::thread::JoinHandleExt;
        let Some(thread) = &self.thread else { return 0 };
        // SAFETY: the thread is not joined yet, so its pthread_t is valid; both calls only
        // write the values they are given.
        unsafe {
            let mut clock: libc::clockid_t = 0;
            let mut ts: libc::timespec = std::mem::zeroed();
            if libc::pthread_getcpuclockid(thread.as_pthread_t(), &mut clock) != 0
                || libc::clock_gettime(clock, &mut ts) != 0
            {
                return 0;
            }
            ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
        }
    }
}

impl Drop for TaskWaker {
    fn drop(&mut self) {
        self.handoff.stop();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The waker threads, one per CPU the tasks may run on.
pub(crate) struct TaskWakers {
    wakers: Vec<TaskWaker>,
    /// Which waker wakes a task that slept on CPU c: `wakers[by_cpu[c]]`. A CPU past the
    /// end, or a task whose CPU is not known, goes to the first waker.
    by_cpu: Vec<u8>,
}

impl TaskWakers {
    /// Starts a waker for each of `cpus`, each running `setup(cpu)` on its thread first.
    /// The first is the one the RT thread wakes, and takes the tasks of any other CPU: the
    /// RT thread's CPU.
    pub(crate) fn start(
        ns: &Namespace,
        cpus: &[usize],
        setup: impl Fn(usize) + Clone + Send + 'static,
    ) -> Result<Self, IpcError> {
        let Some((&first, rest)) = cpus.split_first().filter(|_| cpus.len() <= u8::MAX as usize) else {
            return Err(IpcError::TaskWakerCpus(cpus.len()));
        };
        let mut wakers: Vec<TaskWaker> =
            rest.iter().map(|&cpu| TaskWaker::start(ns, cpu, Vec::new(), setup.clone())).collect::<Result<_, _>>()?;
        let others = wakers.iter().map(|w| w.handoff.clone()).collect();
        wakers.insert(0, TaskWaker::start(ns, first, others, setup)?);
        let mut by_cpu = vec![0u8; cpus.iter().max().map_or(0, |&c| c + 1)];
        for (waker, &cpu) in cpus.iter().enumerate() {
            by_cpu[cpu] = waker as u8;
        }
        Ok(TaskWakers { wakers, by_cpu })
    }

    /// Hands each of `tasks` (bit t for task t) to the waker of the CPU it sleeps on, and
    /// wakes the first waker, which wakes the others that got some. Does not allocate.
    pub(crate) fn hand(&mut self, table: &TaskTable, mut tasks: u64) {
        while tasks != 0 {
            let task = tasks.trailing_zeros() as usize;
            let waker = table.slots[task].sleep_cpu().and_then(|cpu| self.by_cpu.get(cpu)).copied().unwrap_or(0);
            self.wakers[waker as usize].batch |= 1 << task;
            tasks &= tasks - 1;
        }
        for waker in &mut self.wakers {
            waker.handoff.give(std::mem::take(&mut waker.batch));
        }
        self.wakers[0].handoff.ring();
    }

    /// The CPU time of all the waker threads so far, ns.
    pub(crate) fn cpu_ns(&self) -> u64 {
        self.wakers.iter().map(TaskWaker::cpu_ns).sum()
    }

    /// Of the wakes handed over, those that found the task asleep (woken through its bell).
    pub(crate) fn futex_wakes(&self) -> u64 {
        self.wakers.iter().map(|w| w.handoff.futex_wakes.load(Ordering::Relaxed)).sum()
    }

    /// The wakes handed to each waker so far that found the task asleep, in `cpus` order.
    #[cfg(test)]
    fn futex_wakes_by_waker(&self) -> impl Iterator<Item = u64> + '_ {
        self.wakers.iter().map(|w| w.handoff.futex_wakes.load(Ordering::Relaxed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first two CPUs this process may run on.
    fn two_cpus() -> Option<(usize, usize)> {
        // SAFETY: `set` is valid for the call, which only writes it.
        let set = unsafe {
            let mut set: libc::cpu_set_t = std::mem::zeroed();
            (libc::sched_getaffinity(0, size_of::<libc::cpu_set_t>(), &mut set) == 0).then_some(set)?
        };
        // SAFETY: reads the set got above.
        let mut cpus = (0..libc::CPU_SETSIZE as usize).filter(|&c| unsafe { libc::CPU_ISSET(c, &set) });
        Some((cpus.next()?, cpus.next()?))
    }

    /// Task `task` asleep from a thread pinned to `cpu`, until woken; returns once the
    /// thread sleeps in the kernel, so its wake has to make the futex syscall.
    fn sleeper<'s>(table: &'s TaskTable, task: usize, cpu: usize, scope: &'s std::thread::Scope<'s, '_>) {
        let slot = &table.slots[task];
        let seen = slot.wake_count();
        let (tid_tx, tid) = std::sync::mpsc::channel();
        scope.spawn(move || {
            assert!(crate::process::pin_current_thread(cpu), "pinned to CPU {cpu}");
            // SAFETY: no arguments.
            tid_tx.send(unsafe { libc::gettid() }).unwrap();
            // A lost wake shows as a count short after `counted`'s 10 s, not as an hour's hang.
            table.sleep(task, seen, std::time::Duration::from_secs(20));
        });
        let stat = format!("/proc/self/task/{}/stat", tid.recv().unwrap());
        // The state after the command's closing parenthesis: S once asleep in the futex.
        let sleeping = || {
            std::fs::read_to_string(&stat)
                .is_ok_and(|s| s.rsplit(')').next().unwrap_or("").trim_start().starts_with('S'))
        };
        while !(slot.asleep() && sleeping()) {
            std::thread::yield_now();
        }
        assert_eq!(slot.sleep_cpu(), Some(cpu));
    }

    /// The wakers' futex wakes, once `total` are counted (a sleeper may return before its
    /// waker has counted the wake).
    fn counted(wakers: &TaskWakers, total: u64) -> Vec<u64> {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while wakers.futex_wakes() < total && std::time::Instant::now() < deadline {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        wakers.futex_wakes_by_waker().collect()
    }

    /// Each task asleep is woken by the waker of its CPU, and one
    /// that slept on a CPU without a waker by the first waker.
    #[test]
    fn a_task_is_woken_by_the_waker_of_the_cpu_it_sleeps_on() {
        let Some((a, b)) = two_cpus() else {
            return eprintln!("one CPU only: nothing to route");
        };
        let ns = Namespace::new(&format!("t{}-wakers", std::process::id())).unwrap();
        let table = Region::<TaskTable>::create(&ns, "tasks").unwrap();
        let mut wakers = TaskWakers::start(&ns, &[b, a], |_| ()).unwrap();
        std::thread::scope(|s| {
            sleeper(&table, 5, a, s);
            sleeper(&table, 9, b, s);
            for task in [5, 9] {
                table.slots[task].notify(0);
            }
            wakers.hand(&table, 1 << 5 | 1 << 9);
        });
        assert_eq!(counted(&wakers, 2), [1, 1], "task 9 (CPU {b}) to the first waker, task 5 (CPU {a}) to the second");

        let mut only_a = TaskWakers::start(&ns, &[a], |_| ()).unwrap();
        std::thread::scope(|s| {
            sleeper(&table, 9, b, s);
            table.slots[9].notify(0);
            only_a.hand(&table, 1 << 9);
        });
        assert_eq!(counted(&only_a, 1), [1], "CPU {b} has no waker: the first's");
        drop((wakers, only_a, table));
        crate::files::remove_namespace_files(&ns);
    }
}

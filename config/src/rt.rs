//! `[rt]`: how the RT thread asks the OS for real-time service, and the script pool.

use serde::Deserialize;

use crate::error::{ConfigError, invalid};

/// How the RT thread asks the OS for real-time service. Each is tried and, where the OS
/// refuses, logged and skipped.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RtConfig {
    /// SCHED_FIFO priority 1..99; 0 runs a plain thread.
    pub priority: u8,
    /// CPU to pin the RT thread to; none for no pinning.
    pub cpu: Option<usize>,
    /// mlockall(MCL_CURRENT | MCL_FUTURE) so that the cycle never page-faults.
    pub lock_memory: bool,
    /// Script processes kept started and waiting, so that a `StartTask` runs its program
    /// without a process start; 0 starts a process per task start.
    pub script_pool: usize,
    /// While the controller runs, idle CPUs poll instead of halting (a Linux PM QoS CPU
    /// latency limit of 0 us, `/dev/cpu_dma_latency`, as cyclictest holds), so a wake-up
    /// (the cycle's timer, a task's reply) finds its CPU awake; false leaves the idle
    /// states to the OS.
    pub idle_poll: bool,
    /// Which CPUs the script processes the controller starts may run on.
    pub script_cpus: ScriptCpus,
    /// Before its first cycle the RT thread has the controller's private memory rebuilt in
    /// 2 MiB pages (transparent huge pages, `MADV_COLLAPSE`): fewer pages for the cycle to
    /// touch, each a possible stall on a virtual machine; false leaves 4 KiB pages.
    pub huge_pages: bool,
}

/// Where the script processes run beside the RT thread (`[rt] script_cpus`). Sharing the
/// RT thread's CPU costs the cycle its caches and delays its wake-ups while a script holds
/// that CPU (docs/decisions.md, "Script CPUs"); keeping off it leaves the scripts a CPU
/// fewer.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ScriptCpus {
    /// `Others` when at least two CPUs are left besides the RT thread's, else `All`.
    #[default]
    Auto,
    /// Every CPU the controller may use, the RT thread's included.
    All,
    /// Every CPU the controller may use but the RT thread's.
    Others,
}

impl Default for RtConfig {
    fn default() -> Self {
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        RtConfig {
            priority: 80,
            cpu: (cpus > 1).then(|| cpus - 1),
            lock_memory: true,
            script_pool: 2,
            idle_poll: true,
            script_cpus: ScriptCpus::Auto,
            huge_pages: true,
        }
    }
}

impl RtConfig {
    pub(crate) fn validate(&self) -> Result<(), ConfigError> {
        if self.priority > 99 {
            return Err(invalid("rt.priority", "SCHED_FIFO priorities are 1..99 (0: plain thread)"));
        }
        // Each waiting process is a node of the namespace's services, sized for this many.
        if self.script_pool > ipc::limits::MAX_POOL {
            let max = ipc::limits::MAX_POOL;
            return Err(invalid("rt.script_pool", format!("at most {max} waiting script processes (0: none)")));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> RtConfig {
        toml::from_str(text).unwrap()
    }

    /// `[rt] script_cpus`: "auto" by default, the three words read, any other refused by
    /// name.
    #[test]
    fn the_script_cpus_are_read_by_name() {
        assert_eq!(RtConfig::default().script_cpus, ScriptCpus::Auto);
        for (word, cpus) in [("auto", ScriptCpus::Auto), ("all", ScriptCpus::All), ("others", ScriptCpus::Others)] {
            assert_eq!(parse(&format!("script_cpus = \"{word}\"\n")).script_cpus, cpus, "{word}");
        }
        let refused = toml::from_str::<RtConfig>("script_cpus = \"rt\"\n").unwrap_err().to_string();
        assert!(refused.contains("unknown variant `rt`, expected one of `auto`, `all`, `others`"), "{refused}");
    }

    /// `[rt] huge_pages`: on by default, off when asked.
    #[test]
    fn huge_pages_are_on_unless_turned_off() {
        assert!(RtConfig::default().huge_pages);
        assert!(!parse("huge_pages = false\n").huge_pages);
    }

    /// `[rt] script_pool`: 2 waiting processes by default, 0 allowed, more than the
    /// services are sized for refused.
    #[test]
    fn the_script_pool_is_bounded_by_the_services() {
        assert_eq!(RtConfig::default().script_pool, 2);
        assert!(RtConfig::default().idle_poll, "idle CPUs poll by default");
        assert!(!parse("idle_poll = false\n").idle_poll);
        assert!(parse("script_pool = 0\n").validate().is_ok());
        let too_many = format!("script_pool = {}\n", ipc::limits::MAX_POOL + 1);
        assert!(
            matches!(parse(&too_many).validate(), Err(ConfigError::Invalid { key, .. }) if key == "rt.script_pool")
        );
    }
}

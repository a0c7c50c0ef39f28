//! The memory of the controller and of each script process, as RSS and PSS from
//! `/proc/<pid>/smaps_rollup`. RSS counts every page a process maps in full, so the binary's
//! text and the shared memory every process maps would count once per process; PSS divides
//! each shared page among the processes that map it, so the PSS of all of them adds up to
//! the memory they use together.

use serde::Serialize;

/// One process' memory, KiB.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Memory {
    pub rss_kib: u64,
    pub pss_kib: u64,
}

/// Reads `pid`'s memory; `None` when the process is gone.
pub fn read(pid: u32) -> Option<Memory> {
    parse(&std::fs::read_to_string(format!("/proc/{pid}/smaps_rollup")).ok()?)
}

/// The `Rss:` and `Pss:` lines of a `smaps_rollup`.
fn parse(rollup: &str) -> Option<Memory> {
    let field = |name: &str| {
        rollup.lines().find_map(|line| line.strip_prefix(name)?.trim().strip_suffix("kB")?.trim().parse::<u64>().ok())
    };
    Some(Memory { rss_kib: field("Rss:")?, pss_kib: field("Pss:")? })
}

/// The controller and the scripts at one moment (script `i` is task `i`; `None`: gone).
#[derive(Clone, Debug, Default)]
pub struct Sample {
    pub controller: Memory,
    pub scripts: Vec<Option<Memory>>,
}

impl Sample {
    pub fn take(controller: u32, scripts: &[u32]) -> Self {
        Sample { controller: read(controller).unwrap_or_default(), scripts: scripts.iter().map(|&p| read(p)).collect() }
    }

    /// The PSS of all of them, KiB.
    pub fn total_pss_kib(&self) -> u64 {
        self.controller.pss_kib + self.scripts.iter().flatten().map(|m| m.pss_kib).sum::<u64>()
    }

    /// The sample to keep of two: the one that saw more scripts alive, then the larger.
    pub fn larger(self, other: Sample) -> Sample {
        let key = |s: &Sample| (s.scripts.iter().flatten().count(), s.total_pss_kib());
        if key(&other) > key(&self) { other } else { self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rss_and_pss_from_a_rollup() {
        let rollup = "55d0c0a00000-7ffc8a5f2000 ---p 00000000 00:00 0    [rollup]\n\
                      Rss:               30320 kB\n\
                      Pss:               12345 kB\n\
                      Pss_Anon:           8000 kB\n\
                      Shared_Clean:      20000 kB\n";
        assert_eq!(parse(rollup), Some(Memory { rss_kib: 30320, pss_kib: 12345 }));
        assert_eq!(parse("Rss: 1 kB\n"), None);
    }

    #[test]
    fn this_process_has_pss_within_its_rss() {
        let me = read(std::process::id()).expect("our own smaps_rollup");
        assert!(me.pss_kib > 0 && me.pss_kib <= me.rss_kib, "{me:?}");
    }
}

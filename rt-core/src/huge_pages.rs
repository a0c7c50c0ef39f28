//! The controller's memory in 2 MiB pages (transparent huge pages).
//!
//! On a virtual machine a page the RT thread touches may cost it a stall of about 135 us
//! when the hypervisor has to map it again; on this project's CI machine a loop touching
//! 300 pages a millisecond was stalled so in 0.8-2.5 % of its cycles with 4 KiB pages and
//! in 0-0.07 % with 2 MiB ones (README, "Huge pages"). So before its first cycle the RT thread
//! asks the kernel to rebuild the process' private anonymous memory (the heaps, the
//! stacks) and its executable's code in huge pages (`MADV_COLLAPSE`, Linux 6.1). What the
//! kernel refuses is left in 4 KiB pages: the controller runs the same, only more exposed.
//! The shared memory of the IPC lives in `/dev/shm`, which this leaves alone.

/// 2 MiB: the x86-64 and arm64 (4 KiB granule) PMD page.
const HUGE_PAGE: usize = 2 << 20;

/// What one mapping of `/proc/self/maps` is, as far as huge pages go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Private, writable, not backed by a file: heaps, stacks, anonymous `mmap`s.
    Anonymous,
    /// The executable's code.
    Code,
    /// Anything else (shared memory, libraries, the vDSO): left as it is.
    Other,
}

/// One line of `/proc/self/maps`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Mapping {
    start: usize,
    end: usize,
    kind: Kind,
}

impl Mapping {
    /// Reads `start-end perms offset dev inode [path]`; `exe` is the executable's path.
    fn parse(line: &str, exe: &str) -> Option<Mapping> {
        let mut fields = line.split_ascii_whitespace();
        let (start, end) = fields.next()?.split_once('-')?;
        let (start, end) = (usize::from_str_radix(start, 16).ok()?, usize::from_str_radix(end, 16).ok()?);
        let perms = fields.next()?.as_bytes();
        let inode = fields.nth(2)?;
        let path = fields.next().unwrap_or("");
        let private = perms.get(3) == Some(&b'p');
        let kind = match (perms.get(..3)?, inode, path) {
            (b"rw-", "0", "" | "[heap]" | "[stack]") if private => Kind::Anonymous,
            (b"r-x", _, path) if private && path == exe => Kind::Code,
            _ => Kind::Other,
        };
        Some(Mapping { start, end, kind })
    }

    /// The whole huge pages inside the mapping: the only part a huge page can back.
    fn huge_range(&self) -> Option<(usize, usize)> {
        let start = self.start.next_multiple_of(HUGE_PAGE);
        let end = self.end / HUGE_PAGE * HUGE_PAGE;
        (start < end).then(|| (start, end - start))
    }
}

/// The heap of a process that hosts a controller, set before any thread starts (glibc;
/// elsewhere nothing): one arena for every thread, grown 2 MiB ahead of what it holds, never
/// trimmed, and no block `mmap`ed apart. So the heap is one region whose 2 MiB pages with
/// data lie whole inside it, which `back_with_huge_pages` can rebuild (not an arena per
/// thread, each under 2 MiB); and memory locked once stays locked: no `munmap` later,
/// whose TLB shootdown would interrupt the RT thread's CPU too.
pub fn keep_one_heap() {
    #[cfg(target_env = "gnu")]
    // SAFETY: glibc tunables, set while the process has one thread.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, 1);
        libc::mallopt(libc::M_TOP_PAD, HUGE_PAGE as libc::c_int);
        libc::mallopt(libc::M_TRIM_THRESHOLD, -1);
        libc::mallopt(libc::M_MMAP_MAX, 0);
    }
}

/// What `back_with_huge_pages` did, bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HugePages {
    /// Anonymous memory now in huge pages.
    pub anonymous: usize,
    /// Code now in huge pages.
    pub code: usize,
    /// Memory the kernel would not rebuild (no THP, a page it could not move).
    pub refused: usize,
}

/// Rebuilds the process' anonymous memory and code in huge pages, as far as the kernel
/// agrees; at start-up, never in a cycle (it copies memory and takes the `mmap` lock).
pub fn back_with_huge_pages() -> HugePages {
    let started = std::time::Instant::now();
    let maps = match std::fs::read_to_string("/proc/self/maps") {
        Ok(maps) => maps,
        Err(e) => {
            tracing::warn!("cannot read /proc/self/maps ({e}); the controller's memory stays in 4 KiB pages");
            return HugePages::default();
        }
    };
    let exe = std::env::current_exe().map(|p| p.to_string_lossy().into_owned()).unwrap_or_default();
    let mut done = HugePages::default();
    let wanted = maps.lines().filter_map(|line| Mapping::parse(line, &exe)).filter(|m| m.kind != Kind::Other);
    for mapping in wanted {
        let Some((start, len)) = mapping.huge_range() else { continue };
        let addr = start as *mut libc::c_void;
        // SAFETY: advice on a range of this process' own mappings; it changes how the
        // memory is backed, never its contents.
        let ok = unsafe {
            libc::madvise(addr, len, libc::MADV_HUGEPAGE) == 0 && libc::madvise(addr, len, libc::MADV_COLLAPSE) == 0
        };
        match (ok, mapping.kind) {
            (true, Kind::Anonymous) => done.anonymous += len,
            (true, _) => done.code += len,
            (false, _) => {
                tracing::debug!("no huge pages for {mapping:x?} ({})", std::io::Error::last_os_error());
                done.refused += len
            }
        }
    }
    tracing::info!(
        "huge pages: {} MiB of anonymous memory, {} MiB of code; {} MiB refused; in {} ms",
        done.anonymous >> 20,
        done.code >> 20,
        done.refused >> 20,
        started.elapsed().as_millis()
    );
    done
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXE: &str = "/usr/bin/luamotion";

    /// One row per kind of line `/proc/self/maps` has (proc(5)).
    #[test]
    fn the_maps_lines_are_sorted_by_kind() {
        let anonymous = |start, end| Some(Mapping { start, end, kind: Kind::Anonymous });
        let rows: [(&str, Option<Mapping>); 10] = [
            (
                "55f71127c000-55f71141a000 rw-p 00000000 00:00 0                          [heap]",
                anonymous(0x55f71127c000, 0x55f71141a000),
            ),
            (
                "7ffd5a4e2000-7ffd5a503000 rw-p 00000000 00:00 0                          [stack]",
                anonymous(0x7ffd5a4e2000, 0x7ffd5a503000),
            ),
            ("7f8544000000-7f8544a00000 rw-p 00000000 00:00 0 ", anonymous(0x7f8544000000, 0x7f8544a00000)),
            (
                "564700f81000-564701759000 r-xp 0038e000 fe:00 1234567                    /usr/bin/luamotion",
                Some(Mapping { start: 0x564700f81000, end: 0x564701759000, kind: Kind::Code }),
            ),
            (
                "7f854c3fa000-7f854c3fc000 rw-p 001d5000 fe:00 2345                       /usr/lib/x86_64-linux-gnu/libc.so.6",
                Some(Mapping { start: 0x7f854c3fa000, end: 0x7f854c3fc000, kind: Kind::Other }),
            ),
            (
                "7f854c200000-7f854c228000 r-xp 00028000 fe:00 2345                       /usr/lib/x86_64-linux-gnu/libc.so.6",
                Some(Mapping { start: 0x7f854c200000, end: 0x7f854c228000, kind: Kind::Other }),
            ),
            (
                "7f8530000000-7f8530400000 rw-s 00000000 00:1a 77                         /dev/shm/lm.cell1.tasks",
                Some(Mapping { start: 0x7f8530000000, end: 0x7f8530400000, kind: Kind::Other }),
            ),
            (
                "7f8540161000-7f8544000000 ---p 00000000 00:00 0 ",
                Some(Mapping { start: 0x7f8540161000, end: 0x7f8544000000, kind: Kind::Other }),
            ),
            (
                "7ffd5a5f0000-7ffd5a5f2000 r-xp 00000000 00:00 0                          [vdso]",
                Some(Mapping { start: 0x7ffd5a5f0000, end: 0x7ffd5a5f2000, kind: Kind::Other }),
            ),
            ("not a line", None),
        ];
        for (line, expected) in rows {
            assert_eq!(Mapping::parse(line, EXE), expected, "{line}");
        }
    }

    /// Only whole 2 MiB pages inside a mapping can be huge.
    #[test]
    fn only_whole_huge_pages_inside_a_mapping_are_asked_for() {
        let range = |start, end| Mapping { start, end, kind: Kind::Anonymous }.huge_range();
        assert_eq!(range(0x1ff000, 0x601000), Some((0x200000, 0x400000)));
        assert_eq!(range(0x200000, 0x400000), Some((0x200000, 0x200000)));
        assert_eq!(range(0x201000, 0x5ff000), None, "no whole huge page inside");
        assert_eq!(range(0x1000, 0x3000), None);
    }

    /// The size of the huge pages backing the mapping that holds `address`, KiB.
    fn anon_huge_kib_at(address: usize) -> u64 {
        let smaps = std::fs::read_to_string("/proc/self/smaps").expect("smaps");
        let mut inside = false;
        for line in smaps.lines() {
            if let Some(Mapping { start, end, .. }) = Mapping::parse(line, "")
                && line.split_ascii_whitespace().nth(1).is_some_and(|perms| perms.len() == 4)
            {
                inside = (start..end).contains(&address);
            } else if inside && let Some(kib) = line.strip_prefix("AnonHugePages:") {
                return kib.trim().trim_end_matches(" kB").parse().expect("a size");
            }
        }
        panic!("no mapping holds {address:#x}")
    }

    /// A heap block written before the call is in huge pages after it, where the kernel
    /// has transparent huge pages; where it has none, the call says it was refused.
    #[test]
    fn memory_allocated_before_is_rebuilt_in_huge_pages() {
        let block = vec![1u8; 16 << 20];
        let inside = (block.as_ptr() as usize).next_multiple_of(HUGE_PAGE);
        let thp = std::fs::read_to_string("/sys/kernel/mm/transparent_hugepage/enabled").unwrap_or_default();
        let done = back_with_huge_pages();
        if thp.contains("[never]") || thp.is_empty() {
            assert_eq!(done.anonymous, 0, "no THP: {done:?}");
            assert!(done.refused > 0, "{done:?}");
        } else {
            assert!(done.anonymous >= 8 << 20, "{done:?}");
            assert!(anon_huge_kib_at(inside) >= 2048, "the block at {inside:#x} is in 4 KiB pages");
        }
        assert!(block.iter().all(|&b| b == 1), "the contents are kept");
    }
}

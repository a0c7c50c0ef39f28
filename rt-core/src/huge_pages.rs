//! The controller's memory in 2 MiB pages (transparent huge pages).
//!
//! On a virtual machine a page the RT thread touches may cost it a stall of about 135 us
//! when the hypervisor has to map it again; on this project's CI machine a loop touching
//! 300 pages a millisecond was stalled so in 0.8-2.5 % of its cycles with 4 KiB pages and
//! in 0-0.07 % with 2 MiB ones (README, "Huge pages"). So before its first cycle the RT thread
//! asks the kernel to rebuild in huge pages (`MADV_COLLAPSE`, Linux 6.1) the process'
//! private anonymous memory (the heaps, the stacks), the shared memory of the IPC (which
//! `ipc::shm` sizes and maps in whole huge pages) and its executable's code and read-only
//! data (which `build.rs` lays out on 2 MiB boundaries; where the kernel cannot back the
//! file with huge pages, a copy in anonymous ones is moved over it). What the kernel
//! refuses is left in 4 KiB pages: the controller runs the same, only more exposed.

use ipc::shm::HUGE_PAGE;

/// What one mapping of `/proc/self/maps` is, as far as huge pages go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Private, writable, not backed by a file: heaps, stacks, anonymous `mmap`s.
    Anonymous,
    /// Shared memory in `/dev/shm` mapped at an address that is its file offset modulo
    /// 2 MiB, as `ipc::shm` maps its regions: a huge page of the file can back it.
    Shared,
    /// The executable's code (`r-x`) or read-only data (`r--`): `prot` is its protection.
    Image { prot: libc::c_int },
    /// Anything else (libraries, the vDSO, shared memory mapped askew): left as it is.
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
        let offset = usize::from_str_radix(fields.next()?, 16).ok()?;
        let inode = fields.nth(1)?;
        let path = fields.next().unwrap_or("");
        let private = perms.get(3) == Some(&b'p');
        let kind = match (perms.get(..3)?, inode, path) {
            (b"rw-", "0", "" | "[heap]" | "[stack]") if private => Kind::Anonymous,
            (b"rw-", _, path)
                if !private && path.starts_with("/dev/shm/") && start % HUGE_PAGE == offset % HUGE_PAGE =>
            {
                Kind::Shared
            }
            (b"r-x", _, path) if private && path == exe => Kind::Image { prot: libc::PROT_READ | libc::PROT_EXEC },
            (b"r--", _, path) if private && path == exe => Kind::Image { prot: libc::PROT_READ },
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

    /// The huge pages an image mapping can be moved into: its whole ones, and the one its
    /// end lies in when that page ends before `next_start`, the next mapping's start (the
    /// linker leaves such room after each of `luamotion`'s segments, `build.rs`).
    fn huge_range_into_room(&self, next_start: usize) -> Option<(usize, usize)> {
        let start = self.start.next_multiple_of(HUGE_PAGE);
        let rounded = self.end.next_multiple_of(HUGE_PAGE);
        let end = if rounded <= next_start { rounded } else { self.end / HUGE_PAGE * HUGE_PAGE };
        (start < end).then(|| (start, end - start))
    }
}

/// The heap of a process that hosts a controller, set before any thread starts (glibc;
/// elsewhere nothing): one arena for every thread, grown 2 MiB ahead of what it holds, never
/// trimmed, no block `mmap`ed apart, and filled up to its first 2 MiB boundary. So the heap
/// is one region whose 2 MiB pages with data lie whole inside it, which
/// `back_with_huge_pages` can rebuild (not an arena per thread, each under 2 MiB); and
/// memory locked once stays locked: no `munmap` later, whose TLB shootdown would interrupt
/// the RT thread's CPU too.
pub fn keep_one_heap() {
    #[cfg(target_env = "gnu")]
    // SAFETY: glibc tunables, set while the process has one thread.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, 1);
        libc::mallopt(libc::M_TOP_PAD, HUGE_PAGE as libc::c_int);
        libc::mallopt(libc::M_TRIM_THRESHOLD, -1);
        libc::mallopt(libc::M_MMAP_MAX, 0);
        // The heap's first huge page begins before the heap does, so what is allocated
        // first stays in 4 KiB pages. Fill the heap up to that page's end with a block never
        // freed, so that what the controller allocates lands in whole huge pages: where the
        // top of the heap is, a block just taken and given back says (no free block is
        // that large yet).
        let probe = libc::malloc(HUGE_PAGE / 2);
        if !probe.is_null() {
            libc::free(probe);
            let start = probe as usize;
            let pad = libc::malloc(start.next_multiple_of(HUGE_PAGE) - start + 64);
            keep(pad);
        }
    }
}

/// The RT thread's stack: 4 MiB less the guard page the C library adds below it, so that
/// the whole mapping is two huge pages, which the kernel places on a 2 MiB boundary (Linux
/// 6.7 on), and the stack's top 2 MiB, where the cycle's frames are, is a whole huge page
/// `back_with_huge_pages` can rebuild.
pub const RT_STACK: usize = 2 * HUGE_PAGE - 4096;

/// The heap left free in huge pages for allocations after the first cycle.
const HEAP_HEADROOM: usize = 8 << 20;

/// Writes the first byte of a block `malloc` returned (if any): the compiler may leave out
/// an allocation whose memory is never used, and these are made for where they lie.
///
/// # Safety
/// `block` is null or a live allocation of at least one byte.
unsafe fn keep(block: *mut libc::c_void) {
    if !block.is_null() {
        // SAFETY: as the caller guarantees.
        unsafe { std::ptr::write_volatile(block as *mut u8, 0) };
    }
}

/// What `back_with_huge_pages` did, bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HugePages {
    /// Anonymous memory now in huge pages.
    pub anonymous: usize,
    /// Shared memory now in huge pages.
    pub shared: usize,
    /// The executable's code and read-only data now in huge pages (the file's own, or a
    /// copy in anonymous memory moved over it).
    pub code: usize,
    /// Memory the kernel would not rebuild (no THP, a page it could not move).
    pub refused: usize,
}

impl HugePages {
    /// Everything now in huge pages.
    pub fn total(&self) -> usize {
        self.anonymous + self.shared + self.code
    }
}

/// Rebuilds the process' anonymous memory, shared memory and code in huge pages, as far
/// as the kernel agrees; at start-up, never in a cycle (it copies memory and takes the
/// `mmap` lock).
pub fn back_with_huge_pages() -> HugePages {
    let started = std::time::Instant::now();
    // Room on the heap for what the controller's other threads allocate once the cycles
    // run (the supervisor, the servers, tasks attaching), which the RT thread then reads:
    // taken from the top of the heap and given back, so that it lies in the huge pages
    // rebuilt below (the heap of `keep_one_heap` is never trimmed).
    // SAFETY: a plain allocation, freed at once.
    unsafe {
        let headroom = libc::malloc(HEAP_HEADROOM);
        keep(headroom);
        libc::free(headroom);
    }
    let maps = match std::fs::read_to_string("/proc/self/maps") {
        Ok(maps) => maps,
        Err(e) => {
            tracing::warn!("cannot read /proc/self/maps ({e}); the controller's memory stays in 4 KiB pages");
            return HugePages::default();
        }
    };
    let exe = std::env::current_exe().map(|p| p.to_string_lossy().into_owned()).unwrap_or_default();
    let mut done = HugePages::default();
    let mappings: Vec<Mapping> = maps.lines().filter_map(|line| Mapping::parse(line, &exe)).collect();
    for (i, mapping) in mappings.iter().enumerate() {
        let range = match mapping.kind {
            Kind::Other => continue,
            Kind::Image { .. } => mapping.huge_range_into_room(mappings.get(i + 1).map_or(0, |next| next.start)),
            _ => mapping.huge_range(),
        };
        let Some((start, len)) = range else { continue };
        let filled = (mapping.end - start).min(len);
        let result = match mapping.kind {
            Kind::Image { prot } if filled < len => move_to_anonymous(start, len, filled, prot),
            Kind::Image { prot } => collapse(start, len).or_else(|_| move_to_anonymous(start, len, len, prot)),
            _ => collapse(start, len),
        };
        match (result, mapping.kind) {
            (Ok(()), Kind::Anonymous) => done.anonymous += len,
            (Ok(()), Kind::Shared) => done.shared += len,
            (Ok(()), _) => done.code += len,
            (Err(e), _) => {
                tracing::debug!("no huge pages for {mapping:x?} ({e})");
                done.refused += len
            }
        }
    }
    tracing::info!(
        "huge pages: {} MiB of anonymous memory, {} MiB of shared memory, {} MiB of code; {} MiB refused; in {} ms",
        done.anonymous >> 20,
        done.shared >> 20,
        done.code >> 20,
        done.refused >> 20,
        started.elapsed().as_millis()
    );
    done
}

/// Asks the kernel to back `len` bytes from `start` with huge pages; a transient refusal
/// (`EAGAIN`: a page locked or moving, a collapse of the same range under way) is asked
/// again, twice.
fn collapse(start: usize, len: usize) -> std::io::Result<()> {
    let addr = start as *mut libc::c_void;
    // SAFETY: advice on a range of this process' own mappings; it changes how the memory
    // is backed, never its contents.
    if unsafe { libc::madvise(addr, len, libc::MADV_HUGEPAGE) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    let mut attempts = 3;
    loop {
        // SAFETY: as above.
        if unsafe { libc::madvise(addr, len, libc::MADV_COLLAPSE) } == 0 {
            return Ok(());
        }
        let e = std::io::Error::last_os_error();
        attempts -= 1;
        if attempts == 0 || e.raw_os_error() != Some(libc::EAGAIN) {
            return Err(e);
        }
    }
}

/// Backs `len` bytes from `start`, of which the executable's image fills the first
/// `filled` and the rest is unmapped room, with anonymous huge pages, where the kernel
/// cannot back its file's pages with them (no `CONFIG_READ_ONLY_THP_FOR_FS`): the room is
/// reserved (failing if anything was mapped there meanwhile), a copy of the image is made
/// in an aligned anonymous area, rebuilt in huge pages, given the image's protection and
/// moved over image and room by one `mremap`, so every thread finds the same bytes at the
/// same addresses throughout. The price: `perf` sees the range as anonymous memory and
/// cannot name the functions in it (profile with `huge_pages = false`).
fn move_to_anonymous(start: usize, len: usize, filled: usize, prot: libc::c_int) -> std::io::Result<()> {
    let flags = libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_NORESERVE;
    let failed = |cleanup: &[(usize, usize)]| {
        let e = std::io::Error::last_os_error();
        for &(at, len) in cleanup.iter().filter(|(_, len)| *len > 0) {
            // SAFETY: areas this call mapped and nothing else refers to.
            unsafe { libc::munmap(at as *mut libc::c_void, len) };
        }
        Err(e)
    };
    let room = (start + filled, len - filled);
    // SAFETY: `MAP_FIXED_NOREPLACE` maps the room only where nothing is mapped.
    if room.1 > 0
        && unsafe {
            libc::mmap(room.0 as *mut libc::c_void, room.1, libc::PROT_NONE, flags | libc::MAP_FIXED_NOREPLACE, -1, 0)
        } != room.0 as *mut libc::c_void
    {
        return failed(&[]);
    }
    // SAFETY: a fresh anonymous area of this process, which nothing else refers to, is
    // trimmed to an aligned `len`, filled with a copy of the image's readable bytes, and
    // moved over image and room; on any failure it and the room are unmapped.
    unsafe {
        let area = libc::mmap(std::ptr::null_mut(), len + HUGE_PAGE, libc::PROT_READ | libc::PROT_WRITE, flags, -1, 0);
        if area == libc::MAP_FAILED {
            return failed(&[room]);
        }
        let copy = (area as usize).next_multiple_of(HUGE_PAGE);
        let head = copy - area as usize;
        libc::munmap(area, head);
        if head < HUGE_PAGE {
            libc::munmap((copy + len) as *mut libc::c_void, HUGE_PAGE - head);
        }
        std::ptr::copy_nonoverlapping(start as *const u8, copy as *mut u8, filled);
        let fixed = libc::MREMAP_MAYMOVE | libc::MREMAP_FIXED;
        let copy = copy as *mut libc::c_void;
        if collapse(copy as usize, len).is_err()
            || libc::mprotect(copy, len, prot) != 0
            || libc::mremap(copy, len, len, fixed, start as *mut libc::c_void) == libc::MAP_FAILED
        {
            return failed(&[(copy as usize, len), room]);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXE: &str = "/usr/bin/luamotion";

    /// The tests that call `back_with_huge_pages` take turns: two collapses of one range
    /// at once may refuse each other (`EINVAL`, `EAGAIN`), where a process calls it once.
    static ONE_CALL_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

    /// One row per kind of line `/proc/self/maps` has (proc(5)).
    #[test]
    fn the_maps_lines_are_sorted_by_kind() {
        let anonymous = |start, end| Some(Mapping { start, end, kind: Kind::Anonymous });
        let rows: [(&str, Option<Mapping>); 13] = [
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
                Some(Mapping {
                    start: 0x564700f81000,
                    end: 0x564701759000,
                    kind: Kind::Image { prot: libc::PROT_READ | libc::PROT_EXEC },
                }),
            ),
            (
                "564700a00000-564700f81000 r--p 00000000 fe:00 1234567                    /usr/bin/luamotion",
                Some(Mapping {
                    start: 0x564700a00000,
                    end: 0x564700f81000,
                    kind: Kind::Image { prot: libc::PROT_READ },
                }),
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
                Some(Mapping { start: 0x7f8530000000, end: 0x7f8530400000, kind: Kind::Shared }),
            ),
            (
                "7f8530600000-7f8530800000 rw-s 00200000 00:1a 78                         /dev/shm/lm.cell1.board",
                Some(Mapping { start: 0x7f8530600000, end: 0x7f8530800000, kind: Kind::Shared }),
            ),
            (
                "7f8531001000-7f8531401000 rw-s 00000000 00:1a 79                         /dev/shm/iox2_segment",
                Some(Mapping { start: 0x7f8531001000, end: 0x7f8531401000, kind: Kind::Other }),
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

    /// Whether the kernel's transparent huge pages `setting` (`enabled`, `shmem_enabled`)
    /// is there and not `refused` (`never`, `deny`).
    fn thp_allowed(setting: &str, refused: &str) -> bool {
        let path = format!("/sys/kernel/mm/transparent_hugepage/{setting}");
        let value = std::fs::read_to_string(path).unwrap_or_default();
        !value.is_empty() && !value.contains(&format!("[{refused}]"))
    }

    /// The size of the huge pages backing the mapping that holds `address`, KiB, by
    /// `field` of `/proc/self/smaps` (`AnonHugePages:`, `ShmemPmdMapped:`).
    fn huge_kib_at(address: usize, field: &str) -> u64 {
        let smaps = std::fs::read_to_string("/proc/self/smaps").expect("smaps");
        let mut inside = false;
        for line in smaps.lines() {
            if let Some(Mapping { start, end, .. }) = Mapping::parse(line, "")
                && line.split_ascii_whitespace().nth(1).is_some_and(|perms| perms.len() == 4)
            {
                inside = (start..end).contains(&address);
            } else if inside && let Some(kib) = line.strip_prefix(field) {
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
        let done = {
            let _turn = ONE_CALL_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            back_with_huge_pages()
        };
        if !thp_allowed("enabled", "never") {
            assert_eq!(done.anonymous, 0, "no THP: {done:?}");
            assert!(done.refused > 0, "{done:?}");
        } else {
            assert!(done.anonymous >= 8 << 20, "{done:?}");
            assert!(huge_kib_at(inside, "AnonHugePages:") >= 2048, "the block at {inside:#x} is in 4 KiB pages");
        }
        assert!(block.iter().all(|&b| b == 1), "the contents are kept");
    }

    /// A region of the IPC's shared memory, created and written before the call, is in
    /// huge pages after it, where the kernel lets shared memory be huge.
    #[test]
    fn shared_memory_mapped_before_is_rebuilt_in_huge_pages() {
        let ns = ipc::Namespace::new(&format!("huge-{}", std::process::id())).expect("namespace");
        let region = ipc::shm::Region::<schema::shared::SharedData>::create(&ns, "huge").expect("a region");
        let at = &*region as *const _ as usize;
        let done = {
            let _turn = ONE_CALL_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            back_with_huge_pages()
        };
        if !thp_allowed("shmem_enabled", "deny") {
            assert_eq!(done.shared, 0, "shared memory may not be huge: {done:?}");
        } else {
            assert!(done.shared >= 2 << 20, "{done:?}");
            assert!(huge_kib_at(at, "ShmemPmdMapped:") >= 2048, "the region at {at:#x} is in 4 KiB pages");
        }
    }

    /// A thread with the RT thread's stack has its frames in a huge page after the call,
    /// where the kernel places whole huge pages on their boundary (Linux 6.7 on) and has
    /// transparent huge pages.
    #[test]
    fn the_rt_threads_stack_top_is_rebuilt_in_a_huge_page() {
        let release = std::fs::read_to_string("/proc/sys/kernel/osrelease").unwrap_or_default();
        let mut version = release.split(['.', '-']).map(|part| part.parse::<u32>().unwrap_or(0));
        let aligns = (version.next().unwrap_or(0), version.next().unwrap_or(0)) >= (6, 7);
        let huge = std::thread::Builder::new()
            .stack_size(RT_STACK)
            .spawn(|| {
                let frame = 0u8;
                let _turn = ONE_CALL_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
                back_with_huge_pages();
                huge_kib_at(std::hint::black_box(&frame) as *const u8 as usize, "AnonHugePages:")
            })
            .expect("a thread")
            .join()
            .expect("no panic");
        if aligns && thp_allowed("enabled", "never") {
            assert!(huge >= 2048, "the stack's frames are in 4 KiB pages (Linux {release})");
        }
    }

    /// The huge pages of an image mapping reach into the room after it, never into the
    /// next mapping.
    #[test]
    fn an_image_is_rounded_up_into_the_room_after_it() {
        let range = |start, end, next| Mapping { start, end, kind: Kind::Image { prot: 0 } }.huge_range_into_room(next);
        assert_eq!(range(0x400000, 0xbd9000, 0xc00000), Some((0x400000, 0x800000)), "room to the boundary");
        assert_eq!(range(0x400000, 0xbd9000, 0xbff000), Some((0x400000, 0x600000)), "no room: whole pages");
        assert_eq!(range(0x400000, 0x6ac000, 0), Some((0x400000, 0x200000)), "the last mapping: no room");
        assert_eq!(range(0x401000, 0x4ac000, 0x600000), None, "no whole page, rounded or not");
    }

    /// Executable code moved into anonymous huge pages, with the room after it, keeps its
    /// bytes at the same addresses and runs on; with something mapped in the room the move
    /// is refused and the code left as it was.
    #[test]
    fn code_moved_to_anonymous_huge_pages_keeps_its_bytes_and_runs() {
        use std::io::Write;
        // `mov eax, 42; ret` among `int3`s, in the second huge page of an image 8 KiB into it.
        const CALL_AT: usize = HUGE_PAGE + 0x100;
        let mut image = vec![0xcc_u8; HUGE_PAGE + 0x2000];
        image[CALL_AT..CALL_AT + 6].copy_from_slice(&[0xb8, 0x2a, 0x00, 0x00, 0x00, 0xc3]);
        // Beside the test's executable, where files may be executed.
        let exe = std::env::current_exe().expect("the test's executable");
        let mut file = tempfile::tempfile_in(exe.parent().expect("a folder")).expect("a file");
        file.write_all(&image).expect("written");
        let (filled, len) = (image.len(), 2 * HUGE_PAGE);
        let prot = libc::PROT_READ | libc::PROT_EXEC;
        // SAFETY: the file mapped read-only and executable at a free aligned address of this
        // process' own, everything unmapped at the end; the code called is the one above.
        unsafe {
            use std::os::fd::AsRawFd;
            let anon = libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_NORESERVE;
            let free = libc::mmap(std::ptr::null_mut(), 3 * HUGE_PAGE, libc::PROT_NONE, anon, -1, 0);
            assert_ne!(free, libc::MAP_FAILED);
            let at = (free as usize).next_multiple_of(HUGE_PAGE);
            let fixed = libc::MAP_PRIVATE | libc::MAP_FIXED;
            let mapped = libc::mmap(at as *mut libc::c_void, filled, prot, fixed, file.as_raw_fd(), 0);
            assert_eq!(mapped as usize, at, "{}", std::io::Error::last_os_error());
            let bytes = || std::slice::from_raw_parts(at as *const u8, filled);
            let call = || {
                #[cfg(target_arch = "x86_64")]
                assert_eq!(std::mem::transmute::<usize, extern "C" fn() -> u32>(at + CALL_AT)(), 42);
            };
            call();
            assert!(move_to_anonymous(at, len, filled, prot).is_err(), "moved over the mapping in the room");
            assert_eq!(huge_kib_at(at, "AnonHugePages:"), 0);
            call();
            libc::munmap((at + filled) as *mut libc::c_void, len - filled);
            let image_mapping = Mapping { start: at, end: at + filled, kind: Kind::Image { prot } };
            assert_eq!(image_mapping.huge_range_into_room(at + len), Some((at, len)));
            let moved = move_to_anonymous(at, len, filled, prot);
            if !thp_allowed("enabled", "never") {
                assert!(moved.is_err(), "no THP, yet moved");
            } else {
                moved.expect("moved");
                assert_eq!(huge_kib_at(at, "AnonHugePages:"), 4096, "the image at {at:#x} is in 4 KiB pages");
            }
            assert!(bytes() == &image[..], "the same bytes at the same addresses");
            call();
            libc::munmap(free, 3 * HUGE_PAGE);
        }
    }
}

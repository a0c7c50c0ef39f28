//! `keep_one_heap` in a process of its own, before anything else allocates much: what the
//! controller allocates after it lands past the heap's first 2 MiB boundary, in the heap's
//! whole huge pages (a plain `main`, so that no test harness allocates first).

use ipc::shm::HUGE_PAGE;

fn main() {
    rt_core::huge_pages::keep_one_heap();
    if !cfg!(target_env = "gnu") {
        return;
    }
    // Larger than any block freed so far, so it comes from the top of the heap.
    let block = vec![1u8; 64 << 10];
    let offset = block.as_ptr() as usize % HUGE_PAGE;
    assert!(offset < 4096, "the block lies {offset:#x} into a 2 MiB page, not just past a boundary");
    println!("one_heap: a block after keep_one_heap lies {offset:#x} past a 2 MiB boundary");
}

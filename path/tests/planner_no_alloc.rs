//! The planner and the group's smoothing never allocate after `new` (ARCHITECTURE
//! invariant: the RT thread never allocates in steady state): pushing, stepping (each
//! sample smoothed), halting, aborting, stopping and jogging are counted by a global allocator, on the test's own thread only: the harness' main
//! thread may still allocate while the test runs.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

use path::segment::Line;
use path::smoothing::PathSmoother;
use path::{BufferMode, Limits, Motion, Planner, Profile, Segment};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// Set on the thread whose allocations are counted.
    static COUNTED: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTED.try_with(Cell::get).unwrap_or(false) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn nothing_allocates_after_new() {
    let mut p = Planner::new(0.001);
    let mut smoother = PathSmoother::new(501);
    smoother.reset(p.end_pose(), 0.0, 11);
    let motion = |buffer| Motion {
        lin: Profile { vel: 100.0, acc: 5000.0, dec: 5000.0, smooth_ms: 10.0 },
        ang: Profile { vel: 360.0, acc: 1800.0, dec: 1800.0, smooth_ms: 10.0 },
        buffer,
    };
    COUNTED.with(|c| c.set(true));
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    let mut step = |p: &mut Planner| {
        let sample = p.step();
        smoother.push(&sample);
        sample
    };
    let modes = [BufferMode::LookAhead, BufferMode::Low, BufferMode::Buff, BufferMode::High];
    for i in 0..512 {
        let s = p.end_pose();
        let e = [s[0] + 1.0, s[1] + if i % 2 == 0 { 0.5 } else { -0.5 }, 0.0, 0.0, 0.0, i as f64];
        p.push(Segment::Line(Line { start: s, end: e }), motion(modes[i % 4]), &Limits::NONE).unwrap();
    }
    for _ in 0..2000 {
        step(&mut p);
    }
    p.halt();
    for _ in 0..200 {
        step(&mut p);
    }
    p.resume();
    p.set_velocity_scale(30.0);
    for _ in 0..200 {
        step(&mut p);
    }
    let at = p.stopping_pose();
    p.push(Segment::Line(Line { start: at, end: [0.0; 6] }), motion(BufferMode::Abort), &Limits::NONE).unwrap();
    for _ in 0..200 {
        step(&mut p);
    }
    p.stop();
    while step(&mut p).moving {}
    p.jog(2, 10.0, motion(BufferMode::Buff), &Limits::NONE);
    for _ in 0..100 {
        step(&mut p);
    }
    p.jog(2, 0.0, motion(BufferMode::Buff), &Limits::NONE);
    while step(&mut p).moving {}
    let after = ALLOCATIONS.load(Ordering::Relaxed);
    COUNTED.with(|c| c.set(false));
    assert_eq!(after, before, "the planner allocated");
    assert_eq!(p.commands(), 0);
}

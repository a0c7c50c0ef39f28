//! The controller steps FUN147 in its real-time cycle, which must not allocate in steady
//! state (ARCHITECTURE invariants): a program that runs, waits, pauses, stops and starts
//! again allocates nothing once the reference axes have their room.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use fun147::plc::Plc;
use fun147::{Fun147, Inputs, MemPlc, Reg, Relay, SimAxes, assemble};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn steps_allocate_nothing() {
    let text = "001 SPD 5000\n LIN ADR,500,400,300,200,Ps\n WAIT TIME,10\n002 SPD R1000\n LINE ADR,D100,D200,,,Ps\n EXT X1\n003 SPD 2000\n LIN ABS,0,0,0,0,Ps\n WAIT X0\n GOTO 1\n";
    let mut plc = MemPlc::new();
    assemble(text).unwrap().write(&mut plc, Reg::D(2000)).unwrap();
    plc.set_dword(Reg::R(1000), 3000);
    plc.set_dword(Reg::D(100), 100);
    plc.set_dword(Reg::D(200), -50);
    let mut axes = SimAxes::new();
    let mut fun = Fun147::new(0, Reg::D(2000), Reg::D(3000)).unwrap();
    let mut run = |plc: &mut MemPlc, cycles: usize| {
        for i in 0..cycles {
            plc.set_relay(Relay::X(1), i % 700 > 600);
            plc.set_relay(Relay::X(0), i % 900 > 800);
            plc.set_relay(Relay::M(1991), i % 2000 > 1000);
            let inputs = Inputs { en: i % 3000 < 2900, pau: i % 400 < 20, abt: i % 5000 == 4999 };
            fun.step(plc, &mut axes, inputs, 0.001);
            axes.advance(0.001);
        }
    };
    run(&mut plc, 10_000);
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    run(&mut plc, 20_000);
    assert_eq!(ALLOCATIONS.load(Ordering::Relaxed) - before, 0);
    assert!(plc.word(Reg::D(4062)) > 0, "the program ran");
}

//! The group planner's costs, measured with criterion:
//! - pushing one BM_LOOKAHEAD segment onto a queue of 511 (the 512th): typical, where the
//!   backward pass stops after a few junctions, and worst, where a deceleration of 1 mm/s²
//!   makes every queued junction change;
//! - one cycle of 4 groups, each with a full queue of 1 mm look-ahead segments, beside the
//!   budget of 10 % of a 1 ms cycle.
//!
//! Printed first: the path time of a 200-segment polygon with BM_LOOKAHEAD, BM_BUFF and the
//! time-optimal bound for the same limits.
//!
//! `cargo bench -p path --bench planner`

#[path = "../tests/common/look_ahead.rs"]
mod look_ahead;

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use path::segment::Line;
use path::{BufferMode, Limits, Motion, Planner, Pose, Profile, Segment};

const PERIOD_S: f64 = 1e-3;

fn motion(dec: f64) -> Motion {
    Motion {
        lin: Profile { vel: 200.0, acc: 2000.0, dec, smooth_ms: 20.0 },
        ang: Profile { vel: 360.0, acc: 1800.0, dec: 1800.0, smooth_ms: 20.0 },
        buffer: BufferMode::LookAhead,
    }
}

/// The `i`-th 1 mm segment of an endless gentle zig-zag after `from`.
fn segment(from: Pose, i: usize) -> Segment {
    let heading = 0.3 * (i as f64 / 5.0).sin();
    let to = [from[0] + heading.cos(), from[1] + heading.sin(), 0.0, 0.0, 0.0, 0.0];
    Segment::Line(Line { start: from, end: to })
}

/// A planner with `n` queued segments.
fn filled(n: usize, dec: f64) -> Planner {
    let mut p = Planner::new(PERIOD_S);
    for i in 0..n {
        p.push(segment(p.end_pose(), i), motion(dec), &Limits::NONE).unwrap();
    }
    p
}

fn push(c: &mut Criterion) {
    let mut group = c.benchmark_group("push_look_ahead_onto_511");
    for (name, dec) in [("typical", 2000.0), ("every_junction_replanned", 1.0)] {
        group.bench_function(name, |b| {
            b.iter_batched_ref(
                || filled(511, dec),
                |p| {
                    let s = segment(p.end_pose(), 511);
                    p.push(black_box(s), motion(dec), &Limits::NONE).unwrap()
                },
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

fn step(c: &mut Criterion) {
    c.bench_function("step_4_groups_full_queues", |b| {
        b.iter_custom(|iters| {
            let mut groups: Vec<(Planner, usize)> = (0..4).map(|_| (filled(512, 2000.0), 512)).collect();
            let mut spent = Duration::ZERO;
            for _ in 0..iters {
                let start = Instant::now();
                for (p, _) in groups.iter_mut() {
                    black_box(p.step());
                }
                spent += start.elapsed();
                // Keep the queues full, outside the timing.
                for (p, next) in groups.iter_mut() {
                    while p.commands() < 512 {
                        p.push(segment(p.end_pose(), *next), motion(2000.0), &Limits::NONE).unwrap();
                        *next += 1;
                    }
                }
            }
            spent
        })
    });
    println!("budget: 10 % of a 1 ms cycle = 100 µs for the 4 groups");
}

fn path_times(_: &mut Criterion) {
    let (la, buff, bound) = (
        look_ahead::planner_time(BufferMode::LookAhead),
        look_ahead::planner_time(BufferMode::Buff),
        look_ahead::bound_time(),
    );
    println!(
        "200 segments of 1 mm: BM_LOOKAHEAD {la:.4} s, BM_BUFF {buff:.4} s, time-optimal bound {bound:.4} s (look-ahead {:+.2} %)",
        (la / bound - 1.0) * 100.0
    );
}

criterion_group!(benches, path_times, push, step);
criterion_main!(benches);

//! The motion kernel's costs, measured with criterion:
//! - planning one move: a trapezoid from rest, a retarget of a moving axis, and a whole
//!   `MoveAbs` through the profile generator and the filter chain after it (plan + first
//!   sample, smoothing on);
//! - one kernel cycle (read drives, plan, limits, status, write drives) per axis, with
//!   every axis moving, for 1 to 64 axes, and with 96 axes disabled (resting at their
//!   feedback every cycle, as the axes no program uses). The drives' own simulation is
//!   not timed;
//! - groups (HMPL ch. 8): one kernel cycle with 4 groups of 2 axes each running a polygon
//!   of short segments with look-ahead, their queues kept full (512), beside the same
//!   8 axes with no group; and queuing one segment with look-ahead onto a full queue;
//! - the scope's part of a cycle: 16 variables sampled into the scope ring.
//!
//! `cargo bench -p rt-core --bench kernel`

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use devices::ecat::Network;
use devices::profile::{Limits, Trapezoid};
use kernel::Kernel;
use kernel::filter::FilterChain;
use kernel::generator::{Generator, Move, Profile};
use kernel::group::motion::PathCommand;
use kernel::shaping::AXIS_MIN_SHAPER_HZ;
use rt_core::MachineConfig;
use rt_core::config::{AxisConfig, TravelConfig};

const PERIOD_S: f64 = 1e-3;
const LIMITS: Limits = Limits { vel: 500.0, acc: 5_000.0, dec: 3_000.0 };

fn planning(c: &mut Criterion) {
    let mut group = c.benchmark_group("plan_move");
    group.bench_function("trapezoid_from_rest", |b| {
        let mut target = 0.0;
        b.iter(|| {
            target = if target > 500.0 { 1.0 } else { target + 37.5 };
            black_box(Trapezoid::plan(0.0, 0.0, black_box(target), LIMITS))
        })
    });
    group.bench_function("trapezoid_retarget_while_moving", |b| {
        // Moving at 400 mm/s toward +; the new target lies behind: brake, reverse, arrive.
        b.iter(|| black_box(Trapezoid::plan(black_box(120.0), black_box(400.0), black_box(-50.0), LIMITS)))
    });
    group.bench_function("move_abs_through_generator_smoothed", |b| {
        let mut generator = Generator::new(PERIOD_S, Profile { vel: 500.0, acc: 5_000.0, dec: 3_000.0 });
        let mut filters = FilterChain::for_axis(501, AXIS_MIN_SHAPER_HZ, PERIOD_S);
        filters.set_smoothing(100, 0.0);
        let mut target = 0.0;
        b.iter(|| {
            target = if target > 500.0 { 1.0 } else { target + 37.5 };
            generator.command(Move::Absolute(black_box(target)), false).unwrap();
            black_box(filters.push(generator.step()))
        })
    });
    group.finish();
}

/// A machine of `n` default axes, enabled, brought to Op.
fn disabled_machine(n: usize) -> (Network, Kernel) {
    let axis = AxisConfig { travel: TravelConfig::built_in(), ..AxisConfig::default() };
    let config = MachineConfig { axes: vec![axis; n], ..MachineConfig::default() };
    let mut network = Network::new(&config.axes);
    network.start(config.period_ns()).unwrap();
    let kernel = Kernel::new(&config, &network);
    (network, kernel)
}

fn machine(n: usize) -> (Network, Kernel, u64) {
    let (mut network, mut kernel) = disabled_machine(n);
    for a in 0..n {
        kernel.enable(a as i64).unwrap();
    }
    let mut cycle = 0;
    while !kernel.axes().iter().all(|a| a.is_enabled()) {
        cycle += 1;
        network.exchange(PERIOD_S);
        kernel.step(cycle, &mut network);
    }
    (network, kernel, cycle)
}

fn kernel_cycle(c: &mut Criterion) {
    let mut group = c.benchmark_group("kernel_cycle");
    for n in [1usize, 4, 16, 64] {
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::new("axes_moving", n), &n, |b, &n| {
            let (mut network, mut kernel, mut cycle) = machine(n);
            b.iter_custom(|iters| {
                let mut timed = Duration::ZERO;
                for _ in 0..iters {
                    cycle += 1;
                    for a in 0..n {
                        let axis = kernel.axis_mut(a as i64).unwrap();
                        if !axis.is_moving() {
                            let target = if axis.reference().pos > 5.0 { 0.0 } else { 10.0 };
                            axis.move_abs(target).unwrap();
                        }
                    }
                    network.exchange(PERIOD_S);
                    let start = Instant::now();
                    kernel.step(cycle, &mut network);
                    timed += start.elapsed();
                }
                timed
            })
        });
    }
    group.throughput(Throughput::Elements(96));
    group.bench_function(BenchmarkId::new("axes_disabled", 96), |b| {
        let (mut network, mut kernel) = disabled_machine(96);
        let mut cycle = 0;
        b.iter_custom(|iters| timed_cycles(&mut network, &mut kernel, &mut cycle, iters))
    });
    group.finish();
}

/// A point of a polygon of 1 mm segments on a circle of radius 50 about (50, 0), per group.
fn polygon_point(k: usize) -> [f64; 2] {
    let angle = k as f64 * 1.0 / 50.0;
    [50.0 - 50.0 * angle.cos(), 50.0 * angle.sin()]
}

/// `machine(8)` with axes 2g and 2g+1 in group g (g = 0..3), look-ahead on, each queue full.
fn grouped_machine() -> (Network, Kernel, u64, [usize; 4]) {
    let (network, mut kernel, cycle) = machine(8);
    let mut next = [0; 4];
    for g in 0..4i64 {
        kernel.add_axis_to_grp(g, 2 * g).unwrap();
        kernel.add_axis_to_grp(g, 2 * g + 1).unwrap();
        kernel.enable_group(g).unwrap();
        kernel.set_group(g, |s| s.set_buffer_mode(6)).unwrap();
        fill(&mut kernel, g, &mut next[g as usize]);
    }
    (network, kernel, cycle, next)
}

/// Queues polygon points until group `g`'s queue is full.
fn fill(kernel: &mut Kernel, g: i64, next: &mut usize) {
    while kernel.groups()[g as usize].commands() < 512 {
        *next += 1;
        kernel.move_group(g, PathCommand::line_abs(polygon_point(*next)), None).unwrap();
    }
}

/// `iters` cycles with nothing commanded; the kernel's step timed, the drives' not.
fn timed_cycles(network: &mut Network, kernel: &mut Kernel, cycle: &mut u64, iters: u64) -> Duration {
    let mut timed = Duration::ZERO;
    for _ in 0..iters {
        *cycle += 1;
        network.exchange(PERIOD_S);
        let start = Instant::now();
        kernel.step(*cycle, network);
        timed += start.elapsed();
    }
    timed
}

fn groups(c: &mut Criterion) {
    let mut group = c.benchmark_group("groups");
    group.bench_function("kernel_cycle_8_axes_no_group", |b| {
        let (mut network, mut kernel, mut cycle) = machine(8);
        b.iter_custom(|iters| timed_cycles(&mut network, &mut kernel, &mut cycle, iters))
    });
    group.bench_function("kernel_cycle_4_groups_full_queues", |b| {
        let (mut network, mut kernel, mut cycle, mut next) = grouped_machine();
        b.iter_custom(|iters| {
            let mut timed = Duration::ZERO;
            for _ in 0..iters {
                cycle += 1;
                for (g, next) in next.iter_mut().enumerate() {
                    fill(&mut kernel, g as i64, next);
                }
                network.exchange(PERIOD_S);
                let start = Instant::now();
                kernel.step(cycle, &mut network);
                timed += start.elapsed();
            }
            timed
        })
    });
    group.bench_function("queue_one_segment_look_ahead_onto_511", |b| {
        let (mut network, mut kernel, mut cycle, mut next) = grouped_machine();
        b.iter_custom(|iters| {
            let mut timed = Duration::ZERO;
            for _ in 0..iters {
                // One cycle frees a place; the timed push fills it again.
                while kernel.groups()[0].commands() == 512 {
                    cycle += 1;
                    network.exchange(PERIOD_S);
                    kernel.step(cycle, &mut network);
                }
                next[0] += 1;
                let command = PathCommand::line_abs(polygon_point(next[0]));
                let start = Instant::now();
                kernel.move_group(0, command, None).unwrap();
                timed += start.elapsed();
            }
            timed
        })
    });
    group.finish();
}

/// What the scope adds to a cycle: 16 variables of every kind into the ring.
fn scope(c: &mut Criterion) {
    let names = [
        "a0.ref_pos",
        "a0.pos_out",
        "a0.pos_fb",
        "a0.pos_err",
        "a0.vel_fb",
        "a0.ref_vel",
        "a0.motion_status",
        "a0.fault_status",
        "a1.pos_fb",
        "a1.vel_fb",
        "g0.carte_pose_cmd[0]",
        "g0.grp_pg_vel",
        "gpi",
        "gpo",
        "system_dtest0",
        "system_user_table[5]",
    ];
    let codes: Vec<u32> = names.iter().map(|n| calls::scope::Var::parse(n).unwrap().code()).collect();
    let ns = ipc::Namespace::new(&format!("bench{}-scope", std::process::id())).unwrap();
    let ring = ipc::scope::ScopeRing::create(&ns, 1_000_000, &codes).unwrap();
    let mut sampler = rt_core::scope::ScopeSampler::new(ring);
    let shared = schema::layout::zeroed::<schema::shared::SharedData>();
    let mut snapshot = Box::<schema::Snapshot>::default();
    c.bench_function("scope_16_variables", |b| {
        b.iter(|| {
            snapshot.cycle += 1;
            sampler.sample(black_box(&snapshot), &shared)
        })
    });
    drop(sampler);
    ipc::remove_namespace_files(&ns);
}

criterion_group!(benches, planning, kernel_cycle, groups, scope);
criterion_main!(benches);

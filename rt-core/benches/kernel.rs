//! The motion kernel's costs, measured with criterion:
//! - planning one move: a trapezoid from rest, a retarget of a moving axis, and a whole
//!   `MoveAbs` through the profile generator and the filter chain after it (plan + first
//!   sample, smoothing on);
//! - one kernel cycle (read drives, plan, limits, status, write drives) per axis, with
//!   every axis moving, for 1 to 64 axes. The drives' own simulation is not timed.
//!
//! `cargo bench -p rt-core --bench kernel`

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rt_core::MachineConfig;
use rt_core::config::{AxisConfig, TravelConfig};
use rt_core::ecat::Network;
use rt_core::motion::Kernel;
use rt_core::motion::filter::FilterChain;
use rt_core::motion::generator::{Generator, Move, Profile};
use rt_core::profile::{Limits, Trapezoid};

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
        let mut filters = FilterChain::for_axis(501);
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
fn machine(n: usize) -> (Network, Kernel, u64) {
    let axis = AxisConfig { travel: TravelConfig::built_in(), ..AxisConfig::default() };
    let config = MachineConfig { axes: vec![axis; n], ..MachineConfig::default() };
    let mut network = Network::new(&config.axes);
    network.start(config.period_ns()).unwrap();
    let mut kernel = Kernel::new(&config, &network);
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
    group.finish();
}

criterion_group!(benches, planning, kernel_cycle);
criterion_main!(benches);

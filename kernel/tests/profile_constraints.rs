//! A constraint checker in the spirit of LinuxCNC's check_constraints: 10 000 random moves
//! (random targets, limits, smooth times, retargets mid-move, velocity-scale and limit
//! changes, halts and resumes), checked every cycle: the commanded velocity and
//! acceleration never exceed the limits in force (plus 1e-9 relative), nothing is NaN,
//! and every move that ends, ends exactly on its target.

use devices::profile::Kinematics;
use kernel::filter::FilterChain;
use kernel::generator::{Generator, Move, Profile};
use kernel::shaping::AXIS_MIN_SHAPER_HZ;

const PERIOD: f64 = 1e-3;
const MOVES: usize = 10_000;

/// The profile generator and the axis' filter chain after it (smoothing), as an axis
/// runs them: what an axis commands.
struct Smoothed {
    generator: Generator,
    filters: FilterChain,
    output: Kinematics,
}

impl Smoothed {
    fn new(period_s: f64, profile: Profile, max_smooth_samples: usize) -> Self {
        let generator = Generator::new(period_s, profile);
        Smoothed {
            generator,
            filters: FilterChain::for_axis(max_smooth_samples, AXIS_MIN_SHAPER_HZ, period_s),
            output: Kinematics::default(),
        }
    }

    fn set_smooth_samples(&mut self, samples: usize) {
        self.filters.set_smoothing(samples, self.generator.raw().pos);
    }

    fn reset(&mut self, pos: f64) {
        self.generator.reset(pos);
        self.filters.reset(pos);
        self.output = self.generator.raw();
    }

    fn step(&mut self) -> Kinematics {
        self.output = self.filters.push(self.generator.step());
        self.output
    }

    fn is_moving(&self) -> bool {
        self.generator.is_running() || !self.filters.settled()
    }

    fn output(&self) -> Kinematics {
        self.output
    }
}

impl std::ops::Deref for Smoothed {
    type Target = Generator;
    fn deref(&self) -> &Generator {
        &self.generator
    }
}

impl std::ops::DerefMut for Smoothed {
    fn deref_mut(&mut self) -> &mut Generator {
        &mut self.generator
    }
}

/// xorshift64*: deterministic, so a failure names its seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn chance(&mut self, p: f64) -> bool {
        self.uniform(0.0, 1.0) < p
    }
}

/// The bound a velocity must respect: a lowered limit is reached by decelerating, so the
/// bound falls from the old limit at the deceleration; smoothing averages the last window.
#[derive(Default)]
struct Bound {
    raw: f64,
    cycle: usize,
    /// Sliding-window maximum: (cycle, value), values decreasing.
    window: std::collections::VecDeque<(usize, f64)>,
}

impl Bound {
    fn update(&mut self, limit: f64, dec: f64, window: usize) -> f64 {
        self.raw = limit.max(self.raw - dec * PERIOD);
        self.cycle += 1;
        while self.window.back().is_some_and(|&(_, v)| v <= self.raw) {
            self.window.pop_back();
        }
        self.window.push_back((self.cycle, self.raw));
        while self.window.front().is_some_and(|&(c, _)| c + window < self.cycle) {
            self.window.pop_front();
        }
        self.window.front().map_or(self.raw, |&(_, v)| v)
    }
}

fn random_profile(rng: &mut Rng) -> Profile {
    Profile { vel: rng.uniform(20.0, 500.0), acc: rng.uniform(100.0, 50_000.0), dec: rng.uniform(100.0, 50_000.0) }
}

#[test]
fn ten_thousand_random_moves_respect_their_limits() {
    let mut rng = Rng(0x5EED_1234_ABCD_0001);
    let mut moves = 0;
    let mut cycles = 0u64;
    while moves < MOVES {
        let window = (rng.uniform(0.0, 500.0) / 1000.0 / PERIOD).round() as usize;
        let mut profile = random_profile(&mut rng);
        let mut scale = 1.0;
        let mut g = Smoothed::new(PERIOD, profile, 501);
        g.set_smooth_samples(window.max(1));
        g.reset(rng.uniform(-100.0, 100.0));
        let mut bound = Bound::default();
        let mut acc_bound = Bound::default();
        // A scenario: a handful of moves on one axis, with changes thrown in.
        for _ in 0..8 {
            let target = rng.uniform(-50.0, 50.0);
            // A velocity move runs at its own velocity; the axis refuses one above its limit.
            let command = if rng.chance(0.1) {
                Move::Velocity(rng.uniform(-profile.vel, profile.vel))
            } else {
                Move::Absolute(target)
            };
            g.command(command, false).unwrap();
            moves += 1;
            let mut expected = match command {
                Move::Absolute(t) => Some(t),
                _ => None,
            };
            let budget = rng.uniform(10.0, 1_000.0) as usize;
            for step in 0..200_000 {
                if step == budget && rng.chance(0.5) {
                    // Mid-move: retarget, rescale, new limits, halt and resume.
                    match rng.next() % 4 {
                        0 => {
                            let t = rng.uniform(-50.0, 50.0);
                            g.command(Move::Absolute(t), false).unwrap();
                            expected = Some(t);
                            moves += 1;
                        }
                        1 => {
                            // 0 pauses the move (raised again below); otherwise 25 to 100 %.
                            scale = if rng.chance(0.2) { 0.0 } else { rng.uniform(0.25, 1.0) };
                            g.set_scale(scale);
                        }
                        2 => {
                            profile = random_profile(&mut rng);
                            g.set_profile(profile);
                        }
                        _ => {
                            g.halt();
                            for _ in 0..rng.uniform(0.0, 500.0) as usize {
                                let k = g.step();
                                check(
                                    k,
                                    bound.update(profile.vel * scale, profile.dec, window),
                                    acc_bound.update(profile.acc.max(profile.dec), 0.0, window),
                                );
                                cycles += 1;
                            }
                            g.resume();
                        }
                    }
                }
                if step > budget && matches!(command, Move::Velocity(_)) && !g.is_stopping() {
                    g.stop_with(profile.dec);
                }
                if scale == 0.0 && step > budget + 1 {
                    scale = 1.0;
                    g.set_scale(1.0);
                }
                let k = g.step();
                cycles += 1;
                check(
                    k,
                    bound.update(profile.vel * scale, profile.dec, window),
                    acc_bound.update(profile.acc.max(profile.dec), 0.0, window),
                );
                if !g.is_moving() {
                    break;
                }
            }
            assert!(
                !g.is_moving(),
                "every move ends: {command:?} {profile:?} scale {scale} stopping {} halted {} out {:?} target {:?}",
                g.is_stopping(),
                g.is_halted(),
                g.output(),
                g.target()
            );
            if let Some(t) = expected.filter(|_| !matches!(command, Move::Velocity(_))) {
                assert_eq!(g.output().pos, t, "ends exactly on the target");
            }
        }
    }
    assert!(cycles > 1_000_000, "checked {cycles} cycles");
}

fn check(k: devices::profile::Kinematics, vel_bound: f64, acc_bound: f64) {
    assert!(k.pos.is_finite() && k.vel.is_finite() && k.acc.is_finite(), "NaN: {k:?}");
    assert!(k.vel.abs() <= vel_bound * (1.0 + 1e-9), "velocity {} over {vel_bound}", k.vel);
    assert!(k.acc.abs() <= acc_bound * (1.0 + 1e-9), "acceleration {} over {acc_bound}", k.acc);
}

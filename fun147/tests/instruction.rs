//! The instruction, cycle by cycle over the reference axes: one test per behaviour of the
//! FUN147 page (explanation items, interface signals, WR tables, derived commands).

use fun147::axes::{Axes, AxisSet};
use fun147::instr::flags;
use fun147::{Fun147, Inputs, MemPlc, Outputs, Plc, Reg, Relay, SimAxes, assemble};

const PERIOD: f64 = 0.001;
const SR: Reg = Reg::D(2000);
const WR: Reg = Reg::D(3000);
const WR1: Reg = Reg::D(3001);
const RUN: Inputs = Inputs { en: true, pau: false, abt: false };
const OFF: Inputs = Inputs { en: false, pau: false, abt: false };
const PAUSE: Inputs = Inputs { en: true, pau: true, abt: false };
const ABORT: Inputs = Inputs { en: false, pau: false, abt: true };

struct Bench {
    plc: MemPlc,
    axes: SimAxes,
    fun: Fun147,
}

impl Bench {
    fn new(text: &str) -> Self {
        Self::group(0, text, SR, WR)
    }

    fn group(gp: u8, text: &str, sr: Reg, wr: Reg) -> Self {
        let mut plc = MemPlc::new();
        assemble(text).unwrap().write(&mut plc, sr).unwrap();
        Bench { plc, axes: SimAxes::new(), fun: Fun147::new(gp, sr, wr).unwrap() }
    }

    /// One PLC cycle, then the axes move for it.
    fn cycle(&mut self, inputs: Inputs) -> Outputs {
        let out = self.fun.step(&mut self.plc, &mut self.axes, inputs, PERIOD);
        self.axes.advance(PERIOD);
        out
    }

    fn cycles(&mut self, inputs: Inputs, n: usize) -> Outputs {
        (0..n).map(|_| self.cycle(inputs)).last().unwrap()
    }

    /// Cycles until `done` holds after one (at most 100 000); how many it took.
    fn until(&mut self, inputs: Inputs, done: impl Fn(&Self, Outputs) -> bool) -> usize {
        for n in 1..=100_000 {
            let out = self.cycle(inputs);
            if done(self, out) {
                return n;
            }
        }
        panic!("not reached");
    }

    fn wr0(&self) -> u16 {
        self.plc.word(WR)
    }

    fn wr1(&self) -> u16 {
        self.plc.word(WR1)
    }

    fn frequency(&self, axis: u16) -> i32 {
        self.plc.dword(Reg::D(4080 + 2 * axis))
    }

    fn remaining(&self, axis: u16) -> i32 {
        self.plc.dword(Reg::D(4072 + 2 * axis))
    }

    fn error(&self) -> u16 {
        self.plc.word(Reg::D(4060))
    }
}

/// Three steps that each move Ps0 by 100 and wait for X5.
const HOLD3: &str = "001 SPD 1000\n LIN ADR,100,,,,Ps\n WAIT X5\n002 SPD 1000\n LIN ADR,100,,,,Ps\n WAIT X5\n003 SPD 1000\n LIN ADR,100,,,,Ps\n WAIT X5\n";

/// FUN147 WR+0 table: WR+0 = 0 before EN: step 1 runs and WR+0 reads 1; WR+0 = N: step 1
/// (wrap); WR+0 = 1: step 2.
#[test]
fn wr0_chooses_the_step() {
    for (preset, runs) in [(0, 1), (3, 1), (1, 2), (2, 3), (200, 1)] {
        let mut bench = Bench::new(HOLD3);
        bench.plc.set_word(WR, preset);
        bench.cycle(RUN);
        assert_eq!(bench.wr0(), runs, "WR+0 = {preset} before EN");
    }
}

/// FUN147 expl. 7: after ABT the next EN runs step 1, whatever WR+0 held.
#[test]
fn abort_restarts_at_step_1() {
    let mut bench = Bench::new(HOLD3);
    bench.plc.set_word(WR, 1);
    bench.cycles(RUN, 5);
    assert_eq!(bench.wr0(), 2);
    let out = bench.cycle(ABORT);
    assert!(!out.act && bench.axes.is_done(AxisSet(1)));
    bench.cycle(OFF);
    bench.cycle(RUN);
    assert_eq!(bench.wr0(), 1);
    // EN = 0 alone keeps the place: the next EN runs the step after.
    bench.cycle(OFF);
    bench.cycle(RUN);
    assert_eq!(bench.wr0(), 2);
}

/// FUN147 expl. 8 and WR+1 table: ACT and B12 while pulses go out; B9 while waiting for
/// WAIT; B8 while paused, with the output frequency 0; B0-B7 = N throughout.
#[test]
fn act_waiting_and_pause_bits() {
    let mut bench = Bench::new(HOLD3);
    let out = bench.cycle(RUN);
    assert!(out.act);
    assert_eq!(bench.wr1() & (flags::ACT | flags::WAITING | flags::STEPS), flags::ACT | 3);
    assert_eq!(bench.frequency(0), 1000);
    bench.cycle(PAUSE);
    assert_eq!(bench.wr1() & (flags::PAUSE | flags::ACT), flags::PAUSE | flags::ACT);
    assert_eq!(bench.frequency(0), 0, "M1991 OFF: the pause cuts at once");
    bench.cycle(RUN);
    assert_eq!(bench.wr1() & flags::PAUSE, 0);
    bench.until(RUN, |b, _| b.wr1() & flags::WAITING != 0);
    assert_eq!(bench.wr1() & (flags::ACT | flags::STEPS), 3, "no pulses while waiting");
    assert_eq!(bench.frequency(0), 0);
}

/// FUN147 expl. 10 and the note under the WR+1 table: DN comes on when a step's motion
/// ends and stays on until the user writes WR+1 = 0; then B0-B7 show N again.
#[test]
fn dn_is_latched_until_wr1_is_cleared() {
    let mut bench = Bench::new(HOLD3);
    let cycles = bench.until(RUN, |_, out| out.dn);
    assert!(cycles >= 100, "100 pulses at 1 kHz: {cycles}");
    assert!(bench.cycles(RUN, 50).dn);
    bench.plc.set_relay(Relay::X(5), true);
    assert!(bench.cycles(RUN, 5).dn, "kept into step 2");
    bench.plc.set_relay(Relay::X(5), false);
    bench.plc.set_word(WR1, 0);
    let out = bench.cycle(RUN);
    assert!(!out.dn);
    assert_eq!(bench.wr1() & flags::STEPS, 3);
}

/// FUN147 expl. 6: PAU pauses and PAU = 0 outputs the remaining pulses: the remaining count
/// holds while paused and the move ends exactly at the programmed travel. Also with M1991 ON
/// (a decelerating pause).
#[test]
fn pause_resumes_with_exactly_the_travel() {
    for decelerate in [false, true] {
        let mut bench = Bench::new("001 SPD 3000\n LIN ADR,900,-400,,,Ps\n WAIT X5\n");
        bench.plc.set_relay(Relay::M(1991), decelerate);
        bench.cycles(RUN, 40);
        bench.cycles(PAUSE, 150);
        let held = bench.remaining(0);
        assert!(held > 0 && bench.frequency(0) == 0);
        bench.cycles(PAUSE, 20);
        assert_eq!(bench.remaining(0), held, "nothing output while paused");
        bench.until(RUN, |b, _| b.wr1() & flags::WAITING != 0);
        assert_eq!(bench.axes.position(), [900, -400, 0, 0], "M1991 {decelerate}");
    }
}

/// FUN147 expl. 5 and M1991: EN = 0 with M1991 OFF stops at once (frequency 0 in the same
/// cycle, pulses left); with M1991 ON the frequency ramps down and ACT stays on until rest.
#[test]
fn en_off_stops_at_once_or_decelerating() {
    let mut bench = Bench::new(HOLD3);
    bench.cycles(RUN, 30);
    let out = bench.cycle(OFF);
    assert_eq!((out.act, bench.frequency(0)), (false, 0));
    assert!(bench.remaining(0) > 0);
    assert!(bench.plc.relay(Relay::M(1992)), "Ps0 Ready again");

    let mut bench = Bench::new("001 SPD 1000\n LIN ADR,1000,,,,Ps\n");
    bench.plc.set_relay(Relay::M(1991), true);
    bench.cycles(RUN, 30);
    let mut last = bench.frequency(0);
    let mut ramp = 0;
    while bench.cycle(OFF).act {
        let now = bench.frequency(0);
        assert!(now < last || ramp == 0, "{now} after {last}");
        assert!(!bench.plc.relay(Relay::M(1992)), "Ps0 held while decelerating");
        (last, ramp) = (now, ramp + 1);
    }
    assert!((90..=101).contains(&ramp), "a 0.1 s ramp: {ramp} cycles");
    assert!(bench.plc.relay(Relay::M(1992)));
}

/// FUN147 expl. 4 and M1992-M1995: the Ready flags are ON while idle and OFF while owned; an
/// instance whose axis is owned by another waits, and takes it when it is released.
#[test]
fn axis_ownership() {
    let mut bench = Bench::new("001 SPD 1000\n LIN ADR,100,,,,Ps\n");
    assert!((1992..=1995).all(|m| bench.plc.relay(Relay::M(m))));
    let other_sr = Reg::R(0);
    assemble("001 SPD 1000\n LIN ADR,50,50,,,Ps\n").unwrap().write(&mut bench.plc, other_sr).unwrap();
    let mut other = Fun147::new(0, other_sr, Reg::R(100)).unwrap();
    bench.cycle(RUN);
    assert!(!bench.plc.relay(Relay::M(1992)) && bench.plc.relay(Relay::M(1993)));
    let mut waited = 0;
    loop {
        let out = other.step(&mut bench.plc, &mut bench.axes, RUN, PERIOD);
        if out.act {
            break;
        }
        waited += 1;
        assert!(waited < 10_000, "B never started");
        assert_eq!(bench.plc.word(Reg::R(100)), 0, "B has not started");
        bench.cycle(RUN);
    }
    assert!((99..=101).contains(&waited), "B starts when A's 100 pulses are out: {waited}");
    assert!(!bench.plc.relay(Relay::M(1992)) && !bench.plc.relay(Relay::M(1993)));
    assert_eq!(bench.fun.owned(), AxisSet::NONE);
}

/// FUN147 expl. 2: two independent two-axis groups, Gp0 on Ps0/Ps1 and Gp1 on Ps2/Ps3, at
/// once; M1934/D4062 and M1935/D4063 for each group's last step; a Gp1 table naming Ps0 is
/// refused (60).
#[test]
fn two_groups_side_by_side() {
    let mut bench = Bench::new("001 SPD 1000\n LIN ADR,300,400,,,Ps\n");
    let sr1 = Reg::R(0);
    assemble("001 SPD 1000\n LIN ADR,,,10,,Ps\n002 SPD 500\n LIN ADR,,,,-60,Ps\n")
        .unwrap()
        .write(&mut bench.plc, sr1)
        .unwrap();
    let mut gp1 = Fun147::new(1, sr1, Reg::R(100)).unwrap();
    let mut both = [false, false];
    for _ in 0..2000 {
        let a = bench.fun.step(&mut bench.plc, &mut bench.axes, RUN, PERIOD);
        let b = gp1.step(&mut bench.plc, &mut bench.axes, RUN, PERIOD);
        if a.act && b.act {
            both = [true, (1992..=1995).all(|m| !bench.plc.relay(Relay::M(m)))];
        }
        bench.axes.advance(PERIOD);
    }
    assert_eq!(both, [true, true], "all four axes held at once");
    assert_eq!(bench.axes.position(), [300, 400, 10, -60]);
    assert!(bench.plc.relay(Relay::M(1934)) && bench.plc.relay(Relay::M(1935)));
    assert_eq!((bench.plc.word(Reg::D(4062)), bench.plc.word(Reg::D(4063))), (1, 2));
    assert!((1992..=1995).all(|m| bench.plc.relay(Relay::M(m))));

    let mut wrong = Bench::group(1, "001 SPD 1000\n LIN ADR,5,,10,,Ps\n", SR, WR);
    assert!(wrong.cycle(RUN).err);
    assert_eq!(wrong.plc.word(Reg::D(4061)), 60);
}

/// Interface signals: M1934 comes on when Gp0 completes its last step and D4062 holds the
/// number of each completed step; M1934 goes off when another step starts.
#[test]
fn last_step_flag_and_completed_step() {
    let mut bench =
        Bench::new("001 SPD 1000\n LIN ADR,10,,,,Ps\n WAIT X5\n002 SPD 1000\n LIN ADR,10,,,,Ps\n WAIT X5\n GOTO 1\n");
    bench.until(RUN, |b, _| b.wr1() & flags::WAITING != 0);
    assert_eq!((bench.plc.word(Reg::D(4062)), bench.plc.relay(Relay::M(1934))), (1, false));
    bench.plc.set_relay(Relay::X(5), true);
    bench.cycle(RUN);
    bench.plc.set_relay(Relay::X(5), false);
    bench.until(RUN, |b, _| b.wr1() & flags::WAITING != 0);
    assert_eq!((bench.plc.word(Reg::D(4062)), bench.plc.relay(Relay::M(1934))), (2, true));
    bench.plc.set_relay(Relay::X(5), true);
    bench.cycle(RUN);
    assert_eq!((bench.wr0(), bench.plc.relay(Relay::M(1934))), (1, false), "GOTO 1");
}

/// FUN147 SPD table and the program example: SPD 5000, LIN ADR 500,400,300,200: each axis'
/// share of the vector speed, ≈ 3402, 2722, 2041, 1361 Hz; all four finish in one cycle.
#[test]
fn seed_example_frequencies() {
    let mut bench = Bench::new("001 SPD 5000\n LIN ADR,500,400,300,200,Ut\n WAIT TIME,100\n GOTO NEXT\n");
    bench.cycle(RUN);
    let frequencies: Vec<i32> = (0..4).map(|a| bench.frequency(a)).collect();
    assert_eq!(frequencies, [3402, 2722, 2041, 1361]);
    assert_eq!(bench.plc.dword(Reg::D(4068)), 5000, "DR4068: the vector speed");
    let mut cycles = 0;
    while (0..4).all(|a| bench.remaining(a) > 0) {
        bench.cycle(RUN);
        cycles += 1;
    }
    assert!((0..4).all(|a| bench.remaining(a) == 0), "all finish in the same cycle");
    assert!((146..=148).contains(&cycles), "734.85 pulses at 5 kHz ≈ 0.147 s: {cycles}");
    assert_eq!(bench.axes.position(), [500, 400, 300, 200]);
    assert_eq!(bench.plc.dword(Reg::D(4094)), 200, "DR4094: Ps3's position");
}

/// FUN147 LIN table: ADR with 0 or blank, and ABS with blank, do not output; ABS with 0
/// goes to 0. The 2:1 diagram: Ps0:Ps1 = 2:1.
#[test]
fn blank_and_zero() {
    for (text, end) in [
        ("LIN ADR, , ,300, ,Ps", [-7, 9, 300, 4]),
        ("LIN ADR,0,0,300,0,Ps", [-7, 9, 300, 4]),
        ("LIN ABS, , ,300, ,Ps", [-7, 9, 300, 4]),
        ("LIN ABS,0, ,300,0,Ps", [0, 9, 300, 0]),
    ] {
        let mut bench = Bench::new(&format!("001 SPD 1000\n {text}\n"));
        for (axis, at) in [-7, 9, 0, 4].into_iter().enumerate() {
            bench.axes.set_position(axis, at);
        }
        bench.cycles(RUN, 1000);
        assert_eq!(bench.axes.position(), end, "{text}");
    }
    let mut bench = Bench::new("001 SPD 1000\n LIN ADR,1000,500,0,0,Ps\n");
    bench.cycle(RUN);
    assert_eq!((bench.frequency(0), bench.frequency(1), bench.frequency(2)), (894, 447, 0));
}

/// FUN147 ADR/ABS note: from 30000, ABS −10000 outputs 40000 pulses in the negative direction.
#[test]
fn abs_from_30000_to_minus_10000() {
    let mut bench = Bench::new("001 SPD 100000\n LIN ABS,−10000,,,,Ut\n");
    bench.axes.set_position(0, 30000);
    bench.cycle(RUN);
    assert_eq!(bench.remaining(0), 40000);
    assert_eq!(bench.axes.position()[0], 30000 - 100, "one cycle of 100 pulses, negative");
    bench.cycles(RUN, 400);
    assert_eq!(bench.axes.position()[0], -10000);
}

/// FUN147 LIN table: at most ±1,999,999 Ps a move (40), also from a register or an ABS
/// target; SPD table: 1..=1,840,000 from a register (31), each axis 1..=921,600 Hz (37).
#[test]
fn run_time_ranges() {
    let run = |text: &str, setup: &dyn Fn(&mut Bench)| {
        let mut bench = Bench::new(text);
        setup(&mut bench);
        let out = bench.cycle(RUN);
        (out.err, bench.error())
    };
    let travel = |v| move |b: &mut Bench| b.plc.set_dword(Reg::D(100), v);
    let text = "001 SPD 5000\n LIN ADR,D100,,,,Ps\n";
    assert_eq!(run(text, &travel(2_000_000)), (true, 40));
    assert_eq!(run(text, &travel(-2_000_000)), (true, 40));
    assert_eq!(run(text, &travel(1_999_999)), (false, 0));
    assert_eq!(run(text, &travel(-1_999_999)), (false, 0));
    let from = |at| move |b: &mut Bench| b.axes.set_position(0, at);
    assert_eq!(run("001 SPD 5000\n LIN ABS,1000000,,,,Ps\n", &from(-1_000_000)), (true, 40));
    assert_eq!(run("001 SPD 5000\n LIN ABS,1000000,,,,Ps\n", &from(-999_999)), (false, 0));
    let speed = |v| move |b: &mut Bench| b.plc.set_dword(Reg::R(1000), v);
    let text = "001 SPD R1000\n LIN ADR,1000,1000,1000,1000,Ps\n";
    assert_eq!(run(text, &speed(0)), (true, 31));
    assert_eq!(run(text, &speed(1_840_001)), (true, 31));
    assert_eq!(run(text, &speed(1)), (true, 37), "0.5 Hz an axis");
    assert_eq!(run(text, &speed(2)), (false, 0));
    assert_eq!(run(text, &speed(1_840_000)), (false, 0), "920,000 Hz an axis");
    assert_eq!(run("001 SPD 921601\n LIN ADR,1000,,,,Ps\n", &|_| ()), (true, 37));
    assert_eq!(run("001 SPD 921600\n LIN ADR,1000,,,,Ps\n", &|_| ()), (false, 0));
    assert_eq!(run("001 SPD 100\n LINE ADR,0,,0,,Ps\n", &|_| ()), (true, 33));
}

/// FUN147 WAIT table: TIME in 0.01 s counted from the end of the pulses: TIME,100 = 1.00 s
/// and TIME,R500 with R500 = 250 = 2.50 s (1000 and 2500 cycles of 1 ms).
#[test]
fn wait_time() {
    for (operand, cycles) in [("100", 1000), ("R500", 2500), ("0", 0)] {
        let mut bench = Bench::new(&format!(
            "001 SPD 1000\n LIN ADR,10,,,,Ps\n WAIT TIME,{operand}\n002 SPD 1000\n LIN ADR,10,,,,Ps\n"
        ));
        bench.plc.set_word(Reg::R(500), 250);
        bench.until(RUN, |_, out| out.dn);
        let dwell = if bench.wr0() == 2 { 0 } else { bench.until(RUN, |b, _| b.wr0() == 2) };
        assert_eq!(dwell, cycles, "WAIT TIME,{operand}");
    }
}

/// FUN147 WAIT table: WAIT X0 waits with B9 until X0 is ON, then runs the GOTO target.
#[test]
fn wait_relay() {
    let mut bench = Bench::new(
        "001 SPD 1000\n LIN ADR,10,,,,Ps\n WAIT X0\n GOTO 3\n002 SPD 1\n LIN ADR,1,,,,Ps\n003 SPD 1000\n LIN ADR,10,,,,Ps\n",
    );
    bench.cycles(RUN, 500);
    assert_eq!((bench.wr0(), bench.wr1() & flags::WAITING), (1, flags::WAITING));
    bench.plc.set_relay(Relay::X(0), true);
    bench.cycle(RUN);
    assert_eq!((bench.wr0(), bench.wr1() & flags::WAITING), (3, 0));
}

/// FUN147 EXT table: EXT X1 ON during the move abandons the rest and runs GOTO in the same
/// cycle; OFF when the pulses are out, EXT waits as WAIT does.
#[test]
fn ext_cuts_or_waits() {
    let text = "001 SPD 1000\n LIN ADR,1000,,,,Ps\n EXT X1\n002 SPD 1000\n LIN ADR,,100,,,Ps\n";
    let mut bench = Bench::new(text);
    bench.cycles(RUN, 300);
    bench.plc.set_relay(Relay::X(1), true);
    let out = bench.cycle(RUN);
    assert_eq!(bench.wr0(), 2);
    assert!(out.dn && out.act);
    assert_eq!(bench.plc.word(Reg::D(4062)), 1);
    let cut = bench.axes.position()[0];
    assert!((299..=302).contains(&cut), "Ps0 stopped where it was: {cut}");
    bench.cycles(RUN, 500);
    assert_eq!(bench.axes.position(), [cut, 100, 0, 0]);

    let mut bench = Bench::new(text);
    bench.cycles(RUN, 1500);
    assert_eq!((bench.wr0(), bench.wr1() & flags::WAITING), (1, flags::WAITING));
    bench.plc.set_relay(Relay::X(1), true);
    bench.cycle(RUN);
    assert_eq!(bench.wr0(), 2);
}

/// FUN147 LINE table: 1000:500:300:0 runs Ps0 without end, Ps1 and Ps2 in the ratio, Ps3
/// still, with B10, until EXT.
#[test]
fn line_runs_in_the_ratio() {
    let mut bench = Bench::new("001 SPD 5000\n LINE ADR,1000,500,300,0,Ps\n EXT X2\n002 SPD 1000\n LIN ADR,,,,5,Ps\n");
    bench.cycles(RUN, 3000);
    assert_ne!(bench.wr1() & flags::LINE, 0);
    let [p0, p1, p2, p3] = bench.axes.position();
    assert!(p0 > 12_000, "{p0}");
    assert!((2 * p1 - p0).abs() <= 2 && (10 * p2 - 3 * p0).abs() <= 10 && p3 == 0, "{p0} {p1} {p2}");
    bench.plc.set_relay(Relay::X(2), true);
    bench.cycle(RUN);
    assert_eq!((bench.wr0(), bench.wr1() & flags::LINE), (2, 0));
    let at = bench.axes.position();
    bench.cycles(RUN, 100);
    assert_eq!(bench.axes.position(), [at[0], at[1], at[2], 5]);
}

/// FUN147 GOTO table: GOTO 1 loops, GOTO D10 with D10 = 2 goes to step 2, NEXT to k+1; GOTO
/// Dn to a step outside 1..N is error 36; GOTO NEXT after step N ends the program.
#[test]
fn goto_targets() {
    let text = "001 SPD 1000\n LIN ADR,1,,,,Ps\n GOTO D10\n002 SPD 1000\n LIN ADR,1,,,,Ps\n GOTO NEXT\n003 SPD 1000\n LIN ADR,1,,,,Ps\n GOTO 1\n";
    let mut bench = Bench::new(text);
    bench.plc.set_word(Reg::D(10), 2);
    let mut seen = Vec::new();
    for _ in 0..20 {
        bench.cycle(RUN);
        if seen.last() != Some(&bench.wr0()) {
            seen.push(bench.wr0());
        }
    }
    assert_eq!(seen[..7], [1, 2, 3, 1, 2, 3, 1]);
    bench.plc.set_word(Reg::D(10), 4);
    let out = bench.cycles(RUN, 10);
    assert!(out.err && bench.error() == 36);

    let mut bench = Bench::new("001 SPD 1000\n LIN ADR,1,,,,Ps\n002 SPD 1000\n LIN ADR,1,,,,Ps\n");
    let out = bench.cycles(RUN, 10);
    assert!(!out.act && !out.err && bench.plc.relay(Relay::M(1992)));
    assert_eq!((bench.wr0(), bench.axes.position()[0]), (2, 2));
}

/// FUN147 SPD/LIN tables: a variable is two registers, low word first: D101:D100 =
/// 0xFFFF:0xFC18 is −1000.
#[test]
fn double_word_travel() {
    let mut bench = Bench::new("001 SPD 1000\n LIN ADR,D100,,,,Ps\n");
    bench.plc.set_word(Reg::D(100), 0xFC18);
    bench.plc.set_word(Reg::D(101), 0xFFFF);
    bench.cycles(RUN, 1100);
    assert_eq!(bench.axes.position()[0], -1000);
}

/// FUN147 error table and its note: SR+0 ≠ 0xA55C is 34; the register keeps the latest code
/// until the user writes 0; a good start does not clear it; ERR goes off at the next start.
#[test]
fn error_codes_are_kept() {
    let mut bench = Bench::new("001 SPD R1000\n LIN ADR,100,,,,Ps\n");
    bench.plc.set_word(SR, 0xA55B);
    let out = bench.cycle(RUN);
    assert!(out.err && bench.wr1() & flags::ERR != 0);
    assert_eq!(bench.error(), 34);
    bench.plc.set_word(SR, 0xA55C);
    bench.cycle(OFF);
    bench.cycle(RUN);
    assert_eq!(bench.error(), 31, "R1000 = 0: the latest code");
    bench.plc.set_dword(Reg::R(1000), 1000);
    bench.cycle(OFF);
    let out = bench.cycle(RUN);
    assert!(out.act && !out.err);
    assert_eq!(bench.error(), 31, "kept until cleared");
    bench.plc.set_word(Reg::D(4060), 0);
    bench.cycles(RUN, 200);
    assert_eq!(bench.error(), 0);
}

/// FUN147: no dynamic change of the output frequency: SPD's register written during a step
/// changes nothing until the next step reads it.
#[test]
fn speed_is_read_at_the_start_of_a_step() {
    let mut bench = Bench::new("001 SPD R1000\n LIN ADR,500,,,,Ps\n002 SPD R1000\n LIN ADR,500,,,,Ps\n");
    bench.plc.set_dword(Reg::R(1000), 1000);
    bench.cycles(RUN, 10);
    bench.plc.set_dword(Reg::R(1000), 4000);
    bench.cycles(RUN, 100);
    assert_eq!((bench.wr0(), bench.frequency(0)), (1, 1000));
    bench.until(RUN, |b, _| b.wr0() == 2);
    assert_eq!(bench.frequency(0), 4000);
}

/// FUN147 operands: Gp 0..1; SR and WR in R0-R3839, R5000-R8071 or D0-D3999, WR+0..WR+8
/// in one area.
#[test]
fn operands() {
    use fun147::OperandError;
    assert_eq!(Fun147::new(2, SR, WR).unwrap_err(), OperandError::Group(2));
    assert_eq!(Fun147::new(0, Reg::D(4060), WR).unwrap_err(), OperandError::Table(Reg::D(4060)));
    assert_eq!(Fun147::new(0, SR, Reg::R(3832)).unwrap_err(), OperandError::Work(Reg::R(3832)));
    assert_eq!(Fun147::new(0, SR, Reg::D(3992)).unwrap_err(), OperandError::Work(Reg::D(3992)));
    assert!(Fun147::new(1, Reg::R(8000), Reg::R(3830)).is_ok());
    assert!(Fun147::new(0, SR, Reg::D(3991)).is_ok());
}

/// An EN that falls and rises again while a decelerating stop (M1991 ON) is under way starts
/// the next step once the axes are at rest, not before and not never.
#[test]
fn en_again_during_a_decelerating_stop() {
    let mut bench = Bench::new(HOLD3);
    bench.plc.set_relay(Relay::M(1991), true);
    bench.cycles(RUN, 20);
    bench.cycles(OFF, 10);
    assert_eq!(bench.wr0(), 1);
    let out = bench.cycle(RUN);
    assert!(out.act && bench.frequency(0) > 0, "still decelerating");
    let at = bench.until(RUN, |b, _| b.wr0() == 2);
    assert!((80..=95).contains(&at), "a 0.1 s ramp less the 11 cycles already braked: {at}");
    assert_eq!(bench.frequency(0), 1000);
}

/// Axes that count the stops they are told.
struct CountingStops(SimAxes, usize);

impl Axes for CountingStops {
    fn start_line(&mut self, targets: [Option<i64>; 4], speed_hz: f64) {
        self.0.start_line(targets, speed_hz)
    }
    fn start_continuous(&mut self, ratio: [i64; 4], speed_hz: f64) {
        self.0.start_continuous(ratio, speed_hz)
    }
    fn pause(&mut self, axes: AxisSet, decelerate: bool) {
        self.0.pause(axes, decelerate)
    }
    fn resume(&mut self, axes: AxisSet) {
        self.0.resume(axes)
    }
    fn stop(&mut self, axes: AxisSet, decelerate: bool) {
        self.1 += 1;
        self.0.stop(axes, decelerate)
    }
    fn is_done(&self, axes: AxisSet) -> bool {
        self.0.is_done(axes)
    }
    fn position(&self) -> [i64; 4] {
        self.0.position()
    }
    fn remaining(&self) -> [i64; 4] {
        self.0.remaining()
    }
    fn frequency(&self) -> [f64; 4] {
        self.0.frequency()
    }
}

/// EN held at 0 (or ABT held) through a decelerating stop tells the axes to stop once: the
/// interpolator plans one deceleration, not one a cycle.
#[test]
fn a_held_stop_is_told_once() {
    for stop in [OFF, ABORT] {
        let mut bench = Bench::new(HOLD3);
        bench.plc.set_relay(Relay::M(1991), true);
        let mut axes = CountingStops(SimAxes::new(), 0);
        for i in 0..300 {
            let inputs = if i < 20 { RUN } else { stop };
            bench.fun.step(&mut bench.plc, &mut axes, inputs, PERIOD);
            axes.0.advance(PERIOD);
        }
        assert_eq!(axes.1, 1);
        assert!(bench.plc.relay(Relay::M(1992)), "at rest and free");
    }
}

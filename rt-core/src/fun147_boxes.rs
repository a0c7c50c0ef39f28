//! The FUN147 (MHSPO) boxes of docs/fun147.md: up to two instances, Gp 0 and Gp 1, each
//! declared by `MHSPO` and stepped by the RT thread once per cycle before the kernel, on
//! the register image in the namespace's shared memory. A box reads its EN/PAU/ABT
//! relays, steps `fun147::Fun147` and writes its ACT/ERR/DN relays.
//!
//! Its pulse outputs run on the kernel's group interpolator (docs/decisions.md, "FUN147"):
//! Psi is machine axis i, one pulse is 0.001 axis unit, a frequency of f Hz is f/1000
//! units/s, and box Gp moves through group `MAX_GROUPS - 2 + Gp`, which it sets up with
//! the axes it moves and ungroups when it frees them.

use api::ErrorCode as HmplError;
use fun147::{Axes, AxisSet, ErrorCode, Fun147, Inputs, OperandError, Outputs, Plc, Reg, Relay};
use path::planner::{BufferMode, Profile};

use kernel::group::GroupState;
use kernel::group::motion::PathCommand;
use kernel::group::settings::LIN_DEFAULT;
use kernel::ownership::box_owner;
use kernel::{Kernel, MAX_GROUPS};

/// Gp 0 and Gp 1 (FUN147 expl. 2).
pub const BOXES: usize = 2;
/// Pulses per axis unit: 1 Ps = 1 µm on a mm axis.
pub const PULSES_PER_UNIT: f64 = 1000.0;
/// How far a continuous run (LINE) heads before an EXT or a stop ends it, axis units.
const CONTINUOUS_UNITS: f64 = 10_000.0;

/// The group a box moves through.
pub fn box_group(gp: usize) -> usize {
    MAX_GROUPS - BOXES + gp
}

/// The relays a box reads and writes, as its contacts and coils in a ladder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contacts {
    /// EN: execution control; its rising edge starts, 0 stops.
    pub en: Relay,
    /// PAU: pauses the output.
    pub pau: Relay,
    /// ABT: aborts; the next start runs step 1.
    pub abt: Relay,
    /// ACT, a coil: a move is under way.
    pub act: Relay,
    /// ERR, a coil: the last start or step failed.
    pub err: Relay,
    /// DN, a coil: a step completed (WR+1 B14).
    pub dn: Relay,
}

/// What the box's group does for the instruction, kept across cycles.
#[derive(Clone, Copy, Debug, Default)]
struct Motion {
    /// The axes in the box's group, in the order of their coordinates.
    grouped: AxisSet,
    /// The move's target per axis, units (`None`: the axis does not move).
    target: [Option<f64>; 4],
    continuous: bool,
    /// The move's vector speed, units/s.
    speed: f64,
    paused: bool,
    /// Paused at once: resuming queues the rest of the line again.
    cut: bool,
    /// The box stopped the move (EN = 0, ABT, EXT, an error): what is left was dropped.
    stopped: bool,
    /// The axes failed under the box this cycle.
    fault: bool,
}

struct PlcBox {
    instr: Fun147,
    contacts: Contacts,
    motion: Motion,
}

/// The boxes and what MHSPO/MHSPOFree asked for since the last cycle.
#[derive(Default)]
pub struct Boxes {
    slots: [Option<PlcBox>; BOXES],
    /// MHSPO's new box, or MHSPOFree (`None` with `freeing`), for the next cycle.
    declared: [Option<PlcBox>; BOXES],
    freeing: [bool; BOXES],
}

impl Boxes {
    /// MHSPO: box `gp` with its table at `sr`, working area at `wr` and its relays; it
    /// replaces the group's box (stopped at once) at the start of the next cycle.
    pub fn declare(&mut self, gp: i64, sr: Reg, wr: Reg, contacts: Contacts) -> Result<(), OperandError> {
        let gp = u8::try_from(gp).unwrap_or(u8::MAX);
        let instr = Fun147::new(gp, sr, wr)?;
        self.declared[gp as usize] = Some(PlcBox { instr, contacts, motion: Motion::default() });
        self.freeing[gp as usize] = true;
        Ok(())
    }

    /// MHSPOFree: box `gp` stops at once and goes, at the start of the next cycle.
    pub fn free(&mut self, gp: i64) -> Result<(), OperandError> {
        let gp = u8::try_from(gp).unwrap_or(u8::MAX);
        if gp as usize >= BOXES {
            return Err(OperandError::Group(gp));
        }
        self.declared[gp as usize] = None;
        self.freeing[gp as usize] = true;
        Ok(())
    }

    /// Whether group `group` is a declared box's (or is about to be).
    pub fn holds_group(&self, group: i64) -> bool {
        (0..BOXES).any(|gp| {
            box_group(gp) as i64 == group
                && (self.declared[gp].is_some() || (self.slots[gp].is_some() && !self.freeing[gp]))
        })
    }

    /// One cycle of every box, before `Kernel::step`.
    pub fn step(&mut self, kernel: &mut Kernel, plc: &mut impl Plc, period_s: f64) {
        for gp in 0..BOXES {
            if std::mem::take(&mut self.freeing[gp]) {
                self.remove(gp, kernel, plc);
                self.slots[gp] = self.declared[gp].take();
            }
            let Some(b) = &mut self.slots[gp] else { continue };
            let inputs =
                Inputs { en: plc.relay(b.contacts.en), pau: plc.relay(b.contacts.pau), abt: plc.relay(b.contacts.abt) };
            let mut axes = GroupAxes { kernel, motion: &mut b.motion, group: box_group(gp) as i64 };
            axes.watch();
            if axes.motion.fault {
                b.instr.fault(plc, &mut axes, ErrorCode::Axes);
                axes.motion.fault = false;
            }
            let mut out = b.instr.step(plc, &mut axes, inputs, period_s);
            if axes.motion.fault {
                b.instr.fault(plc, &mut axes, ErrorCode::Axes);
                axes.motion.fault = false;
                out = Outputs { act: false, err: true, ..out };
            }
            if b.instr.owned() == AxisSet::NONE {
                axes.ungroup();
            }
            plc.set_relay(b.contacts.act, out.act);
            plc.set_relay(b.contacts.err, out.err);
            plc.set_relay(b.contacts.dn, out.dn);
        }
    }

    /// Stops box `gp` at once, frees its axes and removes it.
    fn remove(&mut self, gp: usize, kernel: &mut Kernel, plc: &mut impl Plc) {
        let Some(mut b) = self.slots[gp].take() else { return };
        let mut axes = GroupAxes { kernel, motion: &mut b.motion, group: box_group(gp) as i64 };
        let owned = b.instr.owned();
        axes.stop(owned, false);
        owned.iter().for_each(|a| plc.set_relay(fun147::plc::ready_flag(a), true));
        axes.ungroup();
        plc.set_relay(b.contacts.act, false);
    }
}

/// Ps0-Ps3 as the box's group moves them.
struct GroupAxes<'a> {
    kernel: &'a mut Kernel,
    motion: &'a mut Motion,
    group: i64,
}

impl GroupAxes<'_> {
    fn state(&self) -> Option<GroupState> {
        self.kernel.group(self.group).ok().map(|g| g.state())
    }

    fn is_moving(&self) -> bool {
        self.kernel.group(self.group).is_ok_and(|g| g.is_moving())
    }

    /// The box's owner id (docs/decisions.md, "Axis ownership").
    fn owner(&self) -> u8 {
        box_owner(self.group as usize - box_group(0))
    }

    /// A group the box set up must stay enabled and out of error stop (an axis disabled,
    /// faulted or at a software limit puts it into Group Error Stop), and its move may end
    /// short only when the box stops it (not by StopAll, HMPL 2.8).
    fn watch(&mut self) {
        let m = *self.motion;
        if m.grouped == AxisSet::NONE {
            return;
        }
        let moving = m.target.iter().any(Option::is_some) && !m.stopped && !m.paused;
        let short = m.continuous || self.remaining() != [0; 4];
        if self.state() != Some(GroupState::Standby) || (moving && short && !self.is_moving()) {
            self.motion.fault = true;
        }
    }

    /// The group holds at least `needed` and is enabled; otherwise the box faults.
    fn ensure_group(&mut self, needed: AxisSet) -> bool {
        let want = AxisSet(self.motion.grouped.0 | needed.0);
        if want == self.motion.grouped && self.state() == Some(GroupState::Standby) {
            return true;
        }
        self.ungroup();
        // An axis whose motion a task owns is not the box's to take (DXMC 0x001F).
        let me = self.owner();
        let free = want.iter().all(|a| self.kernel.axis_owner(a as u8).is_none_or(|o| o == me));
        let built = free
            && want.iter().all(|a| self.kernel.add_axis_to_grp(self.group, a as i64).is_ok())
            && self.kernel.enable_group(self.group).is_ok();
        self.motion.grouped = want;
        if !built {
            self.ungroup();
            self.motion.fault = true;
        }
        built
    }

    /// The box's group stands still and empty; its axes go back to their own generators.
    fn ungroup(&mut self) {
        if self.motion.grouped == AxisSet::NONE {
            return;
        }
        let _ = self.kernel.rest_group(self.group);
        let _ = self.kernel.ungrp_all_axes(self.group);
        self.motion.grouped = AxisSet::NONE;
    }

    /// The line to `motion.target` at `motion.speed`, from where the group stands.
    fn queue(&mut self) -> Result<(), HmplError> {
        let m = *self.motion;
        let here = self.kernel.axes();
        let delta = |a: usize| m.target[a].map_or(0.0, |t| t - here[a].reference().pos);
        let (mut lin, mut ang) = (0.0f64, 0.0f64);
        for a in m.grouped.iter() {
            let coordinate = (0..a).filter(|&b| m.grouped.contains(b)).count();
            if coordinate < 3 { lin += delta(a).powi(2) } else { ang += delta(a).powi(2) }
        }
        let norm = (lin + ang).sqrt();
        // The group moves X, Y, Z with the linear profile and the 4th coordinate with the
        // angular one; each gets its share of the vector speed, so both end together.
        let share = |part: f64| if part > 0.0 && norm > 0.0 { part.sqrt() / norm } else { 1.0 };
        let profile =
            |k: f64| Profile { vel: m.speed * k, acc: LIN_DEFAULT.acc * k, dec: LIN_DEFAULT.dec * k, smooth_ms: 0.0 };
        let (lin_profile, ang_profile) = (profile(share(lin)), profile(share(ang)));
        self.kernel.set_group_value(self.group, |s| {
            (s.lin, s.ang, s.buffer) = (lin_profile, ang_profile, BufferMode::Abort);
        })?;
        let mut target = [None; 6];
        for (coordinate, a) in m.grouped.iter().enumerate() {
            target[coordinate] = m.target[a];
        }
        self.kernel.move_group(self.group, PathCommand::LineAbs { target }, None)?;
        self.kernel.claim_group(self.group, self.owner());
        Ok(())
    }

    fn start(&mut self, target: [Option<f64>; 4], speed_hz: f64, continuous: bool) {
        let needed = AxisSet((0..4).filter(|&a| target[a].is_some()).fold(0, |set, a| set | 1 << a));
        if !self.ensure_group(needed) {
            return;
        }
        *self.motion = Motion { target, continuous, speed: speed_hz / PULSES_PER_UNIT, ..*self.motion };
        (self.motion.paused, self.motion.cut, self.motion.stopped) = (false, false, false);
        if self.queue().is_err() {
            self.motion.fault = true;
        }
    }
}

impl Axes for GroupAxes<'_> {
    fn start_line(&mut self, targets: [Option<i64>; 4], speed_hz: f64) {
        let target = targets.map(|t| t.map(|p| p as f64 / PULSES_PER_UNIT));
        self.start(target, speed_hz, false);
    }

    fn start_continuous(&mut self, ratio: [i64; 4], speed_hz: f64) {
        let norm = ratio.iter().map(|&r| (r as f64).powi(2)).sum::<f64>().sqrt();
        let axes = self.kernel.axes();
        let target: [Option<f64>; 4] = std::array::from_fn(|a| {
            let here = axes.get(a).map_or(0.0, |x| x.reference().pos);
            (ratio[a] != 0).then(|| here + CONTINUOUS_UNITS * ratio[a] as f64 / norm)
        });
        self.start(target, speed_hz, true);
    }

    fn pause(&mut self, _axes: AxisSet, decelerate: bool) {
        self.motion.paused = true;
        self.motion.cut = !decelerate;
        let _ = if decelerate { self.kernel.halt_group(self.group) } else { self.kernel.rest_group(self.group) };
    }

    fn resume(&mut self, _axes: AxisSet) {
        self.motion.paused = false;
        if std::mem::take(&mut self.motion.cut) {
            if self.queue().is_err() {
                self.motion.fault = true;
            }
        } else {
            let _ = self.kernel.resume_group(self.group);
        }
    }

    fn stop(&mut self, _axes: AxisSet, decelerate: bool) {
        (self.motion.paused, self.motion.cut, self.motion.stopped) = (false, false, true);
        if self.motion.continuous {
            self.motion.target = [None; 4];
        }
        let _ = if decelerate && self.is_moving() {
            self.kernel.stop_group(self.group)
        } else {
            self.kernel.rest_group(self.group)
        };
    }

    fn is_done(&self, _axes: AxisSet) -> bool {
        // A move the axes refused never ran: the step is not done, the box fails.
        !self.motion.fault && !self.motion.paused && !self.is_moving()
    }

    fn position(&self) -> [i64; 4] {
        let axes = self.kernel.axes();
        std::array::from_fn(|a| axes.get(a).map_or(0, |x| (x.reference().pos * PULSES_PER_UNIT).round() as i64))
    }

    fn remaining(&self) -> [i64; 4] {
        let position = self.position();
        std::array::from_fn(|a| match self.motion.target[a] {
            Some(t) if !self.motion.continuous => ((t * PULSES_PER_UNIT).round() as i64 - position[a]).abs(),
            _ => 0,
        })
    }

    fn frequency(&self) -> [f64; 4] {
        let axes = self.kernel.axes();
        std::array::from_fn(|a| match axes.get(a) {
            Some(x) if self.motion.grouped.contains(a) => x.reference().vel.abs() * PULSES_PER_UNIT,
            _ => 0.0,
        })
    }
}

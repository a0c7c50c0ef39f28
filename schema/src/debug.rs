//! The debugger's shared words in a task's slot: the console (the DRL registers of the
//! Modbus server) writes the mode, the breakpoints and commands; the
//! script's debugger reads them in its hook and reports where the program stopped.
//! DXMC manual, appendix A.3, registers 0x6B01 to 0x6B05.

use std::sync::atomic::{AtomicU32, Ordering};

use num_enum::{FromPrimitive, IntoPrimitive, TryFromPrimitive};

/// Breakpoints a program can hold at once: 8 set before a run, more added one at a time.
pub const MAX_BREAKPOINTS: usize = 16;

/// Why the program is not running Lua, as the script reports it (DXMC A.3, 0x6B01).
/// An unknown word reads as `None` (not halted).
#[derive(Clone, Copy, Debug, PartialEq, Eq, FromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum Halt {
    /// Running (or not started).
    #[num_enum(default)]
    None = 0,
    /// Stopped on a breakpoint's line.
    BreakPoint = 2,
    /// Stopped by Pause, a step, or Block Run's first line.
    Pause = 3,
}

/// What the console asks of the debugger (DXMC A.3, 0x6B05 codes 4, 11, 12, 13 and the
/// resume of 2 and 44). An unknown code is no command (an error, ignored by the reader).
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum DebugCommand {
    /// Stop at the next line of the main chunk.
    Pause = 1,
    /// Run on from a stop (breakpoints honoured in debug mode).
    Continue = 2,
    /// Stop at the next line of the main chunk, in whatever function.
    StepInto = 3,
    /// Stop at the next line of the main chunk in this function or a caller.
    StepOver = 4,
    /// Stop at the next line of the main chunk in a caller.
    StepOut = 5,
}

/// How a program runs (DXMC A.3, 0x6B05 codes 2, 44, 21). An unknown word reads as
/// `Release`, the mode of a zeroed slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, FromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum RunMode {
    /// Release Run: breakpoints ignored; Pause still works.
    #[num_enum(default)]
    Release = 0,
    /// Debug Run: breakpoints honoured.
    Debug = 1,
    /// Block Run: Debug Run that stops before the first line of the main chunk.
    Block = 2,
}

/// The debugger's words. Zeroed: release mode, no breakpoints, no command.
#[repr(C)]
pub struct DebugBlock {
    mode: AtomicU32,
    /// `(sequence << 8) | DebugCommand`: a new sequence number is a new command.
    command: AtomicU32,
    /// The sequence number of the last command the debugger carried out (a step is
    /// carried out when the program has stopped again, or has ended).
    done: AtomicU32,
    /// Bumped by every change of the breakpoints.
    generation: AtomicU32,
    /// Line numbers of the main chunk; 0 is a free entry.
    breakpoints: [AtomicU32; MAX_BREAKPOINTS],
    halt: AtomicU32,
    /// The line of the main chunk last run (DXMC A.3, 0x6B02: `main.lua` only).
    main_line: AtomicU32,
}

impl DebugBlock {
    // The console's side.

    /// Before a start: the mode, the breakpoints, no pending command, not halted.
    pub fn prepare(&self, mode: RunMode, breakpoints: &[u32]) {
        self.mode.store(mode.into(), Ordering::Relaxed);
        for (i, slot) in self.breakpoints.iter().enumerate() {
            slot.store(breakpoints.get(i).copied().unwrap_or(0), Ordering::Relaxed);
        }
        self.halt.store(Halt::None.into(), Ordering::Relaxed);
        self.main_line.store(0, Ordering::Relaxed);
        self.done.store(self.command.load(Ordering::Relaxed) >> 8, Ordering::Relaxed);
        self.generation.fetch_add(1, Ordering::Release);
    }

    /// Sets the mode of a running program (Debug Run from a Release Run's pause).
    pub fn set_mode(&self, mode: RunMode) {
        self.mode.store(mode.into(), Ordering::Relaxed);
        self.generation.fetch_add(1, Ordering::Release);
    }

    /// Sends a command; returns its sequence number, to compare with `done`.
    pub fn send(&self, command: DebugCommand) -> u32 {
        let seq = ((self.command.load(Ordering::Relaxed) >> 8) + 1) & 0x00FF_FFFF;
        self.command.store(seq << 8 | u32::from(command), Ordering::Release);
        seq
    }

    /// Adds one breakpoint; false when the table is full or the line is 0 or already set.
    pub fn add_breakpoint(&self, line: u32) -> bool {
        if line == 0 || self.breakpoint_lines().contains(&line) {
            return false;
        }
        let Some(free) = self.breakpoints.iter().find(|b| b.load(Ordering::Relaxed) == 0) else { return false };
        free.store(line, Ordering::Relaxed);
        self.generation.fetch_add(1, Ordering::Release);
        true
    }

    /// Deletes one breakpoint; false when none is set on that line.
    pub fn delete_breakpoint(&self, line: u32) -> bool {
        let Some(slot) = self.breakpoints.iter().find(|b| line != 0 && b.load(Ordering::Relaxed) == line) else {
            return false;
        };
        slot.store(0, Ordering::Relaxed);
        self.generation.fetch_add(1, Ordering::Release);
        true
    }

    // Both sides.

    /// The run mode the console set.
    pub fn mode(&self) -> RunMode {
        RunMode::from(self.mode.load(Ordering::Relaxed))
    }

    /// Bumped by every change of mode or breakpoints, so the script rereads them only then.
    pub fn generation(&self) -> u32 {
        self.generation.load(Ordering::Acquire)
    }

    /// The breakpoints set, in no particular order.
    pub fn breakpoint_lines(&self) -> Vec<u32> {
        self.breakpoints.iter().map(|b| b.load(Ordering::Relaxed)).filter(|&l| l != 0).collect()
    }

    /// Whether `line` of the main chunk has a breakpoint (the hook's question: no allocation).
    pub fn has_breakpoint(&self, line: u32) -> bool {
        line != 0 && self.breakpoints.iter().any(|b| b.load(Ordering::Relaxed) == line)
    }

    /// The pending command and its sequence number, if it was not carried out yet.
    pub fn pending(&self) -> Option<(u32, DebugCommand)> {
        let word = self.command.load(Ordering::Acquire);
        let seq = word >> 8;
        if seq == self.done.load(Ordering::Acquire) {
            return None;
        }
        DebugCommand::try_from(word & 0xFF).ok().map(|c| (seq, c))
    }

    /// The sequence number of the last command the script carried out.
    pub fn done(&self) -> u32 {
        self.done.load(Ordering::Acquire)
    }

    /// Why the script is not running Lua, as it reported.
    pub fn halt(&self) -> Halt {
        Halt::from(self.halt.load(Ordering::Acquire))
    }

    /// The line of `main.lua` the program is at (DXMC A.3, 0x6B02).
    pub fn main_line(&self) -> u32 {
        self.main_line.load(Ordering::Relaxed)
    }

    // The script's side.

    /// The command `seq` is carried out.
    pub fn mark_done(&self, seq: u32) {
        self.done.store(seq, Ordering::Release);
    }

    /// Reports why the program stopped (or that it runs again).
    pub fn set_halt(&self, halt: Halt) {
        self.halt.store(halt.into(), Ordering::Release);
    }

    /// Reports the line of `main.lua` the program is at.
    pub fn set_main_line(&self, line: u32) {
        self.main_line.store(line, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block() -> DebugBlock {
        // SAFETY: only atomics, valid when zeroed.
        unsafe { std::mem::zeroed() }
    }

    #[test]
    fn a_command_is_pending_until_done() {
        let b = block();
        b.prepare(RunMode::Debug, &[]);
        assert_eq!(b.pending(), None);
        let seq = b.send(DebugCommand::StepOver);
        assert_eq!(b.pending(), Some((seq, DebugCommand::StepOver)));
        b.mark_done(seq);
        assert_eq!(b.pending(), None);
        let next = b.send(DebugCommand::Continue);
        assert_eq!(b.pending(), Some((next, DebugCommand::Continue)));
        b.prepare(RunMode::Release, &[]);
        assert_eq!(b.pending(), None, "a new run forgets the old command");
    }

    #[test]
    fn breakpoints_are_set_added_and_deleted_one_at_a_time() {
        let b = block();
        b.prepare(RunMode::Debug, &[3, 7]);
        let g = b.generation();
        assert!(b.has_breakpoint(7) && !b.has_breakpoint(4));
        assert!(b.add_breakpoint(4));
        assert!(!b.add_breakpoint(4), "already set");
        assert!(!b.add_breakpoint(0));
        assert!(b.generation() > g);
        assert!(b.delete_breakpoint(3));
        assert!(!b.delete_breakpoint(3));
        let mut lines = b.breakpoint_lines();
        lines.sort();
        assert_eq!(lines, vec![4, 7]);
        for line in 100..100 + MAX_BREAKPOINTS as u32 - 2 {
            assert!(b.add_breakpoint(line));
        }
        assert!(!b.add_breakpoint(999), "full");
    }

    /// The debugger's words in the slot, as both processes read them: an unknown mode
    /// is Release, an unknown halt is none, an unknown command is no command.
    #[test]
    fn debugger_word_codes() {
        for (mode, word) in [(RunMode::Release, 0u32), (RunMode::Debug, 1), (RunMode::Block, 2)] {
            assert_eq!(u32::from(mode), word);
            assert_eq!(RunMode::from(word), mode);
        }
        assert_eq!(RunMode::from(3), RunMode::Release);
        for (halt, word) in [(Halt::None, 0u32), (Halt::BreakPoint, 2), (Halt::Pause, 3)] {
            assert_eq!(u32::from(halt), word);
            assert_eq!(Halt::from(word), halt);
        }
        assert_eq!(Halt::from(1), Halt::None);
        let commands = [
            (DebugCommand::Pause, 1u32),
            (DebugCommand::Continue, 2),
            (DebugCommand::StepInto, 3),
            (DebugCommand::StepOver, 4),
            (DebugCommand::StepOut, 5),
        ];
        let b = block();
        for (command, word) in commands {
            assert_eq!(u32::from(command), word);
            let seq = b.send(command);
            assert_eq!(b.command.load(Ordering::Relaxed), seq << 8 | word);
            assert_eq!(b.pending(), Some((seq, command)));
        }
        for word in [0, 6, 0xFF] {
            b.command.store(0x7F << 8 | word, Ordering::Relaxed);
            assert_eq!(b.pending(), None, "word {word}");
        }
    }
}

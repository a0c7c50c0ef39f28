//! HMPL 2.24/2.25: the IEC on-delay and off-delay timers, on controller time.

use mlua::{UserData, UserDataFields};

/// HMPL's `Timer` (`Timer t = TimerInit`); in Lua `local t = TimerInit()`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Timer {
    input: bool,
    output: bool,
    start_ms: u64,
    elapsed_ms: u64,
}

impl Timer {
    /// TON: the output rises once `input` has been on for `preset_ms`; it falls, and the
    /// elapsed time goes back to 0, when `input` falls.
    pub fn on_delay(&mut self, input: bool, preset_ms: u64, now_ms: u64) -> bool {
        if input && !self.input {
            self.start_ms = now_ms;
        }
        if input {
            self.elapsed_ms = (now_ms - self.start_ms).min(preset_ms);
            self.output = self.elapsed_ms >= preset_ms;
        } else {
            self.elapsed_ms = 0;
            self.output = false;
        }
        self.input = input;
        self.output
    }

    /// TOF: the output is on while `input` is on and falls `preset_ms` after `input` fell;
    /// `input` rising again starts over.
    pub fn off_delay(&mut self, input: bool, preset_ms: u64, now_ms: u64) -> bool {
        if input {
            self.output = true;
            self.elapsed_ms = 0;
        } else {
            if self.input {
                self.start_ms = now_ms;
            }
            if self.output {
                self.elapsed_ms = (now_ms - self.start_ms).min(preset_ms);
                self.output = self.elapsed_ms < preset_ms;
            }
        }
        self.input = input;
        self.output
    }
}

/// `t.Q`, `t.ET` (ms) and `t.IN` for looking at a timer while debugging.
impl UserData for Timer {
    fn add_fields<F: UserDataFields<Self>>(fields: &mut F) {
        fields.add_field_method_get("Q", |_, t| Ok(t.output));
        fields.add_field_method_get("ET", |_, t| Ok(t.elapsed_ms));
        fields.add_field_method_get("IN", |_, t| Ok(t.input));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 2.24: (ms, IN, Q) rows of an on-delay of 1000 ms.
    #[test]
    fn on_delay() {
        let mut t = Timer::default();
        let rows = [
            (0, false, false),
            (100, true, false),
            (1099, true, false),
            (1100, true, true),
            (5000, true, true),
            (5001, false, false),
            (5002, true, false),
            (6002, true, true),
        ];
        for (ms, input, q) in rows {
            assert_eq!(t.on_delay(input, 1000, ms), q, "at {ms} ms, IN {input}");
        }
    }

    /// HMPL 2.25: (ms, IN, Q) rows of an off-delay of 1000 ms.
    #[test]
    fn off_delay() {
        let mut t = Timer::default();
        let rows = [
            (0, false, false),
            (100, true, true),
            (200, false, true),
            (1199, false, true),
            (1200, false, false),
            (1300, true, true),
            (1400, false, true),
            (1900, true, true),
            (2000, false, true),
            (3000, false, false),
        ];
        for (ms, input, q) in rows {
            assert_eq!(t.off_delay(input, 1000, ms), q, "at {ms} ms, IN {input}");
        }
    }
}

//! The controller's own digital I/O (HMPL ch. 9): 8 inputs and 8 outputs, pins 1..8, each
//! invertible, and the E-stop input (default 8, `BindEMO`) whose rising edge stops every
//! task and disables every axis. Inputs are simulated: their electrical level is what
//! `SimSetGPI` last set.

use schema::{GPIO_PINS, GpioSnapshot};

/// HMPL 9.2.6: the E-stop input unless `BindEMO` says otherwise.
pub const DEFAULT_EMO_INPUT: u8 = 8;

/// A pin number that does not exist (the chapter's -1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NoSuchPin;

#[derive(Clone, Copy, Debug)]
pub struct ControllerIo {
    /// Electrical input levels, bit i = pin i + 1.
    level: u8,
    gpi_invert: u8,
    /// Outputs as programs set them, before inversion.
    gpo: u8,
    gpo_invert: u8,
    emo_input: u8,
    emo_was_on: bool,
}

impl Default for ControllerIo {
    fn default() -> Self {
        ControllerIo { level: 0, gpi_invert: 0, gpo: 0, gpo_invert: 0, emo_input: DEFAULT_EMO_INPUT, emo_was_on: false }
    }
}

fn bit(pin: i64) -> Result<u8, NoSuchPin> {
    if (1..=GPIO_PINS).contains(&pin) { Ok(1 << (pin - 1)) } else { Err(NoSuchPin) }
}

/// Sets or clears `pin`'s bit in `bits`.
fn set_bit(bits: &mut u8, pin: i64, value: i64) -> Result<(), NoSuchPin> {
    let b = bit(pin)?;
    if value != 0 {
        *bits |= b
    } else {
        *bits &= !b
    }
    Ok(())
}

impl ControllerIo {
    /// Inputs as programs read them.
    pub fn gpi(&self) -> u8 {
        self.level ^ self.gpi_invert
    }

    /// The simulator's switch on input `pin`.
    pub fn set_level(&mut self, pin: i64, value: i64) -> Result<(), NoSuchPin> {
        set_bit(&mut self.level, pin, value)
    }

    pub fn set_gpo(&mut self, pin: i64, value: i64) -> Result<(), NoSuchPin> {
        set_bit(&mut self.gpo, pin, value)
    }

    pub fn toggle_gpo(&mut self, pin: i64) -> Result<(), NoSuchPin> {
        self.gpo ^= bit(pin)?;
        Ok(())
    }

    pub fn set_all_gpo(&mut self, mask: i64) -> Result<(), NoSuchPin> {
        self.gpo = u8::try_from(mask).map_err(|_| NoSuchPin)?;
        Ok(())
    }

    pub fn set_gpi_invert(&mut self, pin: i64, value: i64) -> Result<(), NoSuchPin> {
        set_bit(&mut self.gpi_invert, pin, value)
    }

    pub fn set_gpo_invert(&mut self, pin: i64, value: i64) -> Result<(), NoSuchPin> {
        set_bit(&mut self.gpo_invert, pin, value)
    }

    /// HMPL 9.2.6: the E-stop input, 1..8, or 0 for none. Edges count from now on.
    pub fn bind_emo(&mut self, pin: i64) -> Result<(), NoSuchPin> {
        if pin != 0 {
            bit(pin)?;
        }
        self.emo_input = pin as u8;
        self.emo_was_on = self.emo_on();
        Ok(())
    }

    fn emo_on(&self) -> bool {
        self.emo_input != 0 && self.gpi() & (1 << (self.emo_input - 1)) != 0
    }

    /// Once per cycle: true on the rising edge of the E-stop input.
    pub fn emo_edge(&mut self) -> bool {
        let now = self.emo_on();
        let edge = now && !self.emo_was_on;
        self.emo_was_on = now;
        edge
    }

    pub fn snapshot(&self) -> GpioSnapshot {
        GpioSnapshot {
            gpi: self.gpi() as u32,
            gpo: self.gpo as u32,
            gpi_invert: self.gpi_invert as u32,
            gpo_invert: self.gpo_invert as u32,
            emo_input: self.emo_input as u32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 9.1 and 9.4: bitmasks as the manual's examples give them.
    #[test]
    fn bitmasks() {
        let mut io = ControllerIo::default();
        io.set_level(1, 1).unwrap();
        io.set_level(4, 1).unwrap();
        assert_eq!(io.gpi(), 9, "GPI 1 and 4 on: 9");
        io.set_gpo(2, 1).unwrap();
        io.set_gpo(3, 1).unwrap();
        assert_eq!(io.snapshot().gpo, 6, "GPO 2 and 3 on: 6");
        io.set_gpi_invert(1, 1).unwrap();
        assert_eq!((io.gpi() & bit(1).unwrap(), io.snapshot().gpi_invert), (0, 1), "inverted input 1");
        assert_eq!(io.set_gpo(9, 1), Err(NoSuchPin));
        assert_eq!(bit(0), Err(NoSuchPin));
        io.toggle_gpo(2).unwrap();
        assert_eq!(io.snapshot().gpo, 4);
        io.set_all_gpo(0xFF).unwrap();
        assert_eq!(io.snapshot().gpo, 0xFF);
        assert_eq!(io.set_all_gpo(0x100), Err(NoSuchPin));
    }

    /// HMPL 9.1, 9.2.6: the E-stop is the rising edge of the bound input.
    #[test]
    fn emo_edges() {
        let mut io = ControllerIo::default();
        assert!(!io.emo_edge());
        io.set_level(8, 1).unwrap();
        assert!(io.emo_edge(), "GPI 8 rises: E-stop");
        assert!(!io.emo_edge(), "an edge, not a level");
        io.set_level(8, 0).unwrap();
        io.bind_emo(0).unwrap();
        io.set_level(8, 1).unwrap();
        assert!(!io.emo_edge(), "BindEMO(0): no input stops anything");
        io.bind_emo(3).unwrap();
        io.set_level(3, 1).unwrap();
        assert!(io.emo_edge(), "BindEMO(3): GPI 3");
        assert_eq!(io.bind_emo(9), Err(NoSuchPin));
        io.set_level(5, 1).unwrap();
        io.bind_emo(5).unwrap();
        assert!(!io.emo_edge(), "binding an input that is already on is no edge");
    }
}

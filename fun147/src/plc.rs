//! The PLC register image FUN147 works on: 16-bit word registers R and D, their 32-bit
//! views (DR/DD: low word at n, high word at n+1, signed) and the relays X, Y, M, S.
//!
//! The areas are the FBs-PLC's operand areas FUN147 names (FUN147 operand table, SPD/LIN
//! "Rxxxx/Dxxxx", WAIT "X0-X255 … S0-S999"): R0-R3839 (HR), R5000-R8071 (ROR), D0-D3999 and
//! the system registers D4060-D4095 the instruction reports in (FUN147 interface signals).

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

/// A 16-bit word register.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Reg {
    /// R0-R3839 (holding) or R5000-R8071 (read-only in the PLC; writable here).
    R(u16),
    /// D0-D3999, and the system registers D4060-D4095.
    D(u16),
}

impl Reg {
    /// Whether the register exists.
    pub fn is_valid(self) -> bool {
        match self {
            Reg::R(n) => n <= 3839 || (5000..=8071).contains(&n),
            Reg::D(n) => n <= 3999 || (4060..=4095).contains(&n),
        }
    }

    /// The register `k` words further on, if it exists and lies in the same area (a table
    /// cannot run from R3839 into R5000).
    pub fn offset(self, k: u16) -> Option<Reg> {
        let moved = match self {
            Reg::R(n) => Reg::R(n.checked_add(k)?),
            Reg::D(n) => Reg::D(n.checked_add(k)?),
        };
        (self.is_valid() && moved.is_valid() && moved.area() == self.area()).then_some(moved)
    }

    /// Whether the 32-bit view at this register (n and n+1) exists.
    pub fn is_valid_double(self) -> bool {
        self.offset(1).is_some()
    }

    /// The register number, without its letter.
    pub fn number(self) -> u16 {
        match self {
            Reg::R(n) | Reg::D(n) => n,
        }
    }

    fn area(self) -> u8 {
        match self {
            Reg::R(n) if n <= 3839 => 0,
            Reg::R(_) => 1,
            Reg::D(n) if n <= 3999 => 2,
            Reg::D(_) => 3,
        }
    }
}

/// A relay (bit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Relay {
    /// Input X0-X255.
    X(u16),
    /// Output Y0-Y255.
    Y(u16),
    /// Internal relay M0-M2001.
    M(u16),
    /// Step relay S0-S999.
    S(u16),
}

impl Relay {
    /// Whether the relay exists.
    pub fn is_valid(self) -> bool {
        match self {
            Relay::X(n) | Relay::Y(n) => n <= 255,
            Relay::M(n) => n <= 2001,
            Relay::S(n) => n <= 999,
        }
    }

    /// Its place among all relays, X0-X255, Y0-Y255, M0-M2001, S0-S999 in that order
    /// (the storage of an image); `None` when it does not exist.
    pub fn index(self) -> Option<usize> {
        self.is_valid().then(|| match self {
            Relay::X(n) => n as usize,
            Relay::Y(n) => 256 + n as usize,
            Relay::M(n) => 512 + n as usize,
            Relay::S(n) => 512 + 2002 + n as usize,
        })
    }

    /// Whether WAIT and EXT may name it: M only up to M1911, the rest being system relays
    /// (FUN147 WAIT and EXT operand tables).
    pub fn is_condition(self) -> bool {
        self.is_valid() && !matches!(self, Relay::M(n) if n > 1911)
    }
}

/// An address that is no register or relay, or one outside its area.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[error("no such address: {0:?}")]
pub struct AddressError(pub String);

/// Parses "<letter><number>" (case-insensitive) with `make`, keeping only what `valid`
/// accepts. Allocates nothing, so the controller's cycle may call it.
fn parse_address<T>(text: &str, make: impl Fn(char, u16) -> Option<T>, valid: impl Fn(&T) -> bool) -> Option<T> {
    let mut chars = text.chars();
    let letter = chars.next().map(|c| c.to_ascii_uppercase());
    let digits = chars.as_str();
    let number = (!digits.is_empty() && digits.len() <= 5 && digits.bytes().all(|b| b.is_ascii_digit()))
        .then(|| digits.parse().ok())
        .flatten();
    letter.zip(number).and_then(|(letter, number)| make(letter, number)).filter(valid)
}

impl Reg {
    /// "R1000", "d100"; `None` for what names no register. (`str::parse` says which text.)
    pub fn parse(text: &str) -> Option<Reg> {
        let make = |letter, n| match letter {
            'R' => Some(Reg::R(n)),
            'D' => Some(Reg::D(n)),
            _ => None,
        };
        parse_address(text, make, |reg| reg.is_valid())
    }
}

impl Relay {
    /// "X0", "m1992"; `None` for what names no relay.
    pub fn parse(text: &str) -> Option<Relay> {
        let make = |letter, n| match letter {
            'X' => Some(Relay::X(n)),
            'Y' => Some(Relay::Y(n)),
            'M' => Some(Relay::M(n)),
            'S' => Some(Relay::S(n)),
            _ => None,
        };
        parse_address(text, make, |relay| relay.is_valid())
    }
}

impl FromStr for Reg {
    type Err = AddressError;

    /// "R1000", "d100".
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Reg::parse(text).ok_or_else(|| AddressError(text.to_owned()))
    }
}

impl FromStr for Relay {
    type Err = AddressError;

    /// "X0", "m1991".
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Relay::parse(text).ok_or_else(|| AddressError(text.to_owned()))
    }
}

impl fmt::Display for Reg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reg::R(n) => write!(f, "R{n}"),
            Reg::D(n) => write!(f, "D{n}"),
        }
    }
}

impl fmt::Display for Relay {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Relay::X(n) => write!(f, "X{n}"),
            Relay::Y(n) => write!(f, "Y{n}"),
            Relay::M(n) => write!(f, "M{n}"),
            Relay::S(n) => write!(f, "S{n}"),
        }
    }
}

/// The register image. Reads of an address that does not exist give 0 and writes to one
/// are ignored; every address FUN147 uses is checked before it is used.
pub trait Plc {
    /// A word register.
    fn word(&self, reg: Reg) -> u16;
    /// Writes a word register.
    fn set_word(&mut self, reg: Reg, value: u16);
    /// A relay.
    fn relay(&self, relay: Relay) -> bool;
    /// Writes a relay.
    fn set_relay(&mut self, relay: Relay, on: bool);

    /// The signed 32-bit view DRn/DDn: low word at n, high word at n+1.
    fn dword(&self, reg: Reg) -> i32 {
        let high = reg.offset(1).map_or(0, |r| self.word(r));
        ((u32::from(high) << 16) | u32::from(self.word(reg))) as i32
    }

    /// Writes the 32-bit view: low word at n, high word at n+1.
    fn set_dword(&mut self, reg: Reg, value: i32) {
        self.set_word(reg, value as u16);
        if let Some(high) = reg.offset(1) {
            self.set_word(high, (value >> 16) as u16);
        }
    }
}

/// M1992-M1995: Ps0-Ps3 Ready (ON) or in use by a FUN140/FUN147 (OFF) (FUN147 expl. 4).
pub fn ready_flag(axis: usize) -> Relay {
    Relay::M(1992 + axis as u16)
}

/// What a PLC holds at power-up for FUN147: the four axes Ready. The lead calls this once
/// on the shared image before any instance runs.
pub fn power_up(plc: &mut impl Plc) {
    for axis in 0..4 {
        plc.set_relay(ready_flag(axis), true);
    }
}

/// An in-memory register image, as at power-up: everything 0 but the Ready flags.
#[derive(Clone)]
pub struct MemPlc {
    r: Vec<u16>,
    d: Vec<u16>,
    relays: Vec<bool>,
}

impl MemPlc {
    /// A fresh image.
    pub fn new() -> Self {
        let mut plc = MemPlc { r: vec![0; 8072], d: vec![0; 4096], relays: vec![false; 256 * 2 + 2002 + 1000] };
        power_up(&mut plc);
        plc
    }

    fn relay_index(relay: Relay) -> Option<usize> {
        relay.index()
    }
}

impl Default for MemPlc {
    fn default() -> Self {
        Self::new()
    }
}

impl Plc for MemPlc {
    fn word(&self, reg: Reg) -> u16 {
        match reg {
            _ if !reg.is_valid() => 0,
            Reg::R(n) => self.r[n as usize],
            Reg::D(n) => self.d[n as usize],
        }
    }

    fn set_word(&mut self, reg: Reg, value: u16) {
        match reg {
            _ if !reg.is_valid() => {}
            Reg::R(n) => self.r[n as usize] = value,
            Reg::D(n) => self.d[n as usize] = value,
        }
    }

    fn relay(&self, relay: Relay) -> bool {
        Self::relay_index(relay).is_some_and(|i| self.relays[i])
    }

    fn set_relay(&mut self, relay: Relay, on: bool) {
        if let Some(i) = Self::relay_index(relay) {
            self.relays[i] = on;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The operand areas: first and last of each, and the gaps between them.
    #[test]
    fn addresses() {
        for (text, ok) in [
            ("R0", true),
            ("R3839", true),
            ("R3840", false),
            ("R5000", true),
            ("r8071", true),
            ("R8072", false),
            ("D3999", true),
            ("D4000", false),
            ("D4060", true),
            ("D4095", true),
            ("D4096", false),
            ("D", false),
            ("D-1", false),
            ("Q1", false),
            ("R65536", false),
        ] {
            assert_eq!(text.parse::<Reg>().is_ok(), ok, "{text}");
        }
        for (text, ok) in [
            ("X0", true),
            ("x255", true),
            ("X256", false),
            ("M2001", true),
            ("M2002", false),
            ("S999", true),
            ("S1000", false),
            ("Y0", true),
        ] {
            assert_eq!(text.parse::<Relay>().is_ok(), ok, "{text}");
        }
        assert_eq!("d100".parse::<Reg>().unwrap().to_string(), "D100");
        assert!(!Relay::M(1912).is_condition() && Relay::M(1911).is_condition());
    }

    /// FUN147 SPD table: a variable is two registers, low word at n, high word at n+1.
    #[test]
    fn double_words() {
        let mut plc = MemPlc::new();
        plc.set_word(Reg::D(101), 0xFFFF);
        plc.set_word(Reg::D(100), 0xFC18);
        assert_eq!(plc.dword(Reg::D(100)), -1000);
        plc.set_dword(Reg::R(1000), 1_840_000);
        assert_eq!((plc.word(Reg::R(1000)), plc.word(Reg::R(1001))), (0x1380, 0x001C));
        assert!(!Reg::R(3839).is_valid_double() && Reg::R(3838).is_valid_double());
        assert_eq!(Reg::R(3839).offset(1), None, "no table runs from R3839 into R5000");
    }
}

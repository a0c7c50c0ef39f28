//! The FUN147 register image in the namespace's shared memory (`schema::plc_image`) as a
//! `fun147::Plc`, and its Modbus addresses (docs/fun147.md, "Modbus"): holding registers in
//! the SDV range the DXMC map reserves (DXMC A.1), relays packed 16 to a word.

use fun147::{Plc, Reg, Relay};
use schema::plc_image::{PlcImage, WordArea};

/// The shared image, read and written in place.
#[derive(Clone, Copy)]
pub struct SharedPlc<'a>(pub &'a PlcImage);

fn word_of(reg: Reg) -> Option<(WordArea, usize)> {
    let word = match reg {
        Reg::R(n) => (WordArea::R, n as usize),
        Reg::D(n) => (WordArea::D, n as usize),
    };
    reg.is_valid().then_some(word)
}

impl Plc for SharedPlc<'_> {
    fn word(&self, reg: Reg) -> u16 {
        word_of(reg).and_then(|(area, n)| self.0.word(area, n)).unwrap_or(0)
    }

    fn set_word(&mut self, reg: Reg, value: u16) {
        if let Some((area, n)) = word_of(reg) {
            self.0.set_word(area, n, value);
        }
    }

    fn relay(&self, relay: Relay) -> bool {
        relay.index().and_then(|i| self.0.relay(i)).unwrap_or(false)
    }

    fn set_relay(&mut self, relay: Relay, on: bool) {
        if let Some(i) = relay.index() {
            self.0.set_relay(i, on);
        }
    }
}

/// The first Modbus address of the image (SDV, DXMC A.1) and one past its last.
pub const MODBUS_FIRST: u16 = 0x3000;
/// One past the last word (S992-S999's word is 0x5BDE).
pub const MODBUS_END: u16 = 0x5BDF;

/// What a Modbus address of the image names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlcWord {
    /// A register.
    Reg(Reg),
    /// Sixteen relays from the first (a word's bit i is relay first + i); relays past the
    /// area's end read 0 and ignore writes.
    Relays(Relay),
}

impl PlcWord {
    /// The register or relays at a Modbus address; `None` where nothing exists.
    pub fn at(address: u16) -> Option<PlcWord> {
        let word = match address {
            0x3000..=0x3EFF => PlcWord::Reg(Reg::R(address - 0x3000)),
            0x3F00..=0x4AFF => PlcWord::Reg(Reg::R(5000 + address - 0x3F00)),
            0x4B00..=0x5AFF => PlcWord::Reg(Reg::D(address - 0x4B00)),
            0x5B00..=0x5B0F => PlcWord::Relays(Relay::X(16 * (address - 0x5B00))),
            0x5B10..=0x5B1F => PlcWord::Relays(Relay::Y(16 * (address - 0x5B10))),
            0x5B20..=0x5B9D => PlcWord::Relays(Relay::M(16 * (address - 0x5B20))),
            0x5BA0..=0x5BDE => PlcWord::Relays(Relay::S(16 * (address - 0x5BA0))),
            _ => return None,
        };
        match word {
            PlcWord::Reg(reg) if !reg.is_valid() => None,
            _ => Some(word),
        }
    }
}

fn relays_from(first: Relay) -> impl Iterator<Item = Relay> {
    (0..16u16).map(move |i| match first {
        Relay::X(n) => Relay::X(n + i),
        Relay::Y(n) => Relay::Y(n + i),
        Relay::M(n) => Relay::M(n + i),
        Relay::S(n) => Relay::S(n + i),
    })
}

/// The word at a Modbus address; `None` where nothing exists.
pub fn read(image: &PlcImage, address: u16) -> Option<u16> {
    let plc = SharedPlc(image);
    Some(match PlcWord::at(address)? {
        PlcWord::Reg(reg) => plc.word(reg),
        PlcWord::Relays(first) => {
            relays_from(first).enumerate().fold(0, |word, (i, relay)| word | (u16::from(plc.relay(relay)) << i))
        }
    })
}

/// Writes the word at a Modbus address; false where nothing exists.
pub fn write(image: &PlcImage, address: u16, value: u16) -> bool {
    let mut plc = SharedPlc(image);
    match PlcWord::at(address) {
        Some(PlcWord::Reg(reg)) => plc.set_word(reg, value),
        Some(PlcWord::Relays(first)) => {
            for (i, relay) in relays_from(first).enumerate() {
                plc.set_relay(relay, value & (1 << i) != 0);
            }
        }
        None => return false,
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// docs/fun147.md, "Modbus": the first and last word of each area and the gaps.
    #[test]
    fn modbus_map() {
        for (address, word) in [
            (0x3000, Some(PlcWord::Reg(Reg::R(0)))),
            (0x37D0, Some(PlcWord::Reg(Reg::R(2000)))),
            (0x3EFF, Some(PlcWord::Reg(Reg::R(3839)))),
            (0x3F00, Some(PlcWord::Reg(Reg::R(5000)))),
            (0x4AFF, Some(PlcWord::Reg(Reg::R(8071)))),
            (0x4B00, Some(PlcWord::Reg(Reg::D(0)))),
            (0x5A9F, Some(PlcWord::Reg(Reg::D(3999)))),
            (0x5AA0, None),
            (0x5ADB, None),
            (0x5ADC, Some(PlcWord::Reg(Reg::D(4060)))),
            (0x5ADE, Some(PlcWord::Reg(Reg::D(4062)))),
            (0x5AFF, Some(PlcWord::Reg(Reg::D(4095)))),
            (0x5B00, Some(PlcWord::Relays(Relay::X(0)))),
            (0x5B1F, Some(PlcWord::Relays(Relay::Y(240)))),
            (0x5B26, Some(PlcWord::Relays(Relay::M(96)))),
            (0x5B9D, Some(PlcWord::Relays(Relay::M(2000)))),
            (0x5B9E, None),
            (0x5BA0, Some(PlcWord::Relays(Relay::S(0)))),
            (0x5BDE, Some(PlcWord::Relays(Relay::S(992)))),
            (MODBUS_END, None),
            (0x2FFF, None),
        ] {
            assert_eq!(PlcWord::at(address), word, "0x{address:04X}");
        }
    }
}

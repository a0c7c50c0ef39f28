//! HMPL ch. 10: the conversion ("range") types of table 10.1.1 between a slave's 16-bit
//! analog word and engineering values, and the controller variables an analog output can
//! follow (HMPL 10.4.1). Pure functions: the core converts what it writes, the query
//! evaluator what it reads, with the same code.

use num_enum::TryFromPrimitive;

/// `HMPL_DAC_SIGNED`: OR'ed with a range, the word is two's complement (its high bit the
/// sign) instead of offset binary (HMPL table 10.1.1). Value: luamotion.
pub const DAC_SIGNED: i64 = 0x100;

/// The ranges of HMPL table 10.1.1 (`HMPL_DAC_*`, values: luamotion). `TryFromPrimitive`:
/// any other number is no range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive)]
#[repr(u8)]
pub enum Range {
    /// `HMPL_DAC_NONE`: no conversion, only the Raw functions.
    None = 0,
    /// `HMPL_DAC_N10_P10`: -10..10 (a voltage module).
    N10P10 = 1,
    /// `HMPL_DAC_P0_P10`: 0..10.
    P0P10 = 2,
    /// `HMPL_DAC_N5_P5`: -5..5.
    N5P5 = 3,
    /// `HMPL_DAC_P0_P5`: 0..5.
    P0P5 = 4,
    /// `HMPL_DAC_P0_P20`: 0..20 (a current module, mA).
    P0P20 = 5,
    /// `HMPL_DAC_P4_P20`: 4..20.
    P4P20 = 6,
    /// `HMPL_DAC_N20_P20`: -20..20.
    N20P20 = 7,
}

impl Range {
    /// Every range with its constant's name, in the order of table 10.1.1.
    pub const ALL: [(Range, &'static str); 8] = [
        (Range::None, "HMPL_DAC_NONE"),
        (Range::N10P10, "HMPL_DAC_N10_P10"),
        (Range::P0P10, "HMPL_DAC_P0_P10"),
        (Range::N5P5, "HMPL_DAC_N5_P5"),
        (Range::P0P5, "HMPL_DAC_P0_P5"),
        (Range::P0P20, "HMPL_DAC_P0_P20"),
        (Range::P4P20, "HMPL_DAC_P4_P20"),
        (Range::N20P20, "HMPL_DAC_N20_P20"),
    ];

    /// The lowest and highest value; `None` for `HMPL_DAC_NONE`.
    pub fn bounds(self) -> Option<(f64, f64)> {
        match self {
            Range::None => None,
            Range::N10P10 => Some((-10.0, 10.0)),
            Range::P0P10 => Some((0.0, 10.0)),
            Range::N5P5 => Some((-5.0, 5.0)),
            Range::P0P5 => Some((0.0, 5.0)),
            Range::P0P20 => Some((0.0, 20.0)),
            Range::P4P20 => Some((4.0, 20.0)),
            Range::N20P20 => Some((-20.0, 20.0)),
        }
    }
}

/// A channel's conversion type: a range, signed or not (`range_type` of HMPL 10.2.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConversionType {
    /// The range of table 10.1.1.
    pub range: Range,
    /// `HMPL_DAC_SIGNED` is set.
    pub signed: bool,
}

impl Default for ConversionType {
    fn default() -> Self {
        ConversionType::NONE
    }
}

impl ConversionType {
    /// No conversion, unsigned: a channel's type until a program sets one.
    pub const NONE: ConversionType = ConversionType { range: Range::None, signed: false };

    /// `range_type` as a program passes it: a range, optionally OR'ed with
    /// `HMPL_DAC_SIGNED`; `None` for anything else.
    pub fn from_code(code: i64) -> Option<Self> {
        if code & !(DAC_SIGNED | 0xFF) != 0 {
            return None;
        }
        let range = Range::try_from((code & 0xFF) as u8).ok()?;
        Some(ConversionType { range, signed: code & DAC_SIGNED != 0 })
    }

    /// The code `GetSlvAIType` returns.
    pub fn code(self) -> i64 {
        self.range as i64 | if self.signed { DAC_SIGNED } else { 0 }
    }

    /// The raw value of a 16-bit word as the Raw functions show it: two's complement when
    /// signed, else 0..65535 (HMPL 10.2.3, 10.3.3; docs/decisions.md, "Slave analog I/O").
    pub fn raw(self, word: u16) -> i64 {
        if self.signed { word as i16 as i64 } else { word as i64 }
    }

    /// The engineering value of a word; `None` without a range. The range is cut into
    /// 65536 steps from its lowest value (the midscale word is the middle exactly), so
    /// the top word reads one step below the top (docs/decisions.md, "Slave analog I/O").
    pub fn value(self, word: u16) -> Option<f64> {
        let (lo, hi) = self.range.bounds()?;
        Some(lo + (hi - lo) * self.step(word) as f64 / STEPS)
    }

    /// The word nearest to `value`; `None` without a range or outside it (NaN included).
    pub fn word(self, value: f64) -> Option<u16> {
        let (lo, hi) = self.range.bounds()?;
        if !(lo..=hi).contains(&value) {
            return None;
        }
        Some(self.word_clamped(value))
    }

    /// The word nearest to `value`, a value outside the range giving the end it passed
    /// (as a converter saturates); needs a range (0 without).
    pub fn word_clamped(self, value: f64) -> u16 {
        let Some((lo, hi)) = self.range.bounds() else { return 0 };
        let step = ((value - lo) / (hi - lo) * STEPS).round();
        // NaN saturates to 0 with `as`; the bound variable is finite anyway.
        let step = step.clamp(0.0, STEPS - 1.0) as u16;
        if self.signed { step ^ 0x8000 } else { step }
    }

    /// A word's step from the range's lowest value: offset binary as is, two's complement
    /// with its sign bit flipped.
    fn step(self, word: u16) -> u16 {
        if self.signed { word ^ 0x8000 } else { word }
    }
}

/// Steps of a 16-bit word.
const STEPS: f64 = 65536.0;

/// A controller variable an analog output follows (HMPL 10.4.1, `HMPL_<VAR>`; values:
/// luamotion, the variable above the axis id `HMPL_AXIS_n` in the low byte).
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive)]
#[repr(u8)]
pub enum AxisVariable {
    /// `HMPL_REF_POS`: reference position.
    RefPos = 1,
    /// `HMPL_REF_VEL`: reference velocity.
    RefVel = 2,
    /// `HMPL_REF_ACC`: reference acceleration.
    RefAcc = 3,
    /// `HMPL_POS_FB`: position feedback.
    PosFb = 4,
    /// `HMPL_VEL_FB`: velocity feedback.
    VelFb = 5,
    /// `HMPL_ACC_FB`: acceleration feedback (the velocity feedback's change a cycle).
    AccFb = 6,
    /// `HMPL_CUR_FB`: current feedback, A.
    CurFb = 7,
}

impl AxisVariable {
    /// Every variable with its constant's name.
    pub const ALL: [(AxisVariable, &'static str); 7] = [
        (AxisVariable::RefPos, "HMPL_REF_POS"),
        (AxisVariable::RefVel, "HMPL_REF_VEL"),
        (AxisVariable::RefAcc, "HMPL_REF_ACC"),
        (AxisVariable::PosFb, "HMPL_POS_FB"),
        (AxisVariable::VelFb, "HMPL_VEL_FB"),
        (AxisVariable::AccFb, "HMPL_ACC_FB"),
        (AxisVariable::CurFb, "HMPL_CUR_FB"),
    ];

    /// The constant `HMPL_<VAR>`: the variable in the second byte.
    pub fn code(self) -> i64 {
        (self as i64) << 8
    }
}

/// `var_id` = `HMPL_AXIS_n | HMPL_<VAR>` split into the axis and the variable; `None`
/// when it names no variable (HMPL 10.4.1).
pub fn split_var_id(var_id: i64) -> Option<(usize, AxisVariable)> {
    if var_id & !0xFFFF != 0 {
        return None;
    }
    let var = AxisVariable::try_from((var_id >> 8) as u8).ok()?;
    Some(((var_id & 0xFF) as usize, var))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One step of a ±10 range: 20 / 65536.
    const LSB_10: f64 = 20.0 / 65536.0;

    fn n10_p10(signed: bool) -> ConversionType {
        ConversionType { range: Range::N10P10, signed }
    }

    /// HMPL table 10.1.1, a 16-bit ±10 V device with `HMPL_DAC_N10_P10`: each row of the
    /// manual's table, read and written; the top word one step below 10.
    #[test]
    fn table_10_1_1_unsigned_rows() {
        let rows: [(u16, f64); 5] = [(65535, 10.0), (49152, 5.0), (32768, 0.0), (16384, -5.0), (0, -10.0)];
        for (word, value) in rows {
            let read = n10_p10(false).value(word).unwrap();
            assert!((read - value).abs() <= LSB_10, "HMPL table 10.1.1: {word} -> {value}, read {read}");
            assert_eq!(n10_p10(false).word(value), Some(word), "HMPL table 10.1.1: {value} -> {word}");
            assert_eq!(n10_p10(false).raw(word), word as i64);
        }
        assert_eq!(n10_p10(false).value(32768), Some(0.0), "the midscale word is 0 exactly");
        assert_eq!(n10_p10(false).value(65535), Some(10.0 - LSB_10));
    }

    /// HMPL table 10.1.1 with `HMPL_DAC_SIGNED | HMPL_DAC_N10_P10`: the manual's rows.
    #[test]
    fn table_10_1_1_signed_rows() {
        let rows: [(i16, f64); 5] = [(32767, 10.0), (16384, 5.0), (0, 0.0), (-16384, -5.0), (-32768, -10.0)];
        for (raw, value) in rows {
            let word = raw as u16;
            let read = n10_p10(true).value(word).unwrap();
            assert!((read - value).abs() <= LSB_10, "HMPL table 10.1.1 signed: {raw} -> {value}, read {read}");
            assert_eq!(n10_p10(true).word(value), Some(word), "HMPL table 10.1.1 signed: {value} -> {raw}");
            assert_eq!(n10_p10(true).raw(word), raw as i64, "the Raw functions show it signed");
        }
    }

    /// Every range of table 10.1.1 runs from its lowest value at the lowest word to one
    /// step below its highest; NONE converts nothing.
    #[test]
    fn every_range_spans_its_bounds() {
        for (range, name) in Range::ALL {
            for signed in [false, true] {
                let ty = ConversionType { range, signed };
                let Some((lo, hi)) = range.bounds() else {
                    assert_eq!((ty.value(0), ty.word(0.0)), (None, None), "{name} converts nothing");
                    continue;
                };
                let (bottom, top) = if signed { (0x8000, 0x7FFF) } else { (0, 0xFFFF) };
                assert_eq!(ty.value(bottom), Some(lo), "{name}");
                assert!((hi - ty.value(top).unwrap() - (hi - lo) / 65536.0).abs() < 1e-12, "{name}");
                assert_eq!(ty.word(hi), Some(top), "{name}: the top value is the top word");
                assert_eq!((ty.word(hi + 0.01), ty.word(lo - 0.01), ty.word(f64::NAN)), (None, None, None));
                assert_eq!((ty.word_clamped(hi * 2.0 + 1.0), ty.word_clamped(f64::NEG_INFINITY)), (top, bottom));
            }
        }
    }

    /// `range_type` codes: the ranges, with or without the signed flag, and nothing else.
    #[test]
    fn conversion_type_codes() {
        for (range, _) in Range::ALL {
            for signed in [false, true] {
                let ty = ConversionType { range, signed };
                assert_eq!(ConversionType::from_code(ty.code()), Some(ty));
            }
        }
        for bad in [8, 0xFF, 0x200, 0x101 | 0x1000, -1, i64::MIN] {
            assert_eq!(ConversionType::from_code(bad), None, "{bad:#x}");
        }
    }

    /// HMPL 10.4.1: `HMPL_AXIS_0 | HMPL_REF_VEL` names axis 0's reference velocity.
    #[test]
    fn variable_ids() {
        assert_eq!(split_var_id(AxisVariable::RefVel.code()), Some((0, AxisVariable::RefVel)));
        assert_eq!(split_var_id(15 | AxisVariable::CurFb.code()), Some((15, AxisVariable::CurFb)));
        for bad in [0, 15, 8 << 8, 0x1_0000 | 0x200, -1] {
            assert_eq!(split_var_id(bad), None, "{bad:#x}");
        }
    }

    /// The scripts' constants are these types' codes.
    #[test]
    fn constants_are_the_codes() {
        use crate::constants::{CONSTANTS, Constant};
        let constant = |name: &str| CONSTANTS.iter().find(|c| c.0 == name).map(|c| c.1);
        for (range, name) in Range::ALL {
            assert_eq!(constant(name), Some(Constant::Int(range as i64)), "{name}");
        }
        assert_eq!(constant("HMPL_DAC_SIGNED"), Some(Constant::Int(DAC_SIGNED)));
        for (var, name) in AxisVariable::ALL {
            assert_eq!(constant(name), Some(Constant::Int(var.code())), "{name}");
        }
    }
}

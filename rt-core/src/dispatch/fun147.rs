//! The FUN147 commands (docs/fun147.md): `MHSPO` declares a box, `MHSPOFree` removes
//! one; the boxes themselves run in `fun147_boxes`, before the kernel, every cycle.

use api::SystemError;
use fun147::{Reg, Relay};

use super::{Done, Outcome};
use crate::fun147_boxes::Contacts;
use crate::machine::Machine;

/// An operand that names no register or relay, or a box the FUN147 rules refuse, is
/// "argument out of range" (0x138F), as any bad argument is. Nothing here allocates: the
/// RT thread runs it.
fn parse<T>(text: &[u8], parse: fn(&str) -> Option<T>) -> Result<T, SystemError> {
    std::str::from_utf8(text).ok().and_then(parse).ok_or(SystemError::HmplArgOutOfRange)
}

/// MHSPO(Gp, SR, WR, EN, PAU, ABT, ACT, ERR, DN).
pub(super) fn declare(m: &mut Machine, gp: i64, sr: &[u8], wr: &[u8], relays: [&[u8]; 6]) -> Outcome {
    let (sr, wr) = (parse(sr, Reg::parse)?, parse(wr, Reg::parse)?);
    let [en, pau, abt, act, err, dn] = relays.map(|r| parse(r, Relay::parse));
    let contacts = Contacts { en: en?, pau: pau?, abt: abt?, act: act?, err: err?, dn: dn? };
    m.boxes.declare(gp, sr, wr, contacts).map_err(|_| SystemError::HmplArgOutOfRange)?;
    Ok(Done::Now)
}

/// MHSPOFree(Gp).
pub(super) fn free(m: &mut Machine, gp: i64) -> Outcome {
    m.boxes.free(gp).map_err(|_| SystemError::HmplArgOutOfRange)?;
    Ok(Done::Now)
}

//! The FUN147 commands (docs/fun147.md): `MHSPO` declares a box, `MHSPOFree` removes
//! one; the boxes themselves run in `fun147_boxes`, before the kernel, every cycle.

use api::SystemError;
use fun147::{Reg, Relay};

use super::{Done, Outcome};
use crate::fun147_boxes::Contacts;
use crate::machine::Machine;

/// An operand that names no register or relay, or a box the FUN147 rules refuse, is
/// "argument out of range" (0x138F), as any bad argument is.
fn parse<T: std::str::FromStr>(text: &[u8]) -> Result<T, SystemError> {
    std::str::from_utf8(text).ok().and_then(|t| t.parse().ok()).ok_or(SystemError::HmplArgOutOfRange)
}

/// MHSPO(Gp, SR, WR, EN, PAU, ABT, ACT, ERR, DN).
pub(super) fn declare(m: &mut Machine, gp: i64, sr: &[u8], wr: &[u8], relays: [&[u8]; 6]) -> Outcome {
    let (sr, wr): (Reg, Reg) = (parse(sr)?, parse(wr)?);
    let [en, pau, abt, act, err, dn] = relays;
    let contacts = Contacts {
        en: parse::<Relay>(en)?,
        pau: parse(pau)?,
        abt: parse(abt)?,
        act: parse(act)?,
        err: parse(err)?,
        dn: parse(dn)?,
    };
    m.boxes.declare(gp, sr, wr, contacts).map_err(|_| SystemError::HmplArgOutOfRange)?;
    Ok(Done::Now)
}

/// MHSPOFree(Gp).
pub(super) fn free(m: &mut Machine, gp: i64) -> Outcome {
    m.boxes.free(gp).map_err(|_| SystemError::HmplArgOutOfRange)?;
    Ok(Done::Now)
}

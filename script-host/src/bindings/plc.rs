//! The FUN147 local functions (docs/fun147.md): the PLC register image in the namespace's
//! shared memory, read and written in place, and the step table's text form.

use std::rc::Rc;

use api::{FunctionSpec, Local};
use calls::plc::SharedPlc;
use fun147::{Plc, Program, Reg, Relay, assemble, disassemble};
use mlua::{Function, Lua, MultiValue};

use super::{Host, binding, bool_arg, error_here, int_arg, lua_string_arg};

/// A register operand: "R1000", "D4062" (a word) or "DR1000", "DD100" (n and n+1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Address {
    Word(Reg),
    Double(Reg),
}

fn address(text: &str) -> Option<Address> {
    let upper = text.to_ascii_uppercase();
    match upper.strip_prefix("DR").or_else(|| upper.strip_prefix("DD")) {
        Some(number) => {
            let reg = format!("{}{number}", &upper[1..2]).parse::<Reg>().ok()?;
            reg.is_valid_double().then_some(Address::Double(reg))
        }
        None => upper.parse().ok().map(Address::Word),
    }
}

fn text_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<String> {
    Ok(lua_string_arg(lua, spec, args, i)?.to_string_lossy())
}

fn reg_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<Address> {
    let text = text_arg(lua, spec, args, i)?;
    address(&text).ok_or_else(|| {
        error_here(
            lua,
            format!(
                "{}: {text:?} is no register R0-R3839, R5000-R8071, D0-D3999, D4060-D4095 (or DR/DD of two)",
                spec.name
            ),
        )
    })
}

fn relay_arg(lua: &Lua, spec: &FunctionSpec, args: &MultiValue, i: usize) -> mlua::Result<Relay> {
    let text = text_arg(lua, spec, args, i)?;
    text.parse().map_err(|_| {
        error_here(lua, format!("{}: {text:?} is no relay X0-X255, Y0-Y255, M0-M2001, S0-S999", spec.name))
    })
}

fn plc(host: &Host) -> SharedPlc<'_> {
    SharedPlc(host.shared.plc())
}

/// The functions of `Local` that belong here.
pub fn local(lua: &Lua, host: Rc<Host>, local: Local) -> mlua::Result<Function> {
    let spec = local.spec();
    match local {
        Local::MHSPOLoad => binding(lua, spec, move |lua, args| {
            host.beat();
            let Address::Word(sr) = reg_arg(lua, spec, &args, 0)? else {
                return Err(error_here(lua, "MHSPOLoad: SR is one register, not DR/DD"));
            };
            let text = text_arg(lua, spec, &args, 1)?;
            let program = assemble(&text).map_err(|e| error_here(lua, format!("MHSPOLoad: {e}")))?;
            program.write(&mut plc(&host), sr).map_err(|e| error_here(lua, format!("MHSPOLoad: {e}")))?;
            Ok(0)
        }),
        Local::MHSPOText => binding(lua, spec, move |lua, args| {
            host.beat();
            let Address::Word(sr) = reg_arg(lua, spec, &args, 0)? else {
                return Err(error_here(lua, "MHSPOText: SR is one register, not DR/DD"));
            };
            let program = Program::read(&plc(&host), sr).map_err(|e| error_here(lua, format!("MHSPOText: {e}")))?;
            Ok(disassemble(&program))
        }),
        Local::GetPlcReg => binding(lua, spec, move |lua, args| {
            host.beat();
            Ok(match reg_arg(lua, spec, &args, 0)? {
                Address::Word(reg) => i64::from(plc(&host).word(reg)),
                Address::Double(reg) => i64::from(plc(&host).dword(reg)),
            })
        }),
        Local::SetPlcReg => binding(lua, spec, move |lua, args| {
            host.beat();
            let (address, value) = (reg_arg(lua, spec, &args, 0)?, int_arg(lua, spec, &args, 1)?);
            let out_of_range = || error_here(lua, format!("SetPlcReg: {value} does not fit (0x138F)"));
            match address {
                Address::Word(reg) if (-32768..=65535).contains(&value) => plc(&host).set_word(reg, value as u16),
                Address::Double(reg) => plc(&host).set_dword(reg, i32::try_from(value).map_err(|_| out_of_range())?),
                Address::Word(_) => return Err(out_of_range()),
            }
            Ok(0)
        }),
        Local::GetPlcRelay => binding(lua, spec, move |lua, args| {
            host.beat();
            Ok(plc(&host).relay(relay_arg(lua, spec, &args, 0)?))
        }),
        Local::SetPlcRelay => binding(lua, spec, move |lua, args| {
            host.beat();
            let (relay, on) = (relay_arg(lua, spec, &args, 0)?, bool_arg(lua, spec, &args, 1)?);
            plc(&host).set_relay(relay, on);
            Ok(0)
        }),
        _ => unreachable!("{} is not a FUN147 function", spec.name),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// docs/fun147.md: words, the DR/DD views, and what does not exist.
    #[test]
    fn addresses() {
        assert_eq!(address("R1000"), Some(Address::Word(Reg::R(1000))));
        assert_eq!(address("d4062"), Some(Address::Word(Reg::D(4062))));
        assert_eq!(address("DR1000"), Some(Address::Double(Reg::R(1000))));
        assert_eq!(address("DD100"), Some(Address::Double(Reg::D(100))));
        for bad in ["DR3839", "D4000", "R3840", "DD", "Q1", "", "DX1"] {
            assert_eq!(address(bad), None, "{bad}");
        }
    }
}

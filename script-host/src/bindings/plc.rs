//! The FUN147 local functions (docs/fun147.md): the PLC register image in the namespace's
//! shared memory, read and written in place, and the step table's text form.

use api::{FunctionSpec, LocalCall};
use calls::plc::SharedPlc;
use fun147::{Plc, Program, Reg, Relay, assemble, disassemble};
use mlua::{IntoLuaMulti, Lua, MultiValue};

use super::{Host, LuaArg, error_here};

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

fn register(lua: &Lua, spec: &FunctionSpec, text: &[u8]) -> mlua::Result<Address> {
    let text = String::from_utf8_lossy(text);
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

fn relay(lua: &Lua, spec: &FunctionSpec, text: &[u8]) -> mlua::Result<Relay> {
    let text = String::from_utf8_lossy(text);
    text.parse().map_err(|_| {
        error_here(lua, format!("{}: {text:?} is no relay X0-X255, Y0-Y255, M0-M2001, S0-S999", spec.name))
    })
}

fn plc(host: &Host) -> SharedPlc<'_> {
    SharedPlc(host.shared.plc())
}

/// The functions of `Local` that belong here.
pub fn call(lua: &Lua, host: &Host, call: LocalCall<'_, LuaArg>) -> mlua::Result<MultiValue> {
    let spec = call.func().spec();
    host.beat();
    match call {
        LocalCall::MHSPOLoad { sr, text } => {
            let Address::Word(sr) = register(lua, spec, &sr)? else {
                return Err(error_here(lua, "MHSPOLoad: SR is one register, not DR/DD"));
            };
            let program =
                assemble(&String::from_utf8_lossy(&text)).map_err(|e| error_here(lua, format!("MHSPOLoad: {e}")))?;
            program.write(&mut plc(host), sr).map_err(|e| error_here(lua, format!("MHSPOLoad: {e}")))?;
            0.into_lua_multi(lua)
        }
        LocalCall::MHSPOText { sr } => {
            let Address::Word(sr) = register(lua, spec, &sr)? else {
                return Err(error_here(lua, "MHSPOText: SR is one register, not DR/DD"));
            };
            let program = Program::read(&plc(host), sr).map_err(|e| error_here(lua, format!("MHSPOText: {e}")))?;
            disassemble(&program).into_lua_multi(lua)
        }
        LocalCall::GetPlcReg { addr } => match register(lua, spec, &addr)? {
            Address::Word(reg) => i64::from(plc(host).word(reg)),
            Address::Double(reg) => i64::from(plc(host).dword(reg)),
        }
        .into_lua_multi(lua),
        LocalCall::SetPlcReg { addr, value } => {
            let address = register(lua, spec, &addr)?;
            let out_of_range = || error_here(lua, format!("SetPlcReg: {value} does not fit (0x138F)"));
            match address {
                Address::Word(reg) if (-32768..=65535).contains(&value) => plc(host).set_word(reg, value as u16),
                Address::Double(reg) => plc(host).set_dword(reg, i32::try_from(value).map_err(|_| out_of_range())?),
                Address::Word(_) => return Err(out_of_range()),
            }
            0.into_lua_multi(lua)
        }
        LocalCall::GetPlcRelay { addr } => plc(host).relay(relay(lua, spec, &addr)?).into_lua_multi(lua),
        LocalCall::SetPlcRelay { addr, on } => {
            plc(host).set_relay(relay(lua, spec, &addr)?, on);
            0.into_lua_multi(lua)
        }
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

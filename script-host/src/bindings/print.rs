//! `Print`'s formatting of a call's Lua values (HMPL 2.20): each value as the `printf`
//! argument it stands for, a string as its bytes.

use api::FunctionSpec;
use ipc::output::{char_boundary, escape};
use mlua::{BorrowedBytes, Value};

use super::LuaArg;
use crate::printf::{self, Arg, Formatted};

/// `Print`'s formatting of `fmt` with `args`. A bad format is a warning on stderr (with
/// the format's start) and `Err`.
pub(super) fn format(spec: &FunctionSpec, fmt: &[u8], args: &[LuaArg]) -> Result<Formatted, ()> {
    let strings: Vec<Option<BorrowedBytes>> =
        args.iter().map(|a| if let Value::String(s) = &a.value { Some(s.as_bytes()) } else { None }).collect();
    let values: Vec<Arg> = args.iter().zip(&strings).map(|(a, s)| printf_arg(&a.value, s.as_deref())).collect();
    printf::format(fmt, &values).map_err(|e| {
        let shown = char_boundary(fmt, 60);
        let more = if shown < fmt.len() { "..." } else { "" };
        eprintln!("warning: {}(\"{}{more}\"): {e}", spec.name, escape(&fmt[..shown]));
    })
}

fn printf_arg<'a>(v: &Value, string: Option<&'a [u8]>) -> Arg<'a> {
    match (v, string) {
        (_, Some(bytes)) => Arg::Str(bytes),
        (Value::Integer(i), _) => Arg::Int(*i),
        (Value::Number(n), _) => Arg::Float(*n),
        (Value::Boolean(b), _) => Arg::Int(*b as i64),
        (other, _) => Arg::Str(other.type_name().as_bytes()),
    }
}

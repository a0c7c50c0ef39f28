//! What an HMPL ch. 22 client call returned a program on the simulation clock, as the
//! script process records it and the controller's record keeps it (`<cycle> client <task>
//! <function> <rc> [<value>]`, docs/replay.md).

use std::fmt;

use api::Local;

use crate::freeport::from_hex;

/// One client call's outcome.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClientOutcome {
    /// The client function called.
    pub function: Local,
    /// The call's first return value (0 or an HMPL system error code).
    pub rc: i64,
    /// The bytes a receive, read or write returned (empty for the others).
    pub value: Vec<u8>,
    /// The socket id a connect returned (0 for the others).
    pub socket: i64,
}

/// What a client function returns besides its code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Returns {
    /// A socket id (HMPL 22.2.3, 22.3.1).
    Socket,
    /// Bytes (HMPL 22.2.4, 22.3.3..22.3.8).
    Bytes,
    /// Nothing (HMPL 22.2.5, 22.2.6, 22.3.2).
    Nothing,
}

/// What `function` returns, `None` when it is not a ch. 22 client function.
pub fn returns(function: Local) -> Option<Returns> {
    use Local::*;
    Some(match function {
        ASCII_ClientConnect | Modbus_ClientConnect => Returns::Socket,
        ASCII_ClientRecv
        | Modbus_ClientRead_HoldReg
        | Modbus_ClientRead_InputReg
        | Modbus_ClientRead_Coils
        | Modbus_ClientRead_Inputs
        | Modbus_ClientWrite_HoldReg
        | Modbus_ClientWrite_Coils => Returns::Bytes,
        ASCII_ClientSend | ASCII_ClientDisconnect | Modbus_ClientDisconnect => Returns::Nothing,
        _ => return None,
    })
}

impl ClientOutcome {
    /// The words after `<task>` in a record line: the function's name, its code, then the
    /// socket id of a connect or the bytes in hex of a call that returns bytes (none: no
    /// bytes).
    pub fn parse(words: &[&str]) -> Option<ClientOutcome> {
        let (name, rc, rest) = match words {
            [name, rc, rest @ ..] => (*name, rc.parse().ok()?, rest),
            _ => return None,
        };
        let function = *Local::ALL.iter().find(|l| l.spec().name == name)?;
        let (value, socket) = match (returns(function)?, rest) {
            (Returns::Socket, [id]) => (Vec::new(), id.parse().ok()?),
            (Returns::Bytes, []) | (Returns::Nothing, []) => (Vec::new(), 0),
            (Returns::Bytes, [hex]) => (from_hex(hex)?, 0),
            _ => return None,
        };
        Some(ClientOutcome { function, rc, value, socket })
    }
}

impl fmt::Display for ClientOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.function.spec().name, self.rc)?;
        match returns(self.function) {
            Some(Returns::Socket) => write!(f, " {}", self.socket),
            Some(Returns::Bytes) if !self.value.is_empty() => {
                f.write_str(" ")?;
                self.value.iter().try_for_each(|b| write!(f, "{b:02x}"))
            }
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcomes_survive_their_text() {
        let outcome =
            |function, rc, value: &[u8], socket| ClientOutcome { function, rc, value: value.to_vec(), socket };
        for o in [
            outcome(Local::Modbus_ClientConnect, 0, b"", 1),
            outcome(Local::ASCII_ClientConnect, 6101, b"", 0),
            outcome(Local::Modbus_ClientRead_HoldReg, 0, &[0, 7, 0xff, 0], 0),
            outcome(Local::ASCII_ClientRecv, 6105, b"", 0),
            outcome(Local::ASCII_ClientSend, 0, b"", 0),
        ] {
            let text = o.to_string();
            assert_eq!(ClientOutcome::parse(&text.split(' ').collect::<Vec<_>>()), Some(o), "{text}");
        }
        for bad in [
            &["Modbus_ClientConnect", "0"][..],
            &["Modbus_ClientConnect", "0", "x"],
            &["ASCII_ClientSend", "0", "00"],
            &["ASCII_ClientRecv", "0", "6g"],
            &["ASCII_ClientRecv", "zero"],
            &["Sleep", "0"],
            &["NoSuchFunction", "0"],
            &[],
        ] {
            assert_eq!(ClientOutcome::parse(bad), None, "{bad:?}");
        }
    }
}

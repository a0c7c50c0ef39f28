//! One line of the Native ASCII server: an HMPL call `Name(arg, ...)` (HMPL 22.1; the
//! manual gives no grammar, docs/decisions.md "Native ASCII server"). Arguments are
//! integers (decimal, negative, `0x` hex), numbers (`1.5`, `-2e3`), strings in double
//! quotes (`\"` and `\\` inside), and the names scripts see as constants (`TRUE`,
//! `HMPL_AXIS_1`, `BM_BUFF`, error names). Whitespace anywhere between tokens and a
//! final `;` are allowed.

use std::collections::HashMap;
use std::sync::LazyLock;

use api::CommandCall;
use api::call::{Doubles, Sink, Value};
use api::constants::{CONSTANTS, Constant, error_ids, numbered};

/// The longest line the server reads, without its newline.
pub const MAX_LINE: usize = 256;

/// Why a line is not a call.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub(crate) enum ParseError {
    #[error("empty line")]
    Empty,
    #[error("not text: byte 0x{0:02X} at column {1}")]
    NotText(u8, usize),
    #[error("expected a function name at column {0}")]
    NoName(usize),
    #[error("expected '(' after {0}")]
    NoOpen(String),
    #[error("expected ',' or ')' at column {0}")]
    NoSeparator(usize),
    #[error("bad argument at column {0}: {1}")]
    BadArgument(usize, String),
    #[error("unterminated string at column {0}")]
    Unterminated(usize),
    #[error("unexpected text after ')' at column {0}")]
    Trailing(usize),
}

/// A call as a line names it: the function's name and its arguments as neutral values.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Call {
    pub name: String,
    pub args: Vec<Value>,
}

/// The constants a script sees, by name.
static NAMES: LazyLock<HashMap<String, Value>> = LazyLock::new(|| {
    let mut names = HashMap::new();
    for (name, value, _) in CONSTANTS {
        let value = match value {
            Constant::Int(i) => Value::Int(*i),
            Constant::Double(d) => Value::Double(*d),
            Constant::Str(s) => Value::Str(s.as_bytes().to_vec()),
        };
        names.insert(name.to_string(), value);
    }
    names.extend(error_ids().map(|(name, id)| (name.to_string(), Value::Int(id as i64))));
    names.extend(numbered().map(|(name, value)| (name, Value::Int(value))));
    names
});

/// Parses one line (without its newline; a final `\r` is ignored).
pub(crate) fn parse(line: &[u8]) -> Result<Call, ParseError> {
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    // Only printable ASCII and tabs: binary garbage is refused before anything else.
    if let Some(i) = line.iter().position(|&b| !(b == b'\t' || (0x20..0x7F).contains(&b))) {
        return Err(ParseError::NotText(line[i], i + 1));
    }
    let mut p = Parser { s: line, i: 0 };
    p.skip_space();
    if p.i == p.s.len() {
        return Err(ParseError::Empty);
    }
    let name = p.name().ok_or(ParseError::NoName(p.i + 1))?;
    p.skip_space();
    if !p.eat(b'(') {
        return Err(ParseError::NoOpen(name));
    }
    let mut args = Vec::new();
    p.skip_space();
    if !p.eat(b')') {
        loop {
            args.push(p.argument()?);
            p.skip_space();
            if p.eat(b')') {
                break;
            }
            if !p.eat(b',') {
                return Err(ParseError::NoSeparator(p.i + 1));
            }
        }
    }
    p.skip_space();
    p.eat(b';');
    p.skip_space();
    if p.i < p.s.len() {
        return Err(ParseError::Trailing(p.i + 1));
    }
    Ok(Call { name, args })
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn eat(&mut self, b: u8) -> bool {
        let hit = self.peek() == Some(b);
        self.i += hit as usize;
        hit
    }

    fn skip_space(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\t')) {
            self.i += 1;
        }
    }

    /// A name: a letter or `_`, then letters, digits, `_` and `.` (`FreePort.Eth.Tx`).
    fn name(&mut self) -> Option<String> {
        let start = self.i;
        if !self.peek().is_some_and(|b| b.is_ascii_alphabetic() || b == b'_') {
            return None;
        }
        while self.peek().is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'.') {
            self.i += 1;
        }
        Some(String::from_utf8_lossy(&self.s[start..self.i]).into_owned())
    }

    fn argument(&mut self) -> Result<Value, ParseError> {
        self.skip_space();
        let column = self.i + 1;
        match self.peek() {
            Some(b'"') => self.string(),
            Some(b) if b.is_ascii_alphabetic() || b == b'_' => {
                let name = self.name().expect("starts a name");
                NAMES.get(&name).cloned().ok_or_else(|| ParseError::BadArgument(column, format!("unknown name {name}")))
            }
            Some(_) => {
                let start = self.i;
                while self.peek().is_some_and(|b| !matches!(b, b',' | b')' | b' ' | b'\t')) {
                    self.i += 1;
                }
                let text = std::str::from_utf8(&self.s[start..self.i]).expect("checked ASCII");
                number(text).ok_or_else(|| ParseError::BadArgument(column, format!("{text:?} is not a number")))
            }
            None => Err(ParseError::BadArgument(column, "missing".into())),
        }
    }

    fn string(&mut self) -> Result<Value, ParseError> {
        let column = self.i + 1;
        self.i += 1;
        let mut text = Vec::new();
        loop {
            match self.peek() {
                None => return Err(ParseError::Unterminated(column)),
                Some(b'"') => {
                    self.i += 1;
                    return Ok(Value::Str(text));
                }
                Some(b'\\') if matches!(self.s.get(self.i + 1), Some(b'"' | b'\\')) => {
                    text.push(self.s[self.i + 1]);
                    self.i += 2;
                }
                Some(b) => {
                    text.push(b);
                    self.i += 1;
                }
            }
        }
    }
}

/// The line a typed command is, as a client would send it (`MoveRel(0, 5.0)`): a number
/// with its point, a string quoted; tables, which no line holds, in braces.
pub fn text(call: &CommandCall) -> String {
    let mut args = Text(Vec::new());
    let Ok(()) = call.write(&mut args);
    format!("{}({})", call.func().spec().name, args.0.join(", "))
}

/// The arguments of a call as the line's text, one after the other.
struct Text(Vec<String>);

impl Sink for Text {
    type Error = std::convert::Infallible;

    fn int(&mut self, value: i64) -> Result<(), Self::Error> {
        self.0.push(value.to_string());
        Ok(())
    }

    fn double(&mut self, value: f64) -> Result<(), Self::Error> {
        self.0.push(format!("{value:?}"));
        Ok(())
    }

    fn bool(&mut self, value: bool) -> Result<(), Self::Error> {
        self.0.push(if value { "TRUE" } else { "FALSE" }.to_string());
        Ok(())
    }

    fn str(&mut self, value: &[u8]) -> Result<(), Self::Error> {
        let text = String::from_utf8_lossy(value).replace('\\', "\\\\").replace('"', "\\\"");
        self.0.push(format!("\"{text}\""));
        Ok(())
    }

    fn bytes(&mut self, value: &[u8]) -> Result<(), Self::Error> {
        self.0.push(format!("{{{}}}", value.iter().map(u8::to_string).collect::<Vec<_>>().join(", ")));
        Ok(())
    }

    fn doubles(&mut self, value: &Doubles) -> Result<(), Self::Error> {
        self.0.push(format!("{{{}}}", value.iter().map(|n| format!("{n:?}")).collect::<Vec<_>>().join(", ")));
        Ok(())
    }
}

/// An integer (decimal or `0x` hex, with a sign) or a finite number.
fn number(text: &str) -> Option<Value> {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let hex = digits.strip_prefix("0x").or_else(|| digits.strip_prefix("0X"));
    if let Some(hex) = hex {
        // Digits only: `from_str_radix` would take a second sign ("-0x-8000000000000000").
        if !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        let n = i64::from_str_radix(hex, 16).ok()?;
        return Some(Value::Int(if negative { -n } else { n }));
    }
    if !digits.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
        return None;
    }
    if let Ok(n) = text.parse::<i64>() {
        return Some(Value::Int(n));
    }
    text.parse::<f64>().ok().filter(|n| n.is_finite()).map(Value::Double)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn call(name: &str, args: Vec<Value>) -> Result<Call, ParseError> {
        Ok(Call { name: name.into(), args })
    }

    /// A typed command's text is the line of that call: it parses back to its values.
    #[test]
    fn typed_commands_as_lines() {
        let jog = CommandCall::MoveRel { axis_id: 0, rel_dist: 5.0 };
        assert_eq!(text(&jog), "MoveRel(0, 5.0)");
        assert_eq!(parse(text(&jog).as_bytes()), call("MoveRel", vec![Value::Int(0), Value::Double(5.0)]));
        let task = CommandCall::StartTaskFunc { task_id: 1, func_name: br#"a"b\c"#[..].into() };
        assert_eq!(
            parse(text(&task).as_bytes()),
            call("StartTaskFunc", vec![Value::Int(1), Value::Str(br#"a"b\c"#.to_vec())])
        );
    }

    #[test]
    fn calls_parse() {
        assert_eq!(parse(b"MoveAbs(0, 100)"), call("MoveAbs", vec![Value::Int(0), Value::Int(100)]));
        assert_eq!(parse(b"  GetPosFb ( 1 ) ;\r"), call("GetPosFb", vec![Value::Int(1)]));
        assert_eq!(parse(b"GetAxisNum()"), call("GetAxisNum", vec![]));
        assert_eq!(parse(b"SetVel(0x1F,-2.5e1)"), call("SetVel", vec![Value::Int(31), Value::Double(-25.0)]));
        assert_eq!(parse(b"MoveRel(0,-3)"), call("MoveRel", vec![Value::Int(0), Value::Int(-3)]));
        assert_eq!(parse(b"MoveAbs(0, .5)"), call("MoveAbs", vec![Value::Int(0), Value::Double(0.5)]));
        assert_eq!(
            parse(br#"StartTaskFunc(1, "Fo\"o, )")"#),
            call("StartTaskFunc", vec![Value::Int(1), Value::Str(b"Fo\"o, )".to_vec())])
        );
        assert_eq!(parse(b"Enable(HMPL_AXIS_2);"), call("Enable", vec![Value::Int(2)]));
        assert_eq!(parse(b"SetGPO(3, TRUE)"), call("SetGPO", vec![Value::Int(3), Value::Int(1)]));
        assert_eq!(parse(b"FreePort.Eth.CloseAll()"), call("FreePort.Eth.CloseAll", vec![]));
    }

    #[test]
    fn bad_lines_say_why() {
        assert_eq!(parse(b""), Err(ParseError::Empty));
        assert_eq!(parse(b"  \r"), Err(ParseError::Empty));
        assert_eq!(parse(b"\x00\xFF\x13garbage"), Err(ParseError::NotText(0, 1)));
        assert_eq!(parse(b"Enable(0)\x1B[A"), Err(ParseError::NotText(0x1B, 10)));
        assert_eq!(parse("Énable(0)".as_bytes()), Err(ParseError::NotText(0xC3, 1)));
        assert_eq!(parse(b"42(0)"), Err(ParseError::NoName(1)));
        assert_eq!(parse(b"Enable 0"), Err(ParseError::NoOpen("Enable".into())));
        assert_eq!(parse(b"Enable(0"), Err(ParseError::NoSeparator(9)));
        assert_eq!(parse(b"MoveAbs(0 1)"), Err(ParseError::NoSeparator(11)));
        assert_eq!(parse(b"MoveAbs(0,)"), Err(ParseError::BadArgument(11, "\"\" is not a number".into())));
        assert_eq!(parse(b"MoveAbs(0, 1e999)"), Err(ParseError::BadArgument(12, "\"1e999\" is not a number".into())));
        assert_eq!(parse(b"MoveAbs(0, nan)"), Err(ParseError::BadArgument(12, "unknown name nan".into())));
        assert_eq!(parse(b"MoveAbs(0, inf)"), Err(ParseError::BadArgument(12, "unknown name inf".into())));
        assert_eq!(parse(b"MoveAbs(0, 0x)"), Err(ParseError::BadArgument(12, "\"0x\" is not a number".into())));
        assert_eq!(parse(b"MoveAbs(0, AXIS)"), Err(ParseError::BadArgument(12, "unknown name AXIS".into())));
        assert_eq!(parse(br#"StartTaskFunc(1, "main)"#), Err(ParseError::Unterminated(18)));
        assert_eq!(parse(b"Enable(0) Enable(1)"), Err(ParseError::Trailing(11)));
        assert_eq!(parse(b"Enable(0);;"), Err(ParseError::Trailing(11)));
    }

    /// Found while writing the property tests below, kept as rows.
    #[test]
    fn regressions() {
        // A second sign after 0x: from_str_radix took it, and -i64::MIN overflowed.
        let bad = |column, text: &str| Err(ParseError::BadArgument(column, format!("{text:?} is not a number")));
        assert_eq!(parse(b"Enable(-0x-8000000000000000)"), bad(8, "-0x-8000000000000000"));
        assert_eq!(parse(b"Enable(0x-5)"), bad(8, "0x-5"));
        assert_eq!(parse(b"Enable(0x+5)"), bad(8, "0x+5"));
        assert_eq!(parse(b"Enable(-0x7FFFFFFFFFFFFFFF)"), call("Enable", vec![Value::Int(-i64::MAX)]));
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        /// A line as a client might type it, with the call it stands for.
        #[derive(Clone, Debug)]
        struct Typed {
            text: String,
            call: Call,
        }

        fn name() -> impl Strategy<Value = String> {
            let registry: Vec<String> = api::registry::all().map(|s| s.name.to_string()).collect();
            prop_oneof![proptest::sample::select(registry), "[A-Za-z_][A-Za-z0-9_.]{0,12}"]
        }

        /// One argument as text and as the value it stands for.
        fn argument() -> impl Strategy<Value = (String, Value)> {
            let constants: Vec<(String, Value)> = NAMES.iter().map(|(n, v)| (n.clone(), v.clone())).collect();
            prop_oneof![
                any::<i64>().prop_map(|n| (n.to_string(), Value::Int(n))),
                (0..=i64::MAX).prop_map(|n| (format!("0x{n:X}"), Value::Int(n))),
                (1..=i64::MAX).prop_map(|n| (format!("-0x{n:x}"), Value::Int(-n))),
                any::<f64>()
                    .prop_filter("finite", |d| d.is_finite())
                    .prop_map(|d| (format!("{d:?}"), Value::Double(d))),
                "[ -~]{0,20}".prop_map(|s| {
                    let quoted = s.replace('\\', "\\\\").replace('"', "\\\"");
                    (format!("\"{quoted}\""), Value::Str(s.into_bytes()))
                }),
                proptest::sample::select(constants),
            ]
        }

        fn space() -> impl Strategy<Value = String> {
            "[ \t]{0,2}"
        }

        fn typed() -> impl Strategy<Value = Typed> {
            (name(), proptest::collection::vec((argument(), space(), space()), 0..6), space(), any::<bool>()).prop_map(
                |(name, args, pad, semicolon)| {
                    let texts: Vec<String> = args.iter().map(|((t, _), a, b)| format!("{a}{t}{b}")).collect();
                    let text =
                        format!("{pad}{name}{pad}({}){}{pad}\r", texts.join(","), if semicolon { ";" } else { "" });
                    Typed { text, call: Call { name, args: args.into_iter().map(|((_, v), _, _)| v).collect() } }
                },
            )
        }

        /// An error is one line that says where, within the line.
        fn says_why(line: &[u8], error: &ParseError) {
            let text = error.to_string();
            assert!(!text.is_empty() && !text.contains(['\n', '\r']), "{text:?}");
            let column = match error {
                ParseError::NotText(_, c)
                | ParseError::NoName(c)
                | ParseError::NoSeparator(c)
                | ParseError::BadArgument(c, _)
                | ParseError::Unterminated(c)
                | ParseError::Trailing(c) => *c,
                ParseError::Empty | ParseError::NoOpen(_) => 1,
            };
            assert!((1..=line.len() + 1).contains(&column), "column {column} of {} bytes: {text}", line.len());
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(10_000))]

            /// Random bytes: a call or a clear error, never a panic.
            #[test]
            fn random_bytes_are_a_call_or_a_clear_error(line in proptest::collection::vec(any::<u8>(), 0..300)) {
                if let Err(e) = parse(&line) {
                    says_why(&line, &e);
                }
            }

            /// Well-formed lines give the call they were made from.
            #[test]
            fn typed_lines_give_their_call(typed in typed()) {
                prop_assert_eq!(parse(typed.text.as_bytes()), Ok(typed.call));
            }

            /// Near-valid lines, one byte changed, cut or added: a call or a clear error.
            #[test]
            fn near_valid_lines_are_a_call_or_a_clear_error(
                typed in typed(),
                at in any::<prop::sample::Index>(),
                byte in any::<u8>(),
                edit in 0..3u8,
            ) {
                let mut line = typed.text.into_bytes();
                let i = at.index(line.len() + 1);
                match edit {
                    0 if i < line.len() => line[i] = byte,
                    1 => line.truncate(i),
                    _ => line.insert(i, byte),
                }
                if let Err(e) = parse(&line) {
                    says_why(&line, &e);
                }
            }
        }
    }
}

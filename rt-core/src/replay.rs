//! What the outside world feeds a run on the simulation clock, stamped with the cycle it
//! takes effect at (`luamotion run --clock sim --record FILE`, `--replay FILE`; the format
//! in docs/replay.md, the choices in docs/decisions.md, "Simulation clock").
//!
//! An input lands at a cycle boundary: a Modbus write of a DV, DH or FUN147 word (queued
//! by the register console) or a simulated input (a controller input's level, an analog
//! terminal's input word, set by the web view) is applied by the lockstep gate at the start of cycle k,
//! before the cycle and before any task's turn after it; bytes serial port 1 receives are
//! stamped with the cycle they take effect at, and a task's `FreePort.Serial.Rx` after
//! cycle c returns only bytes stamped <= c. So the record says exactly what each turn saw,
//! and a replay that feeds the same inputs at the same cycles gives the same trace.
//! Real-time mode never comes here.

use std::collections::VecDeque;
use std::fmt::Write as _;
use std::io::{BufRead, Read};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use calls::clients::ClientOutcome;
use calls::freeport::EthEvent;
use crossbeam::queue::ArrayQueue;
use schema::shared::SharedData;
use schema::{GPIO_PINS, MAX_ANALOG_CHANNELS, MAX_TASKS};

/// The first line of a record file; the number is the format's version.
pub const HEADER: &str = "luamotion-inputs 1";
/// Longest line a record file may have (a serial chunk of 4096 bytes in hex fits).
pub const MAX_LINE: usize = 16 * 1024;
/// Modbus writes and simulated inputs in flight between the servers and the next cycle.
const QUEUE: usize = 4096;

/// One input from outside.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Input {
    /// A Modbus write of one word of DV, DH (DXMC A.1) or the FUN147 image, by address.
    Modbus {
        /// The word's Modbus address.
        address: u16,
        /// The word written.
        value: u16,
    },
    /// Bytes serial port 1 received from its peer (after the line's settings were checked).
    Serial(Vec<u8>),
    /// The electrical level of controller input `pin` (1..8), as `SimSetGPI` sets it.
    Gpi {
        /// 1..8.
        pin: u8,
        /// High.
        on: bool,
    },
    /// The level of input `pin` of the digital I/O terminal at slave `slave` (HMPL 9.5),
    /// as `SimSetSlvGPI` sets it.
    SlvGpi {
        /// The terminal's slave position.
        slave: u16,
        /// The terminal's input, from 1.
        pin: u16,
        /// High.
        on: bool,
    },
    /// The word on input `channel` (1..4) of the analog terminal at slave `slave`, as
    /// `SimSetSlvAIRaw` sets it.
    Ai {
        /// The terminal's slave position.
        slave: u16,
        /// 1..4.
        channel: u8,
        /// The raw word, as the terminal's ADC gives it.
        raw: u16,
    },
    /// What a `FreePort.Eth` session of task `task` got from its socket (the task records
    /// it and replays it itself; the record keeps it).
    Eth {
        /// The task whose session it is.
        task: u8,
        /// The session's handle, as `FreePort.Eth` returned it.
        session: i64,
        /// What the socket gave.
        event: EthEvent,
    },
    /// What an HMPL ch. 22 client call of task `task` returned (the task records it and
    /// replays it itself).
    Client {
        /// The task that called.
        task: u8,
        /// What the call returned.
        outcome: ClientOutcome,
    },
}

impl Input {
    /// An input a simulator command sets (`SimSetGPI`, `SimSetSlvGPI`, `SimSetSlvAIRaw`),
    /// which the lockstep gate applies with that command's code.
    pub fn is_simulated(&self) -> bool {
        matches!(self, Input::Gpi { .. } | Input::SlvGpi { .. } | Input::Ai { .. })
    }
}

/// An input and the cycle it takes effect at.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stamped {
    /// The cycle it takes effect at.
    pub cycle: u64,
    /// The input.
    pub input: Input,
}

/// A record file that cannot be replayed; `line` counts from 1.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The file could not be read: its path and the OS's error.
    #[error("cannot read {0}: {1}")]
    Io(String, std::io::Error),
    /// A line is not a record.
    #[error("line {line}: {what}")]
    Line {
        /// The line's number, from 1.
        line: usize,
        /// What is wrong with it.
        what: String,
    },
}

/// Whether `address` is a word an outside Modbus write of data reaches (DV, DH, FUN147).
pub fn is_data_word(address: u16) -> bool {
    calls::user_area::UserArea::of(address.into()).is_some() || calls::plc::PlcWord::at(address).is_some()
}

/// Writes a DV, DH or FUN147 word by Modbus address; false for any other address.
pub fn write_word(shared: &SharedData, address: u16, value: u16) -> bool {
    calls::user_area::write(shared, address.into(), value) || calls::plc::write(shared.plc(), address, value)
}

/// Reads a record file: its header, then one input a line in the order of their cycles.
pub fn read(path: &Path) -> Result<Vec<Stamped>, RecordError> {
    let io = |e| RecordError::Io(path.display().to_string(), e);
    parse(std::io::BufReader::new(std::fs::File::open(path).map_err(io)?)).map_err(|e| match e {
        RecordError::Io(_, e) => io(e),
        other => other,
    })
}

/// Parses a record; a line longer than `MAX_LINE` is refused without being read whole.
pub fn parse(mut reader: impl BufRead) -> Result<Vec<Stamped>, RecordError> {
    let mut inputs: Vec<Stamped> = Vec::new();
    let mut buf = Vec::new();
    for line in 1.. {
        buf.clear();
        let n = reader
            .by_ref()
            .take(MAX_LINE as u64 + 1)
            .read_until(b'\n', &mut buf)
            .map_err(|e| RecordError::Io(String::new(), e))?;
        if n == 0 {
            if line == 1 {
                return Err(RecordError::Line { line, what: format!("empty; a record starts with `{HEADER}`") });
            }
            break;
        }
        let bad = |what: String| RecordError::Line { line, what };
        if buf.len() > MAX_LINE {
            return Err(bad(format!("longer than {MAX_LINE} bytes")));
        }
        let text = std::str::from_utf8(&buf).map(|t| t.trim_end_matches(['\n', '\r']));
        if line == 1 {
            if text != Ok(HEADER) {
                return Err(bad(format!("not a luamotion input record: the first line must be `{HEADER}`")));
            }
            continue;
        }
        let text = text.map_err(|_| bad("not UTF-8 text".into()))?;
        // Blank lines (spaces included) and comments are no inputs.
        if text.trim().is_empty() || text.starts_with('#') {
            continue;
        }
        let stamped = parse_input(text).map_err(bad)?;
        if let Some(last) = inputs.last()
            && stamped.cycle < last.cycle
        {
            return Err(bad(format!(
                "cycle {} comes after cycle {}: inputs must be in cycle order",
                stamped.cycle, last.cycle
            )));
        }
        inputs.push(stamped);
    }
    Ok(inputs)
}

/// `<cycle> modbus <address> <value>`, `<cycle> serial <hex bytes>`, `<cycle> gpi <pin>
/// <0|1>` or `<cycle> ai <slave> <channel> <word>`.
fn parse_input(text: &str) -> Result<Stamped, String> {
    let words: Vec<&str> = text.split_ascii_whitespace().collect();
    let first = words.first().ok_or("a line of white space only")?;
    let cycle = first.parse::<u64>().map_err(|_| format!("`{first}` is not a cycle number"))?;
    if cycle == 0 {
        return Err("cycle 0: the first cycle is 1".into());
    }
    let input = match words.get(1..).unwrap_or_default() {
        ["modbus", address, value] => {
            let address = address
                .strip_prefix("0x")
                .and_then(|hex| u16::from_str_radix(hex, 16).ok())
                .ok_or_else(|| format!("`{address}` is not a Modbus address (0x0000..0xFFFF)"))?;
            if !is_data_word(address) {
                return Err(format!("0x{address:04X} is not a DV, DH or FUN147 word"));
            }
            let value = value.parse::<u16>().map_err(|_| format!("`{value}` is not a word (0..65535)"))?;
            Input::Modbus { address, value }
        }
        ["serial", hex] => {
            Input::Serial(calls::freeport::from_hex(hex).ok_or_else(|| format!("`{hex}` is not bytes in hex"))?)
        }
        ["gpi", pin, level] => Input::Gpi {
            pin: number(pin, 1..=GPIO_PINS as u64, "a controller input (1..8)")? as u8,
            on: number(level, 0..=1, "a level (0 or 1)")? == 1,
        },
        ["slvgpi", slave, pin, level] => Input::SlvGpi {
            slave: number(slave, 0..=u16::MAX.into(), "a slave (0..65535)")? as u16,
            pin: number(pin, 1..=u16::MAX.into(), "a terminal input (1..)")? as u16,
            on: number(level, 0..=1, "a level (0 or 1)")? == 1,
        },
        ["ai", slave, channel, raw] => Input::Ai {
            slave: number(slave, 0..=u16::MAX.into(), "a slave (0..65535)")? as u16,
            channel: number(channel, 1..=MAX_ANALOG_CHANNELS as u64, "an analog input (1..4)")? as u8,
            raw: number(raw, 0..=u16::MAX.into(), "a word (0..65535)")? as u16,
        },
        ["eth", task, session, event @ ..] if !event.is_empty() => Input::Eth {
            task: number(task, 0..=MAX_TASKS as u64 - 1, "a task (0..63)")? as u8,
            session: session.parse().map_err(|_| format!("`{session}` is not a session id"))?,
            event: EthEvent::parse(event)
                .ok_or_else(|| format!("`{}` is not connect, refused, data <hex> or end", event.join(" ")))?,
        },
        ["client", task, outcome @ ..] if !outcome.is_empty() => Input::Client {
            task: number(task, 0..=MAX_TASKS as u64 - 1, "a task (0..63)")? as u8,
            outcome: ClientOutcome::parse(outcome).ok_or_else(|| {
                format!("`{}` is not a ch. 22 client function, its code and what it returned", outcome.join(" "))
            })?,
        },
        [kind, ..] if !matches!(*kind, "modbus" | "serial" | "gpi" | "slvgpi" | "ai" | "eth" | "client") => {
            return Err(format!("unknown input `{kind}` (known: modbus, serial, gpi, slvgpi, ai, eth, client)"));
        }
        [kind, ..] => {
            let takes = match *kind {
                "modbus" => "an address and a value",
                "serial" => "its bytes in hex",
                "gpi" => "a pin and a level",
                "slvgpi" => "a slave, a pin and a level",
                "eth" => "a task, a session and an event",
                "client" => "a task, a function, its code and what it returned",
                _ => "a slave, a channel and a word",
            };
            return Err(format!("`{kind}` takes {takes}"));
        }
        [] => return Err("a cycle without an input".into()),
    };
    Ok(Stamped { cycle, input })
}

/// A decimal number in `range`, or what it should have been.
fn number(text: &str, range: std::ops::RangeInclusive<u64>, what: &str) -> Result<u64, String> {
    text.parse::<u64>().ok().filter(|n| range.contains(n)).ok_or_else(|| format!("`{text}` is not {what}"))
}

/// The record's text: the header, then the inputs in cycle order.
pub fn format(inputs: &[Stamped]) -> String {
    let mut out = format!("{HEADER}\n");
    for Stamped { cycle, input } in inputs {
        let _ = match input {
            Input::Modbus { address, value } => writeln!(out, "{cycle} modbus 0x{address:04X} {value}"),
            Input::Serial(bytes) => {
                let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
                writeln!(out, "{cycle} serial {hex}")
            }
            Input::Gpi { pin, on } => writeln!(out, "{cycle} gpi {pin} {}", u8::from(*on)),
            Input::SlvGpi { slave, pin, on } => writeln!(out, "{cycle} slvgpi {slave} {pin} {}", u8::from(*on)),
            Input::Ai { slave, channel, raw } => writeln!(out, "{cycle} ai {slave} {channel} {raw}"),
            Input::Eth { task, session, event } => writeln!(out, "{cycle} eth {task} {session} {event}"),
            Input::Client { task, outcome } => writeln!(out, "{cycle} client {task} {outcome}"),
        };
    }
    out
}

/// What the run's outside inputs share: the cycle an input arriving now takes effect at,
/// the servers' queued inputs (Modbus writes, simulated inputs, in the order they came)
/// and, with `--record`, the record.
pub struct Inputs {
    landing: Arc<AtomicU64>,
    queue: ArrayQueue<Input>,
    record: Option<Mutex<Vec<Stamped>>>,
    /// Replaying: the outside peers' inputs are dropped, the record's fed instead.
    replaying: bool,
}

impl Inputs {
    /// `record`: keep every input for `take_record`; `replaying`: ignore the peers.
    pub fn new(record: bool, replaying: bool) -> Arc<Self> {
        Arc::new(Inputs {
            landing: Arc::new(AtomicU64::new(1)),
            queue: ArrayQueue::new(QUEUE),
            record: record.then(|| Mutex::new(Vec::new())),
            replaying,
        })
    }

    /// The cycle an input arriving now takes effect at (serial port 1 stamps its bytes so).
    pub fn landing(&self) -> Arc<AtomicU64> {
        self.landing.clone()
    }

    /// The inputs come from a record file (`run --replay`), not from outside.
    pub fn replaying(&self) -> bool {
        self.replaying
    }

    /// A Modbus write from outside, applied at the start of the next cycle; false when the
    /// queue is full or a replay ignores outside writes.
    pub fn modbus_write(&self, address: u16, value: u16) -> bool {
        !self.replaying && self.queue.push(Input::Modbus { address, value }).is_ok()
    }

    /// A simulated input set from outside (`Input::is_simulated`), applied at the start of
    /// the next cycle; false when the queue is full or a replay ignores outside inputs.
    pub fn sim_input(&self, input: Input) -> bool {
        debug_assert!(input.is_simulated());
        !self.replaying && self.queue.push(input).is_ok()
    }

    /// Keeps an input for the record (nothing without `--record`).
    pub fn record(&self, cycle: u64, input: Input) {
        if let Some(record) = &self.record {
            record.lock().unwrap_or_else(|e| e.into_inner()).push(Stamped { cycle, input });
        }
    }

    /// The record so far, in cycle order (inputs of one cycle in the order they came).
    pub fn take_record(&self) -> Vec<Stamped> {
        let mut inputs = self
            .record
            .as_ref()
            .map(|r| std::mem::take(&mut *r.lock().unwrap_or_else(|e| e.into_inner())))
            .unwrap_or_default();
        inputs.sort_by_key(|s| s.cycle);
        inputs
    }
}

/// The lockstep gate's part: the Modbus writes and simulated inputs, queued or replayed,
/// applied at the start of their cycle.
pub struct Feed {
    inputs: Arc<Inputs>,
    replay: VecDeque<Stamped>,
}

impl Feed {
    /// `replay`: the record's inputs (its serial bytes go to serial port 1, not here).
    pub fn new(inputs: Arc<Inputs>, replay: &[Stamped]) -> Self {
        // Serial port 1 and the tasks feed theirs.
        let replay = replay
            .iter()
            .filter(|s| !matches!(s.input, Input::Serial(_) | Input::Eth { .. } | Input::Client { .. }))
            .cloned()
            .collect();
        Feed { inputs, replay }
    }

    /// Before cycle `cycle`: applies its inputs, a simulated one with `simulate` (false: the
    /// machine lacks that input, and it is not recorded); from now on, arrivals land at the
    /// next cycle.
    pub fn begin(&mut self, cycle: u64, shared: &SharedData, mut simulate: impl FnMut(&Input) -> bool) {
        let mut apply = |input: Input| {
            let applied = match input {
                Input::Modbus { address, value } => write_word(shared, address, value),
                _ if input.is_simulated() => simulate(&input),
                _ => false,
            };
            if applied {
                self.inputs.record(cycle, input);
            } else {
                tracing::warn!(cycle, ?input, "an outside input the machine has no place for: dropped");
            }
        };
        while self.replay.front().is_some_and(|s| s.cycle <= cycle) {
            apply(self.replay.pop_front().expect("front").input);
        }
        while let Some(input) = self.inputs.queue.pop() {
            apply(input);
        }
        self.inputs.landing.store(cycle + 1, Ordering::Release);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(text: impl AsRef<[u8]>) -> Result<Vec<Stamped>, String> {
        parse(text.as_ref()).map_err(|e| e.to_string())
    }

    #[test]
    fn a_record_survives_its_text() {
        let inputs = vec![
            Stamped { cycle: 3, input: Input::Modbus { address: 0x0000, value: 7 } },
            Stamped { cycle: 3, input: Input::Serial(b"hi;\x00\xff".to_vec()) },
            Stamped { cycle: 90, input: Input::Modbus { address: 0x8001, value: 65535 } },
            Stamped { cycle: 91, input: Input::Modbus { address: 0x3000, value: 1 } },
            Stamped { cycle: 91, input: Input::Gpi { pin: 8, on: true } },
            Stamped { cycle: 92, input: Input::Gpi { pin: 1, on: false } },
            Stamped { cycle: 92, input: Input::Ai { slave: 4, channel: 2, raw: 65535 } },
            Stamped { cycle: 92, input: Input::SlvGpi { slave: 5, pin: 16, on: true } },
            Stamped { cycle: 93, input: Input::Eth { task: 63, session: -2, event: EthEvent::Data(b"ok".to_vec()) } },
            Stamped { cycle: 93, input: Input::Eth { task: 0, session: 1, event: EthEvent::End } },
            Stamped {
                cycle: 94,
                input: Input::Client {
                    task: 2,
                    outcome: ClientOutcome {
                        function: api::Local::ASCII_ClientRecv,
                        rc: 0,
                        value: b"ok".to_vec(),
                        socket: 0,
                    },
                },
            },
        ];
        let text = format(&inputs);
        assert!(text.starts_with("luamotion-inputs 1\n3 modbus 0x0000 7\n3 serial 68693b00ff\n"), "{text}");
        assert!(
            text.ends_with(
                "\n92 ai 4 2 65535\n92 slvgpi 5 16 1\n93 eth 63 -2 data 6f6b\n93 eth 0 1 end\n94 client 2 ASCII_ClientRecv 0 6f6b\n"
            ),
            "{text}"
        );
        assert_eq!(parsed(&text).unwrap(), inputs);
        assert_eq!(parsed("luamotion-inputs 1\n# a comment\n\n5 modbus 0x0001 2\r\n").unwrap().len(), 1);
        // Found by tests/replay_fuzz.rs: a line of white space panicked (its first word was
        // read without looking); it is blank, as an empty line.
        assert_eq!(parsed("luamotion-inputs 1\n \n\t\r\n5 modbus 0x0001 2\n\x0c\n").unwrap().len(), 1);
    }

    /// Each bad record is told with its line and what is wrong with it.
    #[test]
    fn bad_records_are_told_by_line() {
        let cases = [
            ("", "line 1: empty"),
            ("\u{7f}ELF\x02\x01\x01", "line 1: not a luamotion input record"),
            ("luamotion-inputs 2\n", "line 1: not a luamotion input record"),
            ("luamotion-inputs 1\n5 modbus 0x0000 1\n4 modbus 0x0000 2\n", "line 3: cycle 4 comes after cycle 5"),
            (
                "luamotion-inputs 1\n5 do 3 1\n",
                "line 2: unknown input `do` (known: modbus, serial, gpi, slvgpi, ai, eth, client)",
            ),
            ("luamotion-inputs 1\n5 client 64 ASCII_ClientSend 0\n", "line 2: `64` is not a task (0..63)"),
            ("luamotion-inputs 1\n5 client 0 Sleep 0\n", "line 2: `Sleep 0` is not a ch. 22 client function"),
            ("luamotion-inputs 1\n5 client 0 ASCII_ClientRecv 0 6g\n", "line 2: `ASCII_ClientRecv 0 6g` is not"),
            ("luamotion-inputs 1\n5 client 0\n", "line 2: `client` takes a task, a function"),
            ("luamotion-inputs 1\n5 eth 64 1 end\n", "line 2: `64` is not a task (0..63)"),
            ("luamotion-inputs 1\n5 eth 0 x end\n", "line 2: `x` is not a session id"),
            ("luamotion-inputs 1\n5 eth 0 1 data 6g\n", "line 2: `data 6g` is not connect, refused, data <hex>"),
            ("luamotion-inputs 1\n5 eth 0 1 open\n", "line 2: `open` is not connect"),
            ("luamotion-inputs 1\n5 eth 0 1\n", "line 2: `eth` takes a task, a session and an event"),
            ("luamotion-inputs 1\n5 gpi 9 1\n", "line 2: `9` is not a controller input (1..8)"),
            ("luamotion-inputs 1\n5 gpi 0 1\n", "line 2: `0` is not a controller input"),
            ("luamotion-inputs 1\n5 gpi 1 2\n", "line 2: `2` is not a level (0 or 1)"),
            ("luamotion-inputs 1\n5 gpi -1 1\n", "line 2: `-1` is not a controller input"),
            ("luamotion-inputs 1\n5 gpi 1\n", "line 2: `gpi` takes a pin and a level"),
            ("luamotion-inputs 1\n5 slvgpi 1 0 1\n", "line 2: `0` is not a terminal input (1..)"),
            ("luamotion-inputs 1\n5 slvgpi 1 2 2\n", "line 2: `2` is not a level (0 or 1)"),
            ("luamotion-inputs 1\n5 slvgpi 70000 1 1\n", "line 2: `70000` is not a slave"),
            ("luamotion-inputs 1\n5 slvgpi 1 1\n", "line 2: `slvgpi` takes a slave, a pin and a level"),
            ("luamotion-inputs 1\n5 ai 1 5 0\n", "line 2: `5` is not an analog input (1..4)"),
            ("luamotion-inputs 1\n5 ai 1 1 65536\n", "line 2: `65536` is not a word (0..65535)"),
            ("luamotion-inputs 1\n5 ai 70000 1 1\n", "line 2: `70000` is not a slave"),
            ("luamotion-inputs 1\n5 ai 1 0x10 1\n", "line 2: `0x10` is not an analog input"),
            ("luamotion-inputs 1\n5 ai 1 1 1 1\n", "line 2: `ai` takes a slave, a channel and a word"),
            ("luamotion-inputs 1\nfive modbus 0x0000 1\n", "line 2: `five` is not a cycle number"),
            ("luamotion-inputs 1\n0 modbus 0x0000 1\n", "line 2: cycle 0"),
            ("luamotion-inputs 1\n1 modbus 0x6B10 1\n", "line 2: 0x6B10 is not a DV, DH or FUN147 word"),
            ("luamotion-inputs 1\n1 modbus 16 1\n", "line 2: `16` is not a Modbus address"),
            ("luamotion-inputs 1\n1 modbus 0x0000 70000\n", "line 2: `70000` is not a word"),
            ("luamotion-inputs 1\n1 modbus 0x0000\n", "line 2: `modbus` takes an address and a value"),
            ("luamotion-inputs 1\n1 serial 6g\n", "line 2: `6g` is not bytes in hex"),
            ("luamotion-inputs 1\n1 serial abc\n", "line 2: `abc` is not bytes in hex"),
            ("luamotion-inputs 1\n1\n", "line 2: a cycle without an input"),
        ];
        for (text, expected) in cases {
            let error = parsed(text).expect_err(text);
            assert!(error.starts_with(expected), "{text:?}: {error}");
        }
        assert!(parsed(b"luamotion-inputs 1\n1 serial \xff\n").unwrap_err().starts_with("line 2: not UTF-8"));
        let huge = format!("luamotion-inputs 1\n1 serial {}\n", "ab".repeat(MAX_LINE));
        assert_eq!(parsed(&huge).unwrap_err(), format!("line 2: longer than {MAX_LINE} bytes"));
    }

    /// Queued writes land at the cycle they are applied at, replayed ones at theirs, and
    /// both go into the record with that cycle.
    #[test]
    fn writes_land_at_cycle_boundaries() {
        let shared: Box<SharedData> = schema::layout::zeroed();
        let inputs = Inputs::new(true, false);
        let replay = [
            Stamped { cycle: 2, input: Input::Modbus { address: 0x0001, value: 11 } },
            Stamped { cycle: 2, input: Input::Serial(vec![1]) },
        ];
        let mut feed = Feed::new(inputs.clone(), &replay);
        assert!(inputs.modbus_write(0x0000, 5));
        assert!(inputs.sim_input(Input::Gpi { pin: 3, on: true }));
        assert_eq!(shared.dv_word(0), Some(0), "not before the cycle");
        let mut simulated = Vec::new();
        feed.begin(1, &shared, |input| {
            simulated.push(input.clone());
            true
        });
        assert_eq!((shared.dv_word(0), shared.dv_word(1)), (Some(5), Some(0)));
        assert_eq!(simulated, [Input::Gpi { pin: 3, on: true }]);
        assert_eq!(inputs.landing().load(Ordering::Acquire), 2);
        // A simulated input the machine lacks is dropped, not recorded.
        assert!(inputs.sim_input(Input::Ai { slave: 9, channel: 1, raw: 1 }));
        feed.begin(2, &shared, |_| false);
        assert_eq!(shared.dv_word(1), Some(11));
        let record = inputs.take_record();
        assert_eq!(
            record,
            [
                Stamped { cycle: 1, input: Input::Modbus { address: 0, value: 5 } },
                Stamped { cycle: 1, input: Input::Gpi { pin: 3, on: true } },
                Stamped { cycle: 2, input: Input::Modbus { address: 1, value: 11 } },
            ]
        );
        let replaying = Inputs::new(false, true);
        assert!(!replaying.modbus_write(0x0000, 1), "a replay takes no outside writes");
        assert!(!replaying.sim_input(Input::Gpi { pin: 1, on: true }), "nor outside simulated inputs");
    }
}

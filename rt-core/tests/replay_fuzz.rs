//! Property tests of replay records (docs/replay.md): text made of the record's own words,
//! records mutated, bytes at random. Parsing never panics; a record it refuses gets an
//! error naming a line of the text; a record it takes is in cycle order and is the same
//! again after `format` and `parse`. 10^4 cases each, a fixed budget.

use proptest::prelude::*;
use rt_core::replay::{self, HEADER, Input, RecordError, Stamped};

fn config() -> ProptestConfig {
    ProptestConfig { cases: 10_000, failure_persistence: None, ..ProptestConfig::default() }
}

/// Parses `text`; checks what any outcome must be.
fn check(text: &[u8]) -> Result<(), TestCaseError> {
    let lines = text.split(|b| *b == b'\n').count();
    match replay::parse(text) {
        Ok(inputs) => {
            prop_assert!(inputs.windows(2).all(|w| w[0].cycle <= w[1].cycle));
            prop_assert!(inputs.iter().all(|s| s.cycle >= 1));
            let again = replay::parse(replay::format(&inputs).as_bytes()).expect("a formatted record parses");
            prop_assert_eq!(again, inputs);
        }
        Err(RecordError::Line { line, what }) => {
            prop_assert!((1..=lines).contains(&line), "line {line} of {lines}: {what}");
            prop_assert!(!what.is_empty());
        }
        Err(e @ RecordError::Io(..)) => prop_assert!(false, "{e}"),
    }
    Ok(())
}

/// A word of a record line: the kinds, numbers at the edges of their ranges, hex, the
/// Eth events, the ch. 22 functions, or text at random.
fn word() -> impl Strategy<Value = String> {
    let words = prop::sample::select(vec![
        "modbus",
        "serial",
        "gpi",
        "slvgpi",
        "ai",
        "eth",
        "client",
        "connect",
        "refused",
        "data",
        "end",
        "0",
        "1",
        "2",
        "8",
        "9",
        "63",
        "64",
        "65535",
        "65536",
        "-1",
        "0x0000",
        "0x1000",
        "0xFFFF",
        "0x",
        "18446744073709551615",
        "18446744073709551616",
        "Modbus_ClientConnect",
        "Modbus_ClientRead_Coils",
        "Modbus_ClientWrite_HoldReg",
        "ASCII_ClientRecv",
        "ASCII_ClientSend",
        "00",
        "ff",
        "abc",
        "0z",
        "#",
    ]);
    prop_oneof![
        3 => words.prop_map(str::to_string),
        1 => any::<u64>().prop_map(|n| n.to_string()),
        1 => proptest::collection::vec(any::<u8>(), 1..6).prop_map(|b| b.iter().map(|b| format!("{b:02x}")).collect()),
        1 => "[ -~]{0,6}",
    ]
}

/// A record line: a cycle, then words; or whitespace, a comment, nothing.
fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => (1u64..20, proptest::collection::vec(word(), 0..5)).prop_map(|(c, w)| format!("{c} {}", w.join(" "))),
        1 => proptest::collection::vec(word(), 0..5).prop_map(|w| w.join(" ")),
        1 => "[ \t\r]{0,3}",
        1 => Just("# a comment".to_string()),
    ]
}

/// Inputs of the kinds the core feeds, in cycle order.
fn inputs() -> impl Strategy<Value = Vec<Stamped>> {
    let input = prop_oneof![
        (any::<u16>(), any::<u16>())
            .prop_filter("a data word", |(a, _)| replay::is_data_word(*a))
            .prop_map(|(address, value)| Input::Modbus { address, value }),
        proptest::collection::vec(any::<u8>(), 1..64).prop_map(Input::Serial),
        (1u8..=8, any::<bool>()).prop_map(|(pin, on)| Input::Gpi { pin, on }),
        (any::<u16>(), 1u16.., any::<bool>()).prop_map(|(slave, pin, on)| Input::SlvGpi { slave, pin, on }),
        (any::<u16>(), 1u8..=4, any::<u16>()).prop_map(|(slave, channel, raw)| Input::Ai { slave, channel, raw }),
    ];
    proptest::collection::vec((1u64..1000, input), 0..10).prop_map(|mut v| {
        v.sort_by_key(|(cycle, _)| *cycle);
        v.into_iter().map(|(cycle, input)| Stamped { cycle, input }).collect()
    })
}

#[derive(Clone, Debug)]
enum Mutation {
    Flip(usize, u8),
    Insert(usize, u8),
    Delete(usize),
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(at, b)| Mutation::Flip(at, b)),
        (any::<usize>(), prop::sample::select(vec![b' ', b'\n', b'\r', b'0', b'x', b'#', 0xFF]))
            .prop_map(|(at, b)| Mutation::Insert(at, b)),
        any::<usize>().prop_map(Mutation::Delete),
        any::<usize>().prop_map(Mutation::Truncate),
    ]
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn records_round_trip(inputs in inputs()) {
        prop_assert_eq!(replay::parse(replay::format(&inputs).as_bytes()).unwrap(), inputs);
    }

    #[test]
    fn lines_of_the_record_s_words(lines in proptest::collection::vec(line(), 0..8)) {
        check(format!("{HEADER}\n{}", lines.join("\n")).as_bytes())?;
    }

    #[test]
    fn records_mutated(inputs in inputs(), mutations in proptest::collection::vec(mutation(), 1..4)) {
        let mut text = replay::format(&inputs).into_bytes();
        for m in mutations {
            let at = |i: usize, len: usize| i % (len + 1);
            match m {
                Mutation::Flip(i, b) if !text.is_empty() => { let i = i % text.len(); text[i] ^= b }
                Mutation::Insert(i, b) => text.insert(at(i, text.len()), b),
                Mutation::Delete(i) if !text.is_empty() => { text.remove(i % text.len()); }
                Mutation::Truncate(i) => text.truncate(at(i, text.len())),
                _ => {}
            }
        }
        check(&text)?;
    }

    #[test]
    fn any_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..300), header in any::<bool>()) {
        let text = if header { [format!("{HEADER}\n").as_bytes(), &bytes].concat() } else { bytes };
        check(&text)?;
    }
}

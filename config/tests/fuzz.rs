//! Property tests of the machine file: the README's machine file mutated, and TOML made of
//! the file's own sections and keys with values at random. Loading never panics; a file it
//! refuses gets an error naming the key (a wrong value) or the file (bad TOML); a file it
//! takes passes validation and loads the same again. 10^4 cases each, a fixed budget.

use std::path::Path;
use std::sync::OnceLock;

use config::{ConfigError, MachineConfig};
use proptest::prelude::*;

fn config() -> ProptestConfig {
    ProptestConfig { cases: 10_000, failure_persistence: None, ..ProptestConfig::default() }
}

/// The README's machine file (the TOML block under "## The machine file").
fn readme_machine_file() -> String {
    let readme = include_str!("../../README.md");
    let section = &readme[readme.find("## The machine file").expect("the README's machine file section")..];
    let start = section.find("```toml\n").expect("its TOML block") + "```toml\n".len();
    section[start..start + section[start..].find("```").expect("the block's end")].to_string()
}

/// One folder for every case, with the README's `main.lua` in it.
fn dir() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("main.lua"), "").unwrap();
        dir
    })
    .path()
}

/// Loads `text` as the machine file `name` (one per test: they run side by side);
/// checks what any outcome must be.
fn load(name: &str, text: &str) -> Result<(), TestCaseError> {
    let path = dir().join(name);
    std::fs::write(&path, text).unwrap();
    match MachineConfig::load(&path) {
        Ok(config) => {
            prop_assert!(config.validate().is_ok());
            let again = MachineConfig::load(&path).expect("a file that loaded loads again");
            prop_assert_eq!(format!("{config:?}"), format!("{again:?}"));
        }
        Err(ConfigError::Parse { path: named, message }) => {
            prop_assert_eq!(named, path);
            prop_assert!(!message.is_empty());
        }
        Err(ConfigError::Invalid { key, message }) => {
            prop_assert!(!key.is_empty() && !message.is_empty(), "{key}: {message}");
        }
        Err(e @ ConfigError::Read { .. }) => prop_assert!(false, "{e}"),
    }
    Ok(())
}

/// Values a mutation puts where one was: out of range, of another type, not finite.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<i64>().prop_map(|v| v.to_string()),
        any::<f64>().prop_map(|v| format!("{v:?}")),
        Just("nan".to_string()),
        Just("-inf".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("1e309".to_string()),
        Just("true".to_string()),
        Just("\"\"".to_string()),
        Just("\"localhost\"".to_string()),
        Just("[]".to_string()),
        Just("{}".to_string()),
        Just("[1, \"a\"]".to_string()),
        "\"[ -~]{0,12}\"",
    ]
}

#[derive(Clone, Debug)]
enum Mutation {
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    SetValue(usize, String),
    Truncate(usize),
    InsertByte(usize, u8),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        1 => any::<usize>().prop_map(Mutation::DeleteLine),
        1 => any::<usize>().prop_map(Mutation::DuplicateLine),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        4 => (any::<usize>(), value()).prop_map(|(l, v)| Mutation::SetValue(l, v)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
        1 => (any::<usize>(), any::<u8>()).prop_map(|(at, b)| Mutation::InsertByte(at, b)),
    ]
}

fn mutate(text: &str, mutations: &[Mutation]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut tail: Option<Vec<u8>> = None;
    for m in mutations {
        let n = lines.len().max(1);
        match m {
            Mutation::DeleteLine(l) if !lines.is_empty() => drop(lines.remove(l % n)),
            Mutation::DuplicateLine(l) if !lines.is_empty() => lines.insert(l % n, lines[l % n].clone()),
            Mutation::SwapLines(a, b) if !lines.is_empty() => lines.swap(a % n, b % n),
            Mutation::SetValue(l, v) if !lines.is_empty() => {
                let line = &mut lines[l % n];
                if let Some(eq) = line.find('=') {
                    *line = format!("{}= {v}", &line[..eq]);
                }
            }
            Mutation::Truncate(at) => {
                tail = Some(lines.join("\n").into_bytes()).map(|b| b[..at % (b.len() + 1)].to_vec())
            }
            Mutation::InsertByte(at, byte) => {
                let mut bytes = lines.join("\n").into_bytes();
                bytes.insert(at % (bytes.len() + 1), *byte);
                tail = Some(bytes);
            }
            _ => {}
        }
        if let Some(bytes) = tail.take() {
            lines = String::from_utf8_lossy(&bytes).lines().map(str::to_string).collect();
        }
    }
    lines.join("\n")
}

/// A section header or a key = value line from the machine file's own names.
fn toml_line() -> impl Strategy<Value = String> {
    let sections = prop::sample::select(vec![
        "[rt]",
        "[[axes]]",
        "[axes.plant]",
        "[axes.travel]",
        "[axes.drive_settings]",
        "[axes.pt]",
        "[[tasks]]",
        "[[slaves]]",
        "[modbus]",
        "[drl]",
        "[serial]",
        "[ascii]",
        "[freeport]",
        "[web]",
        "[identity]",
    ]);
    let keys = prop::sample::select(vec![
        "cycle_us",
        "priority",
        "cpu",
        "lock_memory",
        "script_pool",
        "idle_poll",
        "script_cpus",
        "huge_pages",
        "drive",
        "unit",
        "counts_per_unit",
        "max_vel",
        "max_acc",
        "vel",
        "acc",
        "dec",
        "rx_pdo",
        "tx_pdo",
        "negative_limit",
        "positive_limit",
        "home_switch",
        "index_pitch",
        "bandwidth_hz",
        "id",
        "program",
        "autorun",
        "watchdog_ms",
        "memory_limit_mib",
        "fault_reaction",
        "external",
        "device",
        "inputs",
        "outputs",
        "loopback",
        "bind",
        "port",
        "station",
        "max_connections",
        "idle_timeout_ms",
        "protocol",
        "baud",
        "link",
        "user_port",
        "task",
        "output",
        "model",
        "serial",
    ]);
    prop_oneof![
        1 => sections.prop_map(str::to_string),
        3 => (keys, value()).prop_map(|(k, v)| format!("{k} = {v}")),
    ]
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn the_readme_machine_file_mutated(mutations in proptest::collection::vec(mutation(), 1..4)) {
        load("mutated.toml", &mutate(&readme_machine_file(), &mutations))?;
    }

    #[test]
    fn toml_of_the_machine_file_s_names(lines in proptest::collection::vec(toml_line(), 0..12)) {
        load("names.toml", &lines.join("\n"))?;
    }

    #[test]
    fn any_text(text in "\\PC{0,200}") {
        load("text.toml", &text)?;
    }
}

/// The README's machine file as it is loads: the mutations start from a good file.
#[test]
fn the_readme_machine_file_loads() {
    let path = dir().join("readme.toml");
    std::fs::write(&path, readme_machine_file()).unwrap();
    MachineConfig::load(&path).unwrap();
}

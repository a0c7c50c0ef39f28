//! The machine file shown in the README is one the controller accepts.

use config::MachineConfig;

#[test]
fn the_readme_machine_file_loads() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md")).unwrap();
    let block = readme.split("```toml\n").nth(1).and_then(|b| b.split("```").next()).expect("a toml block");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("main.lua"), "").unwrap();
    let path = dir.path().join("machine.toml");
    std::fs::write(&path, block).unwrap();
    let config = MachineConfig::load(&path).unwrap();
    assert_eq!(config.cycle_us, 1000);
    assert_eq!(config.axes.len(), 1);
    assert_eq!(config.tasks[0].program, dir.path().join("main.lua"));
}

#[test]
fn the_built_in_machine_is_valid() {
    let config = MachineConfig::default();
    config.validate().unwrap();
    assert_eq!(config.axes.len(), 4);
    assert_eq!(config.period_ns(), 1_000_000);
}

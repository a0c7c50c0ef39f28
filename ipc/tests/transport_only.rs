//! Issue 12: `ipc` carries bytes and shared memory only. What the calls mean (the registry,
//! the queries, the Modbus address map) is the `calls` crate's, so `ipc` knows no API.

#[test]
fn ipc_does_not_depend_on_api() {
    let manifest: toml::Table = toml::from_str(include_str!("../Cargo.toml")).expect("ipc's Cargo.toml parses");
    for section in ["dependencies", "dev-dependencies", "build-dependencies"] {
        let deps = manifest.get(section).and_then(|d| d.as_table());
        for name in ["api", "calls"] {
            assert!(deps.is_none_or(|d| !d.contains_key(name)), "ipc's [{section}] names {name}");
        }
    }
    assert!(
        manifest["dependencies"].as_table().is_some_and(|d| d.contains_key("iceoryx2")),
        "the parse saw the dependencies"
    );
}

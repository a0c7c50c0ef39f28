//! The watchdog's report names the line a hung task loops on, though a running program has
//! no hook: the script process samples the line by arming the hook with a signal
//! (script-host's `arming`). In the main chunk, in a coroutine, and in a loop of C string
//! calls, each in its own task of one controller.

mod common;

use common::*;

const WATCHDOG_MS: u64 = 300;

/// (program, the line it hangs on)
const HANGS: [(&str, u32); 3] = [
    ("local n = 0\nPrint('hanging')\nn = n + 1\nwhile true do n = n + 1 end\n", 4),
    (
        "local co = coroutine.wrap(function()\n  local n = 0\n  while true do n = n + 1 end\nend)\nPrint('hanging')\nco()\n",
        3,
    ),
    (
        "local s = string.rep('ab', 50)\nPrint('hanging')\n\n\
         while true do local t = s:rep(3) .. s; local a = t:find('ba', 1, true) end\n",
        4,
    ),
];

#[test]
fn the_watchdog_names_the_line_of_a_hung_loop() {
    let dir = tempfile::tempdir().unwrap();
    let mut machine = String::new();
    for (id, (source, _)) in HANGS.iter().enumerate() {
        program(dir.path(), &format!("hang{id}.lua"), source);
        machine +=
            &format!("[[tasks]]\nid = {id}\nprogram = \"hang{id}.lua\"\nautorun = true\nwatchdog_ms = {WATCHDOG_MS}\n");
    }
    let config = dir.path().join("machine.toml");
    std::fs::write(&config, machine).unwrap();
    let out = run(&unique_ns("hook-lines"), &["--config", config.to_str().unwrap()]);
    let what = format!("stdout:\n{}\nstderr:\n{}", out.stdout, out.stderr);
    for (id, (source, line)) in HANGS.iter().enumerate() {
        assert_eq!(out.lines_of_task(id as u8), ["hanging"], "{what}");
        let alarm = format!("alarm 0x3{id:03x}4102");
        let report = out.stderr.lines().find(|l| l.contains(&alarm)).unwrap_or_else(|| panic!("{alarm}: {what}"));
        assert!(report.contains(&format!(" ms at line {line} ")), "{source}\n{report}");
    }
}

//! Issue 40, item 4: `luamotion lsp` with a client luamotion did not write, Neovim's own
//! (Debian's `neovim`, 0.7, `vim.lsp.start_client`), headless: the diagnostic of a
//! misspelled name arrives, and completion, hover and signature help answer from the
//! registry. With `CI=true` a missing Neovim fails.

mod common;

use std::os::unix::process::CommandExt;
use std::process::{Command, Stdio};
use std::time::Duration;

use common::*;

#[test]
fn neovim_receives_the_diagnostic_and_completions() {
    let nvim = match try_debian_tool("nvim") {
        Ok(nvim) => nvim,
        Err(why) if in_ci() => panic!("CI=true: Neovim is needed: {why}"),
        Err(why) => return eprintln!("skipped: {why}"),
    };
    let dir = tempfile::tempdir().unwrap();
    let file = program(dir.path(), "main.lua", "Enable(0)\nMoveAbs(0, 10)\nMoveAbsolute(0, 20)\n");
    let out = dir.path().join("lsp.out");
    let child = Command::new(nvim)
        .args(["--headless", "--clean", "-c"])
        .arg(format!("luafile {}", repo_path("tests/lua_editor/nvim_lsp.lua").display()))
        .env("LUAMOTION_BIN", BIN)
        .env("LSP_FILE", &file)
        .env("LSP_OUT", &out)
        .env("HOME", dir.path())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .process_group(0)
        .spawn()
        .expect("nvim");
    let finished = finish(child, Duration::from_secs(60));
    let facts = std::fs::read_to_string(&out).unwrap_or_default();
    let context = format!("{facts}\nnvim said: {}\n{}", finished.stdout, finished.stderr);
    assert!(facts.contains("diagnostics true"), "no diagnostic within 20 s: {context}");
    assert!(facts.contains("diagnostic 3:1 E101 unknown global `MoveAbsolute` | did you mean `MoveAbs`?"), "{context}");
    let items: usize =
        facts.lines().find_map(|l| l.strip_prefix("completion items ")).and_then(|n| n.parse().ok()).unwrap_or(0);
    assert!(items > 340, "{context}");
    assert!(facts.contains("completion MoveAbs int MoveAbs(int axis_id, double pos)"), "{context}");
    assert!(facts.contains("completion BM_LOOKAHEAD BM_LOOKAHEAD = 6"), "{context}");
    assert!(facts.contains("hover ```lua | int MoveAbs(int axis_id, double pos)"), "{context}");
    assert!(facts.contains("HMPL 5.2.4"), "{context}");
    assert!(facts.contains("signature int MoveAbs(int axis_id, double pos) active 1"), "{context}");
}

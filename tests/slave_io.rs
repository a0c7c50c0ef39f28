//! End to end: a Lua program sets, toggles and reads the outputs of a digital I/O terminal
//! declared in `[[slaves]]` and of a drive's 0x60FE:01, and reads the terminal's inputs
//! as the simulator switches them (HMPL 9.3, 9.5), all through the running controller.

mod common;

use common::*;

#[test]
fn a_program_drives_a_terminal_and_a_drives_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let main = r#"
        local T = 2
        -- HMPL 9.3: outputs 2 and 3 on (9.5.4: 6), toggled, all from a mask.
        Print("set %d %d all %d", SetSlvGPO(T, 2, 1), SetSlvGPO(T, 3, 1), GetSlvAllGPO(T))
        Print("toggle %d out 3 %d all %d", ToggleSlvGPO(T, 3), GetSlvGPO(T, 3), GetSlvAllGPO(T))
        Print("mask %d from 8: %d", SetSlvAllGPO(T, 0x300), GetSlvAllGPOByStartIdx(T, 8))
        -- HMPL 9.5: inputs the simulator switches, seen after the next frame.
        for _, pin in ipairs({1, 4, 8, 11}) do SimSetSlvGPI(T, pin, 1) end
        Sleep(5)
        Print("in all %d from 8: %d in 4 %d in 5 %d", GetSlvAllGPI(T), GetSlvAllGPIByStartIdx(T, 8), GetSlvGPI(T, 4), GetSlvGPI(T, 5))
        -- A drive's O1..O5 in 0x60FE:01 (bit 17 on); axis 0 has none mapped.
        Print("drive %d out 1 %d raw 0x%X; unmapped %d", SetSlvGPO(1, 1, 1), GetSlvGPO(1, 1), ReadPDO(1, 0x60FE, 1), SetSlvGPO(0, 1, 1))
        -- The manual's -1: no such output, slave or slot.
        Print("bad %d %d %d %d %d", SetSlvGPO(T, 17, 1), SetSlvGPO(7, 1, 1), GetSlvGPI(T | HMPL_SLOT_1, 1), GetSlvGPI(T, 0), SetSlvAllGPO(T, 0x10000))
    "#;
    let program = program(dir.path(), "main.lua", main);
    let toml = format!(
        "[[axes]]\nname = \"x\"\n\n[[axes]]\nname = \"y\"\nrx_pdo = [0x60400010, 0x607A0020, 0x60600008, 0x60FF0020, 0x60FE0120]\n\n\
         [[slaves]]\ndevice = \"digital_io\"\ninputs = 16\noutputs = 16\n\n\
         [[tasks]]\nid = 0\nprogram = {:?}\nautorun = true\n",
        program.display().to_string()
    );
    let config = dir.path().join("machine.toml");
    std::fs::write(&config, toml).unwrap();
    let out = run(&unique_ns("slvio"), &["--config", config.to_str().unwrap()]);
    assert_eq!(
        out.lines_of_task(0),
        vec![
            "set 0 0 all 6",
            "toggle 0 out 3 0 all 2",
            "mask 0 from 8: 6",
            "in all 1161 from 8: 9 in 4 1 in 5 0",
            "drive 0 out 1 1 raw 0x20000; unmapped -1",
            "bad -1 -1 -1 -1 -1",
        ],
        "{}\n{}",
        out.stdout,
        out.stderr
    );
}

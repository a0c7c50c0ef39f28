//! The HMPL manual's catalogue (MH06UC01-2510): the 335 functions of ch. 2 to 22 and the
//! 5 keywords of ch. 19, with the manual's section numbers. `luamotion api markdown`
//! lists each with the way a script reaches it here and, where the simulator differs from
//! a controller on a machine, how. A test holds every entry to a registry function, a
//! system variable or one of the `CONSTRUCTS`.

use crate::registry::{self, FunctionSpec};
use crate::system_vars::SystemVar;

/// Entries per chapter, as the manual's table of contents counts them.
pub const CHAPTER_ENTRIES: [(u8, usize); 21] = [
    (2, 25),
    (3, 15),
    (4, 19),
    (5, 74),
    (6, 8),
    (7, 4),
    (8, 60),
    (9, 21),
    (10, 15),
    (11, 6),
    (12, 11),
    (13, 12),
    (14, 7),
    (15, 9),
    (16, 5),
    (17, 11),
    (18, 6),
    (19, 5),
    (20, 11),
    (21, 2),
    (22, 14),
];

/// (section, name) of every catalogue entry, in the manual's order.
pub const ENTRIES: [(&str, &str); 340] = [
    // ch. 2
    ("2.1", "IsSystemInit"),
    ("2.2", "IsSystemOper"),
    ("2.3", "IsSystemPreOp"),
    ("2.4", "IsSystemError"),
    ("2.5", "GetECATSt"),
    ("2.6", "GetSlvECATSt"),
    ("2.7", "DisableAll"),
    ("2.8", "StopAll"),
    ("2.9", "EStop"),
    ("2.10", "GetSlaveNum"),
    ("2.11", "GetFirmwareVer"),
    ("2.12", "GetFirmwareDate"),
    ("2.13", "GetFirmwareHash"),
    ("2.14", "GetModelNum"),
    ("2.15", "GetSerialNum"),
    ("2.16", "ScanNetwork"),
    ("2.17", "SetHMIScope"),
    ("2.18", "Sleep"),
    ("2.19", "SendEvent"),
    ("2.20", "SendMsgEvent"),
    ("2.21", "RunScheduler"),
    ("2.22", "MutexLock"),
    ("2.23", "MutexUnlock"),
    ("2.24", "TON"),
    ("2.25", "TOF"),
    // ch. 3
    ("3.2", "Print"),
    ("3.3", "StringPrint"),
    ("3.4", "StringLen"),
    ("3.5", "IsStringEqual"),
    ("3.6", "StrFindChar"),
    ("3.7", "StrFindCharEx"),
    ("3.8", "StrFindStr"),
    ("3.9", "StringCopy"),
    ("3.10", "StringCopyEx"),
    ("3.11", "StringCat"),
    ("3.12", "StringCatEx"),
    ("3.13", "StringToDouble"),
    ("3.14", "MemoryCopy"),
    ("3.15", "MemorySet"),
    ("3.16", "IsMemoryEqual"),
    // ch. 4
    ("4.1", "sin"),
    ("4.2", "cos"),
    ("4.3", "tan"),
    ("4.4", "asin"),
    ("4.5", "acos"),
    ("4.6", "atan"),
    ("4.7", "atan2"),
    ("4.8", "abs"),
    ("4.9", "fabs"),
    ("4.10", "ceil"),
    ("4.11", "floor"),
    ("4.12", "ldexp"),
    ("4.13", "exp"),
    ("4.14", "pow"),
    ("4.15", "log"),
    ("4.16", "log10"),
    ("4.17", "sqrt"),
    ("4.18", "cbrt"),
    ("4.19", "hypot"),
    // ch. 5
    ("5.2.1", "Enable"),
    ("5.2.2", "Disable"),
    ("5.2.3", "Reset"),
    ("5.2.4", "MoveAbs"),
    ("5.2.5", "MoveRel"),
    ("5.2.6", "MoveVel"),
    ("5.2.7", "MoveTrq"),
    ("5.2.8", "MovePVT"),
    ("5.2.9", "Stop"),
    ("5.2.10", "Halt"),
    ("5.2.11", "Resume"),
    ("5.3.1", "GetVel"),
    ("5.3.2", "SetVel"),
    ("5.3.3", "GetAcc"),
    ("5.3.4", "SetAcc"),
    ("5.3.5", "SetAccTime"),
    ("5.3.6", "GetDec"),
    ("5.3.7", "SetDec"),
    ("5.3.8", "SetDecTime"),
    ("5.3.9", "GetKillDec"),
    ("5.3.10", "SetKillDec"),
    ("5.3.11", "GetSWRL"),
    ("5.3.12", "SetSWRL"),
    ("5.3.13", "GetSWLL"),
    ("5.3.14", "SetSWLL"),
    ("5.3.15", "GetSMTime"),
    ("5.3.16", "SetSMTime"),
    ("5.3.17", "GetMoveTime"),
    ("5.3.18", "GetSettlingTime"),
    ("5.3.19", "SetPos"),
    ("5.3.20", "GetPosFb"),
    ("5.3.21", "GetPosFbComp"),
    ("5.3.22", "GetPosOffset"),
    ("5.3.23", "GetPosErr"),
    ("5.3.24", "GetVelFb"),
    ("5.3.25", "GetVelErr"),
    ("5.3.26", "GetCurrFb"),
    ("5.3.27", "GetRefPos"),
    ("5.3.28", "GetRefVel"),
    ("5.3.29", "GetRefAcc"),
    ("5.3.30", "GetPosOut"),
    ("5.3.31", "GetVelOut"),
    ("5.3.32", "GetAccOut"),
    ("5.3.33", "IgnoreHWL"),
    ("5.3.34", "IgnoreSWL"),
    ("5.3.35", "IgnorePE"),
    ("5.3.36", "GetAxisNum"),
    ("5.3.37", "SetVelScale"),
    ("5.3.38", "GetVelScale"),
    ("5.3.39", "SetRollover"),
    ("5.3.40", "GetRolloverTurns"),
    ("5.3.41", "SetOpMode"),
    ("5.3.42", "SetBufferMode"),
    ("5.3.43", "GetBufferMode"),
    ("5.3.44", "GetCmdNum"),
    ("5.3.45", "SetPosWindow"),
    ("5.3.46", "GetPosWindow"),
    ("5.3.47", "SetPosWindowTime"),
    ("5.3.48", "GetPosWindowTime"),
    ("5.4.1", "IsEnabled"),
    ("5.4.2", "IsMoving"),
    ("5.4.3", "IsInPos"),
    ("5.4.4", "IsErrorStop"),
    ("5.4.5", "IsGantry"),
    ("5.4.6", "IsGrouped"),
    ("5.4.7", "IsSync"),
    ("5.4.8", "IsHWLL"),
    ("5.4.9", "IsHWRL"),
    ("5.4.10", "IsSWLL"),
    ("5.4.11", "IsSWRL"),
    ("5.4.12", "IsDriveErr"),
    ("5.4.13", "IsPosErr"),
    ("5.4.14", "IsCompActive"),
    ("5.4.15", "IsAcc"),
    // ch. 6
    ("6.2", "EnableGear"),
    ("6.3", "DisableGear"),
    ("6.4", "GearIn"),
    ("6.5", "GearOut"),
    ("6.6", "GetGearRatio"),
    ("6.7", "IsInGear"),
    ("6.8", "IsGearMaster"),
    ("6.9", "IsGearSlave"),
    // ch. 7
    ("7.2", "EnableGantryPair"),
    ("7.3", "DisableGantryPair"),
    ("7.4", "GetGantryPairID"),
    ("7.5", "IsGantryPair"),
    // ch. 8
    ("8.2.1", "EnableGroup"),
    ("8.2.2", "DisableGroup"),
    ("8.2.3", "ResetGroup"),
    ("8.2.4", "StopGroup"),
    ("8.2.5", "HaltGroup"),
    ("8.2.6", "ResumeGroup"),
    ("8.2.7", "JogGroup"),
    ("8.2.8", "JogGroupAxis"),
    ("8.2.9", "LineAbs2D"),
    ("8.2.10", "LineAbs3D"),
    ("8.2.11", "LineRel2D"),
    ("8.2.12", "LineRel3D"),
    ("8.2.13", "Arc2D"),
    ("8.2.14", "ArcCW2D"),
    ("8.2.15", "ArcCCW2D"),
    ("8.2.16", "ArcAngle2D"),
    ("8.2.17", "Circle2D"),
    ("8.3.1", "AddAxisToGrp"),
    ("8.3.2", "RemoveAxisFromGrp"),
    ("8.3.3", "SetupGroup"),
    ("8.3.4", "UngrpAllAxes"),
    ("8.3.5", "GetGroupID"),
    ("8.3.6", "SetGrpMotionProfile"),
    ("8.3.7", "SetGrpAngMotionProfile"),
    ("8.3.8", "GetGrpKin"),
    ("8.3.9", "SetGrpKin"),
    ("8.3.10", "GetGrpVel"),
    ("8.3.11", "SetGrpVel"),
    ("8.3.12", "GetGrpAcc"),
    ("8.3.13", "SetGrpAcc"),
    ("8.3.14", "SetGrpAccTime"),
    ("8.3.15", "GetGrpDec"),
    ("8.3.16", "SetGrpDec"),
    ("8.3.17", "SetGrpDecTime"),
    ("8.3.18", "GetGrpSMTime"),
    ("8.3.19", "SetGrpSMTime"),
    ("8.3.20", "GetGrpCoordSys"),
    ("8.3.21", "SetGrpCoordSys"),
    ("8.3.22", "GetGrpBufferMode"),
    ("8.3.23", "SetGrpBufferMode"),
    ("8.3.24", "GetGrpTransMode"),
    ("8.3.25", "SetGrpTransMode"),
    ("8.3.26", "SetGrpTransPrm"),
    ("8.3.27", "GetGrpCmdNum"),
    ("8.3.28", "SetGrpVelScale"),
    ("8.3.29", "GetGrpVelScale"),
    ("8.3.30", "GetGrpCoordTrans"),
    ("8.3.31", "SetGrpCoordTrans"),
    ("8.3.32", "GetGrpPoseCmd"),
    ("8.3.33", "GetGrpPoseFb"),
    ("8.3.34", "SetGrpLookAheadPrm"),
    ("8.3.35", "SetGrpQueueSize"),
    ("8.4.1", "IsGrpEnabled"),
    ("8.4.2", "IsGrpMoving"),
    ("8.4.3", "IsGrpInPos"),
    ("8.4.4", "IsGrpErrorStop"),
    ("8.5.1", "LineAbs"),
    ("8.5.2", "LineRel"),
    ("8.5.3", "CircleAbs"),
    ("8.5.4", "CircleRel"),
    // ch. 9
    ("9.2.1", "SetGPO"),
    ("9.2.2", "ToggleGPO"),
    ("9.2.3", "SetAllGPO"),
    ("9.2.4", "SetGPIInvert"),
    ("9.2.5", "SetGPOInvert"),
    ("9.2.6", "BindEMO"),
    ("9.3.1", "SetSlvGPO"),
    ("9.3.2", "ToggleSlvGPO"),
    ("9.3.3", "SetSlvAllGPO"),
    ("9.4.1", "GetGPI"),
    ("9.4.2", "GetGPO"),
    ("9.4.3", "GetAllGPI"),
    ("9.4.4", "GetAllGPO"),
    ("9.4.5", "GetAllGPIInvertSt"),
    ("9.4.6", "GetAllGPOInvertSt"),
    ("9.5.1", "GetSlvGPI"),
    ("9.5.2", "GetSlvGPO"),
    ("9.5.3", "GetSlvAllGPI"),
    ("9.5.4", "GetSlvAllGPO"),
    ("9.5.5", "GetSlvAllGPIByStartIdx"),
    ("9.5.6", "GetSlvAllGPOByStartIdx"),
    // ch. 10
    ("10.2.1", "SetSlvAIType"),
    ("10.2.2", "SetSlvAOType"),
    ("10.2.3", "SetSlvAORaw"),
    ("10.2.4", "SetSlvAO"),
    ("10.3.1", "GetSlvAIType"),
    ("10.3.2", "GetSlvAOType"),
    ("10.3.3", "GetSlvAIRaw"),
    ("10.3.4", "GetSlvAI"),
    ("10.3.5", "GetSlvAORaw"),
    ("10.3.6", "GetSlvAO"),
    ("10.4.1", "SetSlvAOMonitor"),
    ("10.4.2", "SetSlvAOParam"),
    ("10.4.3", "GetSlvAOScale"),
    ("10.4.4", "GetSlvAOOffset"),
    ("10.4.5", "IsSlvAOBound"),
    // ch. 11
    ("11.2", "SetUserTable"),
    ("11.3", "GetUserTable"),
    ("11.4", "SetTableValue"),
    ("11.5", "GetTableValue"),
    ("11.6", "SaveUserTable"),
    ("11.7", "LoadUserTable"),
    // ch. 12
    ("12.2", "EnablePT"),
    ("12.3", "DisablePT"),
    ("12.4", "IsPTEnabled"),
    ("12.5", "SetPT_StartPos"),
    ("12.6", "SetPT_EndPos"),
    ("12.7", "SetPT_Interval"),
    ("12.8", "SetPT_PulseWidth"),
    ("12.9", "SetPT_PosArray"),
    ("12.10", "SetPT_StateArray"),
    ("12.11", "SetPT_StartIndex"),
    ("12.12", "SetPT_EndIndex"),
    // ch. 13
    ("13.2", "EnableTouchProbe1"),
    ("13.3", "EnableTouchProbe2"),
    ("13.4", "DisableTouchProbe1"),
    ("13.5", "DisableTouchProbe2"),
    ("13.6", "IsTouchProbe1Enabled"),
    ("13.7", "IsTouchProbe2Enabled"),
    ("13.8", "IsTouchProbe1Triggered"),
    ("13.9", "IsTouchProbe2Triggered"),
    ("13.10", "GetTouchProbe1Pos"),
    ("13.11", "GetTouchProbe2Pos"),
    ("13.12", "SetTouchProbe1Func"),
    ("13.13", "SetTouchProbe2Func"),
    // ch. 14
    ("14.2", "EnableComp"),
    ("14.3", "DisableComp"),
    ("14.4", "SetupComp"),
    ("14.5", "SetupComp2D"),
    ("14.6", "SetupComp3D"),
    ("14.7", "GetCompPos"),
    ("14.8", "SetCompAlgType"),
    // ch. 15
    ("15.2", "EnableAxisVsf"),
    ("15.3", "DisableAxisVsf"),
    ("15.4", "SetAxisVsf"),
    ("15.5", "EnableAxisInShape"),
    ("15.6", "DisableAxisInShape"),
    ("15.7", "SetAxisInShape"),
    ("15.8", "EnableGrpInShape"),
    ("15.9", "DisableGrpInShape"),
    ("15.10", "SetGrpInShape"),
    // ch. 16
    ("16.2", "StartTask"),
    ("16.3", "StartTaskFunc"),
    ("16.4", "StopTask"),
    ("16.5", "StopAllTask"),
    ("16.6", "IsTaskStop"),
    // ch. 17
    ("17.2.1", "ReadSDO"),
    ("17.2.2", "ReadSDOEx"),
    ("17.2.3", "WriteSDO"),
    ("17.2.4", "WriteSDOEx"),
    ("17.2.5", "ReadPDO"),
    ("17.2.6", "ReadPDOEx"),
    ("17.2.7", "WritePDO"),
    ("17.2.8", "ForceWritePDO"),
    ("17.2.9", "ReleasePDO"),
    ("17.3.1", "GetConfigVar"),
    ("17.3.2", "SetConfigVar"),
    // ch. 18
    ("18.2", "GetSystemLastErr"),
    ("18.3", "GetAxisLastErr"),
    ("18.4", "ClearAxisLastErr"),
    ("18.5", "GetGrpLastErr"),
    ("18.6", "ClearGrpLastErr"),
    ("18.7", "GetDriveErr"),
    // ch. 19
    ("19.1", "_TASKID_"),
    ("19.2", "_AUTORUN_"),
    ("19.3", "Till"),
    ("19.4", "HIMC_GPI"),
    ("19.5", "HIMC_GPO"),
    // ch. 20
    ("20.2", "MoveHome"),
    ("20.3", "SetHomeMethod"),
    ("20.4", "SetHomeSwitchVel"),
    ("20.5", "SetHomeZeroVel"),
    ("20.6", "SetHomeAcc"),
    ("20.7", "SetHomeOffset"),
    ("20.8", "SetHomeTimeout"),
    ("20.9", "SetHomedStatus"),
    ("20.10", "IsHomed"),
    ("20.11", "IsHoming"),
    ("20.12", "IsHomeSwitch"),
    // ch. 21
    ("21.1", "GetSlvChNum"),
    ("21.2", "GetSlvSlotNum"),
    // ch. 22
    ("22.2.1", "START_ASCII_AGENT"),
    ("22.2.2", "ASCII_ServerBroadcast"),
    ("22.2.3", "ASCII_ClientConnect"),
    ("22.2.4", "ASCII_ClientRecv"),
    ("22.2.5", "ASCII_ClientSend"),
    ("22.2.6", "ASCII_ClientDisconnect"),
    ("22.3.1", "Modbus_ClientConnect"),
    ("22.3.2", "Modbus_ClientDisconnect"),
    ("22.3.3", "Modbus_ClientRead_HoldReg"),
    ("22.3.4", "Modbus_ClientRead_InputReg"),
    ("22.3.5", "Modbus_ClientRead_Coils"),
    ("22.3.6", "Modbus_ClientRead_Inputs"),
    ("22.3.7", "Modbus_ClientWrite_HoldReg"),
    ("22.3.8", "Modbus_ClientWrite_Coils"),
];

/// Catalogue entries that are neither functions nor variables in Lua, and what stands for
/// them.
pub const CONSTRUCTS: &[(&str, &str)] = &[(
    "_AUTORUN_",
    "`autorun = true` in the task's `[[tasks]]` entry of the machine file starts it with the controller",
)];

/// How a script reaches a catalogue entry.
#[derive(Clone, Copy, Debug)]
pub enum Offered {
    /// A function of the registry.
    Function(&'static FunctionSpec),
    /// A system variable (HMPL 19, 23.2).
    Variable(SystemVar),
    /// Something else, described.
    Construct(&'static str),
}

/// How `name` is offered, or `None` when it is missing.
pub fn offered(name: &str) -> Option<Offered> {
    if let Some(f) = registry::find(name) {
        return Some(Offered::Function(f));
    }
    if let Some(v) = SystemVar::parse(name) {
        return Some(Offered::Variable(v));
    }
    CONSTRUCTS.iter().find(|(n, _)| *n == name).map(|(_, how)| Offered::Construct(how))
}

/// What a catalogue entry does differently in the simulator than on a controller with a
/// machine, where that matters to a program; the entries not named behave as the manual
/// says.
pub const SIMULATION: &[(&str, &str)] = &[
    (
        "ScanNetwork",
        "Starts the simulated segment again (every slave to Pre-Op, the mapping written, Op); refused with 0x138C while an axis or group is enabled.",
    ),
    ("GetSlaveNum", "Counts the simulated slaves: a drive per `[[axes]]` entry, then the `[[slaves]]` terminals."),
    ("GetFirmwareVer", "luamotion's version."),
    ("GetFirmwareDate", "The luamotion executable's modification time (UTC)."),
    ("GetFirmwareHash", "A hash of the luamotion executable."),
    ("GetModelNum", "The machine file's `[identity] model`."),
    ("GetSerialNum", "The machine file's `[identity] serial`."),
    ("SetHMIScope", "Starts/stops the recording of `luamotion scope`, `run --scope`; sends the messages as events."),
    ("Sleep", "Rounded up to whole controller cycles, counted on the controller's clock."),
    ("RunScheduler", "Yields the processor: each task is a process of its own."),
    ("MoveTrq", "Drives the simulated motor and load (the machine file's `[axes.plant]`)."),
    ("GetGPI", "The simulator sets the inputs: `SimSetGPI`."),
    ("GetSlvGPI", "The simulator sets a terminal's inputs: `SimSetSlvGPI`."),
    ("SaveUserTable", "The controller's disk is the file `user_table.bin` in the data directory (`--data-dir`)."),
    ("LoadUserTable", "Reads the file `user_table.bin` in the data directory (`--data-dir`)."),
    ("ReadSDO", "Reads the simulated drive's object dictionary (docs/drive.md) through its CoE mailbox."),
    ("WriteSDO", "Writes the simulated drive's object dictionary (docs/drive.md) through its CoE mailbox."),
    (
        "MoveHome",
        "Home switch, limit switches, index pulses and hard stops are where the machine file's `[axes.travel]` puts them.",
    ),
    (
        "GetSlvAIRaw",
        "Analog terminals are `[[slaves]] device = \"analog_io\"`; the simulator sets an input's word with `SimSetSlvAIRaw`, or an output drives its input (`loopback = true`).",
    ),
    ("GetSlvAI", "The input's word comes from `SimSetSlvAIRaw` or the terminal's loopback."),
    (
        "EnablePT",
        "An axis has the trigger when the machine file wires it to a controller GPO (`[axes.pt] output = n`; no E1 drive is simulated, other axes get 0x1451). Crossings are found on the feedback, interpolated inside the cycle; their exact positions are in `GetPTPulse` and the trace's `FILE.pulses.csv`.",
    ),
    ("SetPT_PulseWidth", "Checked, not seen: the GPO is high for the one cycle in which the pulse falls."),
    (
        "EnableTouchProbe1",
        "The HIWIN drive latches on the encoder index only (CoE manual 3.9); `drive_settings.touch_probe = \"cia402\"` gives a drive probes 1 and 2 on the index or on probe inputs placed along the travel (`[axes.travel] probe_input_1/2`).",
    ),
    ("EnableTouchProbe2", "Only on a drive with `drive_settings.touch_probe = \"cia402\"`; otherwise 0x83II0258."),
    (
        "SetTouchProbe1Func",
        "The external input is a sensor placed along the travel in the machine file (`probe_input_1`), on a `cia402` drive.",
    ),
    ("EnableComp", "The limit is 1 mm; `HCV_ID_max_comp_lim` does not change it."),
    (
        "SetAxisInShape",
        "A rigid load does not ring: give the axis a flexible load (`[axes.plant] load_frequency_hz`, `load_damping`, `load_mass_ratio`) to see what the shaper does; the load's position is in the trace.",
    ),
    (
        "SetAxisVsf",
        "The VSF is a notch on the reference (docs/decisions.md); its effect shows on a flexible load (`[axes.plant] load_*`).",
    ),
    (
        "START_ASCII_AGENT",
        "Listens on 127.0.0.1 (`[ascii] bind`) and port 4000 (`[ascii] user_port`, `--ascii-user-port`).",
    ),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_catalogue_counts_what_the_table_of_contents_counts() {
        for (chapter, count) in CHAPTER_ENTRIES {
            let prefix = format!("{chapter}.");
            let listed = ENTRIES.iter().filter(|(section, _)| section.starts_with(&prefix)).count();
            assert_eq!(listed, count, "HMPL ch. {chapter}");
        }
        assert_eq!(CHAPTER_ENTRIES.iter().map(|(_, n)| n).sum::<usize>(), ENTRIES.len());
    }

    #[test]
    fn every_catalogue_entry_is_offered() {
        let missing: Vec<_> = ENTRIES.iter().filter(|(_, name)| offered(name).is_none()).collect();
        assert!(missing.is_empty(), "not offered: {missing:?}");
    }

    #[test]
    fn registry_functions_cite_their_catalogue_section() {
        for (section, name) in ENTRIES {
            if let Some(Offered::Function(f)) = offered(name) {
                let rest = f.manual.strip_prefix(&format!("HMPL {section}"));
                let same = rest.is_some_and(|r| !r.starts_with(|c: char| c.is_ascii_digit() || c == '.'));
                assert!(same, "{name}: {} vs HMPL {section}", f.manual);
            }
        }
    }

    #[test]
    fn simulation_notes_name_catalogue_entries() {
        for (name, _) in SIMULATION {
            assert!(ENTRIES.iter().any(|(_, n)| n == name), "{name} is not in the catalogue");
        }
    }
}

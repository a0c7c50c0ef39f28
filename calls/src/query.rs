//! Status queries (`api::Kind::Query`), answered from a snapshot in the reader's own
//! address space: one match over `api::QueryCall`, so that every query of the registry has
//! its answer here.

use api::analog::ConversionType;
use api::{ErrorCode, QueryCall, SystemError};

use schema::{
    ANALOG_INPUTS, ANALOG_OUTPUTS, AnalogOutputSnapshot, AnalogSnapshot, AxisSnapshot, DigitalWord, GPIO_PINS,
    GroupSnapshot, PdoEntrySnapshot, PtSnapshot, SLAVE_DIGITAL_INPUTS, SLAVE_DIGITAL_OUTPUTS, Snapshot, TaskState,
    channel_mask, fault_status, group_fault_status, group_motion_status, motion_status,
};

/// A query's answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A Lua integer.
    Int(i64),
    /// A Lua float.
    Double(f64),
    /// A Lua boolean.
    Bool(bool),
    /// An out-pointer buffer (at most 8 bytes: the widest drive object).
    Bytes {
        /// The bytes, the first `len` of them used.
        data: [u8; 8],
        /// How many bytes are used.
        len: u8,
    },
}

/// One or two values: the C return value and an out-pointer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Answer(pub Value, pub Option<Value>);

impl From<Value> for Answer {
    fn from(v: Value) -> Self {
        Answer(v, None)
    }
}

/// AL state codes (HMPL 2.5).
const ECAT_PRE_OP: u32 = 2;
const ECAT_OP: u32 = 8;

/// Answers a status query from the snapshot, in the script process, without a round trip to the core.
pub fn evaluate(call: &QueryCall, s: &Snapshot) -> Result<Answer, ErrorCode> {
    let status = |id, bit| axis(s, id).map(|a| Value::Bool(a.motion_status & bit != 0).into());
    let fault = |id, bit| axis(s, id).map(|a| Value::Bool(a.fault_status & bit != 0).into());
    let double = |id, f: fn(&AxisSnapshot) -> f64| axis(s, id).map(|a| Value::Double(f(a)).into());
    let int = |id, f: fn(&AxisSnapshot) -> i64| axis(s, id).map(|a| Value::Int(f(a)).into());
    let slave = |id: i64| usize::try_from(id).ok().filter(|&i| i < s.slave_count as usize).map(|i| &s.slaves[i]);
    Ok(match *call {
        QueryCall::GetVel { axis_id } => double(axis_id, |a| a.vel)?,
        QueryCall::GetAcc { axis_id } => double(axis_id, |a| a.acc)?,
        QueryCall::GetDec { axis_id } => double(axis_id, |a| a.dec)?,
        QueryCall::GetKillDec { axis_id } => double(axis_id, |a| a.kill_dec)?,
        QueryCall::GetSWRL { axis_id } => double(axis_id, |a| a.swrl)?,
        QueryCall::GetSWLL { axis_id } => double(axis_id, |a| a.swll)?,
        QueryCall::GetSMTime { axis_id } => double(axis_id, |a| a.sm_time)?,
        QueryCall::GetMoveTime { axis_id } => double(axis_id, |a| a.move_time)?,
        QueryCall::GetSettlingTime { axis_id } => double(axis_id, |a| a.settling_time)?,
        QueryCall::GetPosFb { axis_id } => double(axis_id, |a| a.pos_fb)?,
        QueryCall::GetPosFbComp { axis_id } => double(axis_id, |a| a.pos_fb_comp)?,
        QueryCall::GetPosOffset { axis_id } => double(axis_id, |a| a.pos_offset)?,
        QueryCall::GetPosErr { axis_id } => double(axis_id, |a| a.pos_err)?,
        QueryCall::GetVelFb { axis_id } => double(axis_id, |a| a.vel_fb)?,
        QueryCall::GetVelErr { axis_id } => double(axis_id, |a| a.vel_err)?,
        QueryCall::GetCurrFb { axis_id } => double(axis_id, |a| a.curr_fb)?,
        QueryCall::GetRefPos { axis_id } => double(axis_id, |a| a.ref_pos)?,
        QueryCall::GetRefVel { axis_id } => double(axis_id, |a| a.ref_vel)?,
        QueryCall::GetRefAcc { axis_id } => double(axis_id, |a| a.ref_acc)?,
        QueryCall::GetPosOut { axis_id } => double(axis_id, |a| a.pos_out)?,
        QueryCall::GetVelOut { axis_id } => double(axis_id, |a| a.vel_out)?,
        QueryCall::GetAccOut { axis_id } => double(axis_id, |a| a.acc_out)?,
        QueryCall::GetAxisNum {} => Value::Int(s.axis_count as i64).into(),
        QueryCall::GetVelScale { axis_id } => double(axis_id, |a| a.vel_scale)?,
        QueryCall::GetRolloverTurns { axis_id } => int(axis_id, |a| a.rollover_turns as i64)?,
        QueryCall::GetBufferMode { axis_id } => int(axis_id, |a| a.buffer_mode as i64)?,
        QueryCall::GetCmdNum { axis_id } => int(axis_id, |a| a.cmd_num as i64)?,
        QueryCall::GetPosWindow { axis_id } => double(axis_id, |a| a.pos_window)?,
        QueryCall::GetPosWindowTime { axis_id } => double(axis_id, |a| a.pos_window_time)?,
        QueryCall::IsEnabled { axis_id } => status(axis_id, motion_status::ENABLED)?,
        QueryCall::IsMoving { axis_id } => status(axis_id, motion_status::MOVING)?,
        QueryCall::IsInPos { axis_id } => status(axis_id, motion_status::IN_POSITION)?,
        QueryCall::IsErrorStop { axis_id } => fault(axis_id, fault_status::ERROR_STOP)?,
        QueryCall::IsGantry { axis_id } => status(axis_id, motion_status::GANTRY)?,
        QueryCall::IsGrouped { axis_id } => status(axis_id, motion_status::GROUP)?,
        QueryCall::IsSync { axis_id } => status(axis_id, motion_status::SYNCHRONOUS)?,
        QueryCall::IsHWLL { axis_id } => fault(axis_id, fault_status::HW_LEFT_LIMIT)?,
        QueryCall::IsHWRL { axis_id } => fault(axis_id, fault_status::HW_RIGHT_LIMIT)?,
        QueryCall::IsSWLL { axis_id } => fault(axis_id, fault_status::SW_LEFT_LIMIT)?,
        QueryCall::IsSWRL { axis_id } => fault(axis_id, fault_status::SW_RIGHT_LIMIT)?,
        QueryCall::IsDriveErr { axis_id } => fault(axis_id, fault_status::DRIVE_FAULT)?,
        QueryCall::IsPosErr { axis_id } => fault(axis_id, fault_status::POSITION_ERROR)?,
        QueryCall::GetCompPos { axis_id } => double(axis_id, |a| a.comp_pos)?,
        QueryCall::IsCompActive { axis_id } => axis(s, axis_id).map(|a| Value::Bool(a.comp_active != 0).into())?,
        QueryCall::IsAcc { axis_id } => status(axis_id, motion_status::ACCELERATING)?,
        QueryCall::GetGearRatio { axis_slave_id } => double(axis_slave_id, |a| a.gear_ratio)?,
        QueryCall::IsInGear { axis_id } => axis(s, axis_id).map(|a| Value::Bool(a.in_gear != 0).into())?,
        QueryCall::IsGearMaster { axis_id } => axis(s, axis_id).map(|a| Value::Bool(a.gear_master != 0).into())?,
        QueryCall::IsGearSlave { axis_id } => status(axis_id, motion_status::GEAR)?,
        QueryCall::GetGantryPairID { axis_id } => int(axis_id, |a| a.gantry_pair_id as i64)?,
        QueryCall::IsGantryPair { axis_id_1, axis_id_2 } => {
            let (a, b) = (axis(s, axis_id_1)?, axis(s, axis_id_2)?);
            Value::Bool(a.gantry_pair_id >= 0 && a.gantry_pair_id == b.gantry_pair_id).into()
        }
        QueryCall::IsHomed { axis_id } => status(axis_id, motion_status::HOMED)?,
        QueryCall::IsHoming { axis_id } => status(axis_id, motion_status::HOMING)?,
        QueryCall::IsHomeSwitch { axis_id } => status(axis_id, motion_status::HOME_SWITCH)?,
        QueryCall::GetSystemLastErr {} => Value::Int(s.system_last_err as i64).into(),
        QueryCall::GetAxisLastErr { axis_id } => int(axis_id, |a| a.last_err as i64)?,
        QueryCall::GetGrpLastErr { group_id } => {
            let g = usize::try_from(group_id).ok().filter(|&g| g < s.group_last_err.len());
            Value::Int(s.group_last_err[g.ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))?] as i64).into()
        }
        // HMPL 8.3 and 8.4.
        QueryCall::GetGroupID { axis_id } => int(axis_id, |a| a.group_id as i64)?,
        QueryCall::GetGrpKin { group_id } => Value::Int(group(s, group_id)?.kin as i64).into(),
        QueryCall::GetGrpVel { group_id } => Value::Double(group(s, group_id)?.lin_profile[0]).into(),
        QueryCall::GetGrpAcc { group_id } => Value::Double(group(s, group_id)?.lin_profile[1]).into(),
        QueryCall::GetGrpDec { group_id } => Value::Double(group(s, group_id)?.lin_profile[2]).into(),
        QueryCall::GetGrpSMTime { group_id } => Value::Double(group(s, group_id)?.lin_profile[3]).into(),
        QueryCall::GetGrpCoordSys { group_id } => Value::Int(group(s, group_id)?.coord_sys as i64).into(),
        QueryCall::GetGrpBufferMode { group_id } => Value::Int(group(s, group_id)?.buffer_mode as i64).into(),
        QueryCall::GetGrpTransMode { group_id } => Value::Int(group(s, group_id)?.trans_mode as i64).into(),
        QueryCall::GetGrpCmdNum { group_id } => Value::Int(group(s, group_id)?.cmd_num as i64).into(),
        QueryCall::GetGrpVelScale { group_id } => Value::Double(group(s, group_id)?.vel_scale).into(),
        QueryCall::IsGrpEnabled { group_id } => group_status(s, group_id, group_motion_status::ENABLED)?,
        QueryCall::IsGrpMoving { group_id } => group_status(s, group_id, group_motion_status::MOVING)?,
        QueryCall::IsGrpInPos { group_id } => group_status(s, group_id, group_motion_status::IN_POSITION)?,
        QueryCall::IsGrpErrorStop { group_id } => {
            Value::Bool(group(s, group_id)?.fault_status & group_fault_status::ERROR_STOP != 0).into()
        }
        QueryCall::GetDriveErr { axis_id } => int(axis_id, |a| a.drive_err as i64)?,
        QueryCall::ReadPDO { slv_id, obj_index, obj_subindex } => match read_pdo(s, slv_id, obj_index, obj_subindex) {
            Some((value, _)) => Value::Int(value).into(),
            None => Value::Int(-1).into(),
        },
        QueryCall::ReadPDOEx { slv_id, obj_index, obj_subindex } => {
            match read_pdo(s, slv_id, obj_index, obj_subindex) {
                Some((value, len)) => {
                    let mut data = [0; 8];
                    data[..len].copy_from_slice(&value.to_le_bytes()[..len]);
                    Answer(Value::Int(0), Some(Value::Bytes { data, len: len as u8 }))
                }
                None => Answer(Value::Int(-1), Some(Value::Bytes { data: [0; 8], len: 0 })),
            }
        }
        QueryCall::IsSystemInit {} => Value::Bool(false).into(),
        QueryCall::IsSystemOper {} => Value::Bool(s.ecat_state == ECAT_OP && s.system_error == 0).into(),
        QueryCall::IsSystemPreOp {} => Value::Bool(s.ecat_state == ECAT_PRE_OP).into(),
        QueryCall::IsSystemError {} => Value::Bool(s.system_error != 0).into(),
        QueryCall::GetECATSt {} => Value::Int(s.ecat_state as i64).into(),
        QueryCall::GetSlvECATSt { slv_id } => Value::Int(slave(slv_id).map_or(-1, |sl| sl.al_state as i64)).into(),
        QueryCall::GetSlaveNum {} => Value::Int(s.slave_count as i64).into(),
        QueryCall::GetSlvChNum { slv_slot_id, ch_type } => {
            let (id, slot) = api::constants::split_slave_slot(slv_slot_id);
            let count = match (slave(id), slot, ch_type) {
                (Some(sl), 0, 1) => sl.digital_inputs as i64,
                (Some(sl), 0, 2) => sl.digital_outputs as i64,
                (Some(_), 0, 3) => s.analog_of(id as usize).map_or(0, |a| a.input_count as i64),
                (Some(_), 0, 4) => s.analog_of(id as usize).map_or(0, |a| a.output_count as i64),
                _ => -1,
            };
            Value::Int(count).into()
        }
        QueryCall::GetSlvSlotNum { slv_id } => Value::Int(if slave(slv_id).is_some() { 0 } else { -1 }).into(),
        QueryCall::GetGPI { gpi_idx } => pin(s.gpio.gpi, gpi_idx),
        QueryCall::GetGPO { gpo_idx } => pin(s.gpio.gpo, gpo_idx),
        QueryCall::GetAllGPI {} => Value::Int(s.gpio.gpi as i64).into(),
        QueryCall::GetAllGPO {} => Value::Int(s.gpio.gpo as i64).into(),
        QueryCall::GetAllGPIInvertSt {} => Value::Int(s.gpio.gpi_invert as i64).into(),
        QueryCall::GetAllGPOInvertSt {} => Value::Int(s.gpio.gpo_invert as i64).into(),
        QueryCall::GetSlvGPI { slv_slot_id, gpi_idx } => slave_channels(s, slv_slot_id, Inputs, gpi_idx, true),
        QueryCall::GetSlvGPO { slv_slot_id, gpo_idx } => slave_channels(s, slv_slot_id, Outputs, gpo_idx, true),
        QueryCall::GetSlvAllGPI { slv_slot_id } => slave_channels(s, slv_slot_id, Inputs, 1, false),
        QueryCall::GetSlvAllGPO { slv_slot_id } => slave_channels(s, slv_slot_id, Outputs, 1, false),
        QueryCall::GetSlvAllGPIByStartIdx { slv_slot_id, start_idx } => {
            slave_channels(s, slv_slot_id, Inputs, start_idx, false)
        }
        QueryCall::GetSlvAllGPOByStartIdx { slv_slot_id, start_idx } => {
            slave_channels(s, slv_slot_id, Outputs, start_idx, false)
        }
        QueryCall::GetSlvAIType { slv_slot_id, ai_idx } => {
            Value::Int(analog_input(s, slv_slot_id, ai_idx)?.1.code()).into()
        }
        QueryCall::GetSlvAOType { slv_slot_id, ao_idx } => {
            Value::Int(analog_output(s, slv_slot_id, ao_idx)?.1.code()).into()
        }
        QueryCall::GetSlvAIRaw { slv_slot_id, ai_idx } => {
            let (word, ty) = analog_input(s, slv_slot_id, ai_idx)?;
            Value::Int(ty.raw(word)).into()
        }
        QueryCall::GetSlvAORaw { slv_slot_id, ao_idx } => {
            let (word, ty, _) = analog_output(s, slv_slot_id, ao_idx)?;
            Value::Int(ty.raw(word)).into()
        }
        QueryCall::GetSlvAI { slv_slot_id, ai_idx } => {
            let (word, ty) = analog_input(s, slv_slot_id, ai_idx)?;
            Value::Double(ty.value(word).ok_or(ErrorCode::System(SystemError::HmplMotionNotReady))?).into()
        }
        QueryCall::GetSlvAO { slv_slot_id, ao_idx } => {
            let (word, ty, _) = analog_output(s, slv_slot_id, ao_idx)?;
            Value::Double(ty.value(word).ok_or(ErrorCode::System(SystemError::HmplMotionNotReady))?).into()
        }
        QueryCall::GetSlvAOScale { slv_slot_id, ao_idx } => {
            Value::Double(analog_output(s, slv_slot_id, ao_idx)?.2.scale).into()
        }
        QueryCall::GetSlvAOOffset { slv_slot_id, ao_idx } => {
            Value::Double(analog_output(s, slv_slot_id, ao_idx)?.2.offset).into()
        }
        QueryCall::IsSlvAOBound { slv_slot_id, ao_idx } => {
            Value::Int(analog_output(s, slv_slot_id, ao_idx)?.2.bound as i64).into()
        }
        // HMPL ch. 13: touch probes.
        QueryCall::IsTouchProbe1Enabled { axis_id } => probe_bit(s, axis_id, 0, |a| a.tp_enabled)?,
        QueryCall::IsTouchProbe2Enabled { axis_id } => probe_bit(s, axis_id, 1, |a| a.tp_enabled)?,
        QueryCall::IsTouchProbe1Triggered { axis_id } => probe_bit(s, axis_id, 0, |a| a.tp_triggered)?,
        QueryCall::IsTouchProbe2Triggered { axis_id } => probe_bit(s, axis_id, 1, |a| a.tp_triggered)?,
        QueryCall::GetTouchProbe1Pos { axis_id } => probe_pos(s, axis_id, 0),
        QueryCall::GetTouchProbe2Pos { axis_id } => probe_pos(s, axis_id, 1),
        QueryCall::IsTaskStop { task_id } => {
            let task = usize::try_from(task_id).ok().and_then(|t| s.tasks.get(t));
            let task = task.ok_or(ErrorCode::System(SystemError::NotValidTaskid))?;
            Value::Bool(TaskState::from(task.state).is_stopped()).into()
        }
        // HMPL ch. 12.
        QueryCall::IsPTEnabled { axis_id } => Value::Bool(position_trigger(s, axis_id)?.enabled != 0).into(),
        QueryCall::GetPTPulseNum { axis_id } => Value::Int(position_trigger(s, axis_id)?.pulses as i64).into(),
        QueryCall::GetPTMissedNum { axis_id } => Value::Int(position_trigger(s, axis_id)?.missed as i64).into(),
    })
}

/// An axis' position trigger (HMPL ch. 12).
fn position_trigger(s: &Snapshot, id: i64) -> Result<&PtSnapshot, ErrorCode> {
    axis(s, id)?;
    Ok(&s.position_triggers[id as usize])
}

/// HMPL 13.6-13.9: touch probe `probe`'s bit of an axis' word.
fn probe_bit(s: &Snapshot, id: i64, probe: u32, word: fn(&AxisSnapshot) -> u32) -> Result<Answer, ErrorCode> {
    Ok(Value::Bool(word(axis(s, id)?) >> probe & 1 != 0).into())
}

/// HMPL 13.10, 13.11: `0, pos`, or the reason and 0 (the manual's "non-0", not a Lua
/// error): 0x83II0258 when the probe is not in the process data, or no such axis.
fn probe_pos(s: &Snapshot, id: i64, probe: usize) -> Answer {
    let rc = match axis(s, id) {
        Ok(a) if a.tp_mapped >> probe & 1 != 0 => return Answer(Value::Int(0), Some(Value::Double(a.tp_pos[probe]))),
        Ok(_) => ErrorCode::axis(id as u8, api::AxisError::CmdInvalidNoSpecificPdo),
        Err(code) => code,
    };
    Answer(Value::Int(rc.code() as i64), Some(Value::Double(0.0)))
}

/// HMPL 9.4: one pin of a bitmask, 1 or 0; -1 for a pin that does not exist.
fn pin(bits: u32, pin: i64) -> Answer {
    let value = if (1..=GPIO_PINS).contains(&pin) { (bits >> (pin - 1)) as i64 & 1 } else { -1 };
    Value::Int(value).into()
}

/// Which of a slave's digital channels (HMPL 9.5).
#[derive(Clone, Copy)]
enum Channels {
    Inputs,
    Outputs,
}
use Channels::{Inputs, Outputs};

/// HMPL 9.5: a slave's channels from `first` (1-based) on, bit 0 = channel `first`; only
/// that channel's bit when `one`. -1 for no such slave, slot or channel, or when the
/// channels are not in the slave's process data.
fn slave_channels(s: &Snapshot, slv_slot_id: i64, which: Channels, first: i64, one: bool) -> Answer {
    let read = || {
        let (id, slot) = api::constants::split_slave_slot(slv_slot_id);
        let slave = s.slaves.get(usize::try_from(id).ok()?).filter(|_| slot == 0 && id < s.slave_count as i64)?;
        let (words, count): (&[DigitalWord], u8) = match which {
            Inputs => (&SLAVE_DIGITAL_INPUTS, slave.digital_inputs),
            Outputs => (&SLAVE_DIGITAL_OUTPUTS, slave.digital_outputs),
        };
        let skip = u32::try_from(first.checked_sub(1)?).ok().filter(|&k| k < count as u32)?;
        let (raw, word) = words.iter().find_map(|w| Some((read_pdo(s, id, w.index as i64, w.sub as i64)?.0, w)))?;
        let channels = ((raw as u64 >> word.first_bit) as u32 & channel_mask(count)) >> skip;
        Some(if one { channels & 1 } else { channels } as i64)
    };
    Value::Int(read().unwrap_or(-1)).into()
}

/// HMPL ch. 10: slave `slv_slot_id` (slot 0 only) and its analog channel `idx` (1-based)
/// of `count` channels, with its word in the process data (`index`:idx); 0x138F for no such
/// slave, channel or object (docs/decisions.md, "Slave analog I/O").
fn analog_channel(
    s: &Snapshot,
    slv_slot_id: i64,
    idx: i64,
    index: u16,
    count: fn(&AnalogSnapshot) -> u8,
) -> Result<(&AnalogSnapshot, usize, u16), ErrorCode> {
    let read = || {
        let (id, slot) = api::constants::split_slave_slot(slv_slot_id);
        let analog = s.analog_of(usize::try_from(id).ok()?).filter(|_| slot == 0 && id < s.slave_count as i64)?;
        let n = usize::try_from(idx).ok().filter(|n| (1..=count(analog) as usize).contains(n))?;
        let (word, _) = read_pdo(s, id, index as i64, idx)?;
        Some((analog, n - 1, word as u16))
    };
    read().ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))
}

/// An analog input's word and conversion type.
fn analog_input(s: &Snapshot, slv_slot_id: i64, idx: i64) -> Result<(u16, ConversionType), ErrorCode> {
    let (analog, n, word) = analog_channel(s, slv_slot_id, idx, ANALOG_INPUTS, |a| a.input_count)?;
    Ok((word, conversion_type(analog.input_types[n])))
}

/// An analog output's word, conversion type and settings.
fn analog_output(
    s: &Snapshot,
    slv_slot_id: i64,
    idx: i64,
) -> Result<(u16, ConversionType, AnalogOutputSnapshot), ErrorCode> {
    let (analog, n, word) = analog_channel(s, slv_slot_id, idx, ANALOG_OUTPUTS, |a| a.output_count)?;
    let output = analog.outputs[n];
    Ok((word, conversion_type(output.range_type), output))
}

/// A conversion type the core published (it only publishes valid ones).
fn conversion_type(code: u16) -> ConversionType {
    ConversionType::from_code(code as i64).unwrap_or_default()
}

/// An object in a slave's process data: its value (sign-extended) and length in bytes.
fn read_pdo(s: &Snapshot, slave: i64, index: i64, sub: i64) -> Option<(i64, usize)> {
    let slave = s.slaves.get(usize::try_from(slave).ok()?).filter(|_| slave < s.slave_count as i64)?;
    let find = |entries: &[PdoEntrySnapshot], image: &[u8]| {
        entries.iter().find(|e| e.index as i64 == index && e.sub as i64 == sub).map(|e| {
            let len = e.bits as usize / 8;
            let mut raw = [0u8; 8];
            raw[..len].copy_from_slice(&image[e.offset as usize..e.offset as usize + len]);
            let value = u64::from_le_bytes(raw);
            let shift = 64 - e.bits as u32;
            let value = if e.signed != 0 { ((value << shift) as i64) >> shift } else { value as i64 };
            (value, len)
        })
    };
    find(&slave.tx[..slave.tx_count as usize], &slave.inputs)
        .or_else(|| find(&slave.rx[..slave.rx_count as usize], &slave.outputs))
}

/// Group `id` of the snapshot, or HMPL's "argument out of range".
pub fn group(s: &Snapshot, id: i64) -> Result<&GroupSnapshot, ErrorCode> {
    usize::try_from(id).ok().and_then(|g| s.groups.get(g)).ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))
}

fn group_status(s: &Snapshot, id: i64, bit: u32) -> Result<Answer, ErrorCode> {
    Ok(Value::Bool(group(s, id)?.motion_status & bit != 0).into())
}

/// The axis a query names, or HMPL's "argument out of range".
pub fn axis(s: &Snapshot, id: i64) -> Result<&AxisSnapshot, ErrorCode> {
    usize::try_from(id)
        .ok()
        .filter(|&i| i < s.axis_count as usize)
        .map(|i| &s.axes[i])
        .ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))
}

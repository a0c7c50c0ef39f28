//! Status queries (`api::Kind::Query`), answered from a snapshot in the reader's own
//! address space: one match over `api::Query`, so that every query of the registry has
//! its answer here.

use api::{ErrorCode, Query, SystemError};

use ipc::messages::{AxisSnapshot, GPIO_PINS, PdoEntrySnapshot, Snapshot, TaskState, fault_status, motion_status};

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

/// Argument words as the registry types them (see `messages::Request`).
#[derive(Clone, Copy)]
pub struct Words<'a>(pub &'a [u64]);

impl Words<'_> {
    /// Argument word `i` as an integer.
    pub fn int(&self, i: usize) -> i64 {
        self.0[i] as i64
    }

    /// Argument word `i` as a float (its bits).
    pub fn double(&self, i: usize) -> f64 {
        f64::from_bits(self.0[i])
    }
}

/// AL state codes (HMPL 2.5).
const ECAT_PRE_OP: u32 = 2;
const ECAT_OP: u32 = 8;

/// Answers a status query from the snapshot, in the script process, without a round trip to the core.
pub fn evaluate(query: Query, args: Words, s: &Snapshot) -> Result<Answer, ErrorCode> {
    let axis = || axis(s, args.int(0));
    let status = |bit| axis().map(|a| Value::Bool(a.motion_status & bit != 0).into());
    let fault = |bit| axis().map(|a| Value::Bool(a.fault_status & bit != 0).into());
    let double = |f: fn(&AxisSnapshot) -> f64| axis().map(|a| Value::Double(f(a)).into());
    let int = |f: fn(&AxisSnapshot) -> i64| axis().map(|a| Value::Int(f(a)).into());
    let slave = |id: i64| usize::try_from(id).ok().filter(|&i| i < s.slave_count as usize).map(|i| &s.slaves[i]);
    Ok(match query {
        Query::GetVel => double(|a| a.vel)?,
        Query::GetAcc => double(|a| a.acc)?,
        Query::GetDec => double(|a| a.dec)?,
        Query::GetKillDec => double(|a| a.kill_dec)?,
        Query::GetSWRL => double(|a| a.swrl)?,
        Query::GetSWLL => double(|a| a.swll)?,
        Query::GetSMTime => double(|a| a.sm_time)?,
        Query::GetMoveTime => double(|a| a.move_time)?,
        Query::GetSettlingTime => double(|a| a.settling_time)?,
        // No compensation is configured: the compensated feedback is the feedback.
        Query::GetPosFb | Query::GetPosFbComp => double(|a| a.pos_fb)?,
        Query::GetPosOffset => double(|a| a.pos_offset)?,
        Query::GetPosErr => double(|a| a.pos_err)?,
        Query::GetVelFb => double(|a| a.vel_fb)?,
        Query::GetVelErr => double(|a| a.vel_err)?,
        Query::GetCurrFb => double(|a| a.curr_fb)?,
        Query::GetRefPos => double(|a| a.ref_pos)?,
        Query::GetRefVel => double(|a| a.ref_vel)?,
        Query::GetRefAcc => double(|a| a.ref_acc)?,
        Query::GetPosOut => double(|a| a.pos_out)?,
        Query::GetVelOut => double(|a| a.vel_out)?,
        Query::GetAccOut => double(|a| a.acc_out)?,
        Query::GetAxisNum => Value::Int(s.axis_count as i64).into(),
        Query::GetVelScale => double(|a| a.vel_scale)?,
        Query::GetRolloverTurns => int(|a| a.rollover_turns as i64)?,
        Query::GetBufferMode => int(|a| a.buffer_mode as i64)?,
        Query::GetCmdNum => int(|a| a.cmd_num as i64)?,
        Query::GetPosWindow => double(|a| a.pos_window)?,
        Query::GetPosWindowTime => double(|a| a.pos_window_time)?,
        Query::IsEnabled => status(motion_status::ENABLED)?,
        Query::IsMoving => status(motion_status::MOVING)?,
        Query::IsInPos => status(motion_status::IN_POSITION)?,
        Query::IsErrorStop => fault(fault_status::ERROR_STOP)?,
        Query::IsGantry => status(motion_status::GANTRY)?,
        Query::IsGrouped => status(motion_status::GROUP)?,
        Query::IsSync => status(motion_status::SYNCHRONOUS)?,
        Query::IsHWLL => fault(fault_status::HW_LEFT_LIMIT)?,
        Query::IsHWRL => fault(fault_status::HW_RIGHT_LIMIT)?,
        Query::IsSWLL => fault(fault_status::SW_LEFT_LIMIT)?,
        Query::IsSWRL => fault(fault_status::SW_RIGHT_LIMIT)?,
        Query::IsDriveErr => fault(fault_status::DRIVE_FAULT)?,
        Query::IsPosErr => fault(fault_status::POSITION_ERROR)?,
        // Compensation (HMPL ch. 14) has no functions here, so it is never active.
        Query::IsCompActive => axis().map(|_| Value::Bool(false).into())?,
        Query::IsAcc => status(motion_status::ACCELERATING)?,
        Query::GetGearRatio => double(|a| a.gear_ratio)?,
        Query::IsInGear => axis().map(|a| Value::Bool(a.in_gear != 0).into())?,
        Query::IsGearMaster => axis().map(|a| Value::Bool(a.gear_master != 0).into())?,
        Query::IsGearSlave => status(motion_status::GEAR)?,
        Query::GetGantryPairID => int(|a| a.gantry_pair_id as i64)?,
        Query::IsGantryPair => {
            let (a, b) = (axis()?, self::axis(s, args.int(1))?);
            Value::Bool(a.gantry_pair_id >= 0 && a.gantry_pair_id == b.gantry_pair_id).into()
        }
        Query::IsHomed => status(motion_status::HOMED)?,
        Query::IsHoming => status(motion_status::HOMING)?,
        Query::IsHomeSwitch => status(motion_status::HOME_SWITCH)?,
        Query::GetSystemLastErr => Value::Int(s.system_last_err as i64).into(),
        Query::GetAxisLastErr => int(|a| a.last_err as i64)?,
        Query::GetGrpLastErr => {
            let g = usize::try_from(args.int(0)).ok().filter(|&g| g < s.group_last_err.len());
            Value::Int(s.group_last_err[g.ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))?] as i64).into()
        }
        Query::GetDriveErr => int(|a| a.drive_err as i64)?,
        Query::ReadPDO => match read_pdo(s, args) {
            Some((value, _)) => Value::Int(value).into(),
            None => Value::Int(-1).into(),
        },
        Query::ReadPDOEx => match read_pdo(s, args) {
            Some((value, len)) => {
                let mut data = [0; 8];
                data[..len].copy_from_slice(&value.to_le_bytes()[..len]);
                Answer(Value::Int(0), Some(Value::Bytes { data, len: len as u8 }))
            }
            None => Answer(Value::Int(-1), Some(Value::Bytes { data: [0; 8], len: 0 })),
        },
        Query::IsSystemInit => Value::Bool(false).into(),
        Query::IsSystemOper => Value::Bool(s.ecat_state == ECAT_OP && s.system_error == 0).into(),
        Query::IsSystemPreOp => Value::Bool(s.ecat_state == ECAT_PRE_OP).into(),
        Query::IsSystemError => Value::Bool(s.system_error != 0).into(),
        Query::GetECATSt => Value::Int(s.ecat_state as i64).into(),
        Query::GetSlvECATSt => Value::Int(slave(args.int(0)).map_or(-1, |sl| sl.al_state as i64)).into(),
        Query::GetSlaveNum => Value::Int(s.slave_count as i64).into(),
        Query::GetSlvChNum => {
            let (id, slot) = api::constants::split_slave_slot(args.int(0));
            let count = match (slave(id), slot, args.int(1)) {
                (Some(sl), 0, 1) => sl.digital_inputs as i64,
                (Some(sl), 0, 2) => sl.digital_outputs as i64,
                (Some(_), 0, 3 | 4) => 0,
                _ => -1,
            };
            Value::Int(count).into()
        }
        Query::GetSlvSlotNum => Value::Int(if slave(args.int(0)).is_some() { 0 } else { -1 }).into(),
        Query::GetGPI => pin(s.gpio.gpi, args.int(0)),
        Query::GetGPO => pin(s.gpio.gpo, args.int(0)),
        Query::GetAllGPI => Value::Int(s.gpio.gpi as i64).into(),
        Query::GetAllGPO => Value::Int(s.gpio.gpo as i64).into(),
        Query::GetAllGPIInvertSt => Value::Int(s.gpio.gpi_invert as i64).into(),
        Query::GetAllGPOInvertSt => Value::Int(s.gpio.gpo_invert as i64).into(),
        Query::IsTaskStop => {
            let task = usize::try_from(args.int(0)).ok().and_then(|t| s.tasks.get(t));
            let task = task.ok_or(ErrorCode::System(SystemError::NotValidTaskid))?;
            Value::Bool(TaskState::from(task.state).is_stopped()).into()
        }
    })
}

/// HMPL 9.4: one pin of a bitmask, 1 or 0; -1 for a pin that does not exist.
fn pin(bits: u32, pin: i64) -> Answer {
    let value = if (1..=GPIO_PINS).contains(&pin) { (bits >> (pin - 1)) as i64 & 1 } else { -1 };
    Value::Int(value).into()
}

/// An object in a slave's process data: its value (sign-extended) and length in bytes.
fn read_pdo(s: &Snapshot, args: Words) -> Option<(i64, usize)> {
    let slave = s.slaves.get(usize::try_from(args.int(0)).ok()?).filter(|_| args.int(0) < s.slave_count as i64)?;
    let (index, sub) = (args.int(1), args.int(2));
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

/// The axis a query names, or HMPL's "argument out of range".
pub fn axis(s: &Snapshot, id: i64) -> Result<&AxisSnapshot, ErrorCode> {
    usize::try_from(id)
        .ok()
        .filter(|&i| i < s.axis_count as usize)
        .map(|i| &s.axes[i])
        .ok_or(ErrorCode::System(SystemError::HmplArgOutOfRange))
}

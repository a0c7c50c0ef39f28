//! The 32-bit error codes of the HMPL manual, chapter 18 (`0xCCIIEEEE`).
//!
//! `CC` is the class (0x00 system, 0x83 axis, 0x82 group), `II` the axis or group id,
//! `EEEE` the error id of tables 18.1.1.1, 18.1.2.1 and 18.1.3.1. Each variant keeps
//! the manual's name (`eERR_AXIS_CMD_INVALID_DISABLED`), which is also the name of the
//! constant scripts see.

use std::fmt;

use num_enum::{IntoPrimitive, TryFromPrimitive};

macro_rules! error_table {
    ($(#[$meta:meta])* $ty:ident { $( $id:literal $variant:ident $name:literal $meaning:literal, )* }) => {
        $(#[$meta])*
        /// An id no row lists is an error (`TryFromPrimitive`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, TryFromPrimitive)]
        #[repr(u16)]
        pub enum $ty { $( #[doc = $meaning] $variant = $id, )* }

        impl $ty {
            /// Every row of the table, in the manual's order.
            pub const ALL: &'static [$ty] = &[ $( $ty::$variant, )* ];

            /// The error id (`EEEE`).
            pub const fn id(self) -> u16 {
                self as u16
            }

            /// The manual's name, e.g. `eERR_AXIS_CMD_INVALID_DISABLED`.
            pub const fn name(self) -> &'static str {
                match self { $( $ty::$variant => $name, )* }
            }

            /// The manual's explanation, in English.
            pub const fn meaning(self) -> &'static str {
                match self { $( $ty::$variant => $meaning, )* }
            }
        }
    };
}

error_table! {
    /// HMPL ch. 18, table 18.1.1.1: system error codes (`0x0000EEEE`).
    SystemError {
        0x0001 HcvIdNotFound "eERR_HCV_ID_NOT_FOUND" "variable ID not found",
        0x0002 DataExceeded "eERR_DATA_EXCEEDED" "requested data out of range",
        0x0003 HcvIsReadOnly "eERR_HCV_IS_READ_ONLY" "parameter is read-only",
        0x0004 HcvValueOutOfRange "eERR_HCV_VALUE_OUT_OF_RANGE" "input value out of range",
        0x0050 EwmCallbackBusy "eERR_EWM_CALLBACK_BUSY" "EWM callback busy",
        0x0064 EmergencyStop "eERR_EMERGENCY_STOP" "controller emergency-stopped",
        0x0107 NotValidTaskid "eERR_NOT_VALID_TASKID" "invalid task ID",
        0x0108 TaskIsRunning "eERR_TASK_IS_RUNNING" "task is already running",
        0x0109 FuncNotInTask "eERR_FUNC_NOT_IN_TASK" "task does not contain this function",
        0x010A TaskEmpty "eERR_TASK_EMPTY" "task has no content",
        0x010B TaskNotRunning "eERR_TASK_NOT_RUNNING" "task not running",
        0x012C NicInitTout "eERR_NIC_INIT_TOUT" "fieldbus network not ready",
        0x012D HardwareMismatch "eERR_HARDWARE_MISMATCH" "unrecognized hardware",
        0x012E SlaveNumMismatch "eERR_SLAVE_NUM_MISMATCH" "slave count differs from the configuration",
        0x0130 InvalidMckCnfg "eERR_INVALID_MCK_CNFG" "invalid motion-kernel configuration",
        0x0138 HimcLoadConfigFail "eERR_HIMC_LOAD_CONFIG_FAIL" "cannot load config from SSD",
        0x0139 HimcSaveConfigFail "eERR_HIMC_SAVE_CONFIG_FAIL" "cannot save config",
        0x013A HimcSaveConfigCopyFail "eERR_HIMC_SAVE_CONFIG_COPY_FAIL" "cannot copy file to SAVE folder",
        0x013C EthercatLicenseMismatch "eERR_ETHERCAT_LICENSE_MISMATCH" "EtherCAT license mismatch",
        0x01F4 IsrNotStable "eERR_ISR_NOT_STABLE" "interrupt period unstable",
        0x41F4 WarnIsrNotStable "eWRN_ISR_NOT_STABLE" "interrupt period unstable (warning)",
        0x01F5 MckOverload "eERR_MCK_OVERLOAD" "motion kernel overload",
        0xC1F5 DebugMckOverload "eDBG_MCK_OVERLOAD" "motion kernel overload (pre-warning)",
        0x01F6 IsrOverload "eERR_ISR_OVERLOAD" "CPU overload",
        0xC1F6 DebugIsrOverload "eDBG_ISR_OVERLOAD" "CPU overload (pre-warning)",
        0x1388 HmplInvalidArg "eERR_HMPL_INVALID_ARG" "invalid argument in HMPL",
        0x1389 HmplInvalidPtr "eERR_HMPL_INVALID_PTR" "invalid pointer",
        0x138A HmplStackOverflow "eERR_HMPL_STACK_OVERFLOW" "HMPL stack overflow",
        0x138B HmplIllegalMemOp "eERR_HMPL_ILLEGAL_MEM_OP" "illegal memory operation",
        0x138C HmplMotionNotReady "eERR_HMPL_MOTION_NOT_READY" "controller not ready to run this HMPL",
        0x138D HmplStrTooLong "eERR_HMPL_STR_TOO_LONG" "string too long",
        0x138E HmplInvalidStrFormat "eERR_HMPL_INVALID_STR_FORMAT" "bad string format",
        0x138F HmplArgOutOfRange "eERR_HMPL_ARG_OUT_OF_RANGE" "argument out of range",
        0x1392 HmplAsciiAgentRunning "eERR_HMPL_ASCII_AGENT_RUNNING" "an ASCII agent is already running (only one allowed)",
        0x139C HmplCannotRunInDebug "eERR_HMPL_CANNOT_RUN_IN_DEBUG" "function cannot run in debug mode",
        0x13A6 HmplTooManyBrkPoint "eERR_HMPL_TOO_MANY_BRK_POINT" "too many breakpoints in task",
        0x13EC HmplMutexLockTwice "eERR_HMPL_MUTEX_LOCK_TWICE" "locking an already-locked mutex (same task)",
        0x1450 HmplInvalidSysTimeMemory "eERR_HMPL_INVALID_SYS_TIME_MEMORY" "memory too small, needs at least 30 bytes (time-string buffer)",
        0x1451 HmplNotSupported "eERR_HMPL_NOT_SUPPORTED" "function not supported on this platform",
        0x1452 HmplClientNotConnected "eERR_HMPL_CLIENT_NOT_CONNECTED" "cannot connect to client",
        0x14B4 HmplNotInOpMode "eERR_HMPL_NOT_IN_OP_MODE" "function cannot run when not in OP (synchronous) state",
        0x176F HmplInternalError "eERR_HMPL_INTERNAL_ERROR" "HMPL internal error",
        0x1770 HmplExecFailed "eERR_HMPL_EXEC_FAILED" "HMPL execution failed",
        0x1771 HmplAsmLoadFailed "eERR_HMPL_ASM_LOAD_FAILED" "compile failed; assembly file missing",
        0x1772 HmplStarttaskTimeout "eERR_HMPL_STARTTASK_TIMEOUT" "StartTask timeout",
        0x1773 HmplStoptaskTimeout "eERR_HMPL_STOPTASK_TIMEOUT" "StopTask timeout",
        0x17D4 AsciiConnectTimeout "eERR_ASCII_CONNECT_TIMEOUT" "ASCII client connect timeout",
        0x17D5 AsciiConnectFailed "eERR_ASCII_CONNECT_FAILED" "ASCII client connect failed (check ip/port; or limit reached)",
        0x17D6 AsciiMultiConnecting "eERR_ASCII_MULTI_CONNECTING" "multiple ASCII clients connecting simultaneously",
        0x17D7 AsciiMultiDisconnecting "eERR_ASCII_MULTI_DISCONNECTING" "ascii multi disconnecting",
        0x17D8 AsciiDisconnectTimeout "eERR_ASCII_DISCONNECT_TIMEOUT" "ascii disconnect timeout",
        0x17DE AsciiRecvTimeout "eERR_ASCII_RECV_TIMEOUT" "receive timeout",
        0x17DF AsciiRecvFail "eERR_ASCII_RECV_FAIL" "receive failed",
        0x17E0 AsciiMultiRecving "eERR_ASCII_MULTI_RECVING" "ascii multi recving",
        0x17E8 AsciiSendTimeout "eERR_ASCII_SEND_TIMEOUT" "ascii send timeout",
        0x17E9 AsciiSendFail "eERR_ASCII_SEND_FAIL" "ascii send fail",
        0x17EA AsciiMultiSending "eERR_ASCII_MULTI_SENDING" "ascii multi sending",
        0x1838 ModbusConnectTimeout "eERR_MODBUS_CONNECT_TIMEOUT" "modbus connect timeout",
        0x1839 ModbusConnectFailed "eERR_MODBUS_CONNECT_FAILED" "check ip (or limit reached)",
        0x183A ModbusMultiConnecting "eERR_MODBUS_MULTI_CONNECTING" "modbus multi connecting",
        0x183B ModbusMultiDisconnecting "eERR_MODBUS_MULTI_DISCONNECTING" "modbus multi disconnecting",
        0x183C ModbusDisconnectTimeout "eERR_MODBUS_DISCONNECT_TIMEOUT" "modbus disconnect timeout",
        0x183D ModbusDatalengthErr "eERR_MODBUS_DATALENGTH_ERR" "read/write count exceeds limit",
        0x183E ModbusSocketBusy "eERR_MODBUS_SOCKET_BUSY" "two or more commands at once on a client",
        0x183F ModbusJobTimeout "eERR_MODBUS_JOB_TIMEOUT" "modbus job timeout",
        0x1840 ModbusJobFail "eERR_MODBUS_JOB_FAIL" "modbus job fail",
        0xB037 MsgHimcSetDefault "eMSG_HIMC_SET_DEFAULT" "restored factory defaults",
        0xB038 MsgHimcReboot "eMSG_HIMC_REBOOT" "controller reboot",
        0xB039 MsgHimcBoot "eMSG_HIMC_BOOT" "controller boot",
        0xB03A MsgHimcInfo "eMSG_HIMC_INFO" "controller info",
        0xB03B MsgHimcStoreConfig "eMSG_HIMC_STORE_CONFIG" "store configuration",
        0xB03E MsgApiMainIdChangeGet "eMSG_API_MAIN_ID_CHANGE_GET" "got access priority",
        0xB03F MsgApiMainIdChangeRelease "eMSG_API_MAIN_ID_CHANGE_RELEASE" "released access priority",
        0xB2C8 MsgStartHmiScope "eMSG_START_HMI_SCOPE" "scope started",
        0xB2C9 MsgStopHmiScope "eMSG_STOP_HMI_SCOPE" "scope stopped",
        0x3FFF SysLog "eERR_SYS_LOG" "controller error",
        0x7FFF WarnSysLog "eWRN_SYS_LOG" "controller warning",
        0xBFFF MsgSysLog "eMSG_SYS_LOG" "controller message",
        0xFFFF DebugSysLog "eDBG_SYS_LOG" "controller debug",
    }
}

error_table! {
    /// HMPL ch. 18, table 18.1.2.1: axis error codes (`0x83IIEEEE`).
    AxisError {
        0x000A CmdUnkown "eERR_AXIS_CMD_UNKOWN" "unknown command",
        0x001E CmdQueueFull "eERR_AXIS_CMD_QUEUE_FULL" "axis command queue full",
        0x0050 CmdInvalidInSim "eERR_AXIS_CMD_INVALID_IN_SIM" "command not available on virtual machine (simulator)",
        0x0060 CmdInvalidInVirtual "eERR_AXIS_CMD_INVALID_IN_VIRTUAL" "not available on virtual axis",
        0x0064 CmdInvalidState "eERR_AXIS_CMD_INVALID_STATE" "not allowed in current state",
        0x006E CmdInvalidEnabled "eERR_AXIS_CMD_INVALID_ENABLED" "not allowed while enabled",
        0x0078 CmdInvalidDisabled "eERR_AXIS_CMD_INVALID_DISABLED" "not allowed while disabled",
        0x0082 CmdInvalidMoving "eERR_AXIS_CMD_INVALID_MOVING" "not allowed while moving",
        0x008C CmdInvalidStopping "eERR_AXIS_CMD_INVALID_STOPPING" "not allowed while stopping",
        0x0096 CmdInvalidErrorState "eERR_AXIS_CMD_INVALID_ERROR_STATE" "not allowed in error state",
        0x00A0 CmdInvalidInSync "eERR_AXIS_CMD_INVALID_IN_SYNC" "invalid in synchronous state",
        0x00AA CmdInvalidGearMaster "eERR_AXIS_CMD_INVALID_GEAR_MASTER" "invalid for a gear master",
        0x00B4 CmdInvalidPpMode "eERR_AXIS_CMD_INVALID_PP_MODE" "invalid in PP (profile position) mode",
        0x00BE CmdInvalidMapSwitching "eERR_AXIS_CMD_INVALID_MAP_SWITCHING" "invalid while switching compensation map",
        0x00C8 CmdInvalidInputshapingEnabled "eERR_AXIS_CMD_INVALID_INPUTSHAPING_ENABLED" "invalid while input shaping enabled",
        0x00D2 CmdInvalidCompEnabled "eERR_AXIS_CMD_INVALID_COMP_ENABLED" "invalid while compensation enabled",
        0x00DC CmdInvalidGantryMode "eERR_AXIS_CMD_INVALID_GANTRY_MODE" "invalid in gantry mode",
        0x00E6 CmdInvalidGrouped "eERR_AXIS_CMD_INVALID_GROUPED" "invalid when axis is grouped",
        0x00F0 CmdInvalidControlMode "eERR_AXIS_CMD_INVALID_CONTROL_MODE" "invalid in current control mode",
        0x00FA CmdInvalidOpMode "eERR_AXIS_CMD_INVALID_OP_MODE" "invalid operation mode",
        0x0104 CmdInvalidBufferMode "eERR_AXIS_CMD_INVALID_BUFFER_MODE" "invalid buffer mode",
        0x0105 CmdInvalidSetbuffermode "eERR_AXIS_CMD_INVALID_SETBUFFERMODE" "cannot change buffer mode while commands pending",
        0x010E CmdInvalidTpEnabled "eERR_AXIS_CMD_INVALID_TP_ENABLED" "not allowed while touch probe enabled",
        0x012C CmdInvalidParameter "eERR_AXIS_CMD_INVALID_PARAMETER" "invalid parameter",
        0x0136 CmdInvalidPos "eERR_AXIS_CMD_INVALID_POS" "target position out of allowed range",
        0x0140 CmdInvalidVel "eERR_AXIS_CMD_INVALID_VEL" "velocity out of range",
        0x014A CmdInvalidAcc "eERR_AXIS_CMD_INVALID_ACC" "acceleration out of range",
        0x0154 CmdInvalidDec "eERR_AXIS_CMD_INVALID_DEC" "deceleration out of range",
        0x015E CmdInvalidJerk "eERR_AXIS_CMD_INVALID_JERK" "jerk out of range",
        0x0168 CmdInvalidSmTime "eERR_AXIS_CMD_INVALID_SM_TIME" "smooth time out of range",
        0x0172 CmdInvalidKillDec "eERR_AXIS_CMD_INVALID_KILL_DEC" "kill dec out of range",
        0x017C CmdInvalidVelScale "eERR_AXIS_CMD_INVALID_VEL_SCALE" "velocity percent out of range",
        0x0190 CompNotCnfg "eERR_AXIS_COMP_NOT_CNFG" "compensation not configured",
        0x01C2 CmdInvalidMasterSlaveConnection "eERR_AXIS_CMD_INVALID_MASTER_SLAVE_CONNECTION" "invalid master/slave relation",
        0x01CC CmdInvalidSlaveId "eERR_AXIS_CMD_INVALID_SLAVE_ID" "invalid slave axis id",
        0x01D6 CmdInvalidGearRatio "eERR_AXIS_CMD_INVALID_GEAR_RATIO" "gear ratio out of range",
        0x01F4 CmdInvalidRolloverPos "eERR_AXIS_CMD_INVALID_ROLLOVER_POS" "rollover value must be positive",
        0x01FE CmdInvalidRolloverPpMode "eERR_AXIS_CMD_INVALID_ROLLOVER_PP_MODE" "rollover unsupported in profile-position mode (reset rollover to 0 first)",
        0x0208 CmdInvalidForceconstTrqmode "eERR_AXIS_CMD_INVALID_FORCECONST_TRQMODE" "invalid torque constant in torque mode",
        0x0258 CmdInvalidNoSpecificPdo "eERR_AXIS_CMD_INVALID_NO_SPECIFIC_PDO" "PDO lacks a required CoE object",
        0x03F2 DriveFault "eERR_AXIS_DRIVE_FAULT" "drive fault",
        0x03FC DriveAbnormalDisable "eERR_AXIS_DRIVE_ABNORMAL_DISABLE" "drive disabled abnormally",
        0x0406 DriveEnableTout "eERR_AXIS_DRIVE_ENABLE_TOUT" "drive enable took too long",
        0x0407 DriveEnableToutRmt "eERR_AXIS_DRIVE_ENABLE_TOUT_RMT" "enable timeout, check drive access setting",
        0x0410 DriveClearErrorTout "eERR_AXIS_DRIVE_CLEAR_ERROR_TOUT" "clearing drive error took too long",
        0x041A DriveDisableTout "eERR_AXIS_DRIVE_DISABLE_TOUT" "disable took too long",
        0x0424 DriveHomeTout "eERR_AXIS_DRIVE_HOME_TOUT" "homing took too long",
        0x042E DriveHomeFailed "eERR_AXIS_DRIVE_HOME_FAILED" "homing failed",
        0x0456 VelLimit "eERR_AXIS_VEL_LIMIT" "velocity exceeded limit",
        0x4456 WarnVelLimit "eWRN_AXIS_VEL_LIMIT" "velocity clamped by limit (warning)",
        0x0460 AccLimit "eERR_AXIS_ACC_LIMIT" "acceleration exceeded limit",
        0x046A CurrLimit "eERR_AXIS_CURR_LIMIT" "current exceeded limit",
        0x0474 DampingratioLimit "eERR_AXIS_DAMPINGRATIO_LIMIT" "damping ratio out of range",
        0x047E FrequencyLimit "eERR_AXIS_FREQUENCY_LIMIT" "frequency out of range",
        0x07DA Swrl "eERR_AXIS_SWRL" "position command hit right software limit",
        0x07E4 Swll "eERR_AXIS_SWLL" "hit left software limit",
        0x07EE Hwrl "eERR_AXIS_HWRL" "right hardware limit triggered",
        0x07F8 Hwll "eERR_AXIS_HWLL" "left hardware limit triggered",
        0x0802 CompLimit "eERR_AXIS_COMP_LIMIT" "compensation exceeds maximum",
        0x083E Perr "eERR_AXIS_PERR" "position error exceeds limit",
        0x0848 Verr "eERR_AXIS_VERR" "velocity error exceeds limit",
        0x08A2 PvtMotionVelLimit "eERR_AXIS_PVT_MOTION_VEL_LIMIT" "PVT velocity out of protection range",
        0x08AC PvtMotionAccLimit "eERR_AXIS_PVT_MOTION_ACC_LIMIT" "PVT acceleration out of range",
        0x08B6 PvtMotionInvalidTime "eERR_AXIS_PVT_MOTION_INVALID_TIME" "PVT timing invalid",
        0x0BB8 CtrlErr "eERR_AXIS_CTRL_ERR" "internal axis error",
        0x0FA0 CmdGearDisabled "eERR_AXIS_CMD_GEAR_DISABLED" "gear command not allowed when gear disabled (i.e. GearIn before EnableGear)",
        0x0FA1 CmdInvalidAxisInCam "eERR_AXIS_CMD_INVALID_AXIS_IN_CAM" "gear command invalid for a cam axis",
        0x1388 CamCmdInvalidEngageWindow "eERR_CAM_CMD_INVALID_ENGAGE_WINDOW" "cam engage window out of range",
        0x1389 CamCmdInvalidEngagePosition "eERR_CAM_CMD_INVALID_ENGAGE_POSITION" "cam engage position outside the cam table",
        0x138A CamCmdInvalidMasterScaleFactor "eERR_CAM_CMD_INVALID_MASTER_SCALE_FACTOR" "cam master scale factor out of range",
        0x138B CamCmdInvalidCamScaleFactor "eERR_CAM_CMD_INVALID_CAM_SCALE_FACTOR" "cam scale factor out of range",
        0x138C CamCmdInvalidCamtableId "eERR_CAM_CMD_INVALID_CAMTABLE_ID" "cam table id out of range",
        0x138D CamCmdInvalidDisengageWindow "eERR_CAM_CMD_INVALID_DISENGAGE_WINDOW" "cam disengage window out of range",
        0x138E CamCmdInvalidDisengagePosition "eERR_CAM_CMD_INVALID_DISENGAGE_POSITION" "cam disengage position out of range",
        0x138F CamCmdInvalidOperationInEngagedState "eERR_CAM_CMD_INVALID_OPERATION_IN_ENGAGED_STATE" "cam command invalid while engaged",
        0x1390 CamCmdInvalidStartMode "eERR_CAM_CMD_INVALID_START_MODE" "cam start mode not a valid value",
        0x1391 CamCmdInvalidMoveMode "eERR_CAM_CMD_INVALID_MOVE_MODE" "cam move mode not a valid value",
        0x1392 CamEngagedFailed "eERR_CAM_ENGAGED_FAILED" "window too small: the master may pass the engage window",
        0x1393 CamCmdNotinuse "eERR_CAM_CMD_NOTINUSE" "ending a trajectory-mode cam is not supported",
        0x1394 CamCmdCamDisabled "eERR_CAM_CMD_CAM_DISABLED" "cam command not allowed while cam is disabled",
        0x1395 CamCmdInvalidAxisNotIncam "eERR_CAM_CMD_INVALID_AXIS_NOT_INCAM" "cam command invalid: axis is not a cam axis",
        0x1396 CamCmdInvalidAxisNotInDisengaged "eERR_CAM_CMD_INVALID_AXIS_NOT_IN_DISENGAGED" "cam command invalid: axis not disengaged",
        0x1397 CamCmdInvalidAxisInGear "eERR_CAM_CMD_INVALID_AXIS_IN_GEAR" "cam command invalid: axis is a gear axis",
    }
}

error_table! {
    /// HMPL ch. 18, table 18.1.3.1: group error codes (`0x82IIEEEE`).
    GroupError {
        0x000A CmdUnknown "eERR_CRD_CMD_UNKNOWN" "unknown group command",
        0x0014 CmdReachMaxNumAxis "eERR_CRD_CMD_REACH_MAX_NUM_AXIS" "group reached max axis count",
        0x001E CmdInvalidKinSetting "eERR_CRD_CMD_INVALID_KIN_SETTING" "invalid kinematics",
        0x001F CmdInvalidSpecificKin "eERR_CRD_CMD_INVALID_SPECIFIC_KIN" "invalid in special kinematics mode",
        0x0028 CmdAxisDuplicated "eERR_CRD_CMD_AXIS_DUPLICATED" "axis already in group",
        0x0032 CmdGrpSizeEmpty "eERR_CRD_CMD_GRP_SIZE_EMPTY" "group empty",
        0x003C CmdGrpSizeFull "eERR_CRD_CMD_GRP_SIZE_FULL" "group full",
        0x0046 CmdInvalidMoving "eERR_CRD_CMD_INVALID_MOVING" "invalid while group moving",
        0x0050 CmdInvalidDisabled "eERR_CRD_CMD_INVALID_DISABLED" "invalid while group not enabled",
        0x005A CmdInvalidInputshapingParameterIncomplete "eERR_CRD_CMD_INVALID_INPUTSHAPING_PARAMETER_INCOMPLETE" "shaper parameters incomplete",
        0x006E CmdInvalidState "eERR_CRD_CMD_INVALID_STATE" "invalid in current motion state",
        0x0078 CmdQueueFull "eERR_CRD_CMD_QUEUE_FULL" "'wait for previous command to finish' (queue full)",
        0x0082 CmdGrpAxisInvalid "eERR_CRD_CMD_GRP_AXIS_INVALID" "group invalid",
        0x008C CmdQueueIsNotEmpty "eERR_CRD_CMD_QUEUE_IS_NOT_EMPTY" "group queue not empty",
        0x0096 CmdInvalidQueueSize "eERR_CRD_CMD_INVALID_QUEUE_SIZE" "invalid queue size",
        0x00D2 CmdInvalidPos "eERR_CRD_CMD_INVALID_POS" "target position/orientation out of range",
        0x00DC CmdInvalidLinVel "eERR_CRD_CMD_INVALID_LIN_VEL" "crd cmd invalid lin vel",
        0x00E6 CmdInvalidLinAcc "eERR_CRD_CMD_INVALID_LIN_ACC" "crd cmd invalid lin acc",
        0x00F0 CmdInvalidLinDec "eERR_CRD_CMD_INVALID_LIN_DEC" "crd cmd invalid lin dec",
        0x00FA CmdInvalidLinJerk "eERR_CRD_CMD_INVALID_LIN_JERK" "crd cmd invalid lin jerk",
        0x0104 CmdInvalidLinSmTime "eERR_CRD_CMD_INVALID_LIN_SM_TIME" "crd cmd invalid lin sm time",
        0x010E CmdInvalidDampingratio "eERR_CRD_CMD_INVALID_DAMPINGRATIO" "crd cmd invalid dampingratio",
        0x0118 CmdInvalidFrequency "eERR_CRD_CMD_INVALID_FREQUENCY" "crd cmd invalid frequency",
        0x0140 CmdInvalidAngVel "eERR_CRD_CMD_INVALID_ANG_VEL" "crd cmd invalid ang vel",
        0x014A CmdInvalidAngAcc "eERR_CRD_CMD_INVALID_ANG_ACC" "crd cmd invalid ang acc",
        0x0154 CmdInvalidAngDec "eERR_CRD_CMD_INVALID_ANG_DEC" "crd cmd invalid ang dec",
        0x015E CmdInvalidAngJerk "eERR_CRD_CMD_INVALID_ANG_JERK" "crd cmd invalid ang jerk",
        0x0168 CmdInvalidAngSmTime "eERR_CRD_CMD_INVALID_ANG_SM_TIME" "crd cmd invalid ang sm time",
        0x0190 CmdInvalidVelScale "eERR_CRD_CMD_INVALID_VEL_SCALE" "crd cmd invalid vel scale",
        0x019A CmdInvalidTransVel "eERR_CRD_CMD_INVALID_TRANS_VEL" "crd cmd invalid trans vel",
        0x01A4 CmdInvalidTransDis "eERR_CRD_CMD_INVALID_TRANS_DIS" "crd cmd invalid trans dis",
        0x01A5 CmdInvalidTransDev "eERR_CRD_CMD_INVALID_TRANS_DEV" "crd cmd invalid trans dev",
        0x01A6 CmdInvalidTransCurve "eERR_CRD_CMD_INVALID_TRANS_CURVE" "crd cmd invalid trans curve",
        0x01B8 CmdTransModeUnknown "eERR_CRD_CMD_TRANS_MODE_UNKNOWN" "unknown transition mode",
        0x01C2 CmdCoordSysUnknown "eERR_CRD_CMD_COORD_SYS_UNKNOWN" "unknown coordinate system",
        0x01CC CmdBlendModeUnknown "eERR_CRD_CMD_BLEND_MODE_UNKNOWN" "unknown blending (buffer) mode",
        0x01FE CmdLinInvalidParam "eERR_CRD_CMD_LIN_INVALID_PARAM" "invalid line parameters",
        0x0262 CmdCircInvalidParam "eERR_CRD_CMD_CIRC_INVALID_PARAM" "invalid circle parameters",
        0x026C CmdCircInvalidCenter "eERR_CRD_CMD_CIRC_INVALID_CENTER" "center too close to start or end",
        0x0276 CmdCircAngleSmall "eERR_CRD_CMD_CIRC_ANGLE_SMALL" "central angle too small",
        0x0280 CmdCircInvalidRadius "eERR_CRD_CMD_CIRC_INVALID_RADIUS" "invalid radius (e.g. start and end radii differ)",
        0x028A CmdCircInvalidCoord "eERR_CRD_CMD_CIRC_INVALID_COORD" "invalid circle coordinate system",
        0x02C6 CmdBezierInvalidParam "eERR_CRD_CMD_BEZIER_INVALID_PARAM" "(Bezier: no HMPL API)",
        0x02D0 CmdBsplineInvalidParam "eERR_CRD_CMD_BSPLINE_INVALID_PARAM" "(B-spline: no HMPL API)",
        0x02DA CmdCurveInvalidStartpos "eERR_CRD_CMD_CURVE_INVALID_STARTPOS" "crd cmd curve invalid startpos",
        0x02E4 CmdCoordInvalidParam "eERR_CRD_CMD_COORD_INVALID_PARAM" "invalid coordinate-transform params",
        0x02EE CmdNurbsInvalidParam "eERR_CRD_CMD_NURBS_INVALID_PARAM" "(NURBS: no HMPL API)",
        0x02F8 CmdLookaheadInvalidParam "eERR_CRD_CMD_LOOKAHEAD_INVALID_PARAM" "invalid look-ahead params",
        0x03F2 AxisAbnormallyDisabled "eERR_CRD_AXIS_ABNORMALLY_DISABLED" "one or more group axes disabled abnormally",
        0x03FC AxisSwl "eERR_CRD_AXIS_SWL" "a group axis exceeded a software limit",
    }
}

macro_rules! sdo_aborts {
    ($( $code:literal $variant:ident $meaning:literal, )*) => {
        /// SDO abort codes (CiA 301; DXMC manual 9.3, table of SDO abort codes). A code no
        /// row lists is an error (`TryFromPrimitive`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, TryFromPrimitive, IntoPrimitive)]
        #[repr(u32)]
        pub enum SdoAbort { $( #[doc = $meaning] $variant = $code, )* }

        impl SdoAbort {
            /// Every row of the table.
            pub const ALL: &'static [SdoAbort] = &[ $( SdoAbort::$variant, )* ];

            /// The abort's meaning (CiA 301), in English.
            pub fn meaning(self) -> &'static str {
                match self { $( SdoAbort::$variant => $meaning, )* }
            }
        }
    };
}

sdo_aborts! {
    0x0503_0000 ToggleBit "toggle bit not alternated",
    0x0504_0000 Timeout "SDO protocol timed out",
    0x0504_0001 UnknownCommand "command specifier not valid or unknown",
    0x0601_0000 UnsupportedAccess "unsupported access to an object",
    0x0601_0001 WriteOnly "attempt to read a write-only object",
    0x0601_0002 ReadOnly "attempt to write a read-only object",
    0x0602_0000 NoObject "object does not exist in the object dictionary",
    0x0604_0041 NotMappable "object cannot be mapped to the PDO",
    0x0604_0042 PdoTooLong "the mapped objects would exceed the PDO length",
    0x0607_0010 LengthMismatch "data type does not match, length of service parameter does not match",
    0x0607_0012 LengthTooHigh "data type does not match, length of service parameter too high",
    0x0607_0013 LengthTooLow "data type does not match, length of service parameter too low",
    0x0609_0011 NoSubIndex "sub-index does not exist",
    0x0609_0030 ValueRange "value range of parameter exceeded",
    0x0609_0031 ValueTooHigh "value of parameter written too high",
    0x0609_0032 ValueTooLow "value of parameter written too low",
    0x0800_0000 General "general error",
    0x0800_0020 CannotStore "data cannot be transferred or stored",
    0x0800_0021 LocalControl "data cannot be transferred or stored because of local control",
    0x0800_0022 DeviceState "data cannot be transferred or stored because of the present device state",
}

impl SdoAbort {
    /// The 32-bit abort code the mailbox carries.
    pub fn code(self) -> u32 {
        self.into()
    }
}

impl fmt::Display for SdoAbort {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "SDO abort 0x{:08X}: {}", self.code(), self.meaning())
    }
}

impl std::error::Error for SdoAbort {}

/// Class byte `CC` of an error code (HMPL ch. 18.1).
const CLASS_AXIS: u32 = 0x83;
const CLASS_GROUP: u32 = 0x82;

/// One 32-bit HMPL error code, typed by its class.
///
/// Scripts see the unsigned value (`0x83020078`), so that hex literals compare equal;
/// HMPL's C `int` would show axis and group codes as negative numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ErrorCode {
    /// Class 0x00: a system error (table 18.1.1.1).
    System(SystemError),
    /// Class 0x83: an error of one axis (table 18.1.2.1).
    Axis {
        /// The axis id (`II`).
        axis: u8,
        /// The error id (`EEEE`).
        error: AxisError,
    },
    /// Class 0x82: an error of one group (table 18.1.3.1).
    Group {
        /// The group id (`II`).
        group: u8,
        /// The error id (`EEEE`).
        error: GroupError,
    },
}

impl ErrorCode {
    /// An axis error of axis `axis`.
    pub const fn axis(axis: u8, error: AxisError) -> Self {
        ErrorCode::Axis { axis, error }
    }

    /// A group error of group `group`.
    pub const fn group(group: u8, error: GroupError) -> Self {
        ErrorCode::Group { group, error }
    }

    /// The code as the manual writes it: `0xCCIIEEEE`.
    pub const fn code(self) -> u32 {
        match self {
            ErrorCode::System(e) => e.id() as u32,
            ErrorCode::Axis { axis, error } => CLASS_AXIS << 24 | (axis as u32) << 16 | error.id() as u32,
            ErrorCode::Group { group, error } => CLASS_GROUP << 24 | (group as u32) << 16 | error.id() as u32,
        }
    }

    /// Decodes a 32-bit code; `None` for 0 (no error) and for ids no table lists.
    pub fn from_code(code: u32) -> Option<Self> {
        let class = code >> 24;
        let index = (code >> 16) as u8;
        let id = code as u16;
        match class {
            0 if index == 0 => SystemError::try_from(id).ok().map(ErrorCode::System),
            CLASS_AXIS => AxisError::try_from(id).ok().map(|error| ErrorCode::axis(index, error)),
            CLASS_GROUP => GroupError::try_from(id).ok().map(|error| ErrorCode::group(index, error)),
            _ => None,
        }
    }

    /// The manual's name of the error id, e.g. `eERR_AXIS_CMD_INVALID_DISABLED`.
    pub const fn name(self) -> &'static str {
        match self {
            ErrorCode::System(e) => e.name(),
            ErrorCode::Axis { error, .. } => error.name(),
            ErrorCode::Group { error, .. } => error.name(),
        }
    }

    /// The manual's explanation of the error id.
    pub const fn meaning(self) -> &'static str {
        match self {
            ErrorCode::System(e) => e.meaning(),
            ErrorCode::Axis { error, .. } => error.meaning(),
            ErrorCode::Group { error, .. } => error.meaning(),
        }
    }
}

impl From<SystemError> for ErrorCode {
    fn from(e: SystemError) -> Self {
        ErrorCode::System(e)
    }
}

impl fmt::Display for ErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:08X} {} ({})", self.code(), self.name(), self.meaning())
    }
}

/// Describes any 32-bit code, known or not, for messages.
pub fn describe(code: u32) -> String {
    match ErrorCode::from_code(code) {
        Some(e) => e.to_string(),
        None if code == 0 => "0 (no error)".to_string(),
        None => format!("0x{code:08X} (unknown code)"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 18.1: the manual's own codes as byte literals, and every row of the three
    /// tables decoded from its code; ids no table lists decode to nothing.
    #[test]
    fn error_codes_round_trip() {
        let axis = ErrorCode::axis(2, AxisError::ALL[0]);
        assert_eq!(axis.code() >> 16, 0x8302);
        assert_eq!(ErrorCode::from_code(0x0000_010A), Some(ErrorCode::System(SystemError::TaskEmpty)));
        for &e in SystemError::ALL {
            assert_eq!(ErrorCode::from_code(e.id() as u32), Some(ErrorCode::System(e)));
        }
        for &e in AxisError::ALL {
            let code = ErrorCode::axis(7, e);
            assert_eq!(ErrorCode::from_code(code.code()), Some(code));
        }
        for &e in GroupError::ALL {
            let code = ErrorCode::group(3, e);
            assert_eq!(ErrorCode::from_code(code.code()), Some(code));
        }
        assert_eq!(ErrorCode::from_code(0), None);
        assert_eq!(ErrorCode::from_code(0x0000_FFFE), None);
        assert_eq!(ErrorCode::from_code(0x8300_FFFE), None);
        assert!(SystemError::try_from(0xFFFE).is_err());
    }

    /// CiA 301 SDO abort codes: the 32-bit code each row carries, and back.
    #[test]
    fn sdo_abort_codes_round_trip() {
        assert_eq!(SdoAbort::NoObject.code(), 0x0602_0000);
        assert_eq!(SdoAbort::try_from(0x0609_0011), Ok(SdoAbort::NoSubIndex));
        for &abort in SdoAbort::ALL {
            assert_eq!(SdoAbort::try_from(abort.code()), Ok(abort));
        }
        assert!(SdoAbort::try_from(0x0602_0001).is_err());
        assert!(SdoAbort::try_from(0).is_err());
    }
}

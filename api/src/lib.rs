//! The contract between scripts and the controller: the registry of API functions, the
//! HMPL error codes, the DXMC alarm format and the constants scripts see.

// Every public item is part of a contract with other processes or crates: say what it is.

pub mod alarms;
pub mod analog;
pub mod call;
pub mod catalogue;
pub mod constants;
pub mod docs;
pub mod errors;
pub mod event_rate;
mod functions;
pub mod hcv;
pub mod libm;
pub mod registry;
pub mod strings;
pub mod system_vars;

pub use errors::{AxisError, ErrorCode, GroupError, SdoAbort, SystemError};
pub use functions::{Command, CommandCall, Local, LocalCall, Query, QueryCall};
pub use registry::{ArgSpec, ArgType, Func, FunctionSpec, Kind, Quantity, Refusal, Role, ValueType};

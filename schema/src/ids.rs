//! How many of each thing the controller addresses: the sizes of every table the
//! snapshot and the shared data hold.

/// 32 drives + 64 virtual axes (DXMC), more than HMPL's 16.
pub const MAX_AXES: usize = 96;
/// Group ids HMPL addresses (0x00..0x0f).
pub const MAX_GROUPS: usize = 16;
/// HMPL task ids 0..63 (HMPL ch. 16).
pub const MAX_TASKS: usize = 64;

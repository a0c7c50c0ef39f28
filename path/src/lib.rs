//! The group interpolator of HMPL chapter 8, free of the controller around it: the
//! segments a group command makes (`segment.rs`), and, with later modules, their
//! construction from the commands, corner transitions, coordinate frames and the planning
//! of the path velocity. Everything here is computed from its inputs alone, never from a
//! clock, so the kernel can run it in its cycle.

pub mod planner;
pub mod segment;

pub use planner::{BufferMode, Limits, LookAhead, Motion, Planner, Profile, Sample};
pub use segment::{Pose, Segment};

//! The group interpolator of HMPL chapter 8, free of the controller around it: the
//! segments a group command makes (`segment.rs`), their construction from the commands
//! (`commands.rs`), corner transitions (`blend.rs`), coordinate systems (`frames.rs`), the
//! planning of the path velocity (`planner/`), its sample of each cycle (`sample.rs`) and the
//! group's smoothing along the path (`smoothing.rs`). Everything here is computed from its
//! inputs alone, never from a clock, so the kernel can run it in its cycle.

pub mod blend;
pub mod commands;
pub mod frames;
pub mod planner;
pub mod sample;
pub mod segment;
pub mod smoothing;

pub use planner::{BufferMode, Limits, LookAhead, Motion, Planner, Profile};
pub use sample::{Corners, Sample};
pub use segment::{Pose, Segment};

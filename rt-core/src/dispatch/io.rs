//! HMPL ch. 9: the controller's digital I/O.

use super::{Done, Outcome, drive_objects::out_of_range};
use crate::io::NoSuchPin;

/// Ch. 9: 0, or -1 for a pin that does not exist.
pub(super) fn pin(result: Result<(), NoSuchPin>) -> Outcome {
    result.map(|()| Done::Now).map_err(|_| out_of_range())
}

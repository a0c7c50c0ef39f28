//! HMPL ch. 6 (electronic gear) and 7 (gantry): couplings between axes, which the kernel
//! keeps; groups (HMPL ch. 8) join them here.

use api::ErrorCode;

use super::{Outcome, axis::motion, now};
use kernel::Kernel;

/// A coupling command: needs EtherCAT in Op, like every motion command.
pub(super) fn coupling(
    m: &mut crate::machine::Machine,
    f: impl FnOnce(&mut Kernel) -> Result<(), ErrorCode>,
) -> Outcome {
    motion(m, |m| now(f(&mut m.kernel)))
}

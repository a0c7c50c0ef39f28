//! HMPL ch. 13: an axis' touch probes, carried out on the kernel's `TouchProbes` (the
//! drive's 0x60B8 goes out with the axis' next frame).

use api::AxisError;

use super::Outcome;
use super::axis::axis;
use crate::machine::Machine;
use kernel::touch_probe::TouchProbes;

/// Runs `f` on axis `a`'s touch probes.
pub(super) fn probes(m: &mut Machine, a: i64, f: impl FnOnce(&mut TouchProbes) -> Result<(), AxisError>) -> Outcome {
    axis(m, a, |ax| f(ax.touch_probes_mut()))
}

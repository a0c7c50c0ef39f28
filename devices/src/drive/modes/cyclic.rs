//! Cyclic synchronous modes (CoE manual 3.6 to 3.8): csp follows 0x607A, csv 0x60FF and
//! cst 0x6071 every cycle, with no profile of their own; halt is ignored. Statusword bit
//! 12 is "target used as loop input" (tables 3-14 and 3-15).

use crate::drive::modes::{ModeInput, ModeOfOperation, Setpoint};
use crate::drive::od;

pub fn step(mode: ModeOfOperation, input: &ModeInput) -> Setpoint {
    match mode {
        ModeOfOperation::CyclicSyncPosition => {
            let pos = input.od.get(od::TARGET_POSITION) as f64;
            Setpoint::Position { pos, vel: (pos - input.demand.pos) / input.period_s }
        }
        ModeOfOperation::CyclicSyncVelocity => Setpoint::Velocity { vel: input.od.get(od::TARGET_VELOCITY) as f64 },
        _ => Setpoint::Force(input.od.get(od::TARGET_TORQUE) as f64 / 1000.0),
    }
}

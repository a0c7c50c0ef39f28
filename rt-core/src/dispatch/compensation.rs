//! HMPL ch. 14: dynamic error compensation, kept by the kernel (`motion/compensation.rs`).

use api::call::Doubles;

use super::{Done, Outcome, axis::motion, now};
use crate::machine::Machine;
use kernel::compensation::Setup;

/// HMPL 14.4: a 1-D table.
pub(super) fn setup_1d(
    m: &mut Machine,
    axis: i64,
    start: i64,
    base: f64,
    interval: f64,
    num: i64,
    reference: i64,
) -> Outcome {
    // Out-of-range integers become numbers the setup refuses.
    let setup = Setup::new(start, &[base], &[interval], &[num as f64], &[reference as f64], 1);
    motion(m, |m| now(m.kernel.setup_comp(axis, setup)))
}

/// HMPL 14.5, 14.6: a 2-D or 3-D table, each argument a table of `dims` numbers.
pub(super) fn setup_nd(m: &mut Machine, axis: i64, start: i64, tables: [&Doubles; 4], dims: usize) -> Outcome {
    let mut numbers = [[0.0; 3]; 4];
    let mut lens = [0; 4];
    for ((table, row), len) in tables.iter().zip(&mut numbers).zip(&mut lens) {
        *len = table.len().min(dims);
        for (slot, value) in row.iter_mut().zip(table.iter()) {
            *slot = value;
        }
    }
    let [b, i, n, r] = &numbers;
    let setup = Setup::new(start, &b[..lens[0]], &i[..lens[1]], &n[..lens[2]], &r[..lens[3]], dims);
    motion(m, |m| now(m.kernel.setup_comp(axis, setup)))
}

/// HMPL 14.2: answered once the values are copied, before the kernel's step (`resume`).
pub(super) fn enable(m: &mut Machine, axis: i64) -> Outcome {
    motion(m, |m| {
        m.kernel.enable_comp(axis)?;
        Ok(Done::Later)
    })
}

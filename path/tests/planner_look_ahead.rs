//! BM_LOOKAHEAD (HMPL 8.1.4) against the time-optimal bound for the same limits.

mod common;

use common::look_ahead::{bound_time, planner_time};
use path::BufferMode;

#[test]
fn look_ahead_comes_within_10_percent_of_the_time_optimal_bound() {
    let (look_ahead, buff, bound) = (planner_time(BufferMode::LookAhead), planner_time(BufferMode::Buff), bound_time());
    println!("200 segments of 1 mm: BM_LOOKAHEAD {look_ahead:.4} s, BM_BUFF {buff:.4} s, bound {bound:.4} s");
    assert!(look_ahead >= bound * 0.99, "below the bound: {look_ahead} < {bound}");
    assert!(look_ahead <= bound * 1.10, "{look_ahead} s is more than 10 % above {bound} s");
    assert!(buff > 2.0 * look_ahead, "stopping at every junction takes far longer: {buff}");
}

//! The console's way into the core: the DRL program control and the controller state of
//! the Modbus server (DXMC manual appendix A.3) are carried out in the RT thread, which
//! owns the tasks and the axes. A bounded lock-free queue, as between the core and the
//! supervisor: the console never waits for a cycle, the cycle never waits for the console.

use std::sync::Arc;

use crossbeam::queue::ArrayQueue;
use num_enum::{FromPrimitive, IntoPrimitive};

/// Orders in flight; a console sends a few per Modbus request.
const CAPACITY: usize = 64;
/// Orders the RT thread carries out per cycle.
const ORDERS_PER_CYCLE: usize = 8;

/// DXMC manual 3.6 and A.3, registers 0x6A80 (current) and 0x6A81 (target). An unknown
/// 0x6A80 word reads as `Initial`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, FromPrimitive, IntoPrimitive)]
#[repr(u32)]
pub enum ControllerState {
    /// Power-up, before the first switch.
    #[num_enum(default)]
    Initial = 0,
    /// A switch failed (here: the EtherCAT network is not in Op).
    Fail = 1,
    /// "Standby": motion commands are refused (DXMC 0x0020).
    Edit = 2,
    /// "Online operation".
    Run = 4,
    /// "Online diagnosis": motion allowed, as in Run.
    Diagnosis = 5,
}

impl ControllerState {
    /// A target state the console may ask for (0x6A81 takes 2, 4 and 5).
    pub fn target(value: u16) -> Option<Self> {
        let state = ControllerState::from(u32::from(value));
        matches!(state, ControllerState::Edit | ControllerState::Run | ControllerState::Diagnosis).then_some(state)
    }

    /// DXMC 0x0020: motion commands need online operation or online diagnosis.
    pub fn allows_motion(self) -> bool {
        matches!(self, ControllerState::Run | ControllerState::Diagnosis)
    }
}

/// What a console asks the RT thread to do (DXMC A.3's program control and state registers).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConsoleOrder {
    /// Start a task's program at its top level (its program path is in its slot).
    StartTask(u8),
    /// Stop a task as `StopTask` does.
    StopTask(u8),
    /// Switch the controller state (0x6A81).
    SwitchState(ControllerState),
    /// Set a task's run speed, 1..100 % (DXMC A.3, 0x6B03).
    SetRunSpeed {
        /// The task, 0..MAX_TASKS.
        task: u8,
        /// The run speed, percent.
        pct: u8,
    },
}

/// The console's end.
#[derive(Clone)]
pub struct Console {
    orders: Arc<ArrayQueue<ConsoleOrder>>,
}

/// The RT thread's end.
pub struct ConsoleInbox {
    orders: Arc<ArrayQueue<ConsoleOrder>>,
}

/// A console's two ends: the console (the Modbus server, the DRL console) keeps the
/// `Console`, the controller takes the inbox (`RunOptions::console`).
pub fn channel() -> (Console, ConsoleInbox) {
    let orders = Arc::new(ArrayQueue::new(CAPACITY));
    (Console { orders: orders.clone() }, ConsoleInbox { orders })
}

/// The queue to the RT thread is full: the order was not sent.
#[derive(Debug, thiserror::Error)]
#[error("the controller is busy: too many console orders in flight")]
pub struct ConsoleBusy;

impl Console {
    /// Queues `order` for the next cycles without waiting.
    pub fn send(&self, order: ConsoleOrder) -> Result<(), ConsoleBusy> {
        self.orders.push(order).map_err(|_| ConsoleBusy)
    }
}

impl ConsoleInbox {
    /// The orders for this cycle, at most `ORDERS_PER_CYCLE`.
    pub fn drain(&self) -> impl Iterator<Item = ConsoleOrder> + '_ {
        std::iter::from_fn(|| self.orders.pop()).take(ORDERS_PER_CYCLE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// DXMC A.3: 0x6A80 reads 0 Initial, 1 Fail, 2 Edit, 4 Run, 5 Diagnosis; 0x6A81 takes 2, 4, 5.
    #[test]
    fn controller_state_codes() {
        let rows = [
            (0, ControllerState::Initial, None),
            (1, ControllerState::Fail, None),
            (2, ControllerState::Edit, Some(ControllerState::Edit)),
            (3, ControllerState::Initial, None),
            (4, ControllerState::Run, Some(ControllerState::Run)),
            (5, ControllerState::Diagnosis, Some(ControllerState::Diagnosis)),
        ];
        for (code, current, target) in rows {
            assert_eq!(ControllerState::from(code), current, "0x6A80 = {code}");
            assert_eq!(ControllerState::target(code as u16), target, "0x6A81 = {code}");
        }
        assert!(ControllerState::Run.allows_motion() && ControllerState::Diagnosis.allows_motion());
        assert!(!ControllerState::Edit.allows_motion());
    }

    #[test]
    fn at_most_a_few_orders_per_cycle() {
        let (console, inbox) = channel();
        for t in 0..20 {
            console.send(ConsoleOrder::StartTask(t)).unwrap();
        }
        assert_eq!(inbox.drain().count(), ORDERS_PER_CYCLE);
        assert_eq!(inbox.drain().count(), ORDERS_PER_CYCLE);
        assert_eq!(inbox.drain().count(), 4);
    }
}

//! The EtherCAT state machine of a slave (CoE manual 2.3, table 2-3; ETG.1000.6 for the
//! codes the manual does not give).

/// AL states, with their AL Control / AL Status codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
#[repr(u8)]
pub enum AlState {
    Init = 1,
    PreOp = 2,
    SafeOp = 4,
    Op = 8,
}

impl AlState {
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The next state up, one level at a time.
    fn up(self) -> Option<AlState> {
        match self {
            AlState::Init => Some(AlState::PreOp),
            AlState::PreOp => Some(AlState::SafeOp),
            AlState::SafeOp => Some(AlState::Op),
            AlState::Op => None,
        }
    }
}

/// AL status codes (ETG.1000.6, table "AL Status Codes").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum AlStatusCode {
    InvalidRequestedStateChange = 0x0011,
    InvalidInputMapping = 0x0024,
    InvalidOutputMapping = 0x0025,
    InvalidDcSyncConfiguration = 0x0030,
    InvalidSyncCycleTime = 0x0035,
}

impl AlStatusCode {
    pub fn code(self) -> u16 {
        self as u16
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Esm {
    state: AlState,
    error: Option<AlStatusCode>,
}

impl Default for Esm {
    fn default() -> Self {
        Esm { state: AlState::Init, error: None }
    }
}

impl Esm {
    pub fn state(&self) -> AlState {
        self.state
    }

    /// The AL status error indication and its code, if the last request was refused.
    pub fn error(&self) -> Option<AlStatusCode> {
        self.error
    }

    /// A state request of the master: up one level at a time ("no skipping"), down to
    /// any lower state. `check` validates the slave's configuration for the transition.
    pub fn request(
        &mut self,
        target: AlState,
        check: impl FnOnce(AlState, AlState) -> Result<(), AlStatusCode>,
    ) -> Result<(), AlStatusCode> {
        let allowed = target <= self.state || self.state.up() == Some(target);
        let result = if allowed { check(self.state, target) } else { Err(AlStatusCode::InvalidRequestedStateChange) };
        match result {
            Ok(()) => {
                self.state = target;
                self.error = None;
            }
            Err(code) => self.error = Some(code),
        }
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CoE manual 2.3: states may not be skipped going up; ETG.1000.6: down to any state.
    #[test]
    fn up_one_level_at_a_time_down_to_any() {
        let ok = |_: AlState, _: AlState| Ok(());
        let mut esm = Esm::default();
        assert_eq!(esm.request(AlState::Op, ok), Err(AlStatusCode::InvalidRequestedStateChange));
        assert_eq!(esm.state(), AlState::Init);
        assert_eq!(esm.error(), Some(AlStatusCode::InvalidRequestedStateChange));
        for target in [AlState::PreOp, AlState::SafeOp, AlState::Op] {
            assert_eq!(esm.request(target, ok), Ok(()));
        }
        assert_eq!(esm.error(), None);
        assert_eq!(esm.request(AlState::Init, ok), Ok(()));
        assert_eq!(esm.state(), AlState::Init);
    }
}

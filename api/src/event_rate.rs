//! HMPL 2.19/2.20: the rate at which one sender may put events on the event stream, on
//! controller time; shared by the scripts' `SendEvent`/`SendMsgEvent` and the Native ASCII
//! server's `SendEvent`.

/// Events at 1000 per second on average, in bursts of up to 100.
#[derive(Clone, Copy, Debug, Default)]
pub struct Throttle {
    tokens: f64,
    last_ms: Option<u64>,
}

const EVENTS_PER_MS: f64 = 1.0;
const BURST: f64 = 100.0;

impl Throttle {
    /// Takes one event's token at controller time `now_ms`; otherwise the ms until one is there.
    pub fn take(&mut self, now_ms: u64) -> Result<(), u64> {
        let last = *self.last_ms.get_or_insert_with(|| {
            self.tokens = BURST;
            now_ms
        });
        self.tokens = (self.tokens + now_ms.saturating_sub(last) as f64 * EVENTS_PER_MS).min(BURST);
        self.last_ms = Some(now_ms);
        if self.tokens >= 1.0 {
            self.tokens -= 1.0;
            Ok(())
        } else {
            Err(((1.0 - self.tokens) / EVENTS_PER_MS).ceil() as u64)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 2.19: a burst of 100, then one event per ms of controller time.
    #[test]
    fn the_throttle_lets_1000_events_per_second_through() {
        let mut t = Throttle::default();
        let mut sent = 0;
        let mut now = 0;
        while now <= 2000 {
            match t.take(now) {
                Ok(()) => sent += 1,
                Err(wait) => {
                    assert!(wait >= 1);
                    now += wait;
                }
            }
        }
        assert!((2090..=2101).contains(&sent), "{sent} events in 2 s");
        assert_eq!(Throttle::default().take(5), Ok(()), "the first event goes at once");
    }
}

//! The process image between the cycle and the master's thread, without a lock: the
//! cycle publishes its outputs and rings the master, and takes the inputs of the last
//! frame that came back (triple buffers: neither side ever waits for the other, and the
//! buffers are made once, at start-up).
//!
//! The inputs the cycle reads were sent one cycle before: the frame of cycle n carries
//! cycle n's outputs and brings back the inputs cycle n+1 reads, as a master that sends
//! its frame at the start of the next cycle does.

use std::thread::Thread;

use devices::ecat::{AlState, Exchange};
use triple_buffer::{Input, Output, TripleBuffer};

/// What the master's thread publishes after each frame.
#[derive(Clone, Debug)]
pub struct Returned {
    /// Frames exchanged since start-up; the cycle tells a fresh frame by it.
    pub sequence: u64,
    /// The working counter of the process data, `None` when no frame came back in time.
    pub working_counter: Option<u16>,
    /// The lowest AL state the slaves reported in the frame.
    pub lowest: AlState,
    /// The input image, as the cycle lays it out.
    pub inputs: Vec<u8>,
}

/// The cycle's side.
pub struct CycleSide {
    outputs: Input<Vec<u8>>,
    returned: Output<Returned>,
    master: Thread,
    last_sequence: u64,
    expected_working_counter: u16,
    state: AlState,
}

/// The master thread's side.
pub struct MasterSide {
    /// The outputs the cycle published last.
    pub outputs: Output<Vec<u8>>,
    /// Where the frames' inputs go.
    pub returned: Input<Returned>,
}

/// Both sides, for images of these lengths; `master` is the thread the cycle rings.
pub fn handoff(
    outputs_len: usize,
    inputs_len: usize,
    expected_working_counter: u16,
    master: Thread,
) -> (CycleSide, MasterSide) {
    let (outputs_in, outputs_out) = TripleBuffer::new(&vec![0u8; outputs_len]).split();
    let initial = Returned { sequence: 0, working_counter: None, lowest: AlState::Init, inputs: vec![0; inputs_len] };
    let (returned_in, returned_out) = TripleBuffer::new(&initial).split();
    (
        CycleSide {
            outputs: outputs_in,
            returned: returned_out,
            master,
            last_sequence: 0,
            expected_working_counter,
            state: AlState::Op,
        },
        MasterSide { outputs: outputs_out, returned: returned_in },
    )
}

impl CycleSide {
    /// Takes the inputs of the last frame into `inputs`, hands `outputs` over for the next
    /// one and rings the master. Never waits: no lock, no allocation, one futex wake.
    pub fn exchange(&mut self, outputs: &[u8], inputs: &mut [u8]) -> Exchange {
        let returned = self.returned.read();
        let fresh = returned.sequence != self.last_sequence;
        self.last_sequence = returned.sequence;
        let result = match returned.working_counter {
            _ if !fresh => Exchange::Missing,
            None => Exchange::Missing,
            Some(found) if found != self.expected_working_counter => {
                Exchange::WorkingCounter { found, expected: self.expected_working_counter }
            }
            Some(_) => Exchange::Fresh,
        };
        if result != Exchange::Missing {
            self.state = returned.lowest;
            let n = inputs.len().min(returned.inputs.len());
            inputs[..n].copy_from_slice(&returned.inputs[..n]);
        }
        let buffer = self.outputs.input_buffer_mut();
        let n = buffer.len().min(outputs.len());
        buffer[..n].copy_from_slice(&outputs[..n]);
        self.outputs.publish();
        self.master.unpark();
        result
    }

    /// The lowest AL state of the last frame back (Op, as the start-up left it, before).
    pub fn state(&self) -> AlState {
        self.state
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A master that answers each ring with the outputs plus one, and the working
    /// counter it is told; the cycle sees each frame once, a cycle later.
    #[test]
    fn the_cycle_takes_the_last_frame_and_hands_its_outputs_over() {
        let (mut cycle, mut master) = handoff(2, 2, 3, std::thread::current());
        let mut inputs = [0u8; 2];
        assert_eq!(cycle.exchange(&[1, 2], &mut inputs), Exchange::Missing, "no frame yet");
        let answer = |master: &mut MasterSide, sequence, wkc| {
            let outputs = master.outputs.read().clone();
            let slot = master.returned.input_buffer_mut();
            slot.sequence = sequence;
            slot.working_counter = wkc;
            slot.lowest = AlState::Op;
            slot.inputs = outputs.iter().map(|b| b + 1).collect();
            master.returned.publish();
        };
        answer(&mut master, 1, Some(3));
        assert_eq!(cycle.exchange(&[5, 6], &mut inputs), Exchange::Fresh);
        assert_eq!(inputs, [2, 3], "the frame of the first outputs");
        assert_eq!(cycle.exchange(&[7, 8], &mut inputs), Exchange::Missing, "no frame since");
        assert_eq!(inputs, [2, 3], "the last inputs stay");
        answer(&mut master, 2, Some(1));
        assert_eq!(cycle.exchange(&[0, 0], &mut inputs), Exchange::WorkingCounter { found: 1, expected: 3 });
        assert_eq!(inputs, [8, 9], "the latest outputs went out");
        answer(&mut master, 3, None);
        assert_eq!(cycle.exchange(&[0, 0], &mut inputs), Exchange::Missing, "a frame that did not come back");
    }
}

//! A command on the wire (`ipc::call::Request`): the one place that knows how a typed
//! call (`api::CommandCall`) lies in the argument words and the blob, both ways.
//!
//! In the declaration's order, each argument takes one word: an `Int` its value, a
//! `Double` the bits of its `f64`, a `Bool` 0 or 1. A `Str` or `Bytes` also puts its bytes
//! in the blob, a `Doubles` its numbers as 8-byte little-endian `f64`s; their word is
//! their length (bytes for `Str` and `Bytes`, numbers for `Doubles`), and the blob holds
//! them one after the other in argument order. `MovePVT(axis, time, pos, vel, num_pt)` is
//! thus the words `axis, len(time), len(pos), len(vel), num_pt` and the blob
//! `time ++ pos ++ vel`.

use std::borrow::Cow;

use api::call::{Doubles, Sink, Source, TypedCall};
use api::{Command, CommandCall};
use ipc::call::{BLOB_SIZE, MAX_ARGS, Request};

/// Why a call does not fit in a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum EncodeError {
    /// Strings and tables together exceed the blob.
    #[error("the arguments exceed {BLOB_SIZE} bytes")]
    BlobFull,
}

/// Why a request is not a call of its function: only a sender that does not use `encode`
/// makes one. The core answers it with HMPL's "invalid argument".
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    /// No command has the request's function id.
    #[error("no command has id {0}")]
    UnknownFunction(u16),
    /// The request has another number of argument words than the function's arguments.
    #[error("{func:?} takes {takes} arguments, the request has {given}")]
    ArgumentCount {
        /// The function.
        func: Command,
        /// Its arguments.
        takes: usize,
        /// The request's words.
        given: usize,
    },
    /// A string or table lies outside the blob's used bytes.
    #[error("argument {0} lies outside the blob")]
    OutsideBlob(usize),
}

/// Writes `call` into `request`: its function id, argument words and blob.
pub fn encode(call: &CommandCall, request: &mut Request) -> Result<(), EncodeError> {
    request.func = call.func().id();
    request.argc = 0;
    request.blob_len = 0;
    call.write(&mut Writer(request))
}

/// The typed call a request carries. Reads the blob in place: no allocation.
pub fn decode(request: &Request) -> Result<CommandCall<'_>, DecodeError> {
    let func = Command::from_id(request.func).ok_or(DecodeError::UnknownFunction(request.func))?;
    let takes = func.spec().args.len();
    let given = request.argc as usize;
    let count = DecodeError::ArgumentCount { func, takes, given };
    if given != takes || request.blob_len as usize > BLOB_SIZE {
        return Err(count);
    }
    let mut reader = Reader { request, next: 0, blob_at: 0 };
    let call = CommandCall::read(func, &mut reader)?;
    Ok(call)
}

struct Writer<'r>(&'r mut Request);

impl Writer<'_> {
    fn word(&mut self, word: u64) -> Result<(), EncodeError> {
        // The registry's longest function has fewer arguments than a request has words
        // (a test holds every function to it).
        assert!((self.0.argc as usize) < MAX_ARGS, "a registry function has more than {MAX_ARGS} arguments");
        self.0.args[self.0.argc as usize] = word;
        self.0.argc += 1;
        Ok(())
    }

    fn blob(&mut self, bytes: &[u8], len: usize) -> Result<(), EncodeError> {
        if !self.0.append_blob(bytes) {
            return Err(EncodeError::BlobFull);
        }
        self.word(len as u64)
    }
}

impl Sink for Writer<'_> {
    type Error = EncodeError;

    fn int(&mut self, value: i64) -> Result<(), EncodeError> {
        self.word(value as u64)
    }

    fn double(&mut self, value: f64) -> Result<(), EncodeError> {
        self.word(value.to_bits())
    }

    fn bool(&mut self, value: bool) -> Result<(), EncodeError> {
        self.word(value as u64)
    }

    fn str(&mut self, value: &[u8]) -> Result<(), EncodeError> {
        self.blob(value, value.len())
    }

    fn bytes(&mut self, value: &[u8]) -> Result<(), EncodeError> {
        self.blob(value, value.len())
    }

    fn doubles(&mut self, value: &Doubles) -> Result<(), EncodeError> {
        match value {
            Doubles::LittleEndian(bytes) => self.blob(bytes, value.len()),
            Doubles::Values(numbers) => {
                let bytes: Vec<u8> = numbers.iter().flat_map(|n| n.to_le_bytes()).collect();
                self.blob(&bytes, numbers.len())
            }
        }
    }
}

struct Reader<'r> {
    request: &'r Request,
    next: usize,
    blob_at: usize,
}

impl<'r> Reader<'r> {
    fn word(&mut self) -> u64 {
        // `decode` checked that the request has a word for every argument.
        let word = self.request.args[self.next];
        self.next += 1;
        word
    }

    /// The next `unit`-byte items of the blob, their count in the argument word.
    fn blob(&mut self, unit: usize) -> Result<&'r [u8], DecodeError> {
        let index = self.next;
        let bytes = usize::try_from(self.word() as i64).ok().and_then(|n| n.checked_mul(unit));
        let end = bytes.and_then(|b| self.blob_at.checked_add(b));
        let piece =
            end.and_then(|end| self.request.blob().get(self.blob_at..end)).ok_or(DecodeError::OutsideBlob(index))?;
        self.blob_at += piece.len();
        Ok(piece)
    }
}

impl<'r> Source<'r> for Reader<'r> {
    type Error = DecodeError;

    fn int(&mut self) -> Result<i64, DecodeError> {
        Ok(self.word() as i64)
    }

    fn double(&mut self) -> Result<f64, DecodeError> {
        Ok(f64::from_bits(self.word()))
    }

    fn bool(&mut self) -> Result<bool, DecodeError> {
        Ok(self.word() != 0)
    }

    fn str(&mut self) -> Result<Cow<'r, [u8]>, DecodeError> {
        self.blob(1).map(Cow::Borrowed)
    }

    fn bytes(&mut self) -> Result<Cow<'r, [u8]>, DecodeError> {
        self.blob(1).map(Cow::Borrowed)
    }

    fn doubles(&mut self) -> Result<Doubles<'r>, DecodeError> {
        self.blob(8).map(Doubles::LittleEndian)
    }
}

#[cfg(test)]
mod tests {
    use api::call::{Value, from_values};
    use api::{ArgType, Role};

    use super::*;

    /// Neutral values for every argument of `func`, different for each seed.
    fn values(func: Command, seed: i64) -> Vec<Value> {
        let spec = func.spec();
        (0..spec.args.len() as i64)
            .zip(spec.args)
            .map(|(i, arg)| {
                let n = seed * 31 + i;
                match arg.ty {
                    ArgType::Int => Value::Int(n - 7),
                    ArgType::Double => Value::Double(n as f64 * 0.25 - 3.0),
                    ArgType::Bool => Value::Bool(n % 2 == 0),
                    ArgType::Str => Value::Str(format!("f{n}").into_bytes()),
                    ArgType::Bytes => Value::List((0..n % 5 + 1).map(|b| Value::Int(b * 40)).collect()),
                    ArgType::Doubles => {
                        Value::List((0..n % 4 + 2).map(|x| Value::Double(x as f64 * 1.5 - n as f64)).collect())
                    }
                    other => panic!("{}: a command takes no {other:?}", spec.name),
                }
            })
            .collect()
    }

    /// Every command of the registry, from neutral values to a request and back: the same
    /// typed call, with one word per argument.
    #[test]
    fn every_command_round_trips_through_a_request() {
        for &func in Command::ALL {
            for seed in [1, 2, 5] {
                let values = values(func, seed);
                let call: CommandCall = from_values(func, &values).unwrap_or_else(|e| panic!("{func:?}: {e:?}"));
                let mut request = Request::new(0);
                encode(&call, &mut request).unwrap();
                assert_eq!((request.func, request.argc as usize), (func.id(), func.spec().args.len()), "{func:?}");
                assert_eq!(decode(&request), Ok(call), "{func:?} seed {seed}");
            }
        }
    }

    /// HMPL 5.2.8: MovePVT's layout, byte for byte. Words: the axis, the three tables'
    /// lengths, num_pt; blob: time, pos, vel as little-endian `f64`s one after the other.
    #[test]
    fn pvt_layout() {
        let values = [
            Value::Int(2),
            Value::List(vec![Value::Int(0), Value::Double(1000.0)]),
            Value::List(vec![Value::Double(1.5), Value::Int(-2)]),
            Value::List(vec![Value::Int(0), Value::Double(0.5)]),
            Value::Int(2),
        ];
        let call: CommandCall = from_values(Command::MovePVT, &values).unwrap();
        let mut request = Request::new(0);
        encode(&call, &mut request).unwrap();
        assert_eq!(&request.args[..request.argc as usize], &[2, 2, 2, 2, 2]);
        #[rustfmt::skip]
        let blob: [u8; 48] = [
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, // time[0] = 0.0
            0x00, 0x00, 0x00, 0x00, 0x00, 0x40, 0x8F, 0x40, // time[1] = 1000.0
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF8, 0x3F, // pos[0] = 1.5
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC0, // pos[1] = -2.0
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, // vel[0] = 0.0
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xE0, 0x3F, // vel[1] = 0.5
        ];
        assert_eq!(request.blob(), &blob);
        let Ok(CommandCall::MovePVT { axis_id: 2, time, pos, vel, num_pt: 2 }) = decode(&request) else {
            panic!("not MovePVT(2, .., 2)")
        };
        let numbers = |d: &Doubles| d.iter().collect::<Vec<_>>();
        assert_eq!(
            (numbers(&time), numbers(&pos), numbers(&vel)),
            (vec![0.0, 1000.0], vec![1.5, -2.0], vec![0.0, 0.5])
        );
    }

    /// A string and a byte table: their lengths in the words, their bytes in the blob.
    #[test]
    fn string_and_bytes_layout() {
        let values = [Value::Int(3), Value::Str(b"main".to_vec())];
        let call: CommandCall = from_values(Command::StartTaskFunc, &values).unwrap();
        let mut request = Request::new(0);
        encode(&call, &mut request).unwrap();
        assert_eq!((&request.args[..2], request.blob()), (&[3, 4][..], &b"main"[..]));
        let values =
            [1, 0x6060, 0, 1].map(Value::Int).into_iter().chain([Value::List(vec![Value::Int(8)])]).collect::<Vec<_>>();
        let call: CommandCall = from_values(Command::WriteSDOEx, &values).unwrap();
        encode(&call, &mut request).unwrap();
        assert_eq!((&request.args[..5], request.blob()), (&[1, 0x6060, 0, 1, 1][..], &[8u8][..]));
    }

    /// What a sender other than `encode` may put in a request: each is refused, none panics.
    #[test]
    fn malformed_requests() {
        assert_eq!(decode(&Request::new(999)), Err(DecodeError::UnknownFunction(999)));
        let mut request = Request::new(Command::MoveAbs.id());
        request.push_int(0);
        assert!(matches!(decode(&request), Err(DecodeError::ArgumentCount { takes: 2, given: 1, .. })));
        request.push_double(1.0);
        request.push_int(0);
        assert!(matches!(decode(&request), Err(DecodeError::ArgumentCount { takes: 2, given: 3, .. })));
        // A table longer than the blob holds, and one of negative length.
        for len in [3, -1, i64::MAX] {
            let mut request = Request::new(Command::MovePVT.id());
            [0, len, 0, 0, 0].into_iter().for_each(|w| request.push_int(w));
            request.set_blob(&[0; 16]);
            assert_eq!(decode(&request), Err(DecodeError::OutsideBlob(1)), "length {len}");
        }
        let mut request = Request::new(Command::StartTaskFunc.id());
        request.push_int(0);
        request.push_int(1);
        request.blob_len = u32::MAX;
        assert!(matches!(decode(&request), Err(DecodeError::ArgumentCount { .. })), "blob_len past the blob");
    }

    /// Tables that do not fit in the blob together are refused by the encoder.
    #[test]
    fn blob_full() {
        let table = |n: usize| Value::List(vec![Value::Double(0.0); n]);
        let fits = BLOB_SIZE / 8 / 3;
        let values = [Value::Int(0), table(fits), table(fits), table(fits), Value::Int(1)];
        let call: CommandCall = from_values(Command::MovePVT, &values).unwrap();
        assert_eq!(encode(&call, &mut Request::new(0)), Ok(()));
        let values = [Value::Int(0), table(fits), table(fits), table(fits + 1), Value::Int(1)];
        let call: CommandCall = from_values(Command::MovePVT, &values).unwrap();
        assert_eq!(encode(&call, &mut Request::new(0)), Err(EncodeError::BlobFull));
    }

    /// The moved axis is the declaration's: the slave of GearIn, argument 0 of a move, none
    /// for a setter; the group of ClearGrpLastErr.
    #[test]
    fn roles_from_the_declaration() {
        let call = |func, ints: &[i64]| -> CommandCall<'static> {
            let values: Vec<Value> = ints.iter().map(|&i| Value::Int(i)).collect();
            from_values::<CommandCall>(func, Box::leak(values.into_boxed_slice())).unwrap()
        };
        assert_eq!(call(Command::GearIn, &[3, 5, 1]).arg_with(Role::Moves), Some(5));
        assert_eq!(call(Command::MoveAbs, &[4, 1]).arg_with(Role::Moves), Some(4));
        assert_eq!(call(Command::GearOut, &[6]).arg_with(Role::Moves), Some(6));
        assert_eq!(call(Command::SetVel, &[4, 1]).arg_with(Role::Moves), None);
        assert_eq!(call(Command::Enable, &[4]).arg_with(Role::Moves), None);
        assert_eq!(call(Command::ClearGrpLastErr, &[2]).arg_with(Role::Group), Some(2));
        assert_eq!(call(Command::ClearGrpLastErr, &[2]).arg_with(Role::Moves), None);
    }

    /// Every command fits a request's words.
    #[test]
    fn every_command_fits_the_words() {
        for &func in Command::ALL {
            assert!(func.spec().args.len() <= MAX_ARGS, "{func:?}");
        }
    }
}

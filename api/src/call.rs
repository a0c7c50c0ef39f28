//! Typed calls: `declare_functions!` gives each kind of the registry an enum with one
//! variant per function and its arguments as named, typed fields (`CommandCall`,
//! `QueryCall`, `LocalCall`). A call is read from a `Source` and written to a `Sink` in the
//! declaration's order; a local's arguments that only a front end has the type of (a Lua
//! function, a timer, any value) come from a `ValueSource` as that front end's own values.
//! This module has the neutral source every front end shares (`from_values`: the ASCII
//! server, the web view and the tests; the Lua bindings read through it too), whose
//! `ArgError` each front end words itself. The wire encoding is the `calls` crate's (api
//! knows no transport).

use std::borrow::Cow;

/// Where the typed arguments of a call come from, one after the other in the
/// declaration's order. Strings and byte tables borrow from the source where they can.
pub trait Source<'a> {
    /// Why an argument could not be read.
    type Error;
    /// A C `int`.
    fn int(&mut self) -> Result<i64, Self::Error>;
    /// A C `double`.
    fn double(&mut self) -> Result<f64, Self::Error>;
    /// A C `int` condition.
    fn bool(&mut self) -> Result<bool, Self::Error>;
    /// A `char*`: its bytes (UTF-8 when a front end made it).
    fn str(&mut self) -> Result<Cow<'a, [u8]>, Self::Error>;
    /// A `uint8_t*`.
    fn bytes(&mut self) -> Result<Cow<'a, [u8]>, Self::Error>;
    /// A `double*`.
    fn doubles(&mut self) -> Result<Doubles<'a>, Self::Error>;
}

/// Where the typed arguments of a call go, one after the other in the declaration's order.
pub trait Sink {
    /// Why an argument could not be taken.
    type Error;
    /// A C `int`.
    fn int(&mut self, value: i64) -> Result<(), Self::Error>;
    /// A C `double`.
    fn double(&mut self, value: f64) -> Result<(), Self::Error>;
    /// A C `int` condition.
    fn bool(&mut self, value: bool) -> Result<(), Self::Error>;
    /// A `char*`.
    fn str(&mut self, value: &[u8]) -> Result<(), Self::Error>;
    /// A `uint8_t*`.
    fn bytes(&mut self, value: &[u8]) -> Result<(), Self::Error>;
    /// A `double*`.
    fn doubles(&mut self, value: &Doubles) -> Result<(), Self::Error>;
}

/// A `Source` of the arguments of the functions that run in the script process
/// (`LocalCall`), some of which only a front end has the type of.
pub trait ValueSource<'a>: Source<'a> {
    /// The front end's own value (a Lua value).
    type Value;
    /// An argument of type `ty` (`Func`, `Timer`, `Any`, `Memory`) as the front end's value;
    /// a front end that can tell refuses one that is not a `ty` (a Lua function, a timer).
    fn value(&mut self, ty: crate::ArgType) -> Result<Self::Value, Self::Error>;
    /// The values left (`...`), each as the front end's value.
    fn rest(&mut self) -> Result<Vec<Self::Value>, Self::Error>;
    /// Whether the next argument is left out (none, or nil): an argument declared
    /// `or nil` is then `None`, and is taken past.
    fn absent(&mut self) -> bool;
}

/// A typed call of one kind of the registry (`CommandCall`, `QueryCall`, `LocalCall`),
/// read from the sources `S` it can be read from.
pub trait TypedCall<'a, S: Source<'a>>: Sized {
    /// The kind's function enum (`Command`, `Query`, `Local`).
    type Func: Copy;
    /// Reads the arguments of `func` from `source`, in the declaration's order.
    fn read(func: Self::Func, source: &mut S) -> Result<Self, S::Error>;
}

/// The type of a `LocalCall`'s field, by the argument's declared type: a marker type per
/// `ArgType` (named as the declaration names it), and `(T, nil)` for one declared `or nil`.
/// The registry's macro names them; derives see through a projection, not a macro.
pub mod field {
    use std::borrow::Cow;

    /// The field type of an argument declared as `Self`, in a call whose front end's own
    /// values are `V`.
    pub trait Field<'a, V> {
        /// The field's type.
        type Type;
    }

    macro_rules! fields {
        ($( $(#[doc = $doc:literal])* $ty:ident => $field:ty; )*) => { $(
            $(#[doc = $doc])*
            pub struct $ty;
            impl<'a, V> Field<'a, V> for $ty {
                type Type = $field;
            }
        )* };
    }

    fields! {
        /// `ArgType::Int`.
        Int => i64;
        /// `ArgType::Double`.
        Double => f64;
        /// `ArgType::Bool`.
        Bool => bool;
        /// `ArgType::Str`.
        Str => Cow<'a, [u8]>;
        /// `ArgType::Bytes`.
        Bytes => Cow<'a, [u8]>;
        /// `ArgType::Doubles`.
        Doubles => super::Doubles<'a>;
        /// `ArgType::Func`: the front end's function.
        Func => V;
        /// `ArgType::Timer`: the front end's timer.
        Timer => V;
        /// `ArgType::Any`.
        Any => V;
        /// `ArgType::Memory`: the front end's table.
        Memory => V;
        /// `ArgType::Rest`: the values left.
        Rest => Vec<V>;
    }

    /// `or nil` after an argument's type: it may be left out.
    #[allow(non_camel_case_types)]
    pub struct nil;

    impl<'a, V, T: Field<'a, V>> Field<'a, V> for (T, nil) {
        type Type = Option<T::Type>;
    }
}

/// A `double*` argument: numbers a front end collected, or 8-byte little-endian numbers
/// as they lie in a buffer (read in place, without copying: the core decodes on its RT
/// thread, which does not allocate).
#[derive(Clone, Debug)]
pub enum Doubles<'a> {
    /// The numbers.
    Values(Cow<'a, [f64]>),
    /// Whole 8-byte little-endian numbers, one after the other.
    LittleEndian(&'a [u8]),
}

impl Doubles<'_> {
    /// How many numbers.
    pub fn len(&self) -> usize {
        match self {
            Doubles::Values(v) => v.len(),
            Doubles::LittleEndian(b) => b.len() / 8,
        }
    }

    /// True without numbers.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number `i`, if there is one.
    pub fn get(&self, i: usize) -> Option<f64> {
        match self {
            Doubles::Values(v) => v.get(i).copied(),
            Doubles::LittleEndian(b) => {
                b.get(i * 8..i * 8 + 8).map(|n| f64::from_le_bytes(n.try_into().expect("8 bytes")))
            }
        }
    }

    /// The numbers in order.
    pub fn iter(&self) -> impl Iterator<Item = f64> + '_ {
        (0..self.len()).filter_map(|i| self.get(i))
    }
}

/// Equal when they hold the same numbers, bit for bit (NaN equals itself).
impl PartialEq for Doubles<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && self.iter().zip(other.iter()).all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

/// A value as a front end hands it over, before the registry's types are applied.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// Nothing (Lua's `nil`).
    Nil,
    /// A boolean.
    Bool(bool),
    /// An integer.
    Int(i64),
    /// A floating-point number.
    Double(f64),
    /// A string's bytes.
    Str(Vec<u8>),
    /// A sequence (a Lua table's `1..n`), for `uint8_t*` and `double*`.
    List(Vec<Value>),
    /// A value of a type no argument takes, by the front end's name for it (`"function"`).
    Other(&'static str),
}

/// What an argument should have been.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expected {
    /// An integer, or a number with an integral value.
    Integer,
    /// Any number.
    Number,
    /// A boolean, or a number where 0 is false.
    BoolOrNumber,
    /// A string that is valid UTF-8.
    Utf8String,
    /// A string (a number is taken as its text).
    String,
    /// A sequence whose elements are integers 0..255.
    ByteTable,
    /// A sequence of bytes or a string.
    BytesOrString,
    /// A sequence of numbers.
    Numbers,
    /// A function (a `Till` condition, an ASCII agent's parser).
    Function,
    /// A timer made by `TimerInit`.
    Timer,
}

/// What came instead: enough for a front end to name it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Got {
    /// No value at this position.
    Missing,
    /// `Value::Nil`.
    Nil,
    /// A boolean.
    Bool,
    /// An integer, with its value.
    Int(i64),
    /// A number, with its value.
    Double(f64),
    /// A string.
    Str,
    /// A sequence.
    List,
    /// `Value::Other`, with its name.
    Other(&'static str),
}

impl Got {
    /// What `value` is.
    pub fn of(value: &Value) -> Self {
        match value {
            Value::Nil => Got::Nil,
            Value::Bool(_) => Got::Bool,
            Value::Int(n) => Got::Int(*n),
            Value::Double(n) => Got::Double(*n),
            Value::Str(_) => Got::Str,
            Value::List(_) => Got::List,
            Value::Other(name) => Got::Other(name),
        }
    }
}

/// Why neutral values do not make a call; each front end words it itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ArgError {
    /// Argument `index` (from 0), or an element of it, is not what the function takes.
    Type {
        /// Which argument, from 0.
        index: usize,
        /// What it should have been.
        expected: Expected,
        /// What came: the argument, or the element of a sequence that did not fit.
        got: Got,
    },
    /// More values than the function has arguments.
    TooMany {
        /// The function's arguments.
        takes: usize,
        /// The values given.
        given: usize,
    },
}

/// Refuses more values than `spec` takes (`FunctionSpec::max_args`): a front end that
/// checks the count before it reads any value does nothing for a refused call.
pub fn check_count(spec: &crate::FunctionSpec, given: usize) -> Result<(), ArgError> {
    match spec.max_args() {
        Some(takes) if given > takes => Err(ArgError::TooMany { takes, given }),
        _ => Ok(()),
    }
}

/// The typed call of `func` from neutral values, in the declaration's order: the one
/// encoder of every front end. The first argument that does not fit is the error; then
/// values past the last argument.
pub fn from_values<'a, C: TypedCall<'a, Values<'a>>>(func: C::Func, values: &'a [Value]) -> Result<C, ArgError> {
    let mut source = Values::new(values);
    let call = C::read(func, &mut source)?;
    if values.len() > source.next {
        return Err(ArgError::TooMany { takes: source.next, given: values.len() });
    }
    Ok(call)
}

/// Neutral values as a `Source`, read one after the other (a front end that reads its
/// arguments one by one uses it too).
pub struct Values<'a> {
    values: &'a [Value],
    next: usize,
}

impl<'a> Values<'a> {
    /// Reads `values` from the first.
    pub fn new(values: &'a [Value]) -> Self {
        Values { values, next: 0 }
    }

    /// The next value and its index; `Missing` past the end.
    fn take(&mut self) -> (usize, Option<&'a Value>) {
        let index = self.next;
        self.next += 1;
        (index, self.values.get(index))
    }

    fn refuse<T>(index: usize, expected: Expected, value: Option<&Value>) -> Result<T, ArgError> {
        Err(ArgError::Type { index, expected, got: value.map_or(Got::Missing, Got::of) })
    }
}

impl<'a> Source<'a> for Values<'a> {
    type Error = ArgError;

    fn int(&mut self) -> Result<i64, ArgError> {
        match self.take() {
            (_, Some(Value::Int(n))) => Ok(*n),
            // Beyond 2^53 a float no longer tells neighbouring integers apart.
            (_, Some(Value::Double(n))) if n.fract() == 0.0 && n.abs() < 9.0e15 => Ok(*n as i64),
            (i, other) => Self::refuse(i, Expected::Integer, other),
        }
    }

    fn double(&mut self) -> Result<f64, ArgError> {
        match self.take() {
            (_, Some(Value::Int(n))) => Ok(*n as f64),
            (_, Some(Value::Double(n))) => Ok(*n),
            (i, other) => Self::refuse(i, Expected::Number, other),
        }
    }

    fn bool(&mut self) -> Result<bool, ArgError> {
        match self.take() {
            (_, Some(Value::Bool(b))) => Ok(*b),
            (_, Some(Value::Int(n))) => Ok(*n != 0),
            (_, Some(Value::Double(n))) => Ok(*n != 0.0),
            (i, other) => Self::refuse(i, Expected::BoolOrNumber, other),
        }
    }

    fn str(&mut self) -> Result<Cow<'a, [u8]>, ArgError> {
        match self.take() {
            (_, Some(Value::Str(s))) if std::str::from_utf8(s).is_ok() => Ok(Cow::Borrowed(s)),
            (i, Some(other @ Value::Str(_))) => Self::refuse(i, Expected::Utf8String, Some(other)),
            (_, Some(Value::Int(n))) => Ok(Cow::Owned(n.to_string().into_bytes())),
            (_, Some(Value::Double(n))) => Ok(Cow::Owned(n.to_string().into_bytes())),
            (i, other) => Self::refuse(i, Expected::String, other),
        }
    }

    fn bytes(&mut self) -> Result<Cow<'a, [u8]>, ArgError> {
        match self.take() {
            (_, Some(Value::Str(s))) => Ok(Cow::Borrowed(s)),
            (i, Some(Value::List(items))) => items
                .iter()
                .map(|item| match item {
                    Value::Int(b) if (0..=255).contains(b) => Ok(*b as u8),
                    other => Self::refuse(i, Expected::ByteTable, Some(other)),
                })
                .collect::<Result<Vec<u8>, _>>()
                .map(Cow::Owned),
            (i, other) => Self::refuse(i, Expected::BytesOrString, other),
        }
    }

    fn doubles(&mut self) -> Result<Doubles<'a>, ArgError> {
        match self.take() {
            (i, Some(Value::List(items))) => items
                .iter()
                .map(|item| match item {
                    Value::Int(n) => Ok(*n as f64),
                    Value::Double(n) => Ok(*n),
                    other => Self::refuse(i, Expected::Numbers, Some(other)),
                })
                .collect::<Result<Vec<f64>, _>>()
                .map(|v| Doubles::Values(Cow::Owned(v))),
            // HMPL passes NULL (0) for a `double*` it does not use (8.5, `trans_par`).
            (_, None | Some(Value::Nil | Value::Int(0))) => Ok(Doubles::Values(Cow::Owned(Vec::new()))),
            (i, other) => Self::refuse(i, Expected::Numbers, other),
        }
    }
}

/// Neutral values stand for themselves: a front end that has neutral values only (the
/// ASCII server) has no function or timer to pass.
impl<'a> ValueSource<'a> for Values<'a> {
    type Value = Value;

    fn value(&mut self, _: crate::ArgType) -> Result<Value, ArgError> {
        Ok(self.take().1.cloned().unwrap_or(Value::Nil))
    }

    fn rest(&mut self) -> Result<Vec<Value>, ArgError> {
        let rest = self.values.get(self.next..).unwrap_or(&[]).to_vec();
        self.next = self.next.max(self.values.len());
        Ok(rest)
    }

    fn absent(&mut self) -> bool {
        let absent = matches!(self.values.get(self.next), None | Some(Value::Nil));
        if absent {
            self.next += 1;
        }
        absent
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Command, CommandCall, Local, LocalCall, Query, QueryCall};

    fn command<'a>(func: Command, values: &'a [Value]) -> Result<CommandCall<'a>, ArgError> {
        from_values(func, values)
    }

    fn refused(index: usize, expected: Expected, got: Got) -> ArgError {
        ArgError::Type { index, expected, got }
    }

    /// A good call for each type an argument has: integers (an integral float too), numbers
    /// (an integer too), strings (a number as its text), bytes (a table or a string), tables
    /// of numbers, conditions.
    #[test]
    fn good_calls() {
        assert_eq!(
            command(Command::MoveAbs, &[Value::Double(2.0), Value::Int(3)]),
            Ok(CommandCall::MoveAbs { axis_id: 2, pos: 3.0 })
        );
        assert_eq!(
            from_values::<QueryCall>(Query::IsGantryPair, &[Value::Int(0), Value::Int(1)]),
            Ok(QueryCall::IsGantryPair { axis_id_1: 0, axis_id_2: 1 })
        );
        assert_eq!(from_values::<QueryCall>(Query::GetAxisNum, &[]), Ok(QueryCall::GetAxisNum {}));
        let name = [Value::Int(1), Value::Str(b"main".to_vec())];
        assert_eq!(
            command(Command::StartTaskFunc, &name),
            Ok(CommandCall::StartTaskFunc { task_id: 1, func_name: Cow::Borrowed(b"main") })
        );
        let number = [Value::Int(1), Value::Double(2.5)];
        assert_eq!(
            command(Command::StartTaskFunc, &number),
            Ok(CommandCall::StartTaskFunc { task_id: 1, func_name: Cow::Borrowed(b"2.5") })
        );
        let sdo = |value: Value| [Value::Int(1), Value::Int(0x6060), Value::Int(0), Value::Int(2), value];
        let bytes = |call: Result<CommandCall, ArgError>| match call {
            Ok(CommandCall::WriteSDOEx { obj_value, .. }) => obj_value.into_owned(),
            other => panic!("{other:?}"),
        };
        assert_eq!(
            bytes(command(Command::WriteSDOEx, &sdo(Value::List(vec![Value::Int(1), Value::Int(255)])))),
            [1, 255]
        );
        assert_eq!(bytes(command(Command::WriteSDOEx, &sdo(Value::Str(vec![0xff, 0])))), [0xff, 0]);
        let pvt = [
            Value::Int(0),
            Value::List(vec![Value::Int(0), Value::Double(10.0)]),
            Value::List(vec![Value::Double(1.0), Value::Double(2.0)]),
            Value::List(vec![Value::Int(0), Value::Int(0)]),
            Value::Int(2),
        ];
        let Ok(CommandCall::MovePVT { time, pos, .. }) = command(Command::MovePVT, &pvt) else { panic!("MovePVT") };
        assert_eq!((time.iter().collect::<Vec<_>>(), pos.get(1), pos.len()), (vec![0.0, 10.0], Some(2.0), 2));
        let mut conditions = [Value::Bool(true), Value::Int(0), Value::Double(0.5)];
        let mut source = Values::new(&conditions);
        assert_eq!((source.bool(), source.bool(), source.bool()), (Ok(true), Ok(false), Ok(true)));
        conditions[0] = Value::Str(Vec::new());
        assert_eq!(Values::new(&conditions).bool(), Err(refused(0, Expected::BoolOrNumber, Got::Str)));
    }

    /// Each neutral error: which argument, what was expected, what came.
    #[test]
    fn argument_errors() {
        let moveabs = |values: &[Value]| command(Command::MoveAbs, values).map(|_| ()).unwrap_err();
        assert_eq!(moveabs(&[Value::Str(b"0".to_vec()), Value::Int(1)]), refused(0, Expected::Integer, Got::Str));
        assert_eq!(moveabs(&[Value::Double(0.5), Value::Int(1)]), refused(0, Expected::Integer, Got::Double(0.5)));
        assert_eq!(moveabs(&[Value::Double(1e16), Value::Int(1)]), refused(0, Expected::Integer, Got::Double(1e16)));
        assert_eq!(moveabs(&[Value::Int(0), Value::Nil]), refused(1, Expected::Number, Got::Nil));
        assert_eq!(moveabs(&[Value::Int(0)]), refused(1, Expected::Number, Got::Missing));
        assert_eq!(
            moveabs(&[Value::Int(0), Value::Other("function")]),
            refused(1, Expected::Number, Got::Other("function"))
        );
        assert_eq!(moveabs(&[Value::Int(0), Value::Int(1), Value::Int(2)]), ArgError::TooMany { takes: 2, given: 3 });
        // The first argument that does not fit is the one reported.
        assert_eq!(moveabs(&[Value::Bool(true), Value::List(Vec::new())]), refused(0, Expected::Integer, Got::Bool));

        let task_func = |name: Value| command(Command::StartTaskFunc, &[Value::Int(0), name]).map(|_| ()).unwrap_err();
        assert_eq!(task_func(Value::Str(vec![0xff])), refused(1, Expected::Utf8String, Got::Str));
        assert_eq!(task_func(Value::List(Vec::new())), refused(1, Expected::String, Got::List));

        let sdo = |value: Value| {
            let values = [Value::Int(1), Value::Int(0x6060), Value::Int(0), Value::Int(1), value];
            command(Command::WriteSDOEx, &values).map(|_| ()).unwrap_err()
        };
        assert_eq!(
            sdo(Value::List(vec![Value::Int(1), Value::Int(256)])),
            refused(4, Expected::ByteTable, Got::Int(256))
        );
        assert_eq!(sdo(Value::List(vec![Value::Double(1.0)])), refused(4, Expected::ByteTable, Got::Double(1.0)));
        assert_eq!(sdo(Value::Int(1)), refused(4, Expected::BytesOrString, Got::Int(1)));

        let pvt = |time: Value| {
            let values = [Value::Int(0), time, Value::List(Vec::new()), Value::List(Vec::new()), Value::Int(0)];
            command(Command::MovePVT, &values).map(|_| ()).unwrap_err()
        };
        assert_eq!(
            pvt(Value::List(vec![Value::Int(0), Value::Str(Vec::new())])),
            refused(1, Expected::Numbers, Got::Str)
        );
        assert_eq!(pvt(Value::Double(1.0)), refused(1, Expected::Numbers, Got::Double(1.0)));
        assert_eq!(pvt(Value::Int(1)), refused(1, Expected::Numbers, Got::Int(1)));
        // HMPL 8.5: NULL (0 or nil) for a `double*` is an empty table.
        for null in [Value::Int(0), Value::Nil] {
            let values = [Value::Int(0), null, Value::List(Vec::new()), Value::List(Vec::new()), Value::Int(0)];
            assert!(command(Command::MovePVT, &values).is_ok());
        }
    }

    /// A local's call: the front end's own values where only it has the type, the rest of
    /// a variadic function, and an argument declared `or nil` left out or nil.
    #[test]
    fn local_calls() {
        fn local(func: Local, values: &[Value]) -> Result<LocalCall<'_, Value>, ArgError> {
            from_values(func, values)
        }
        let eq = [Value::Int(1), Value::Str(Vec::new())];
        assert_eq!(
            local(Local::expect_eq, &eq),
            Ok(LocalCall::expect_eq { actual: Value::Int(1), expected: Value::Str(Vec::new()), message: None })
        );
        let nil = [Value::Bool(true), Value::Nil];
        assert_eq!(
            local(Local::expect_true, &nil),
            Ok(LocalCall::expect_true { value: Value::Bool(true), message: None })
        );
        let broadcast = [Value::Str(b"hi".to_vec()), Value::Int(1)];
        assert_eq!(
            local(Local::ASCII_ServerBroadcast, &broadcast),
            Ok(LocalCall::ASCII_ServerBroadcast { message: Cow::Borrowed(b"hi"), length: Some(1) })
        );
        let setup = [Value::Int(0), Value::Int(1), Value::Int(2)];
        assert_eq!(
            local(Local::SetupGroup, &setup),
            Ok(LocalCall::SetupGroup { group_id: 0, axis_ids: vec![Value::Int(1), Value::Int(2)] })
        );
        assert_eq!(local(Local::Sleep, &[Value::Nil]), Err(refused(0, Expected::Integer, Got::Nil)));
        assert_eq!(local(Local::Sleep, &[Value::Int(1), Value::Int(2)]), Err(ArgError::TooMany { takes: 1, given: 2 }));
    }

    /// Tables in a buffer and collected numbers compare by their numbers, NaN too.
    #[test]
    fn doubles_compare_by_value() {
        let bytes: Vec<u8> = [1.5f64, f64::NAN].iter().flat_map(|n| n.to_le_bytes()).collect();
        let wire = Doubles::LittleEndian(&bytes);
        assert_eq!(wire, Doubles::Values(Cow::Owned(vec![1.5, f64::NAN])));
        assert_ne!(wire, Doubles::Values(Cow::Owned(vec![1.5])));
        assert_eq!((wire.len(), wire.get(0), wire.get(2)), (2, Some(1.5), None));
    }
}

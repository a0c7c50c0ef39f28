//! The one declaration of every API function a script can call.
//!
//! Each function is declared once, in `functions.rs`, with its manual name, argument
//! order, return values, manual reference and whether the Native ASCII server may call
//! it. The Lua bindings, the command dispatch of the core, the generated API reference
//! and the editor annotations are all derived from these tables.

use std::collections::HashMap;
use std::sync::LazyLock;

/// Where a call is carried out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Needs the core: one request/reply round trip, applied in the next cycle.
    Command,
    /// Reads the state snapshot in the script's own address space: no round trip.
    Query,
    /// Runs in the script process (waits, printing).
    Local,
}

/// The type of one argument, as a script passes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArgType {
    /// C `int`: a Lua integer (a float with an integral value is accepted).
    Int,
    /// C `double`: any Lua number.
    Double,
    /// C `char*`: a Lua string.
    Str,
    /// A Lua function, for `Till(function() ... end)`.
    Func,
    /// `uint8_t*`: a table of integers 0..255, or a string.
    Bytes,
    /// `double*`: a table of numbers.
    Doubles,
    /// `...` of a printf-style function: any number of values.
    Rest,
    /// A boolean, or a number where 0 is false (HMPL's `int` conditions).
    Bool,
    /// A timer made by `TimerInit` (HMPL's `Timer*`).
    Timer,
}

/// The type of one returned value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueType {
    Int,
    Double,
    /// HMPL's TRUE/FALSE, returned to Lua as a boolean: 0 is true in Lua.
    Bool,
    Str,
    /// An out-pointer buffer: a table of integers 0..255.
    Bytes,
    /// An out-pointer array of doubles: a table of numbers.
    Doubles,
    /// A timer for `TON`/`TOF`.
    Timer,
}

#[derive(Clone, Copy, Debug)]
pub struct ArgSpec {
    pub name: &'static str,
    pub ty: ArgType,
}

/// One function of the registry.
#[derive(Debug)]
pub struct FunctionSpec {
    pub name: &'static str,
    pub func: Func,
    /// The manual section that defines it, e.g. `HMPL 5.2.4`.
    pub manual: &'static str,
    /// Callable from the Native ASCII server (the manual's icon).
    pub ascii: bool,
    pub args: &'static [ArgSpec],
    /// Returned values, first the C return value, then the out-pointers. Empty: `void`.
    pub returns: &'static [ValueType],
    /// One paragraph for the reference and the editor annotations.
    pub doc: &'static [&'static str],
}

impl FunctionSpec {
    pub fn kind(&self) -> Kind {
        match self.func {
            Func::Command(_) => Kind::Command,
            Func::Query(_) => Kind::Query,
            Func::Local(_) => Kind::Local,
        }
    }

    /// The C-like signature the manual prints, e.g. `int MoveAbs(int axis_id, double pos)`.
    pub fn signature(&self) -> String {
        let ret = match self.returns.first() {
            None => "void",
            Some(ValueType::Int | ValueType::Bool) => "int",
            Some(ValueType::Double) => "double",
            Some(ValueType::Str) => "char*",
            Some(ValueType::Bytes) => "uint8_t*",
            Some(ValueType::Doubles) => "double*",
            Some(ValueType::Timer) => "Timer",
        };
        let args: Vec<String> = self
            .args
            .iter()
            .map(|a| match a.ty {
                ArgType::Int => format!("int {}", a.name),
                ArgType::Double => format!("double {}", a.name),
                ArgType::Str => format!("char *{}", a.name),
                ArgType::Func => format!("condition {}", a.name),
                ArgType::Bytes => format!("uint8_t *{}", a.name),
                ArgType::Doubles => format!("double *{}", a.name),
                ArgType::Rest => "...".to_string(),
                ArgType::Bool => format!("int {}", a.name),
                ArgType::Timer => format!("Timer *{}", a.name),
            })
            .collect();
        format!("{ret} {}({})", self.name, args.join(", "))
    }
}

/// A function, typed by where it runs, so that each side matches exhaustively on its own kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    Command(crate::Command),
    Query(crate::Query),
    Local(crate::Local),
}

/// Every function of the registry, commands first.
pub fn all() -> impl Iterator<Item = &'static FunctionSpec> {
    crate::functions::COMMANDS.iter().chain(crate::functions::QUERIES).chain(crate::functions::LOCALS)
}

/// Looks a function up by its manual name.
pub fn find(name: &str) -> Option<&'static FunctionSpec> {
    static BY_NAME: LazyLock<HashMap<&'static str, &'static FunctionSpec>> =
        LazyLock::new(|| all().map(|f| (f.name, f)).collect());
    BY_NAME.get(name).copied()
}

/// Declares one kind of functions: an enum with a variant per function, and its table.
macro_rules! declare_functions {
    (
        $enum:ident, $table:ident;
        $(
            $(#[doc = $doc:literal])*
            [$manual:literal $(, $ascii:ident)?]
            fn $name:ident ( $( $arg:ident : $aty:ident ),* $(,)? ) $(-> $ret:tt)? ;
        )*
    ) => {
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(u16)]
        #[allow(non_camel_case_types)]
        pub enum $enum { $( $name, )* }

        impl $enum {
            pub const ALL: &'static [$enum] = &[ $( $enum::$name, )* ];

            pub fn spec(self) -> &'static $crate::registry::FunctionSpec {
                &$table[self as usize]
            }

            /// The wire id of the function (its position in the table).
            pub fn id(self) -> u16 {
                self as u16
            }

            pub fn from_id(id: u16) -> Option<Self> {
                Self::ALL.get(id as usize).copied()
            }
        }

        pub static $table: &[$crate::registry::FunctionSpec] = &[ $(
            $crate::registry::FunctionSpec {
                name: stringify!($name),
                func: $crate::registry::Func::$enum($enum::$name),
                manual: $manual,
                ascii: declare_functions!(@ascii $($ascii)?),
                args: &[ $( $crate::registry::ArgSpec {
                    name: stringify!($arg),
                    ty: $crate::registry::ArgType::$aty,
                }, )* ],
                returns: declare_functions!(@ret $($ret)?),
                doc: &[ $( $doc, )* ],
            },
        )* ];
    };
    (@ascii ascii) => { true };
    (@ascii) => { false };
    (@ret) => { &[] };
    (@ret ( $( $t:ident ),* )) => { &[ $( $crate::registry::ValueType::$t, )* ] };
    (@ret $t:ident) => { &[ $crate::registry::ValueType::$t ] };
}

pub(crate) use declare_functions;

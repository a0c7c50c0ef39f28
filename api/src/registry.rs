//! The one declaration of every API function a script can call.
//!
//! Each function is declared once, in `functions.rs`, with its manual name, argument
//! order, return values, manual reference and whether the Native ASCII server may call
//! it. The Lua bindings, the command dispatch of the core, the generated API reference
//! and the editor annotations are all derived from these tables.

use std::collections::HashMap;
use std::sync::LazyLock;

use crate::{AxisError, GroupError, SystemError};

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
    /// Any Lua value, taken as the function says (DRL `FreePort.Eth.Tx`'s message).
    Any,
    /// `void*` of HMPL ch. 3's memory functions: a table of Lua integers (a C `int[]`,
    /// 4 bytes each) or of floats (a `double[]`, 8 bytes each).
    Memory,
}

/// The type of one returned value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ValueType {
    /// A Lua integer.
    Int,
    /// A Lua float.
    Double,
    /// HMPL's TRUE/FALSE, returned to Lua as a boolean: 0 is true in Lua.
    Bool,
    /// A Lua string.
    Str,
    /// An out-pointer buffer: a table of integers 0..255.
    Bytes,
    /// An out-pointer array of doubles: a table of numbers.
    Doubles,
    /// A timer for `TON`/`TOF`.
    Timer,
    /// Any Lua value (DRL `FreePort.Eth.Tx` returns a copy of its message).
    Any,
    /// A `void*` out-parameter: a table of integers or floats as `ArgType::Memory`.
    Memory,
}

/// What a command's argument is physically; the core checks every argument that has one
/// against its range before the command runs (`rt-core/src/dispatch.rs`), so that no
/// setter can forget it and NaN or infinity never reach the kernel. Positions, velocities
/// and accelerations are in the axis' units (mm or deg, HMPL 1.2), times in ms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// The id of an axis; the axis-bound quantities after it belong to this axis.
    Axis,
    /// A coordinate of the axis: fits the drive's 32-bit counts (HMPL 5.3.19, 5.3.12).
    Position,
    /// A position the axis moves to: also fits the drive's counts with the axis' offset.
    Target,
    /// A distance from where the axis is headed: that place plus it is a `Target`.
    Distance,
    /// A window or length: at least one count, at most the counts' span.
    Length,
    /// A rollover length: 0 (off) or a `Length` (HMPL 5.3.39).
    Rollover,
    /// A speed: at least one count per second, at most the machine file's `max_vel`.
    Speed,
    /// A velocity whose sign is the direction: |v| at most `max_vel` (HMPL 5.2.6).
    Velocity,
    /// An acceleration, deceleration or kill deceleration: at least one count per s²,
    /// at most the machine file's `max_acc`.
    Acceleration,
    /// See `Acceleration`.
    Deceleration,
    /// See `Acceleration`.
    KillDeceleration,
    /// An acceleration or deceleration time (HMPL 5.3.5, 5.3.8) and the in-position time
    /// (HMPL 5.3.47): > 0, at most a minute.
    AccTime,
    /// See `AccTime`.
    DecTime,
    /// See `AccTime`.
    Time,
    /// The smooth time, 0..500 ms (HMPL table 5.1.1.2).
    SmoothTime,
    /// A velocity override, 0..100 % (HMPL 5.3.37).
    Percent,
    /// A gear ratio, |ratio| at most 1000 (HMPL 6.4).
    GearRatio,
    /// A torque in N·m whose per mille of rated torque fits the drive's 0x6071 (INT16).
    Torque,
    /// PVT times, ms from 0, at most a minute, and velocities, |v| at most `max_vel`
    /// (HMPL 5.2.8).
    PvtTime,
    /// See `PvtTime`.
    PvtVelocity,
    /// The id of a group (HMPL ch. 8); the group-bound quantities after it belong to it.
    Group,
    /// A coordinate of a group's path: a position, distance or center (mm), an orientation
    /// (deg), a normal vector or a transform: finite, at most 1e9.
    PathCoordinate,
    /// An arc's angle, deg: finite, less than 1e9.
    PathAngle,
    /// The linear profile velocity, 0..5000 mm/s (HMPL 8.3.6).
    PathVelocity,
    /// The linear profile acceleration, > 0..50000 mm/s² (HMPL 8.3.6).
    PathAcceleration,
    /// The linear profile deceleration, > 0..50000 mm/s² (HMPL 8.3.6).
    PathDeceleration,
    /// The group's smooth time, 0..500 ms (HMPL 8.3.6, 8.3.19).
    PathSmoothTime,
    /// An acceleration time, ms > 0 (HMPL 8.3.14); the acceleration it gives is checked too.
    PathAccTime,
    /// A deceleration time, ms > 0 (HMPL 8.3.17).
    PathDecTime,
    /// The angular profile velocity, 0..7200 deg/s (HMPL 8.3.7).
    AngularVelocity,
    /// The angular profile acceleration, > 0..72000 deg/s² (HMPL 8.3.7).
    AngularAcceleration,
    /// The angular profile deceleration, > 0..72000 deg/s² (HMPL 8.3.7).
    AngularDeceleration,
    /// The angular smooth time, 0..500 ms (HMPL 8.3.7).
    AngularSmoothTime,
    /// A group's velocity override, 0..100 % (HMPL 8.3.28).
    PathVelScale,
    /// A signed jog velocity: |v| at most 5000 mm/s or 7200 deg/s (HMPL 8.2.7, 8.2.8).
    GroupJogVelocity,
    /// `motion_profile` of HMPL 8.5: {vel, acc, dec, smooth_time}, each as SetGrpMotionProfile.
    MotionProfile,
    /// A transition parameter: finite and not negative; its range is checked with the
    /// mode that uses it (table 8.3.26.1).
    TransitionParameter,
    /// A look-ahead parameter: finite and not negative (HMPL 8.3.34).
    LookAheadParameter,
    /// The VSF's frequency, 0.1..200 Hz (HMPL 15.4).
    VsfFrequency,
    /// The VSF's damping ratio, 0.7..1.5 (HMPL 15.4).
    VsfDamping,
    /// An axis' input-shaper frequency, 1.5..300 Hz (HMPL 15.7).
    ShaperFrequency,
    /// An input shaper's damping ratio, 0..0.3 (HMPL 15.7).
    ShaperDamping,
    /// A group's input-shaper frequency, 3.0..300 Hz (HMPL 15.10).
    GroupShaperFrequency,
    /// A group's input-shaper damping ratio, 0..0.3 (HMPL 15.10).
    GroupShaperDamping,
    /// A number of no axis or group that only has to be finite (HMPL ch. 10's analog values,
    /// scales and offsets; their own ranges are the command's).
    Finite,
    /// A number of a compensation table's setup (HMPL 14.4-14.6: base, interval, point
    /// count, reference axis): a coordinate the compensated axis can show, as `Position`;
    /// the setup checks the rest.
    CompTable,
}

/// Which error a value out of range records: the axis', the group's or the system's
/// (HMPL ch. 18).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// The axis' last error (`0x83IIEEEE`).
    Axis(AxisError),
    /// The group's last error (`0x82IIEEEE`).
    Group(GroupError),
    /// A system error (`0x0000EEEE`), for a quantity of no axis or group.
    System(SystemError),
}

impl Quantity {
    /// Whether the quantity belongs to a group (the last `Group` argument before it) rather
    /// than to an axis.
    pub fn is_group_bound(self) -> bool {
        matches!(self.error(), Refusal::Group(_))
    }

    /// Whether the quantity belongs to no axis or group.
    pub fn is_free(self) -> bool {
        matches!(self.error(), Refusal::System(_))
    }

    /// The error a value out of range records (HMPL tables 18.1.2.1 and 18.1.3.1).
    pub fn error(self) -> Refusal {
        use Refusal::{Axis as A, Group as G};
        match self {
            Quantity::Axis | Quantity::Length | Quantity::Time | Quantity::Torque | Quantity::CompTable => {
                A(AxisError::CmdInvalidParameter)
            }
            Quantity::Position | Quantity::Target | Quantity::Distance => A(AxisError::CmdInvalidPos),
            Quantity::Rollover => A(AxisError::CmdInvalidRolloverPos),
            Quantity::Speed | Quantity::Velocity => A(AxisError::CmdInvalidVel),
            Quantity::Acceleration | Quantity::AccTime => A(AxisError::CmdInvalidAcc),
            Quantity::Deceleration | Quantity::DecTime => A(AxisError::CmdInvalidDec),
            Quantity::KillDeceleration => A(AxisError::CmdInvalidKillDec),
            Quantity::SmoothTime => A(AxisError::CmdInvalidSmTime),
            Quantity::Percent => A(AxisError::CmdInvalidVelScale),
            Quantity::GearRatio => A(AxisError::CmdInvalidGearRatio),
            Quantity::PvtTime => A(AxisError::PvtMotionInvalidTime),
            Quantity::PvtVelocity => A(AxisError::PvtMotionVelLimit),
            Quantity::Group | Quantity::PathCoordinate | Quantity::PathAngle => G(GroupError::CmdInvalidPos),
            Quantity::PathVelocity | Quantity::GroupJogVelocity => G(GroupError::CmdInvalidLinVel),
            Quantity::PathAcceleration | Quantity::PathAccTime => G(GroupError::CmdInvalidLinAcc),
            Quantity::PathDeceleration | Quantity::PathDecTime => G(GroupError::CmdInvalidLinDec),
            Quantity::PathSmoothTime => G(GroupError::CmdInvalidLinSmTime),
            Quantity::AngularVelocity => G(GroupError::CmdInvalidAngVel),
            Quantity::AngularAcceleration => G(GroupError::CmdInvalidAngAcc),
            Quantity::AngularDeceleration => G(GroupError::CmdInvalidAngDec),
            Quantity::AngularSmoothTime => G(GroupError::CmdInvalidAngSmTime),
            Quantity::PathVelScale => G(GroupError::CmdInvalidVelScale),
            Quantity::MotionProfile => G(GroupError::CmdInvalidLinVel),
            Quantity::TransitionParameter => G(GroupError::CmdInvalidTransVel),
            Quantity::LookAheadParameter => G(GroupError::CmdLookaheadInvalidParam),
            Quantity::VsfFrequency | Quantity::ShaperFrequency => A(AxisError::FrequencyLimit),
            Quantity::VsfDamping | Quantity::ShaperDamping => A(AxisError::DampingratioLimit),
            Quantity::GroupShaperFrequency => G(GroupError::CmdInvalidFrequency),
            Quantity::GroupShaperDamping => G(GroupError::CmdInvalidDampingratio),
            Quantity::Finite => Refusal::System(SystemError::HmplArgOutOfRange),
        }
    }
}

/// One argument of a registry function.
#[derive(Clone, Copy, Debug)]
pub struct ArgSpec {
    /// Its name in the manual's prototype.
    pub name: &'static str,
    /// How a script passes it.
    pub ty: ArgType,
    /// What the argument is, for the core's range check; `None` for what has no range of
    /// its own (pins, flags, modes checked by the command itself).
    pub quantity: Option<Quantity>,
    /// What the argument names for the core beyond its range, if anything.
    pub role: Option<Role>,
    /// Declared `or nil`: a trailing argument a call may leave out.
    pub optional: bool,
}

/// What an argument names, declared with `as Role` after its type, so that the core reads
/// it from the typed call (`arg_with`) instead of a list of its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// The axis a motion command sets going: the task whose command set it going owns it
    /// until that motion is over, another task's command is refused (DXMC 0x001F), and an
    /// E-stop refuses it until the axis is enabled again.
    Moves,
    /// The axis whose motion a command ends or changes without setting it going
    /// (`Disable`): refused as `Moves` while another task owns that motion, in any
    /// controller state.
    Changes,
    /// The group the function addresses (HMPL ch. 18.5, 18.6).
    Group,
    /// The group a group motion command sets going (HMPL ch. 8): as `Moves`, for every
    /// axis of the group.
    MovesGroup,
}

/// One function of the registry.
#[derive(Debug)]
pub struct FunctionSpec {
    /// The manual's name, which is also the Lua global; a dotted name (`FreePort.Eth.Tx`,
    /// declared `["DXMC 8.3" as "FreePort.Eth.Tx"] fn EthTx(..)`) lives in nested tables.
    pub name: &'static str,
    /// The typed function, which tells where it runs.
    pub func: Func,
    /// The manual section that defines it, e.g. `HMPL 5.2.4`.
    pub manual: &'static str,
    /// Callable from the Native ASCII server (the manual's icon).
    pub ascii: bool,
    /// The arguments, in the manual's order.
    pub args: &'static [ArgSpec],
    /// Returned values, first the C return value, then the out-pointers. Empty: `void`.
    pub returns: &'static [ValueType],
    /// One paragraph for the reference and the editor annotations.
    pub doc: &'static [&'static str],
}

impl FunctionSpec {
    /// Each argument with its quantity and the index of its owner before it: the last
    /// `Axis` argument for an axis-bound quantity, the last `Group` for a group-bound one.
    pub fn quantities(&self) -> impl Iterator<Item = (usize, Quantity, Option<usize>)> + '_ {
        self.args.iter().enumerate().filter_map(|(i, arg)| {
            let q = arg.quantity?;
            let owner = if q.is_group_bound() { Quantity::Group } else { Quantity::Axis };
            let at = self.args[..i].iter().rposition(|a| a.quantity == Some(owner)).filter(|_| !q.is_free());
            Some((i, q, at))
        })
    }

    /// Where the function runs.
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
            Some(ValueType::Any) => "any",
            Some(ValueType::Memory) => "void*",
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
                ArgType::Any => format!("any {}", a.name),
                ArgType::Memory => format!("void *{}", a.name),
            })
            .collect();
        format!("{ret} {}({})", self.name, args.join(", "))
    }

    /// The most values a call may pass: every declared argument (the trailing ones a
    /// function says it may do without included); `None` for a variadic one (`...`).
    pub fn max_args(&self) -> Option<usize> {
        match self.args.last() {
            Some(ArgSpec { ty: ArgType::Rest, .. }) => None,
            _ => Some(self.args.len()),
        }
    }

    /// The fewest values a call must pass: up to the last argument a front end cannot do
    /// without. Left out are `or nil` arguments, `...`, an unused `double*` (HMPL passes
    /// NULL, 8.5) and values the function takes as they come (`Any`, nil included).
    pub fn min_args(&self) -> usize {
        let can_be_left_out =
            |a: &ArgSpec| a.optional || matches!(a.ty, ArgType::Rest | ArgType::Doubles | ArgType::Any);
        self.args.iter().rposition(|a| !can_be_left_out(a)).map_or(0, |last| last + 1)
    }

    /// Why a call that passed `given` values, more than `max_args`, is refused, in every
    /// front end's words: `MoveAbs takes 2 argument(s), got 4: int MoveAbs(int axis_id, double pos)`.
    pub fn too_many_args(&self, given: usize) -> String {
        format!("{} takes {} argument(s), got {given}: {}", self.name, self.args.len(), self.signature())
    }
}

/// A function, typed by where it runs, so that each side matches exhaustively on its own kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    /// Carried out by the core in its cycle.
    Command(crate::Command),
    /// Answered from the snapshot in the script process.
    Query(crate::Query),
    /// Runs in the script process alone.
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

/// Declares one kind of functions: an enum with a variant per function, and its table;
/// with `=> CallEnum`, also the typed call: one variant per function with its arguments as
/// named, typed fields, read from a `call::Source` in the declaration's order. Commands and
/// queries (`=> CommandCall<'a>` when an argument borrows: `Str`, `Bytes`, `Doubles`; the
/// lifetime must be named `'a`) are also written to a `call::Sink`. The locals
/// (`=> LocalCall<'a, V>`) are read from a `call::ValueSource`, whose own values `V` stand
/// for the arguments only a front end has the type of (`Func`, `Timer`, `Any`, `Memory`;
/// `Rest` is a `Vec<V>`); a trailing argument declared `or nil` may be left out (`Option`).
macro_rules! declare_functions {
    (
        $enum:ident, $table:ident => $call:ident <$lt:lifetime, $v:ident>;
        $($fns:tt)*
    ) => {
        declare_functions! { @table $enum, $table; $($fns)* }
        declare_functions! { @local_call $enum => $call <$lt, $v>; $($fns)* }
    };
    (
        $enum:ident, $table:ident => $call:ident $(<$lt:lifetime>)?;
        $($fns:tt)*
    ) => {
        declare_functions! { @table $enum, $table; $($fns)* }
        declare_functions! { @call $enum => $call $(<$lt>)?; $($fns)* }
    };
    (
        @local_call $enum:ident => $call:ident <$lt:lifetime, $v:ident>;
        $(
            $(#[doc = $doc:literal])*
            [$manual:literal $(as $lua:literal)? $(, $ascii:ident)?]
            fn $name:ident ( $( $arg:ident : $aty:ident $(or $nil:ident)? $([$q:ident])? $(as $role:ident)? ),* $(,)? ) $(-> $ret:tt)? ;
        )*
    ) => {
        #[doc = concat!("A typed call of a `", stringify!($enum), "`: its arguments as the registry declares them, ")]
        #[doc = "those only a front end has the type of as its own values `V`."]
        #[derive(Clone, Debug, PartialEq)]
        #[allow(non_camel_case_types, non_snake_case, unused_parens)]
        pub enum $call<$lt, $v> {
            $(
                #[doc = concat!("`", stringify!($name), "` (", $manual, ").")]
                $name { $( #[doc = concat!("`", stringify!($arg), "`.")] $arg: <($crate::call::field::$aty $(, $crate::call::field::$nil)?) as $crate::call::field::Field<$lt, $v>>::Type, )* },
            )*
        }

        impl<$lt, $v> $call<$lt, $v> {
            /// The registry function this is a call of.
            pub fn func(&self) -> $enum {
                match self { $( $call::$name { .. } => $enum::$name, )* }
            }
        }

        impl<$lt, S: $crate::call::ValueSource<$lt>> $crate::call::TypedCall<$lt, S> for $call<$lt, S::Value> {
            type Func = $enum;
            fn read(func: $enum, source: &mut S) -> Result<Self, S::Error> {
                Ok(match func {
                    $( $enum::$name => $call::$name { $( $arg: declare_functions!(@read_field source $aty $($nil)?), )* }, )*
                })
            }
        }
    };
    (
        @call $enum:ident => $call:ident $(<$lt:lifetime>)?;
        $(
            $(#[doc = $doc:literal])*
            [$manual:literal $(as $lua:literal)? $(, $ascii:ident)?]
            fn $name:ident ( $( $arg:ident : $aty:ident $([$q:ident])? $(as $role:ident)? ),* $(,)? ) $(-> $ret:tt)? ;
        )*
    ) => {
        #[doc = concat!("A typed call of a `", stringify!($enum), "`: its arguments as the registry declares them.")]
        #[derive(Clone, Debug, PartialEq)]
        #[allow(non_camel_case_types)]
        pub enum $call $(<$lt>)? {
            $(
                #[doc = concat!("`", stringify!($name), "` (", $manual, ").")]
                $name { $( #[doc = concat!("`", stringify!($arg), "`.")] $arg: declare_functions!(@ty $aty), )* },
            )*
        }

        impl $(<$lt>)? $call $(<$lt>)? {
            /// The registry function this is a call of.
            pub fn func(&self) -> $enum {
                match self { $( $call::$name { .. } => $enum::$name, )* }
            }

            /// Writes the arguments to `sink`, in the declaration's order.
            #[allow(unused_variables)]
            pub fn write<K: $crate::call::Sink>(&self, sink: &mut K) -> Result<(), K::Error> {
                match self { $( $call::$name { $( $arg, )* } => { $( declare_functions!(@write sink $arg $aty); )* } )* }
                Ok(())
            }

            /// The argument the declaration marks `as role` (an axis or group id), if any.
            #[allow(unused_variables, unused_mut)]
            pub fn arg_with(&self, role: $crate::registry::Role) -> Option<i64> {
                let mut found = None;
                match self { $( $call::$name { $( $arg, )* } => { $( $( declare_functions!(@role found role $arg $role); )? )* } )* }
                found
            }
        }

        declare_functions!(@typed $enum, $call $(, $lt)?; func, source; match func {
            $( $enum::$name => $call::$name { $( $arg: declare_functions!(@read source $aty), )* }, )*
        });
    };
    (
        @table $enum:ident, $table:ident;
        $(
            $(#[doc = $doc:literal])*
            [$manual:literal $(as $lua:literal)? $(, $ascii:ident)?]
            fn $name:ident ( $( $arg:ident : $aty:ident $(or $nil:ident)? $([$q:ident])? $(as $role:ident)? ),* $(,)? ) $(-> $ret:tt)? ;
        )*
    ) => {
        #[doc = concat!("The registry's functions of kind `", stringify!($enum), "`, one variant each.")]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(u16)]
        #[allow(non_camel_case_types)]
        pub enum $enum { $( #[doc = concat!("`", stringify!($name), "` (", $manual, ").")] $name, )* }

        impl $enum {
            /// Every function of this kind, in wire-id order.
            pub const ALL: &'static [$enum] = &[ $( $enum::$name, )* ];

            /// Its row of the registry.
            pub fn spec(self) -> &'static $crate::registry::FunctionSpec {
                &$table[self as usize]
            }

            /// The wire id of the function (its position in the table).
            pub fn id(self) -> u16 {
                self as u16
            }

            /// The function with wire id `id`; `None` for an id past the table.
            pub fn from_id(id: u16) -> Option<Self> {
                Self::ALL.get(id as usize).copied()
            }
        }

        pub static $table: &[$crate::registry::FunctionSpec] = &[ $(
            $crate::registry::FunctionSpec {
                name: declare_functions!(@name $name $($lua)?),
                func: $crate::registry::Func::$enum($enum::$name),
                manual: $manual,
                ascii: declare_functions!(@ascii $($ascii)?),
                args: &[ $( $crate::registry::ArgSpec {
                    name: stringify!($arg),
                    ty: $crate::registry::ArgType::$aty,
                    quantity: declare_functions!(@quantity $($q)?),
                    role: declare_functions!(@role $($role)?),
                    optional: declare_functions!(@optional $($nil)?),
                }, )* ],
                returns: declare_functions!(@ret $($ret)?),
                doc: &[ $( $doc, )* ],
            },
        )* ];
    };
    (@typed $enum:ident, $call:ident, $lt:lifetime; $func:ident, $source:ident; $body:expr) => {
        impl<$lt, S: $crate::call::Source<$lt>> $crate::call::TypedCall<$lt, S> for $call<$lt> {
            type Func = $enum;
            fn read($func: $enum, $source: &mut S) -> Result<Self, S::Error> {
                Ok($body)
            }
        }
    };
    (@typed $enum:ident, $call:ident; $func:ident, $source:ident; $body:expr) => {
        impl<'s, S: $crate::call::Source<'s>> $crate::call::TypedCall<'s, S> for $call {
            type Func = $enum;
            fn read($func: $enum, $source: &mut S) -> Result<Self, S::Error> {
                Ok($body)
            }
        }
    };
    (@read_field $s:ident $aty:ident $nil:ident) => {
        if $s.absent() { None } else { Some(declare_functions!(@read $s $aty)) }
    };
    (@read_field $s:ident $aty:ident) => { declare_functions!(@read $s $aty) };
    (@ty Int) => { i64 };
    (@ty Double) => { f64 };
    (@ty Bool) => { bool };
    (@ty Str) => { ::std::borrow::Cow<'a, [u8]> };
    (@ty Bytes) => { ::std::borrow::Cow<'a, [u8]> };
    (@ty Doubles) => { $crate::call::Doubles<'a> };
    (@read $s:ident Int) => { $s.int()? };
    (@read $s:ident Double) => { $s.double()? };
    (@read $s:ident Bool) => { $s.bool()? };
    (@read $s:ident Str) => { $s.str()? };
    (@read $s:ident Bytes) => { $s.bytes()? };
    (@read $s:ident Doubles) => { $s.doubles()? };
    (@read $s:ident Rest) => { $s.rest()? };
    (@read $s:ident $front_end:ident) => { $s.value($crate::registry::ArgType::$front_end)? };
    (@write $s:ident $v:ident Int) => { $s.int(*$v)? };
    (@write $s:ident $v:ident Double) => { $s.double(*$v)? };
    (@write $s:ident $v:ident Bool) => { $s.bool(*$v)? };
    (@write $s:ident $v:ident Str) => { $s.str($v)? };
    (@write $s:ident $v:ident Bytes) => { $s.bytes($v)? };
    (@write $s:ident $v:ident Doubles) => { $s.doubles($v)? };
    (@role $found:ident $want:ident $arg:ident $role:ident) => {
        if $want == $crate::registry::Role::$role {
            $found = Some(*$arg);
        }
    };
    (@role $role:ident) => { Some($crate::registry::Role::$role) };
    (@role) => { None };
    (@optional $nil:ident) => { true };
    (@optional) => { false };
    (@quantity $q:ident) => { Some($crate::registry::Quantity::$q) };
    (@quantity) => { None };
    (@name $name:ident $lua:literal) => { $lua };
    (@name $name:ident) => { stringify!($name) };
    (@ascii ascii) => { true };
    (@ascii) => { false };
    (@ret) => { &[] };
    (@ret ( $( $t:ident ),* )) => { &[ $( $crate::registry::ValueType::$t, )* ] };
    (@ret $t:ident) => { &[ $crate::registry::ValueType::$t ] };
}

pub(crate) use declare_functions;

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 11: a number that reaches the kernel has a range. Every `double` a command
    /// takes declares its quantity, and each quantity but `Axis` names its axis.
    #[test]
    fn every_number_a_command_takes_has_a_range() {
        for spec in crate::functions::COMMANDS {
            for arg in spec.args {
                if matches!(arg.ty, ArgType::Double | ArgType::Doubles) {
                    assert!(arg.quantity.is_some(), "{}: argument {} has no quantity", spec.name, arg.name);
                }
            }
            for (i, q, owner) in spec.quantities() {
                let own = matches!(q, Quantity::Axis | Quantity::Group) || q.is_free();
                assert!(own || owner.is_some(), "{}: argument {i} has no axis or group before it", spec.name);
            }
            for arg in spec.args.iter().filter(|a| matches!(a.role, Some(Role::Moves | Role::Changes))) {
                assert_eq!(arg.quantity, Some(Quantity::Axis), "{}: {} moves no axis", spec.name, arg.name);
            }
            for arg in spec.args.iter().filter(|a| a.role == Some(Role::MovesGroup)) {
                assert_eq!(arg.quantity, Some(Quantity::Group), "{}: {} moves no group", spec.name, arg.name);
            }
        }
    }
}

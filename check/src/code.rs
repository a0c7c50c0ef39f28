//! What the check reports, one code per kind of mistake, as luacheck and rustc number
//! theirs: errors are certain to fail or to do what the program did not mean; warnings
//! may be meant and can be allowed one by one (`--allow W201`).

use serde::Serialize;

/// How sure the check is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// `luamotion run` refuses to start.
    Error,
    /// Reported; the program runs.
    Warning,
}

/// One kind of mistake.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Code {
    /// The program is no Lua 5.4.
    Syntax,
    /// A global that no program sets and the API does not have.
    UnknownGlobal,
    /// More or fewer values than the function takes.
    ArgumentCount,
    /// A literal of a type the argument refuses.
    ArgumentType,
    /// A value where a function belongs (`Till(IsInPos(0))`).
    NotAFunction,
    /// What the sandbox refuses (`io`, `os`, bytecode, a module outside the project).
    Sandbox,
    /// An assignment to a name of the API.
    ReadOnly,
    /// A command's return code compared with `true` or `false`.
    CodeComparedWithBoolean,
    /// A global read that the program never sets (nil, unless meant).
    UnsetGlobal,
}

impl Code {
    /// Every code, for `--allow` and the reference.
    pub const ALL: &'static [Code] = &[
        Code::Syntax,
        Code::UnknownGlobal,
        Code::ArgumentCount,
        Code::ArgumentType,
        Code::NotAFunction,
        Code::Sandbox,
        Code::ReadOnly,
        Code::CodeComparedWithBoolean,
        Code::UnsetGlobal,
    ];

    /// Its name in reports, e.g. `E102`.
    pub fn id(self) -> &'static str {
        match self {
            Code::Syntax => "E100",
            Code::UnknownGlobal => "E101",
            Code::ArgumentCount => "E102",
            Code::ArgumentType => "E103",
            Code::NotAFunction => "E104",
            Code::Sandbox => "E105",
            Code::ReadOnly => "E106",
            Code::CodeComparedWithBoolean => "W201",
            Code::UnsetGlobal => "W202",
        }
    }

    /// The code named `id` (`E102`, `w201`).
    pub fn parse(id: &str) -> Option<Code> {
        Code::ALL.iter().copied().find(|c| c.id().eq_ignore_ascii_case(id))
    }

    /// Errors are the E codes, warnings the W codes.
    pub fn severity(self) -> Severity {
        match self {
            Code::CodeComparedWithBoolean | Code::UnsetGlobal => Severity::Warning,
            _ => Severity::Error,
        }
    }

    /// One line for the reference.
    pub fn summary(self) -> &'static str {
        match self {
            Code::Syntax => "the file is not Lua 5.4",
            Code::UnknownGlobal => "an API name or constant that does not exist (with the nearest that does)",
            Code::ArgumentCount => "a call with more or fewer values than the function takes",
            Code::ArgumentType => "a literal argument of a type the function refuses",
            Code::NotAFunction => "a value where a callback function belongs",
            Code::Sandbox => {
                "what the sandbox refuses: io, os, package, debug, files, bytecode, modules outside the project"
            }
            Code::ReadOnly => "an assignment to a function, constant or read-only variable of the API",
            Code::CodeComparedWithBoolean => "a command's return code (0 on success) compared with true or false",
            Code::UnsetGlobal => "a global the program reads but never sets",
        }
    }
}

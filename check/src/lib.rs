//! `luamotion check`: a static check of Lua programs against the API registry, before
//! anything moves. A misspelled API name or constant, a call with the wrong number of
//! values or a literal of the wrong type, a value where a callback belongs
//! (`Till(IsInPos(0))`), what the sandbox refuses, a command's code compared with
//! `true`, and an assignment to a name of the API.
//!
//! From the outside in: `check_paths` takes files and folders, `Checker::check_source` one
//! program; `walk` goes over the program parsed by full_moon (Lua 5.4) with its scopes;
//! `environment` is the globals a script VM starts with, from the registry; `code` the
//! kinds of mistakes, `diagnostic` how one is shown, `suggest` "did you mean";
//! `luacheckrc` the same environment for luacheck; `editor` what `luamotion lsp` answers.

pub mod code;
pub mod diagnostic;
pub mod editor;
pub mod environment;
pub mod luacheckrc;
pub mod suggest;
mod walk;

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use full_moon::ast::{Ast, Call, Prefix, Suffix, Var};
use full_moon::tokenizer::TokenType;
use full_moon::visitors::Visitor;

pub use code::{Code, Severity};
pub use diagnostic::Diagnostic;
pub use environment::Environment;

/// Why files could not be checked.
#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    /// A file or folder that cannot be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// What was given.
        path: PathBuf,
        /// What the OS said.
        source: std::io::Error,
    },
}

/// What to report.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Warnings left out (`--allow W201`).
    pub allowed: Vec<Code>,
}

/// One checked file: its text, for showing the lines, and what was found.
#[derive(Debug)]
pub struct Checked {
    /// Its text.
    pub source: String,
    /// What was found, in the order of the source.
    pub diagnostics: Vec<Diagnostic>,
}

impl Checked {
    /// Whether anything found is an error.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(|d| d.severity == Severity::Error)
    }

    /// Every finding as rustc shows its own.
    pub fn render(&self) -> String {
        self.diagnostics.iter().map(|d| d.render(&self.source)).collect()
    }
}

/// The check, with the environment built once.
#[derive(Default)]
pub struct Checker {
    environment: Environment,
    options: Options,
}

impl Checker {
    /// A check with `options`.
    pub fn new(options: Options) -> Self {
        Checker { environment: Environment::new(), options }
    }

    /// Checks the program `source`, named `file`, whose `require`s look in `folder`
    /// (none: `require` is not checked).
    pub fn check_source(&self, file: &str, source: &str, folder: Option<&Path>) -> Vec<Diagnostic> {
        // The parser and the walk recurse per level, and a debug build's frames are large:
        // a thread of its own with room for Lua's levels. A panic of the parser (full_moon
        // has `unreachable!`s a stray character reaches) is a finding, not a crash.
        let found = std::thread::scope(|scope| {
            let run = || self.findings(source, folder);
            std::thread::Builder::new().stack_size(PARSER_STACK).spawn_scoped(scope, run).map(|t| t.join())
        });
        let found = match found {
            Ok(Ok(found)) => found,
            _ => {
                let message = "not Lua 5.4: the parser gave up on this text (a character Lua has no use for?)";
                vec![Diagnostic::new(Code::Syntax, (1, 1, 1), message.to_string(), None)]
            }
        };
        self.finish(file, found)
    }

    fn findings(&self, source: &str, folder: Option<&Path>) -> Vec<Diagnostic> {
        if let Some((line, column)) = too_deep(source) {
            let message = format!("more than {MAX_LEVELS} nested levels: Lua refuses it too (C stack overflow)");
            return vec![Diagnostic::new(Code::Syntax, (line, column, 1), message, None)];
        }
        let parsed = full_moon::parse_fallible(source, full_moon::LuaVersion::lua54());
        if let Some(error) = parsed.errors().first() {
            let (start, _) = error.range();
            let message = format!("not Lua 5.4: {}", error.error_message());
            return vec![Diagnostic::new(Code::Syntax, (start.line(), start.character(), 1), message, None)];
        }
        let mut defined = globals_set(parsed.ast());
        if let Some(folder) = folder {
            defined.extend(module_globals(parsed.ast(), folder));
        }
        let missing = |name: &str| folder.and_then(|folder| missing_module(folder, name));
        let mut walk = walk::Walk::new(&self.environment, &defined, &missing);
        walk.chunk(parsed.ast().nodes());
        walk.found
    }

    fn finish(&self, file: &str, mut found: Vec<Diagnostic>) -> Vec<Diagnostic> {
        found.retain(|d| !self.options.allowed.iter().any(|c| c.id() == d.code));
        found.sort_by_key(|d| (d.line, d.column));
        for d in &mut found {
            d.file = file.to_string();
        }
        found
    }

    /// Checks one file.
    pub fn check_file(&self, path: &Path) -> Result<Checked, CheckError> {
        let source = std::fs::read_to_string(path).map_err(|source| CheckError::Read { path: path.into(), source })?;
        let folder = path.parent().map(|p| if p.as_os_str().is_empty() { Path::new(".") } else { p });
        let diagnostics = self.check_source(&path.display().to_string(), &source, folder);
        Ok(Checked { source, diagnostics })
    }

    /// Checks files, and the `.lua` files of folders (recursively), in name order.
    pub fn check_paths(&self, paths: &[PathBuf]) -> Result<Vec<Checked>, CheckError> {
        let mut files = Vec::new();
        for path in paths {
            lua_files(path, &mut files)?;
        }
        files.iter().map(|f| self.check_file(f)).collect()
    }
}

fn lua_files(path: &Path, files: &mut Vec<PathBuf>) -> Result<(), CheckError> {
    let read = |source| CheckError::Read { path: path.to_path_buf(), source };
    if !path.is_dir() {
        std::fs::metadata(path).map_err(read)?;
        files.push(path.to_path_buf());
        return Ok(());
    }
    let mut entries: Vec<PathBuf> =
        std::fs::read_dir(path).map_err(read)?.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for entry in entries {
        if entry.is_dir() || (entry.extension().is_some_and(|e| e == "lua") && !is_definitions(&entry)) {
            lua_files(&entry, files)?;
        }
    }
    Ok(())
}

/// Lua's own limit of nested levels (LUAI_MAXCCALLS, 200): blocks, brackets and the
/// operators its parser takes by recursion.
const MAX_LEVELS: usize = 200;
/// Room for `MAX_LEVELS` levels of full_moon's parser and the walk in a debug build.
const PARSER_STACK: usize = 256 << 20;

/// Where a program first goes deeper than `MAX_LEVELS`: each open block or bracket is a
/// level, and so is each operator of a chain the parser takes by recursion (`..`, `^`,
/// unary operators) until the expression ends. Tokens only: no recursion here.
fn too_deep(source: &str) -> Option<(usize, usize)> {
    use full_moon::tokenizer::{Lexer, LexerResult, Symbol};
    let mut lexer = Lexer::new(source, full_moon::LuaVersion::lua54());
    let (mut depth, mut chain) = (0usize, 0usize);
    while let Some(LexerResult::Ok(token) | LexerResult::Recovered(token, _)) = lexer.process_next() {
        let TokenType::Symbol { symbol } = token.token_type() else { continue };
        match symbol {
            Symbol::LeftParen
            | Symbol::LeftBrace
            | Symbol::LeftBracket
            | Symbol::Function
            | Symbol::Do
            | Symbol::If
            | Symbol::Repeat => depth += 1,
            Symbol::RightParen | Symbol::RightBrace | Symbol::RightBracket | Symbol::End | Symbol::Until => {
                depth = depth.saturating_sub(1);
                chain = 0;
            }
            Symbol::TwoDots | Symbol::Caret | Symbol::Not | Symbol::Hash | Symbol::Minus | Symbol::Tilde => chain += 1,
            Symbol::Comma | Symbol::Semicolon | Symbol::Equal | Symbol::Local | Symbol::Return | Symbol::Then => {
                chain = 0
            }
            _ => {}
        }
        if depth + chain > MAX_LEVELS {
            let at = token.start_position();
            return Some((at.line(), at.character()));
        }
    }
    None
}

/// An editor's definition file (`---@meta`, as `scripts/luamotion.d.lua`): no program.
fn is_definitions(path: &Path) -> bool {
    std::fs::read_to_string(path).is_ok_and(|text| text.starts_with("---@meta"))
}

/// Names a program assigns as globals anywhere (`x = 1`, `function f() end`), and the
/// modules it requires by a literal name: scope does not matter here, a program that sets
/// a global in one place may read it in another.
#[derive(Default)]
struct Globals {
    set: HashSet<String>,
    required: Vec<String>,
}

impl Visitor for Globals {
    fn visit_assignment(&mut self, assignment: &full_moon::ast::Assignment) {
        for var in assignment.variables() {
            if let Var::Name(token) = var {
                self.set.insert(token.token().to_string());
            }
        }
    }

    fn visit_function_declaration(&mut self, declaration: &full_moon::ast::FunctionDeclaration) {
        let name = declaration.name();
        if name.names().len() == 1 && name.method_name().is_none() {
            self.set.extend(name.names().iter().map(|t| t.token().to_string()));
        }
    }

    fn visit_function_call(&mut self, call: &full_moon::ast::FunctionCall) {
        let Prefix::Name(token) = call.prefix() else { return };
        if token.token().to_string() != "require" {
            return;
        }
        let Some(Suffix::Call(Call::AnonymousCall(args))) = call.suffixes().next() else { return };
        if let Some((_, name)) = walk::first_string(args) {
            self.required.push(name.to_string());
        }
    }
}

fn globals_set(ast: &Ast) -> HashSet<String> {
    let mut globals = Globals::default();
    globals.visit_ast(ast);
    globals.set
}

/// The file of module `name` in `folder`, as the project's `require` finds it
/// (`motion.pallet` is `motion/pallet.lua`).
fn module_path(folder: &Path, name: &str) -> Option<PathBuf> {
    let valid = !name.is_empty()
        && name.split('.').all(|part| !part.is_empty() && part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'));
    valid.then(|| folder.join(format!("{}.lua", name.replace('.', "/"))))
}

/// Why `require(name)` fails, in the words of the project's `require`.
fn missing_module(folder: &Path, name: &str) -> Option<String> {
    match module_path(folder, name) {
        None => Some(format!("require: bad module name {name:?} (names are like util or motion.pallet)")),
        Some(path) if !path.is_file() => Some(format!("require: no module '{name}' in {}", folder.display())),
        Some(_) => None,
    }
}

/// The globals the modules a program requires set, and theirs, once each.
fn module_globals(ast: &Ast, folder: &Path) -> HashSet<String> {
    let mut found = HashSet::new();
    let mut seen = HashSet::new();
    let mut queue = {
        let mut globals = Globals::default();
        globals.visit_ast(ast);
        globals.required
    };
    while let Some(name) = queue.pop() {
        if !seen.insert(name.clone()) {
            continue;
        }
        let Some(text) = module_path(folder, &name).and_then(|p| std::fs::read_to_string(p).ok()) else { continue };
        let parsed = full_moon::parse_fallible(&text, full_moon::LuaVersion::lua54());
        let mut globals = Globals::default();
        globals.visit_ast(parsed.ast());
        found.extend(globals.set);
        queue.extend(globals.required);
    }
    found
}

//! The walk over a parsed program: which names are local where (Lua's scopes: a local is
//! seen after its statement, a function's parameters in its body, a `repeat` block's
//! locals in its `until`), and the rules at each global, call and comparison.

use std::collections::HashSet;

use api::{ArgType, FunctionSpec, ValueType};
use full_moon::ast::{
    BinOp, Block, Call, Expression, Field, FunctionArgs, FunctionBody, FunctionCall, Index, LastStmt, Parameter,
    Prefix, Stmt, Suffix, UnOp, Var,
};
use full_moon::node::Node;
use full_moon::tokenizer::{Symbol, TokenReference, TokenType};

use crate::code::Code;
use crate::diagnostic::Diagnostic;
use crate::environment::{Environment, Known};
use crate::suggest;

/// What the walk knows beyond the environment.
pub struct Walk<'a> {
    pub(crate) environment: &'a Environment,
    /// Globals the program (or a module it requires) assigns somewhere.
    pub(crate) defined: &'a HashSet<String>,
    /// Modules `require` cannot find: (name, why).
    pub(crate) missing_module: &'a dyn Fn(&str) -> Option<String>,
    scopes: Vec<HashSet<String>>,
    pub(crate) found: Vec<Diagnostic>,
}

/// A literal's type, or what an API call returns, as far as the source tells.
#[derive(Clone, Copy, Debug)]
enum Shape {
    Integer,
    /// A float literal; `true` when its value is integral (`2.0`).
    Float(bool),
    Str,
    Boolean,
    Nil,
    Table,
    Function,
    /// What an API function returns first.
    Returned(&'static FunctionSpec, ValueType),
}

impl Shape {
    fn describe(self) -> String {
        match self {
            Shape::Integer => "an integer".into(),
            Shape::Float(_) => "a float".into(),
            Shape::Str => "a string".into(),
            Shape::Boolean => "a boolean".into(),
            Shape::Nil => "nil".into(),
            Shape::Table => "a table".into(),
            Shape::Function => "a function".into(),
            Shape::Returned(spec, ty) => format!("the {} `{}` returns", value_name(ty), spec.name),
        }
    }
}

fn value_name(ty: ValueType) -> &'static str {
    match ty {
        ValueType::Int => "integer",
        ValueType::Double => "number",
        ValueType::Bool => "boolean",
        ValueType::Str => "string",
        ValueType::Bytes | ValueType::Doubles | ValueType::Memory => "table",
        ValueType::Timer => "timer",
        ValueType::Any => "value",
    }
}

/// Line, column and width of a token.
fn at_token(token: &TokenReference) -> (usize, usize, usize) {
    let (start, end) = (token.token().start_position(), token.token().end_position());
    let width = if end.line() == start.line() { end.character() - start.character() } else { 1 };
    (start.line(), start.character(), width)
}

/// Line, column and width of a node (its first line).
fn at_node(node: &impl Node) -> (usize, usize, usize) {
    match node.range() {
        Some((start, end)) => {
            let width = if end.line() == start.line() { end.character() - start.character() } else { 1 };
            (start.line(), start.character(), width)
        }
        None => (1, 1, 1),
    }
}

/// The identifier a token is.
fn name_of(token: &TokenReference) -> &str {
    match token.token().token_type() {
        TokenType::Identifier { identifier } => identifier.as_str(),
        _ => "",
    }
}

fn symbol_of(expression: &Expression) -> Option<Symbol> {
    match expression {
        Expression::Symbol(token) => match token.token().token_type() {
            TokenType::Symbol { symbol } => Some(*symbol),
            _ => None,
        },
        _ => None,
    }
}

/// A call's first value if it is a string literal (`require 'util'`, `require("util")`):
/// its token and its text.
pub(crate) fn first_string(args: &FunctionArgs) -> Option<(&TokenReference, &str)> {
    let token = match args {
        FunctionArgs::String(token) => token,
        FunctionArgs::Parentheses { arguments, .. } => match arguments.iter().next()? {
            Expression::String(token) => token,
            _ => return None,
        },
        _ => return None,
    };
    match token.token().token_type() {
        TokenType::StringLiteral { literal, .. } => Some((token, literal.as_str())),
        _ => None,
    }
}

/// The values of a call's arguments.
fn arguments(args: &FunctionArgs) -> Vec<&Expression> {
    match args {
        FunctionArgs::Parentheses { arguments, .. } => arguments.iter().collect(),
        _ => Vec::new(),
    }
}

impl<'a> Walk<'a> {
    pub(crate) fn new(
        environment: &'a Environment,
        defined: &'a HashSet<String>,
        missing_module: &'a dyn Fn(&str) -> Option<String>,
    ) -> Self {
        Walk { environment, defined, missing_module, scopes: Vec::new(), found: Vec::new() }
    }

    fn report(&mut self, code: Code, at: (usize, usize, usize), message: String, help: Option<String>) {
        self.found.push(Diagnostic::new(code, at, message, help));
    }

    fn is_local(&self, name: &str) -> bool {
        self.scopes.iter().any(|scope| scope.contains(name))
    }

    fn declare(&mut self, name: &str) {
        if let Some(scope) = self.scopes.last_mut() {
            scope.insert(name.to_string());
        }
    }

    /// What a global name read (not assigned) is; `None` for a local.
    fn global(&self, name: &str) -> Option<Option<Known>> {
        (!self.is_local(name)).then(|| self.environment.get(name))
    }

    /// The program's chunk.
    pub(crate) fn chunk(&mut self, block: &Block) {
        self.block(block, &[], None);
    }

    /// A block in a scope of its own that starts with `names`; `until` is read inside it.
    fn block(&mut self, block: &Block, names: &[&str], until: Option<&Expression>) {
        self.scopes.push(names.iter().map(|n| n.to_string()).collect());
        for stmt in block.stmts() {
            self.stmt(stmt);
        }
        if let Some(LastStmt::Return(ret)) = block.last_stmt() {
            for expression in ret.returns() {
                self.expression(expression);
            }
        }
        if let Some(until) = until {
            self.expression(until);
        }
        self.scopes.pop();
    }

    fn stmt(&mut self, stmt: &Stmt) {
        match stmt {
            Stmt::Assignment(assignment) => {
                for expression in assignment.expressions() {
                    self.expression(expression);
                }
                for var in assignment.variables() {
                    match var {
                        Var::Name(token) => self.assigned(token),
                        Var::Expression(var) => self.suffixed(var.prefix(), var.suffixes().collect()),
                        _ => {}
                    }
                }
            }
            Stmt::Do(block) => self.block(block.block(), &[], None),
            Stmt::FunctionCall(call) => self.call(call),
            Stmt::FunctionDeclaration(declaration) => {
                let name = declaration.name();
                let names: Vec<&TokenReference> = name.names().iter().collect();
                match (names.as_slice(), name.method_name()) {
                    ([only], None) => self.assigned(only),
                    ([first, ..], _) => {
                        if let Some(None) = self.global(name_of(first)) {
                            self.unknown(first, false);
                        }
                    }
                    _ => {}
                }
                let method = name.method_name().is_some();
                self.body(declaration.body(), method);
            }
            Stmt::GenericFor(for_in) => {
                for expression in for_in.expressions() {
                    self.expression(expression);
                }
                let names: Vec<&str> = for_in.names().iter().map(name_of).collect();
                self.block(for_in.block(), &names, None);
            }
            Stmt::If(if_stmt) => {
                self.expression(if_stmt.condition());
                self.block(if_stmt.block(), &[], None);
                for else_if in if_stmt.else_if().into_iter().flatten() {
                    self.expression(else_if.condition());
                    self.block(else_if.block(), &[], None);
                }
                if let Some(block) = if_stmt.else_block() {
                    self.block(block, &[], None);
                }
            }
            Stmt::LocalAssignment(local) => {
                for expression in local.expressions() {
                    self.expression(expression);
                }
                for name in local.names() {
                    self.declare(name_of(name));
                }
            }
            Stmt::LocalFunction(function) => {
                self.declare(name_of(function.name()));
                self.body(function.body(), false);
            }
            Stmt::NumericFor(numeric) => {
                self.expression(numeric.start());
                self.expression(numeric.end());
                if let Some(step) = numeric.step() {
                    self.expression(step);
                }
                self.block(numeric.block(), &[name_of(numeric.index_variable())], None);
            }
            Stmt::Repeat(repeat) => self.block(repeat.block(), &[], Some(repeat.until())),
            Stmt::While(while_stmt) => {
                self.expression(while_stmt.condition());
                self.block(while_stmt.block(), &[], None);
            }
            _ => {}
        }
    }

    fn body(&mut self, body: &FunctionBody, method: bool) {
        let mut names: Vec<&str> = body
            .parameters()
            .iter()
            .filter_map(|p| match p {
                Parameter::Name(token) => Some(name_of(token)),
                _ => None,
            })
            .collect();
        if method {
            names.push("self");
        }
        self.block(body.block(), &names, None);
    }

    /// `name = ...` or `function name()` of a global: the API's names are read-only.
    fn assigned(&mut self, token: &TokenReference) {
        let name = name_of(token);
        if self.is_local(name) {
            return;
        }
        let what = match self.environment.get(name) {
            Some(Known::Function(spec)) => format!("`{name}` is an API function ({})", spec.manual),
            Some(Known::ApiTable) => format!("`{name}` holds API functions"),
            Some(Known::Constant) => format!("`{name}` is a constant of the API"),
            Some(Known::SystemVariable { writable: false }) => format!("{name} is read-only"),
            Some(Known::Lua) => return,
            Some(Known::SystemVariable { writable: true }) | None => {
                if let Some(why) = Environment::refused(name) {
                    self.report(Code::Sandbox, at_token(token), why.to_string(), None);
                }
                return;
            }
        };
        let help = Some(format!("use a name of your own, or `local {name}` to keep it to this scope"));
        self.report(Code::ReadOnly, at_token(token), format!("assignment to a read-only name: {what}"), help);
    }

    /// A global the environment does not have: known to the program, refused by the
    /// sandbox, misspelled, or never set.
    fn unknown(&mut self, token: &TokenReference, called: bool) {
        let name = name_of(token);
        if let Some(why) = Environment::refused(name) {
            return self.report(Code::Sandbox, at_token(token), why.to_string(), None);
        }
        if self.defined.contains(name) {
            return;
        }
        let nearest = suggest::nearest(name, self.environment.candidates());
        let help = nearest.map(|n| self.describe(n));
        match (called, nearest) {
            (false, None) => self.report(
                Code::UnsetGlobal,
                at_token(token),
                format!("`{name}` is read but never set: it is nil"),
                None,
            ),
            _ => self.report(Code::UnknownGlobal, at_token(token), format!("unknown global `{name}`"), help),
        }
    }

    /// "did you mean `MoveAbs`? int MoveAbs(int axis_id, double pos) (HMPL 5.2.4)"
    fn describe(&self, name: &str) -> String {
        let spec = match self.environment.get(name) {
            Some(Known::Function(spec)) => Some(spec),
            _ => self.environment.dotted(name),
        };
        match spec {
            Some(spec) => format!("did you mean `{name}`? {} ({})", spec.signature(), spec.manual),
            None => format!("did you mean `{name}`?"),
        }
    }

    fn call(&mut self, call: &FunctionCall) {
        self.suffixed(call.prefix(), call.suffixes().collect());
    }

    /// `prefix.a.b(args)[i]...`: the global at its start, the API function it names, the
    /// values of its calls and indexes.
    fn suffixed(&mut self, prefix: &Prefix, suffixes: Vec<&Suffix>) {
        let root = match prefix {
            Prefix::Name(token) => Some(token),
            Prefix::Expression(expression) => {
                self.expression(expression);
                None
            }
            _ => None,
        };
        let mut spec = None;
        if let Some(token) = root {
            let name = name_of(token);
            let dots: Vec<&TokenReference> = suffixes
                .iter()
                .map_while(|s| match s {
                    Suffix::Index(Index::Dot { name, .. }) => Some(name),
                    _ => None,
                })
                .collect();
            let called_next = matches!(suffixes.get(dots.len()), Some(Suffix::Call(Call::AnonymousCall(_))));
            match self.global(name) {
                None => {}
                Some(Some(Known::Function(found))) if dots.is_empty() && !self.defined.contains(name) => {
                    spec = Some(found)
                }
                Some(Some(Known::ApiTable)) => spec = self.dotted_path(name, &dots, called_next),
                Some(Some(_)) => {}
                Some(None) => self.unknown(token, called_next && dots.is_empty()),
            }
            if name == "require" && !self.is_local(name) {
                self.require(&suffixes);
            }
            if name == "load" && !self.is_local(name) {
                self.load(&suffixes);
            }
        }
        let mut first_call = true;
        for suffix in suffixes {
            match suffix {
                Suffix::Call(Call::AnonymousCall(args)) => {
                    if first_call && let Some(spec) = spec.take() {
                        self.api_call(spec, args);
                    }
                    first_call = false;
                    self.args(args);
                }
                Suffix::Call(Call::MethodCall(method)) => {
                    first_call = false;
                    self.args(method.args());
                }
                Suffix::Index(Index::Brackets { expression, .. }) => self.expression(expression),
                _ => {}
            }
        }
    }

    /// `FreePort.Eth.Tx`: the registry function a dotted path names, or a report of a
    /// member the table does not have.
    fn dotted_path(&mut self, root: &str, dots: &[&TokenReference], called: bool) -> Option<&'static FunctionSpec> {
        let mut path = root.to_string();
        for token in dots {
            path = format!("{path}.{}", name_of(token));
            if let Some(spec) = self.environment.dotted(&path) {
                return Some(spec).filter(|_| called);
            }
            if !self.environment.is_dotted_prefix(&path) {
                let nearest = suggest::nearest(&path, self.environment.candidates().filter(|c| c.contains('.')));
                let help = nearest.map(|n| self.describe(n));
                self.report(Code::UnknownGlobal, at_token(token), format!("`{path}` is no function of the API"), help);
                return None;
            }
        }
        None
    }

    fn args(&mut self, args: &FunctionArgs) {
        match args {
            FunctionArgs::Parentheses { arguments, .. } => {
                for expression in arguments {
                    self.expression(expression);
                }
            }
            FunctionArgs::TableConstructor(table) => self.table(table),
            _ => {}
        }
    }

    fn table(&mut self, table: &full_moon::ast::TableConstructor) {
        for field in table.fields() {
            match field {
                Field::ExpressionKey { key, value, .. } => {
                    self.expression(key);
                    self.expression(value);
                }
                Field::NameKey { value, .. } => self.expression(value),
                Field::NoKey(value) => self.expression(value),
                _ => {}
            }
        }
    }

    fn expression(&mut self, expression: &Expression) {
        match expression {
            Expression::BinaryOperator { lhs, binop, rhs } => {
                if matches!(binop, BinOp::TwoEqual(_) | BinOp::TildeEqual(_)) {
                    self.compared(lhs, rhs);
                }
                self.expression(lhs);
                self.expression(rhs);
            }
            Expression::Parentheses { expression, .. } | Expression::UnaryOperator { expression, .. } => {
                self.expression(expression)
            }
            Expression::Function(function) => self.body(function.body(), false),
            Expression::FunctionCall(call) => self.call(call),
            Expression::TableConstructor(table) => self.table(table),
            Expression::Var(Var::Name(token)) => {
                if let Some(None) = self.global(name_of(token)) {
                    self.unknown(token, false);
                }
            }
            Expression::Var(Var::Expression(var)) => self.suffixed(var.prefix(), var.suffixes().collect()),
            _ => {}
        }
    }

    /// `MoveAbs(0, 10) == true`: a command's code is 0 on success, never a boolean.
    fn compared(&mut self, lhs: &Expression, rhs: &Expression) {
        for (call, other) in [(lhs, rhs), (rhs, lhs)] {
            let boolean = matches!(symbol_of(other), Some(Symbol::True | Symbol::False));
            if let (true, Some(Shape::Returned(spec, ValueType::Int))) = (boolean, self.shape(call)) {
                let help = format!("compare with 0: `{}(...) == 0` is success (HMPL ch. 18)", spec.name);
                self.report(
                    Code::CodeComparedWithBoolean,
                    at_node(other),
                    format!("`{}` returns a code (0 on success), never true or false", spec.name),
                    Some(help),
                );
            }
        }
    }

    /// What an expression is, where the source says it plainly.
    fn shape(&self, expression: &Expression) -> Option<Shape> {
        match expression {
            Expression::Number(token) => {
                let text = token.token().to_string();
                let hex = text.starts_with("0x") || text.starts_with("0X");
                if hex || !text.contains(['.', 'e', 'E']) {
                    Some(Shape::Integer)
                } else {
                    Some(Shape::Float(text.parse::<f64>().is_ok_and(|v| v.fract() == 0.0)))
                }
            }
            Expression::String(_) => Some(Shape::Str),
            Expression::Symbol(_) => match symbol_of(expression)? {
                Symbol::True | Symbol::False => Some(Shape::Boolean),
                Symbol::Nil => Some(Shape::Nil),
                _ => None,
            },
            Expression::TableConstructor(_) => Some(Shape::Table),
            Expression::Function(_) => Some(Shape::Function),
            Expression::Parentheses { expression, .. } => self.shape(expression),
            Expression::UnaryOperator { unop: UnOp::Minus(_), expression } => {
                self.shape(expression).filter(|s| matches!(s, Shape::Integer | Shape::Float(_)))
            }
            Expression::UnaryOperator { unop: UnOp::Not(_), .. } => Some(Shape::Boolean),
            Expression::FunctionCall(call) => {
                let Prefix::Name(token) = call.prefix() else { return None };
                let mut suffixes = call.suffixes();
                let (Some(Suffix::Call(Call::AnonymousCall(_))), None) = (suffixes.next(), suffixes.next()) else {
                    return None;
                };
                let name = name_of(token);
                match self.global(name)? {
                    Some(Known::Function(spec)) if !self.defined.contains(name) => {
                        spec.returns.first().map(|ty| Shape::Returned(spec, *ty))
                    }
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// A call of a registry function: the count of its values and the literal ones'
    /// types against the declaration.
    fn api_call(&mut self, spec: &'static FunctionSpec, args: &FunctionArgs) {
        let values: Vec<Option<&Expression>> = match args {
            FunctionArgs::Parentheses { .. } => arguments(args).into_iter().map(Some).collect(),
            // `f"text"` and `f{...}`: one value.
            _ => vec![None],
        };
        // A last value that is a call or `...` may stand for any number of values.
        let open = matches!(values.last(), Some(Some(Expression::FunctionCall(_))))
            || values.last().and_then(|v| v.and_then(symbol_of)) == Some(Symbol::Ellipsis);
        let given = values.len();
        let (min, max) = (spec.min_args(), spec.max_args());
        let fixed = if open { given - 1 } else { given };
        let too_many = max.is_some_and(|max| fixed > max);
        let too_few = !open && given < min;
        if too_many || too_few {
            let takes = match max {
                Some(max) if max == min => format!("{max} argument(s)"),
                Some(max) => format!("{min} to {max} arguments"),
                None => format!("at least {min} argument(s)"),
            };
            let at = match args {
                FunctionArgs::Parentheses { parentheses, .. } => {
                    let (open, close) = parentheses.tokens();
                    let (line, column, _) = at_token(open);
                    let (end_line, end_column, _) = at_token(close);
                    (line, column, if end_line == line { end_column + 1 - column } else { 1 })
                }
                _ => at_node(args),
            };
            let message = format!("`{}` takes {takes}, got {given}", spec.name);
            self.report(Code::ArgumentCount, at, message, Some(spec.signature()));
        }
        for (arg, value) in spec.args.iter().zip(&values) {
            let Some(value) = value else { continue };
            let Some(shape) = self.shape(value) else { continue };
            self.argument(spec, arg, value, shape);
        }
    }

    /// One literal value against the argument it is passed for.
    fn argument(&mut self, spec: &FunctionSpec, arg: &api::ArgSpec, value: &Expression, shape: Shape) {
        use Shape::*;
        let number = matches!(shape, Integer | Float(_));
        let returned_number = matches!(shape, Returned(_, ValueType::Int | ValueType::Double));
        let refused = match arg.ty {
            ArgType::Int => !(matches!(shape, Integer | Float(true)) || returned_number),
            ArgType::Double => !(number || returned_number),
            ArgType::Str => matches!(shape, Boolean | Nil | Table | Function),
            ArgType::Bool => matches!(shape, Str | Nil | Table | Function),
            ArgType::Bytes => matches!(shape, Integer | Float(_) | Boolean | Nil | Function),
            ArgType::Doubles => matches!(shape, Str | Boolean | Function | Float(_)),
            ArgType::Timer => !matches!(shape, Returned(_, ValueType::Timer)),
            ArgType::Memory => matches!(shape, Integer | Float(_) | Str | Boolean | Function),
            ArgType::Func => {
                if !matches!(shape, Function) {
                    let help = format!("pass a function: {}(function() return ... end)", spec.name);
                    self.report(
                        Code::NotAFunction,
                        at_node(value),
                        format!("`{}` takes a function for `{}`, got {}", spec.name, arg.name, shape.describe()),
                        Some(help),
                    );
                }
                return;
            }
            ArgType::Rest | ArgType::Any => false,
        };
        // Only a returned value of a known type is judged: a call's integer may well be
        // a position.
        let judged = !matches!(shape, Returned(..)) || matches!(arg.ty, ArgType::Timer);
        if refused && judged && !(arg.optional && matches!(shape, Nil)) {
            let takes = match arg.ty {
                ArgType::Int if matches!(shape, Float(false)) => "an integer (a float with a fraction is refused)",
                ArgType::Int => "an integer",
                ArgType::Double => "a number",
                ArgType::Str => "a string",
                ArgType::Bool => "a boolean or number",
                ArgType::Bytes => "a table of bytes or a string",
                ArgType::Doubles => "a table of numbers (or 0 for none)",
                ArgType::Timer => "a timer made by TimerInit()",
                _ => "a table",
            };
            self.report(
                Code::ArgumentType,
                at_node(value),
                format!("`{}` takes {takes} for `{}`, got {}", spec.name, arg.name, shape.describe()),
                Some(spec.signature()),
            );
        }
    }

    /// `require('name')` of a module the project does not have.
    fn require(&mut self, suffixes: &[&Suffix]) {
        let Some(Suffix::Call(Call::AnonymousCall(args))) = suffixes.first() else { return };
        let Some((token, literal)) = first_string(args) else { return };
        if let Some(why) = (self.missing_module)(literal) {
            self.report(Code::Sandbox, at_token(token), why, None);
        }
    }

    /// `load(chunk, name, "b")`: the sandbox loads text chunks only.
    fn load(&mut self, suffixes: &[&Suffix]) {
        let Some(Suffix::Call(Call::AnonymousCall(args))) = suffixes.first() else { return };
        if let Some(Expression::String(token)) = arguments(args).get(2)
            && let TokenType::StringLiteral { literal, .. } = token.token().token_type()
            && literal.contains('b')
        {
            let message = "load takes source text only: precompiled chunks can crash the VM (mode \"t\")".to_string();
            self.report(Code::Sandbox, at_token(token), message, None);
        }
    }
}

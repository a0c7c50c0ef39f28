//! One finding, and how it is shown: `file:line:col: error[E101]: message` with the
//! source line and a caret under the place, as rustc and luacheck show theirs; or JSON.

use serde::Serialize;

use crate::code::{Code, Severity};

/// One mistake at one place.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Diagnostic {
    /// The file, as given.
    pub file: String,
    /// 1-based line and column (in characters) of the place.
    pub line: usize,
    /// See `line`.
    pub column: usize,
    /// How many characters the caret covers.
    pub width: usize,
    /// `error` or `warning`.
    pub severity: Severity,
    /// The code's id, e.g. `E101`.
    pub code: &'static str,
    /// What is wrong.
    pub message: String,
    /// What to do instead, if the check knows.
    pub help: Option<String>,
}

impl Diagnostic {
    pub(crate) fn new(code: Code, at: (usize, usize, usize), message: String, help: Option<String>) -> Self {
        let (line, column, width) = at;
        Diagnostic {
            file: String::new(),
            line,
            column,
            width: width.max(1),
            severity: code.severity(),
            code: code.id(),
            message,
            help,
        }
    }

    /// The rustc-style text, with the line of `source` it points at.
    pub fn render(&self, source: &str) -> String {
        let severity = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        let mut text =
            format!("{}:{}:{}: {severity}[{}]: {}\n", self.file, self.line, self.column, self.code, self.message);
        if let Some(line) = source.lines().nth(self.line.saturating_sub(1)) {
            let number = self.line.to_string();
            let pad = " ".repeat(number.len());
            let caret = format!("{}{}", " ".repeat(self.column.saturating_sub(1)), "^".repeat(self.width));
            text.push_str(&format!("{pad} |\n{number} | {line}\n{pad} | {caret}\n"));
        }
        if let Some(help) = &self.help {
            text.push_str(&format!("  = help: {help}\n"));
        }
        text
    }
}

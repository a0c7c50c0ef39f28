//! What an editor asks of the registry (`luamotion lsp`): the names to complete with
//! their signatures and the manual's references, the doc of the name under the cursor,
//! and the call the cursor is in.

use api::FunctionSpec;

use crate::environment::{Environment, Known};

/// What a completion item is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ItemKind {
    /// An API function.
    Function,
    /// A constant.
    Constant,
    /// A system variable.
    Variable,
}

/// One name to complete.
#[derive(Clone, Debug)]
pub struct Item {
    /// The name, dotted for `FreePort.Eth.Tx`.
    pub label: String,
    /// What it is.
    pub kind: ItemKind,
    /// The signature, or the constant's value and source.
    pub detail: String,
    /// The registry's doc and the manual's reference (Markdown).
    pub documentation: String,
}

/// Every name of the API a program can use, with what the registry says of it.
pub fn completions(environment: &Environment) -> Vec<Item> {
    let function = |spec: &FunctionSpec| Item {
        label: spec.name.to_string(),
        kind: ItemKind::Function,
        detail: spec.signature(),
        documentation: function_doc(spec),
    };
    let globals = environment.globals().filter_map(|(name, known)| {
        let kind = match known {
            Known::Function(spec) => return Some(function(spec)),
            Known::Constant => ItemKind::Constant,
            Known::SystemVariable { .. } => ItemKind::Variable,
            Known::ApiTable | Known::Lua => return None,
        };
        let note = environment.note(name)?;
        Some(Item { label: name.to_string(), kind, detail: note.detail.clone(), documentation: note.doc.clone() })
    });
    let mut items: Vec<Item> = globals.chain(environment.dotted_functions().map(function)).collect();
    items.sort_by(|a, b| a.label.cmp(&b.label));
    items
}

fn function_doc(spec: &FunctionSpec) -> String {
    format!("```lua\n{}\n```\n{}\n\n{}", spec.signature(), spec.doc.join(" "), spec.manual)
}

/// The doc of the API name `word` (dotted names too), as Markdown.
pub fn hover(environment: &Environment, word: &str) -> Option<String> {
    if let Some(spec) = environment.dotted(word) {
        return Some(function_doc(spec));
    }
    match environment.get(word)? {
        Known::Function(spec) => Some(function_doc(spec)),
        _ => environment.note(word).map(|note| format!("`{}`\n\n{}", note.detail, note.doc)),
    }
}

/// Byte offset of (0-based) `line` and `character` (UTF-16 units, as LSP counts) in `text`.
fn offset(text: &str, line: usize, character: usize) -> Option<usize> {
    let start: usize = text.split_inclusive('\n').take(line).map(str::len).sum();
    let rest = text.get(start..)?;
    let mut units = 0;
    for (i, c) in rest.char_indices() {
        if units >= character || c == '\n' {
            return Some(start + i);
        }
        units += c.len_utf16();
    }
    Some(text.len())
}

fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '.'
}

/// The (dotted) name the cursor is on or just after.
pub fn word_at(text: &str, line: usize, character: usize) -> Option<String> {
    let at = offset(text, line, character)?;
    let start = text[..at].rfind(|c: char| !is_name_char(c)).map_or(0, |i| i + 1);
    let end = text[at..].find(|c: char| !is_name_char(c)).map_or(text.len(), |i| at + i);
    let word = text[start..end].trim_matches('.');
    (!word.is_empty()).then(|| word.to_string())
}

/// The API call the cursor is in, and which of its arguments (from 0) it is at: the
/// nearest `(` before it that is not closed, and the commas between at that level.
pub fn call_at(
    environment: &Environment,
    text: &str,
    line: usize,
    character: usize,
) -> Option<(&'static FunctionSpec, usize)> {
    let at = offset(text, line, character)?;
    let before = &text[..at];
    let (mut depth, mut commas) = (0usize, 0usize);
    for (i, c) in before.char_indices().rev() {
        match c {
            ')' | '}' | ']' => depth += 1,
            '(' | '{' | '[' if depth > 0 => depth -= 1,
            '{' | '[' => return None,
            '(' => {
                let name_end = before[..i].trim_end();
                let start = name_end.rfind(|c: char| !is_name_char(c)).map_or(0, |j| j + 1);
                let name = &name_end[start..];
                let spec = environment.dotted(name).or_else(|| match environment.get(name) {
                    Some(Known::Function(spec)) => Some(spec),
                    _ => None,
                })?;
                return Some((spec, commas));
            }
            ',' if depth == 0 => commas += 1,
            _ => {}
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_call_and_argument_at_the_cursor() {
        let env = Environment::new();
        let text = "local p = GetPosFb(0)\nMoveAbs(0, GetPosFb(1) + 5, \nFreePort.Eth.Tx(1, ";
        let at = |line, character| call_at(&env, text, line, character).map(|(s, n)| (s.name, n));
        assert_eq!(at(0, 19), Some(("GetPosFb", 0)));
        assert_eq!(at(1, 8), Some(("MoveAbs", 0)));
        assert_eq!(at(1, 11), Some(("MoveAbs", 1)));
        assert_eq!(at(1, 21), Some(("GetPosFb", 0)));
        assert_eq!(at(1, 28), Some(("MoveAbs", 2)));
        assert_eq!(at(2, 19), Some(("FreePort.Eth.Tx", 1)));
        assert_eq!(at(0, 5), None);
        assert_eq!(word_at(text, 2, 10).as_deref(), Some("FreePort.Eth.Tx"));
        assert_eq!(word_at(text, 1, 3).as_deref(), Some("MoveAbs"));
    }

    #[test]
    fn completions_and_hover_come_from_the_registry() {
        let env = Environment::new();
        let items = completions(&env);
        let item = |label: &str| items.iter().find(|i| i.label == label).unwrap_or_else(|| panic!("{label}"));
        assert_eq!(item("MoveAbs").detail, "int MoveAbs(int axis_id, double pos)");
        assert!(item("MoveAbs").documentation.contains("HMPL 5.2.4"));
        assert_eq!(item("BM_LOOKAHEAD").kind, ItemKind::Constant);
        assert_eq!(item("system_fclk").kind, ItemKind::Variable);
        assert!(items.len() > 340 + 40, "{}", items.len());
        assert!(hover(&env, "MoveAbs").unwrap().contains("int MoveAbs(int axis_id, double pos)"));
        assert!(hover(&env, "FreePort.Eth.Tx").unwrap().contains("DXMC 8.3"));
        assert!(hover(&env, "nothing_of_the_api").is_none());
    }
}

//! `luamotion lsp`: a language server over stdio (lsp-server) for any editor: the check's
//! findings as the program is typed, completion of the API's names with their signatures
//! and the manual's references, hover with the registry's doc, and signature help. All
//! of it is `check`'s, hence the registry's.

use std::collections::HashMap;
use std::path::PathBuf;

use anyhow::Result;
use check::editor::{self, ItemKind};
use check::{Checker, Environment, Severity};
use lsp_server::{Connection, Message, Notification, Request, Response};
use lsp_types::notification::{DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, PublishDiagnostics};
use lsp_types::request::{Completion, HoverRequest, SignatureHelpRequest};
use lsp_types::{
    CompletionItem, CompletionItemKind, CompletionOptions, Diagnostic, DiagnosticSeverity, Documentation, Hover,
    HoverContents, HoverProviderCapability, MarkupContent, MarkupKind, NumberOrString, ParameterInformation,
    ParameterLabel, Position, PublishDiagnosticsParams, Range, ServerCapabilities, SignatureHelp, SignatureHelpOptions,
    SignatureInformation, TextDocumentSyncCapability, TextDocumentSyncKind, Uri,
};

/// Serves one editor on stdin/stdout until it says exit.
pub fn lsp() -> Result<std::process::ExitCode> {
    let (connection, threads) = Connection::stdio();
    let capabilities = ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(vec![".".into()]),
            ..Default::default()
        }),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        signature_help_provider: Some(SignatureHelpOptions {
            trigger_characters: Some(vec!["(".into(), ",".into()]),
            ..Default::default()
        }),
        ..Default::default()
    };
    connection
        .initialize(serde_json::to_value(capabilities)?)
        .map_err(|e| anyhow::anyhow!("the editor ended the connection before it initialized ({e})"))?;
    Server::default().serve(&connection)?;
    threads.join()?;
    Ok(std::process::ExitCode::SUCCESS)
}

#[derive(Default)]
struct Server {
    checker: Checker,
    environment: Environment,
    /// The open documents' text.
    documents: HashMap<String, String>,
}

impl Server {
    fn serve(&mut self, connection: &Connection) -> Result<()> {
        for message in &connection.receiver {
            match message {
                Message::Request(request) => {
                    if connection.handle_shutdown(&request)? {
                        return Ok(());
                    }
                    let response = self.answer(request);
                    connection.sender.send(Message::Response(response))?;
                }
                Message::Notification(notification) => {
                    if let Some(uri) = self.update(notification) {
                        connection.sender.send(Message::Notification(self.diagnostics(&uri)))?;
                    }
                }
                Message::Response(_) => {}
            }
        }
        Ok(())
    }

    /// A document opened, changed or closed; the one to check again.
    fn update(&mut self, notification: Notification) -> Option<Uri> {
        use lsp_types::notification::Notification as _;
        match notification.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let params: lsp_types::DidOpenTextDocumentParams = serde_json::from_value(notification.params).ok()?;
                self.documents.insert(params.text_document.uri.as_str().to_string(), params.text_document.text);
                Some(params.text_document.uri)
            }
            DidChangeTextDocument::METHOD => {
                let params: lsp_types::DidChangeTextDocumentParams =
                    serde_json::from_value(notification.params).ok()?;
                let text = params.content_changes.into_iter().last()?.text;
                self.documents.insert(params.text_document.uri.as_str().to_string(), text);
                Some(params.text_document.uri)
            }
            DidCloseTextDocument::METHOD => {
                let params: lsp_types::DidCloseTextDocumentParams = serde_json::from_value(notification.params).ok()?;
                self.documents.remove(params.text_document.uri.as_str());
                None
            }
            _ => None,
        }
    }

    fn diagnostics(&self, uri: &Uri) -> Notification {
        use lsp_types::notification::Notification as _;
        let text = self.documents.get(uri.as_str()).map_or("", String::as_str);
        let path = file_path(uri);
        let folder = path.as_ref().and_then(|p| p.parent());
        let name = path.as_ref().map_or_else(|| uri.as_str().to_string(), |p| p.display().to_string());
        let diagnostics = self
            .checker
            .check_source(&name, text, folder)
            .into_iter()
            .map(|d| {
                let start = Position::new(d.line.saturating_sub(1) as u32, d.column.saturating_sub(1) as u32);
                let end = Position::new(start.line, start.character + d.width as u32);
                let message = match &d.help {
                    Some(help) => format!("{}\n{help}", d.message),
                    None => d.message.clone(),
                };
                Diagnostic {
                    range: Range::new(start, end),
                    severity: Some(match d.severity {
                        Severity::Error => DiagnosticSeverity::ERROR,
                        Severity::Warning => DiagnosticSeverity::WARNING,
                    }),
                    code: Some(NumberOrString::String(d.code.to_string())),
                    source: Some("luamotion".into()),
                    message,
                    ..Default::default()
                }
            })
            .collect();
        let params = PublishDiagnosticsParams { uri: uri.clone(), diagnostics, version: None };
        Notification::new(PublishDiagnostics::METHOD.to_string(), params)
    }

    fn answer(&self, request: Request) -> Response {
        use lsp_types::request::Request as _;
        let id = request.id.clone();
        let result = match request.method.as_str() {
            Completion::METHOD => serde_json::to_value(self.completion()),
            HoverRequest::METHOD => {
                let params: Option<lsp_types::HoverParams> = serde_json::from_value(request.params).ok();
                serde_json::to_value(params.and_then(|p| self.hover(&p.text_document_position_params)))
            }
            SignatureHelpRequest::METHOD => {
                let params: Option<lsp_types::SignatureHelpParams> = serde_json::from_value(request.params).ok();
                serde_json::to_value(params.and_then(|p| self.signature(&p.text_document_position_params)))
            }
            other => {
                let message = format!("luamotion lsp does not answer {other}");
                return Response::new_err(id, lsp_server::ErrorCode::MethodNotFound as i32, message);
            }
        };
        Response::new_ok(id, result.unwrap_or(serde_json::Value::Null))
    }

    fn completion(&self) -> Vec<CompletionItem> {
        editor::completions(&self.environment)
            .into_iter()
            .map(|item| CompletionItem {
                kind: Some(match item.kind {
                    ItemKind::Function => CompletionItemKind::FUNCTION,
                    ItemKind::Constant => CompletionItemKind::CONSTANT,
                    ItemKind::Variable => CompletionItemKind::VARIABLE,
                }),
                label: item.label,
                detail: Some(item.detail),
                documentation: Some(Documentation::MarkupContent(markdown(item.documentation))),
                ..Default::default()
            })
            .collect()
    }

    fn text_at(&self, at: &lsp_types::TextDocumentPositionParams) -> Option<(&str, usize, usize)> {
        let text = self.documents.get(at.text_document.uri.as_str())?;
        Some((text, at.position.line as usize, at.position.character as usize))
    }

    fn hover(&self, at: &lsp_types::TextDocumentPositionParams) -> Option<Hover> {
        let (text, line, character) = self.text_at(at)?;
        let doc = editor::hover(&self.environment, &editor::word_at(text, line, character)?)?;
        Some(Hover { contents: HoverContents::Markup(markdown(doc)), range: None })
    }

    fn signature(&self, at: &lsp_types::TextDocumentPositionParams) -> Option<SignatureHelp> {
        let (text, line, character) = self.text_at(at)?;
        let (spec, argument) = editor::call_at(&self.environment, text, line, character)?;
        let parameters = spec
            .args
            .iter()
            .map(|a| ParameterInformation { label: ParameterLabel::Simple(a.name.to_string()), documentation: None })
            .collect();
        let signature = SignatureInformation {
            label: spec.signature(),
            documentation: Some(Documentation::MarkupContent(markdown(format!(
                "{}\n\n{}",
                spec.doc.join(" "),
                spec.manual
            )))),
            parameters: Some(parameters),
            active_parameter: Some(argument as u32),
        };
        Some(SignatureHelp {
            signatures: vec![signature],
            active_signature: Some(0),
            active_parameter: Some(argument as u32),
        })
    }
}

fn markdown(value: String) -> MarkupContent {
    MarkupContent { kind: MarkupKind::Markdown, value }
}

/// The file a `file://` URI names, for `require`'s folder and the findings' file name.
fn file_path(uri: &Uri) -> Option<PathBuf> {
    if !uri.scheme()?.as_str().eq_ignore_ascii_case("file") {
        return None;
    }
    Some(PathBuf::from(uri.path().as_estr().decode().into_string().ok()?.into_owned()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_uri_is_its_decoded_path() {
        let uri = |s: &str| s.parse::<Uri>().unwrap();
        assert_eq!(file_path(&uri("file:///home/cell%201/main.lua")), Some(PathBuf::from("/home/cell 1/main.lua")));
        assert_eq!(file_path(&uri("untitled:Untitled-1")), None);
    }
}

//! `axle lsp`: a language server over stdio. It calls the same parser, checker,
//! formatter and diagnostics as the CLI; each feature has its own file. The
//! mobility analysis (an SVD) runs when a file is opened or saved, not on every
//! change. A request that fails inside a handler is answered with an error, and
//! the server reads on.

mod actions;
mod completion;
mod diagnostics;
mod document;
mod format;
mod hover;
mod hover_value;
mod navigate;
mod rename;
mod stdlib;
mod symbols;
mod transport;

use crate::check::Passes;
use document::Document;
use lsp_server::{ErrorCode, Message, Notification, Request, RequestId, Response, ResponseError};
use lsp_types::*;
use serde_json::Value;
use std::collections::HashMap;
use std::io::Write;

/// A handler's error: answered to the editor as a JSON-RPC error.
pub(crate) struct Failure {
    code: ErrorCode,
    message: String,
}

impl Failure {
    pub(crate) fn invalid(message: impl Into<String>) -> Failure {
        Failure {
            code: ErrorCode::InvalidParams,
            message: message.into(),
        }
    }

    pub(crate) fn refused(message: impl Into<String>) -> Failure {
        Failure {
            code: ErrorCode::RequestFailed,
            message: message.into(),
        }
    }
}

type Answer = Result<Value, Failure>;

/// The open documents, by URI.
#[derive(Default)]
pub struct Server {
    docs: HashMap<String, Document>,
    shutting_down: bool,
}

/// Serves on stdin/stdout until `exit` or the end of input; returns the exit code
/// (0 after `shutdown` then `exit`, 1 otherwise, as the protocol asks).
pub fn run_stdio() -> i32 {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let stdin = std::io::stdin();
        let mut lock = stdin.lock();
        while let Some(m) = transport::read(&mut lock) {
            if tx.send(m).is_err() {
                break;
            }
        }
    });
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let mut server = Server::default();
    for incoming in rx {
        let result = match incoming {
            transport::Incoming::Garbage(why) => transport::write_parse_error(&mut out, &why),
            transport::Incoming::Message(m) => {
                let (replies, exit) = server.handle(m);
                let mut r = Ok(());
                for reply in replies {
                    r = r.and_then(|_| transport::write(&mut out, &reply));
                }
                if let Some(code) = exit {
                    return code;
                }
                r
            }
        };
        if result.is_err() {
            // The editor closed our stdout: nobody is listening any more.
            return 1;
        }
        let _ = out.flush();
    }
    1
}

fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Options(
            TextDocumentSyncOptions {
                open_close: Some(true),
                change: Some(TextDocumentSyncKind::FULL),
                save: Some(TextDocumentSyncSaveOptions::Supported(true)),
                ..Default::default()
            },
        )),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(vec![".".into(), " ".into()]),
            ..Default::default()
        }),
        document_symbol_provider: Some(OneOf::Left(true)),
        document_formatting_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Right(RenameOptions {
            prepare_provider: Some(true),
            work_done_progress_options: Default::default(),
        })),
        code_action_provider: Some(CodeActionProviderCapability::Options(CodeActionOptions {
            code_action_kinds: Some(vec![CodeActionKind::QUICKFIX]),
            ..Default::default()
        })),
        ..Default::default()
    }
}

impl Server {
    /// Handles one message: the messages to send back, and an exit code when
    /// the session ends.
    pub fn handle(&mut self, m: Message) -> (Vec<Message>, Option<i32>) {
        match m {
            Message::Request(r) => {
                let id = r.id.clone();
                let method = r.method.clone();
                let answer = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.request(r)))
                    .unwrap_or_else(|_| {
                        Err(Failure {
                            code: ErrorCode::InternalError,
                            message: format!("axle lsp: internal error while answering `{method}` (a bug: please report it with the file)"),
                        })
                    });
                (vec![Message::Response(respond(id, answer))], None)
            }
            Message::Notification(n) if n.method == "exit" => {
                (Vec::new(), Some(if self.shutting_down { 0 } else { 1 }))
            }
            Message::Notification(n) => {
                let out =
                    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.notification(n)))
                        .unwrap_or_default();
                (out, None)
            }
            Message::Response(_) => (Vec::new(), None),
        }
    }

    fn request(&mut self, r: Request) -> Answer {
        if self.shutting_down {
            return Err(Failure {
                code: ErrorCode::InvalidRequest,
                message: "the server is shutting down".into(),
            });
        }
        use lsp_types::request::*;
        match r.method.as_str() {
            Initialize::METHOD => Ok(serde_json::json!({
                "capabilities": capabilities(),
                "serverInfo": { "name": "axle", "version": env!("CARGO_PKG_VERSION") },
            })),
            Shutdown::METHOD => {
                self.shutting_down = true;
                Ok(Value::Null)
            }
            HoverRequest::METHOD => {
                let p: HoverParams = params(r.params)?;
                let pos = &p.text_document_position_params;
                let doc = self.doc(&pos.text_document.uri)?;
                to_value(hover::hover(doc, pos.position))
            }
            GotoDefinition::METHOD => {
                let p: GotoDefinitionParams = params(r.params)?;
                let pos = &p.text_document_position_params;
                let doc = self.doc(&pos.text_document.uri)?;
                to_value(navigate::definition(doc, pos.position))
            }
            References::METHOD => {
                let p: ReferenceParams = params(r.params)?;
                let pos = &p.text_document_position;
                let doc = self.doc(&pos.text_document.uri)?;
                to_value(navigate::references(
                    doc,
                    pos.position,
                    p.context.include_declaration,
                ))
            }
            Completion::METHOD => {
                let p: CompletionParams = params(r.params)?;
                let pos = &p.text_document_position;
                let doc = self.doc(&pos.text_document.uri)?;
                to_value(completion::complete(doc, pos.position))
            }
            DocumentSymbolRequest::METHOD => {
                let p: DocumentSymbolParams = params(r.params)?;
                let doc = self.doc(&p.text_document.uri)?;
                to_value(symbols::symbols(doc))
            }
            Formatting::METHOD => {
                let p: DocumentFormattingParams = params(r.params)?;
                let doc = self.doc(&p.text_document.uri)?;
                to_value(format::format(doc)?)
            }
            PrepareRenameRequest::METHOD => {
                let p: TextDocumentPositionParams = params(r.params)?;
                let doc = self.doc(&p.text_document.uri)?;
                to_value(rename::prepare(doc, p.position)?)
            }
            Rename::METHOD => {
                let p: RenameParams = params(r.params)?;
                let pos = &p.text_document_position;
                let doc = self.doc(&pos.text_document.uri)?;
                to_value(rename::rename(doc, pos.position, &p.new_name)?)
            }
            CodeActionRequest::METHOD => {
                let p: CodeActionParams = params(r.params)?;
                let doc = self.doc(&p.text_document.uri)?;
                to_value(actions::quick_fixes(doc, p.range))
            }
            other => Err(Failure {
                code: ErrorCode::MethodNotFound,
                message: format!("axle lsp does not answer `{other}`"),
            }),
        }
    }

    fn notification(&mut self, n: Notification) -> Vec<Message> {
        use lsp_types::notification::*;
        let (uri, version, text, passes) = match n.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<DidOpenTextDocumentParams>(n.params) else {
                    return Vec::new();
                };
                let d = p.text_document;
                (d.uri, Some(d.version), d.text, Passes::ALL)
            }
            DidChangeTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<DidChangeTextDocumentParams>(n.params) else {
                    return Vec::new();
                };
                // Full synchronisation: the last change holds the whole text.
                let Some(c) = p.content_changes.into_iter().last() else {
                    return Vec::new();
                };
                let d = p.text_document;
                (d.uri, Some(d.version), c.text, Passes::FAST)
            }
            DidSaveTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<DidSaveTextDocumentParams>(n.params) else {
                    return Vec::new();
                };
                let uri = p.text_document.uri;
                let text = match (p.text, self.docs.get(uri.as_str())) {
                    (Some(t), _) => t,
                    (None, Some(d)) => d.text().to_string(),
                    (None, None) => return Vec::new(),
                };
                (uri, None, text, Passes::ALL)
            }
            DidCloseTextDocument::METHOD => {
                if let Ok(p) = serde_json::from_value::<DidCloseTextDocumentParams>(n.params) {
                    self.docs.remove(p.text_document.uri.as_str());
                    let clear =
                        PublishDiagnosticsParams::new(p.text_document.uri, Vec::new(), None);
                    return vec![publish(clear)];
                }
                return Vec::new();
            }
            _ => return Vec::new(),
        };
        let doc = Document::new(uri.clone(), text, passes);
        let out = diagnostics::publish(&doc, version);
        self.docs.insert(uri.as_str().to_string(), doc);
        vec![publish(out)]
    }

    fn doc(&self, uri: &Uri) -> Result<&Document, Failure> {
        self.docs.get(uri.as_str()).ok_or_else(|| {
            Failure::invalid(format!(
                "`{}` is not open: open it first (textDocument/didOpen)",
                uri.as_str()
            ))
        })
    }
}

fn publish(p: PublishDiagnosticsParams) -> Message {
    use lsp_types::notification::{Notification as _, PublishDiagnostics};
    Message::Notification(Notification::new(PublishDiagnostics::METHOD.into(), p))
}

fn params<P: serde::de::DeserializeOwned>(v: Value) -> Result<P, Failure> {
    serde_json::from_value(v).map_err(|e| Failure::invalid(format!("invalid parameters: {e}")))
}

fn to_value(v: impl serde::Serialize) -> Answer {
    serde_json::to_value(v).map_err(|e| Failure {
        code: ErrorCode::InternalError,
        message: e.to_string(),
    })
}

fn respond(id: RequestId, answer: Answer) -> Response {
    match answer {
        Ok(v) => Response::new_ok(id, v),
        Err(f) => Response {
            id,
            response_result: Err(ResponseError {
                code: f.code as i32,
                message: f.message,
                data: None,
            }),
        },
    }
}

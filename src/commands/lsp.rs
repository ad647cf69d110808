//! `lmfilm lsp`: a language server over stdio (issue 40) for `.lm` and
//! `.lmr` files: diagnostics as you type, hover with what a symbol means,
//! completion of names, go-to-definition of a symbol's rules. The
//! protocol is `lsp-server`'s; what is answered is `lsys::assist`'s.

use std::collections::HashMap;
use std::io::{self, BufRead, Write};

use lsp_server::{ErrorCode, Message, Notification, Request, Response};
use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::lsys::assist;

/// Serves one editor until `exit` or the end of its input.
///
/// One thread reads a message and answers it, flushed, before it reads
/// the next (issue 53). lsp-server's threaded `Connection::stdio` with
/// its `initialize` and `handle_shutdown` took input that closed early
/// (an editor restarting the server, `printf … | lmfilm lsp`) for an
/// error, "disconnected channel" with exit 2, and the process could end
/// before its writer thread had written the last answers. The end of
/// input is a normal end; a malformed message is still an error.
pub fn lsp() -> Result<()> {
    match serve(&mut io::stdin().lock(), &mut io::stdout().lock()) {
        Ok(End::Done) => Ok(()),
        Ok(End::Abrupt) => Err(Error::other(
            "lsp: `exit` without `shutdown` first (exit code 1, as LSP asks)",
        )),
        // The editor closed our stdout: nobody is left to answer.
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Error::input(format!("lsp: {e}"))),
    }
}

/// How serving ended.
enum End {
    /// The end of input, or `exit` after `shutdown`: exit code 0.
    Done,
    /// `exit` without `shutdown` first: exit code 1.
    Abrupt,
}

/// Where the editor is in the protocol's life cycle.
#[derive(Clone, Copy, PartialEq)]
enum Lifecycle {
    /// Before `initialize`.
    Starting,
    Serving,
    /// After `shutdown`.
    Shut,
}

/// Answers every request and notification read until `exit` or the end
/// of input.
fn serve(input: &mut impl BufRead, output: &mut impl Write) -> io::Result<End> {
    let mut documents: HashMap<String, String> = HashMap::new();
    let mut stage = Lifecycle::Starting;
    while let Some(message) = Message::read(input)? {
        match message {
            Message::Request(req) => {
                Message::from(respond(&mut stage, &documents, &req)).write(output)?;
            }
            Message::Notification(n) if n.method == "exit" => {
                return Ok(match stage {
                    Lifecycle::Shut => End::Done,
                    _ => End::Abrupt,
                });
            }
            // Notifications before `initialize` and after `shutdown` are dropped.
            Message::Notification(n) if stage == Lifecycle::Serving => {
                if let Some(uri) = update(&mut documents, &n) {
                    let diagnostics = diagnose(&uri, &documents[&uri]);
                    let params = json!({ "uri": uri, "diagnostics": diagnostics });
                    let method = "textDocument/publishDiagnostics".to_string();
                    Message::from(Notification::new(method, params)).write(output)?;
                }
            }
            Message::Notification(_) | Message::Response(_) => {}
        }
    }
    Ok(End::Done)
}

/// The response to one request, moving the life cycle on at `initialize`
/// and `shutdown`.
fn respond(stage: &mut Lifecycle, documents: &HashMap<String, String>, req: &Request) -> Response {
    let id = req.id.clone();
    let refuse =
        |code: ErrorCode, why: &str| Response::new_err(id.clone(), code as i32, why.into());
    match (*stage, req.method.as_str()) {
        (Lifecycle::Starting, "initialize") => {
            *stage = Lifecycle::Serving;
            let capabilities = json!({
                "textDocumentSync": 1,
                "hoverProvider": true,
                "completionProvider": { "triggerCharacters": ["_"] },
                "definitionProvider": true,
            });
            Response::new_ok(id, json!({ "capabilities": capabilities }))
        }
        (Lifecycle::Starting, _) => refuse(ErrorCode::ServerNotInitialized, "not initialized yet"),
        (Lifecycle::Serving, "shutdown") => {
            *stage = Lifecycle::Shut;
            Response::new_ok(id, ())
        }
        (Lifecycle::Serving, _) => Response::new_ok(id, answer(documents, req)),
        (Lifecycle::Shut, _) => refuse(ErrorCode::InvalidRequest, "shut down"),
    }
}

/// Keeps the text of open documents; the uri of one that changed.
fn update(documents: &mut HashMap<String, String>, n: &Notification) -> Option<String> {
    let doc = &n.params["textDocument"];
    let uri = doc["uri"].as_str()?.to_string();
    let text = match n.method.as_str() {
        "textDocument/didOpen" => doc["text"].as_str()?.to_string(),
        // Full sync: the last change holds the whole text.
        "textDocument/didChange" => n.params["contentChanges"].as_array()?.last()?["text"]
            .as_str()?
            .to_string(),
        "textDocument/didClose" => {
            documents.remove(&uri);
            return None;
        }
        _ => return None,
    };
    documents.insert(uri.clone(), text);
    Some(uri)
}

/// A file's name from its uri: what decides its form.
fn name(uri: &str) -> &str {
    uri.rsplit('/').next().unwrap_or(uri)
}

/// The range of one character at a 1-based line and column.
fn range(line: usize, column: usize) -> Value {
    let (l, c) = (line.saturating_sub(1), column.saturating_sub(1));
    json!({
        "start": { "line": l, "character": c },
        "end": { "line": l, "character": c + 1 },
    })
}

fn diagnose(uri: &str, text: &str) -> Vec<Value> {
    assist::check(name(uri), text)
        .map(|d| {
            json!({
                "range": range(d.line, d.column),
                "severity": 1,
                "source": "lmfilm",
                "message": d.message,
            })
        })
        .into_iter()
        .collect()
}

fn answer(documents: &HashMap<String, String>, req: &Request) -> Value {
    let p = &req.params;
    let Some(uri) = p["textDocument"]["uri"].as_str() else {
        return Value::Null;
    };
    let Some(text) = documents.get(uri) else {
        return Value::Null;
    };
    let line = p["position"]["line"].as_u64().unwrap_or(0) as usize + 1;
    let column = p["position"]["character"].as_u64().unwrap_or(0) as usize + 1;
    match req.method.as_str() {
        "textDocument/hover" => match assist::hover(name(uri), text, line, column) {
            Some(md) => json!({ "contents": { "kind": "markdown", "value": md } }),
            None => Value::Null,
        },
        "textDocument/completion" => {
            let items: Vec<Value> = assist::complete(text, line, column)
                .into_iter()
                .map(|(label, detail)| json!({ "label": label, "detail": detail }))
                .collect();
            json!(items)
        }
        "textDocument/definition" => {
            let places: Vec<Value> = assist::definitions(name(uri), text, line, column)
                .into_iter()
                .map(|(l, c)| json!({ "uri": uri, "range": range(l, c) }))
                .collect();
            json!(places)
        }
        _ => Value::Null,
    }
}

//! `lmfilm lsp`: a language server over stdio (issue 40) for `.lm` and
//! `.lmr` files: diagnostics as you type, hover with what a symbol means,
//! completion of names, go-to-definition of a symbol's rules. The
//! protocol is `lsp-server`'s; what is answered is `lsys::assist`'s.

use std::collections::HashMap;

use lsp_server::{Connection, Message, Notification, Request, Response};
use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::lsys::assist;

/// Serves one editor until it asks to exit.
pub fn lsp() -> Result<()> {
    let (connection, io) = Connection::stdio();
    let capabilities = json!({
        "textDocumentSync": 1,
        "hoverProvider": true,
        "completionProvider": { "triggerCharacters": ["_"] },
        "definitionProvider": true,
    });
    let failed = |e: String| Error::input(format!("lsp: {e}"));
    connection
        .initialize(capabilities)
        .map_err(|e| failed(e.to_string()))?;
    serve(&connection).map_err(|e| failed(e.to_string()))?;
    drop(connection);
    io.join().map_err(|e| failed(e.to_string()))?;
    Ok(())
}

type Sent = std::result::Result<(), Box<dyn std::error::Error + Send + Sync>>;

fn serve(connection: &Connection) -> Sent {
    let mut documents: HashMap<String, String> = HashMap::new();
    for message in &connection.receiver {
        match message {
            Message::Request(req) => {
                if connection.handle_shutdown(&req)? {
                    return Ok(());
                }
                let result = answer(&documents, &req);
                connection
                    .sender
                    .send(Response::new_ok(req.id.clone(), result).into())?;
            }
            Message::Notification(n) => {
                if let Some(uri) = update(&mut documents, &n) {
                    let diagnostics = diagnose(&uri, &documents[&uri]);
                    let params = json!({ "uri": uri, "diagnostics": diagnostics });
                    connection.sender.send(
                        Notification::new("textDocument/publishDiagnostics".into(), params).into(),
                    )?;
                }
            }
            Message::Response(_) => {}
        }
    }
    Ok(())
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

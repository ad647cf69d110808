//! `lmfilm lsp` over stdio (issue 40): an editor opens a readable file
//! with a mistake and gets its diagnostic, mends it and gets none, and
//! asks hover, completion and go-to-definition.

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{ChildStdout, Command, Stdio};

use serde_json::{json, Value};

fn send(to: &mut impl Write, message: Value) {
    let body = message.to_string();
    write!(to, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
    to.flush().unwrap();
}

fn receive(from: &mut BufReader<ChildStdout>) -> Value {
    let mut length = 0;
    loop {
        let mut line = String::new();
        assert!(from.read_line(&mut line).unwrap() > 0, "the server closed");
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(n) = line.strip_prefix("Content-Length: ") {
            length = n.parse().unwrap();
        }
    }
    let mut body = vec![0; length];
    from.read_exact(&mut body).unwrap();
    serde_json::from_slice(&body).unwrap()
}

/// The next message that is not a log or a request of the server's.
fn next(from: &mut BufReader<ChildStdout>, method: Option<&str>, id: Option<u64>) -> Value {
    loop {
        let m = receive(from);
        let fits = match (method, id) {
            (Some(name), _) => m["method"] == name,
            (_, Some(id)) => m["id"] == id,
            _ => true,
        };
        if fits {
            return m;
        }
    }
}

#[test]
fn the_language_server_answers_over_stdio() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut to = child.stdin.take().unwrap();
    let mut from = BufReader::new(child.stdout.take().unwrap());
    let uri = "file:///tmp/scene.lmr";
    send(
        &mut to,
        json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}}),
    );
    let init = next(&mut from, None, Some(1));
    assert_eq!(
        init["result"]["capabilities"]["hoverProvider"], true,
        "{init}"
    );
    send(
        &mut to,
        json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}),
    );

    let broken = "axiom\nsphere(radius: 0.5) A\nproductions\nrule A at_age 1 {\n    1 -> turn_left(30) A\n}\n";
    send(
        &mut to,
        json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {
        "textDocument": {"uri": uri, "languageId": "lmfilm", "version": 1, "text": broken}}}),
    );
    let d = next(&mut from, Some("textDocument/publishDiagnostics"), None);
    let diags = d["params"]["diagnostics"].as_array().unwrap();
    assert_eq!(diags.len(), 1, "{d}");
    assert_eq!(
        diags[0]["range"]["start"],
        json!({"line": 1, "character": 7}),
        "{d}"
    );
    let message = diags[0]["message"].as_str().unwrap();
    assert!(
        message.contains("no parameter `radius`") && message.contains("diameter"),
        "{message}"
    );

    let mended = broken.replace("radius", "diameter");
    send(
        &mut to,
        json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
        "textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"text": mended}]}}),
    );
    let d = next(&mut from, Some("textDocument/publishDiagnostics"), None);
    assert_eq!(d["params"]["diagnostics"], json!([]), "{d}");

    let at = |id: u64, method: &str, line: u64, character: u64| {
        json!({"jsonrpc": "2.0", "id": id, "method": method, "params": {
            "textDocument": {"uri": uri}, "position": {"line": line, "character": character}}})
    };
    send(&mut to, at(2, "textDocument/hover", 4, 12));
    let h = next(&mut from, None, Some(2));
    let text = h["result"]["contents"]["value"].as_str().unwrap();
    assert!(
        text.contains("turn_left(angle: an angle in degrees)"),
        "{h}"
    );
    assert!(text.contains("Classic: `+`"), "{h}");

    send(&mut to, at(3, "textDocument/completion", 4, 14));
    let c = next(&mut from, None, Some(3));
    let labels: Vec<&str> = c["result"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["label"].as_str().unwrap())
        .collect();
    assert!(
        labels.contains(&"turn_left") && labels.contains(&"turn_right"),
        "{labels:?}"
    );
    assert!(labels.iter().all(|l| l.starts_with("turn_")), "{labels:?}");

    send(&mut to, at(4, "textDocument/definition", 1, 22));
    let g = next(&mut from, None, Some(4));
    assert_eq!(
        g["result"][0]["range"]["start"],
        json!({"line": 3, "character": 0}),
        "{g}"
    );

    send(
        &mut to,
        json!({"jsonrpc": "2.0", "id": 5, "method": "shutdown"}),
    );
    next(&mut from, None, Some(5));
    send(&mut to, json!({"jsonrpc": "2.0", "method": "exit"}));
    drop(to);
    assert!(child.wait().unwrap().success());
}

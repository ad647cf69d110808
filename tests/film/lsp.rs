//! `lmfilm lsp` over stdio (issue 40): an editor opens a readable file
//! with a mistake and gets its diagnostic, mends it and gets none, and
//! asks hover, completion and go-to-definition. Input that closes early
//! (issue 53) still has every request answered and ends normally.

use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdout, Command, Output, Stdio};

use serde_json::{json, Value};

fn send(to: &mut impl Write, message: Value) {
    let body = message.to_string();
    write!(to, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
    to.flush().unwrap();
}

fn receive(from: &mut impl BufRead) -> Value {
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

fn frame(message: &Value) -> Vec<u8> {
    let mut bytes = Vec::new();
    send(&mut bytes, message.clone());
    bytes
}

/// `lmfilm lsp` with its stdin, stdout and stderr piped.
fn lsp_piped() -> Child {
    Command::new(env!("CARGO_BIN_EXE_lmfilm"))
        .arg("lsp")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Runs `lmfilm lsp` on `input` with its stdin closed right after, as
/// `printf … | lmfilm lsp` does.
fn run_on(input: &[u8]) -> Output {
    let mut child = lsp_piped();
    child.stdin.take().unwrap().write_all(input).unwrap();
    child.wait_with_output().unwrap()
}

/// Every message in what the server wrote.
fn messages(mut out: &[u8]) -> Vec<Value> {
    let mut all = Vec::new();
    while !out.is_empty() {
        all.push(receive(&mut out));
    }
    all
}

const URI: &str = "file:///tmp/closing.lmr";

fn initialize() -> Value {
    json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}})
}
fn initialized() -> Value {
    json!({"jsonrpc": "2.0", "method": "initialized", "params": {}})
}
fn open() -> Value {
    json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument":
        {"uri": URI, "languageId": "lmfilm", "version": 1, "text": "axiom\nsphere(diameter: 1) A\n"}}})
}
fn hover(id: u64) -> Value {
    json!({"jsonrpc": "2.0", "id": id, "method": "textDocument/hover", "params": {
        "textDocument": {"uri": URI}, "position": {"line": 1, "character": 2}}})
}
fn shutdown(id: u64) -> Value {
    json!({"jsonrpc": "2.0", "id": id, "method": "shutdown"})
}
fn exit() -> Value {
    json!({"jsonrpc": "2.0", "method": "exit"})
}

/// The race was between the input closing and the last answers being
/// written: each case runs this many times.
const TRIES: usize = 20;

/// The ids of requests sent before `initialize` and after `shutdown`, and
/// the error codes LSP answers them with.
const EARLY: u64 = 8;
const LATE: u64 = 9;
fn refusal(id: &Value) -> Value {
    match id.as_u64() {
        Some(EARLY) => json!(-32002),
        Some(LATE) => json!(-32600),
        _ => Value::Null,
    }
}

/// Input that ends right after each case's messages: every request is
/// answered once, with the error code given or a result, and the server
/// exits with the code LSP asks (1 only for `exit` without `shutdown`).
#[test]
fn input_closing_early_still_answers_every_request() {
    let cases: Vec<(&str, Vec<Value>, i32)> = vec![
        ("nothing", vec![], 0),
        ("initialize", vec![initialize()], 0),
        ("initialize and a request", vec![initialize(), hover(2)], 0),
        ("a request before initialize", vec![hover(EARLY)], 0),
        (
            "a request",
            vec![initialize(), initialized(), open(), hover(2)],
            0,
        ),
        (
            "shutdown",
            vec![initialize(), initialized(), hover(2), shutdown(3)],
            0,
        ),
        (
            "shutdown and exit",
            vec![initialize(), initialized(), hover(2), shutdown(3), exit()],
            0,
        ),
        (
            "a request after shutdown",
            vec![
                initialize(),
                initialized(),
                shutdown(3),
                hover(LATE),
                exit(),
            ],
            0,
        ),
        (
            "exit without shutdown",
            vec![initialize(), initialized(), hover(2), exit()],
            1,
        ),
    ];
    for (case, sent, code) in cases {
        let input: Vec<u8> = sent.iter().flat_map(frame).collect();
        let mut asked: Vec<&Value> = sent
            .iter()
            .map(|m| &m["id"])
            .filter(|id| !id.is_null())
            .collect();
        asked.sort_by_key(|id| id.as_u64());
        for _ in 0..TRIES {
            let out = run_on(&input);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(code), "{case}: {stderr}");
            assert_eq!(stderr.is_empty(), code == 0, "{case}: {stderr}");
            let got = messages(&out.stdout);
            let mut answered: Vec<&Value> = got
                .iter()
                .filter(|m| m.get("method").is_none())
                .map(|m| &m["id"])
                .collect();
            answered.sort_by_key(|id| id.as_u64());
            assert_eq!(answered, asked, "{case}: {got:?}");
            for m in got.iter().filter(|m| m.get("method").is_none()) {
                let error = refusal(&m["id"]);
                assert_eq!(m["error"]["code"], error, "{case}: {m}");
                assert_eq!(m.get("result").is_some(), error.is_null(), "{case}: {m}");
            }
        }
    }
}

/// A stream that is not LSP is still an error, after what came before it
/// was answered.
#[test]
fn a_malformed_header_is_an_error_after_the_answers_before_it() {
    let mut input = frame(&initialize());
    input.extend_from_slice(b"Content-Length 2\r\n\r\n{}");
    for _ in 0..TRIES {
        let out = run_on(&input);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("malformed header"), "{stderr}");
        let got = messages(&out.stdout);
        assert_eq!(got.len(), 1, "{got:?}");
        assert_eq!(got[0]["id"], 1, "{got:?}");
    }
}

/// An editor that stops reading has gone: nobody is left to answer, and
/// that is no error.
#[test]
fn stdout_closed_ends_quietly() {
    let sent = [
        initialize(),
        initialized(),
        open(),
        hover(2),
        shutdown(3),
        exit(),
    ];
    let input: Vec<u8> = sent.iter().flat_map(frame).collect();
    for _ in 0..TRIES {
        let mut child = lsp_piped();
        drop(child.stdout.take());
        // The server may be gone before all of it is written.
        let _ = child.stdin.take().unwrap().write_all(&input);
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(stderr.is_empty(), "{stderr}");
    }
}

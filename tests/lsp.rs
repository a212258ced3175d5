//! `axle lsp` driven over stdio as an editor drives it: initialize, open a file
//! with mistakes, fix one, then hover, definition, references, completion,
//! symbols, formatting, rename and quick fixes on the McPherson; shutdown and
//! exit. Ranges are checked against positions found in the text itself, and
//! every response is snapshotted. Bad input (garbage, an unknown file, bytes
//! that are not UTF-8, a 10 MB file) gets an error or a degraded answer, and
//! the server stays up.

use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::Duration;

const MCPHERSON: &str = include_str!("../examples/mcpherson.axle");
const URI: &str = "file:///work/examples/mcpherson.axle";

struct Editor {
    child: Child,
    stdin: ChildStdin,
    from_server: Receiver<Value>,
    next_id: i64,
}

impl Editor {
    fn start() -> Editor {
        let mut child = Command::new(env!("CARGO_BIN_EXE_axle"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("axle lsp starts");
        let stdin = child.stdin.take().expect("stdin");
        let stdout = child.stdout.take().expect("stdout");
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut r = BufReader::new(stdout);
            loop {
                let mut len = None;
                loop {
                    let mut line = String::new();
                    if r.read_line(&mut line).unwrap_or(0) == 0 {
                        return;
                    }
                    let line = line.trim_end();
                    if line.is_empty() {
                        break;
                    }
                    if let Some(v) = line.strip_prefix("Content-Length: ") {
                        len = v.parse::<usize>().ok();
                    }
                }
                let mut body = vec![0; len.expect("Content-Length")];
                r.read_exact(&mut body).expect("body");
                if tx
                    .send(serde_json::from_slice(&body).expect("JSON"))
                    .is_err()
                {
                    return;
                }
            }
        });
        Editor {
            child,
            stdin,
            from_server: rx,
            next_id: 0,
        }
    }

    fn raw(&mut self, bytes: &[u8]) {
        self.stdin.write_all(bytes).expect("write");
        self.stdin.flush().expect("flush");
    }

    fn send(&mut self, m: Value) {
        let body = serde_json::to_vec(&m).unwrap();
        let mut framed = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
        framed.extend(body);
        self.raw(&framed);
    }

    fn recv(&mut self) -> Value {
        self.from_server
            .recv_timeout(Duration::from_secs(60))
            .expect("the server answers")
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({ "jsonrpc": "2.0", "method": method, "params": params }));
    }

    /// Sends a request and returns its response (notifications in between are skipped).
    fn request(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        self.send(json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }));
        loop {
            let m = self.recv();
            if m["id"] == json!(id) {
                return m;
            }
        }
    }

    fn diagnostics(&mut self) -> Value {
        loop {
            let m = self.recv();
            if m["method"] == "textDocument/publishDiagnostics" {
                return m["params"].clone();
            }
        }
    }

    fn open(&mut self, uri: &str, text: &str) -> Value {
        self.notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": "axle", "version": 1, "text": text } }),
        );
        self.diagnostics()
    }

    fn initialize(&mut self) -> Value {
        let r = self.request(
            "initialize",
            json!({ "processId": null, "capabilities": {} }),
        );
        self.notify("initialized", json!({}));
        r
    }

    fn finish(mut self) {
        let r = self.request("shutdown", Value::Null);
        assert_eq!(r["result"], Value::Null);
        self.notify("exit", Value::Null);
        let status = self.child.wait().expect("exits");
        assert_eq!(
            status.code(),
            Some(0),
            "exit after shutdown is a clean exit"
        );
    }
}

/// The LSP position (0-based line, UTF-16 column) of the `nth` occurrence of
/// `needle` in `text`, plus `shift` characters.
fn pos(text: &str, needle: &str, nth: usize, shift: usize) -> Value {
    let at = text.match_indices(needle).nth(nth).expect("in the text").0 + shift;
    let line = text[..at].matches('\n').count();
    let col = text[..at]
        .rsplit('\n')
        .next()
        .unwrap()
        .encode_utf16()
        .count();
    json!({ "line": line, "character": col })
}

fn at(uri: &str, p: Value) -> Value {
    json!({ "textDocument": { "uri": uri }, "position": p })
}

const MISTAKES: &str = "model m\n// é: a comment with a non-ASCII letter before the mistakes\nground chassis {\n    marker B at (0, 0, 0) mm\n}\npart arm {\n    marker B at (0, 0, 0) mm\n    marker S at (100, 0, 0) mm\n}\nbushing b {\n    i chassis.B\n    j amr.B\n    k (1, 1, 1) N/mm\n    kt (1, 1, 1) N*mm/deg\n}\nspring s {\n    i chassis.C\n    j arm.S\n    k 30 N/mm\n    free_length 100 mm\n}\n";

#[test]
fn an_editor_session_on_a_file_with_mistakes() {
    let mut ed = Editor::start();
    let init = ed.initialize();
    insta::assert_json_snapshot!("initialize", init["result"]);
    let uri = "file:///work/mistakes.axle";
    let diags = ed.open(uri, MISTAKES);
    insta::assert_json_snapshot!("mistakes_diagnostics", diags);
    let list = diags["diagnostics"].as_array().unwrap();
    assert_eq!(list.len(), 2);
    // `amr` in `j amr.B`, and `C` in `i chassis.C`, where the text has them.
    assert_eq!(list[0]["code"], "E0101");
    assert_eq!(list[0]["range"]["start"], pos(MISTAKES, "amr", 0, 0));
    assert_eq!(list[0]["range"]["end"], pos(MISTAKES, "amr", 0, 3));
    assert_eq!(list[1]["range"]["start"], pos(MISTAKES, "chassis.C", 0, 8));

    // The quick fix for `amr` is the checker's candidate.
    let range = &list[0]["range"];
    let actions = ed.request(
        "textDocument/codeAction",
        json!({ "textDocument": { "uri": uri }, "range": range, "context": { "diagnostics": [] } }),
    );
    insta::assert_json_snapshot!("mistakes_quick_fix", actions["result"]);
    let edit = &actions["result"][0]["edit"]["changes"][uri][0];
    assert_eq!(edit["newText"], "arm");

    // Fix `amr`: its diagnostic disappears, the other stays.
    let fixed = MISTAKES.replace("amr", "arm");
    ed.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 2 }, "contentChanges": [{ "text": fixed }] }),
    );
    let diags = ed.diagnostics();
    let list = diags["diagnostics"].as_array().unwrap();
    assert_eq!(list.len(), 1);
    assert_eq!(list[0]["range"]["start"], pos(&fixed, "chassis.C", 0, 8));
    assert_eq!(diags["version"], 2);
    ed.finish();
}

#[test]
fn a_syntax_error_keeps_the_items_that_parsed() {
    let mut ed = Editor::start();
    ed.initialize();
    // A vector with two components in bushing `B`: a syntax error there, but the
    // parts, the other bushings and the wheel still have symbols and hovers.
    let broken = MCPHERSON.replace("k (310, 2400, 180) N/mm", "k (310, 2400) N/mm");
    assert_ne!(broken, MCPHERSON);
    let uri = "file:///work/broken.axle";
    let diags = ed.open(uri, &broken);
    let codes: Vec<&Value> = diags["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| &d["code"])
        .collect();
    assert_eq!(codes, [&json!("E0001")]);
    let symbols = ed.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": uri } }),
    );
    let names: Vec<&str> = symbols["result"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"upright") && names.contains(&"A") && names.contains(&"left"));
    assert!(
        !names.contains(&"B"),
        "the broken bushing is left out: {names:?}"
    );
    let hover = ed.request(
        "textDocument/hover",
        at(uri, pos(&broken, "upright.L8", 0, 9)),
    );
    assert!(
        hover["result"]["contents"]["value"]
            .as_str()
            .unwrap()
            .contains("marker** `upright.L8`")
    );
    let def = ed.request(
        "textDocument/definition",
        at(uri, pos(&broken, "i chassis.A", 0, 2)),
    );
    assert_eq!(
        def["result"]["range"]["start"],
        pos(&broken, "chassis {", 0, 0)
    );
    // Rename is refused: a use inside the broken bushing would be missed.
    let rename = ed.request(
        "textDocument/rename",
        json!({ "textDocument": { "uri": uri }, "position": pos(&broken, "chassis {", 0, 0), "newName": "body" }),
    );
    assert!(
        rename["error"]["message"]
            .as_str()
            .unwrap()
            .contains("syntax errors")
    );
    ed.finish();
}

#[test]
fn the_mcpherson_in_an_editor() {
    let mut ed = Editor::start();
    ed.initialize();
    let diags = ed.open(URI, MCPHERSON);
    assert_eq!(diags["diagnostics"], json!([]), "the example checks clean");
    let t = MCPHERSON;
    let mut hovers = serde_json::Map::new();
    for (what, needle, shift) in [
        ("part", "i chassis.B", 2),
        ("marker", "i chassis.B", 10),
        ("bushing", "bushing B {", 8),
        ("stiffness", "4500, 1100", 0),
        ("load_set", "default loads thesis_table_5_1", 14),
        ("module", "import mcpherson_loads", 7),
        ("wheel", "wheel left {", 6),
    ] {
        let h = ed.request("textDocument/hover", at(URI, pos(t, needle, 0, shift)));
        hovers.insert(what.into(), h["result"].clone());
    }
    // The module's hover names its file, not a machine-dependent path.
    insta::assert_json_snapshot!("mcpherson_hovers", hovers);
    let stiffness = hovers["stiffness"]["contents"]["value"].as_str().unwrap();
    // 4500 N*mm/deg in internal units: 4500 * 180 / pi = 257831.0078089 N*mm/rad.
    assert!(stiffness.contains("257831.007809 N*mm/rad"), "{stiffness}");

    // Definition of a marker used by a joint; of the stdlib module (a read-only file).
    let def = ed.request(
        "textDocument/definition",
        at(URI, pos(t, "j upright.L8", 0, 10)),
    );
    assert_eq!(def["result"]["range"]["start"], pos(t, "marker L8", 1, 7));
    let def = ed.request(
        "textDocument/definition",
        at(URI, pos(t, "mcpherson_loads", 0, 3)),
    );
    let module_uri = def["result"]["uri"].as_str().unwrap();
    assert!(
        module_uri.ends_with("/mcpherson_loads.axle"),
        "{module_uri}"
    );
    let path = module_uri.strip_prefix("file://").unwrap();
    let meta = std::fs::metadata(path).expect("the stdlib copy exists");
    assert!(meta.permissions().readonly());
    assert_eq!(
        std::fs::read_to_string(path).unwrap(),
        axle::stdlib::module("mcpherson_loads").unwrap()
    );

    // Every use of the part `upright`, with its definition.
    let refs = ed.request(
        "textDocument/references",
        json!({ "textDocument": { "uri": URI }, "position": pos(t, "part upright", 0, 5), "context": { "includeDeclaration": true } }),
    );
    let starts: Vec<Value> = refs["result"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["range"]["start"].clone())
        .collect();
    let expected: Vec<Value> = t
        .match_indices("upright")
        .filter(|(i, _)| {
            !t[..*i].ends_with("// ")
                && t[..*i]
                    .rsplit('\n')
                    .next()
                    .is_some_and(|l| !l.trim_start().starts_with("//"))
        })
        .map(|(i, _)| {
            let line = t[..i].matches('\n').count();
            let col = t[..i].rsplit('\n').next().unwrap().len();
            json!({ "line": line, "character": col })
        })
        .collect();
    assert_eq!(starts, expected);

    // Completion: top-level keywords, parts after `i `, markers after `upright.`,
    // units after a number, load sets after `default loads `.
    let mut completions = serde_json::Map::new();
    for (what, edit) in [
        ("top_level", "\n"),
        ("part_after_i", "\njoint new spherical {\n    i "),
        (
            "marker_after_dot",
            "\njoint new spherical {\n    i upright.",
        ),
        ("property", "\nspring new {\n    "),
        ("unit", "\nparam k = 30 "),
        ("load_set", "\ndefault loads "),
    ] {
        let text = format!("{t}{edit}");
        ed.notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": URI, "version": 3 }, "contentChanges": [{ "text": text }] }),
        );
        ed.diagnostics();
        let end = pos(&text, edit, 0, edit.len());
        let c = ed.request("textDocument/completion", at(URI, end));
        let labels: Vec<Value> = c["result"]
            .as_array()
            .unwrap()
            .iter()
            .map(|i| i["label"].clone())
            .collect();
        completions.insert(what.into(), Value::Array(labels));
    }
    insta::assert_json_snapshot!("mcpherson_completions", completions);
    ed.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": URI, "version": 4 }, "contentChanges": [{ "text": t }] }),
    );
    ed.diagnostics();

    let symbols = ed.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": URI } }),
    );
    insta::assert_json_snapshot!("mcpherson_symbols", symbols["result"]);

    // The example is formatted already: no edit. A messy copy gets one edit.
    let f = ed.request("textDocument/formatting", json!({ "textDocument": { "uri": URI }, "options": { "tabSize": 4, "insertSpaces": true } }));
    assert_eq!(f["result"], json!([]));
    let messy = t.replace("    k 30 N/mm", "  k   30 N/mm");
    ed.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": URI, "version": 5 }, "contentChanges": [{ "text": messy }] }),
    );
    ed.diagnostics();
    let f = ed.request("textDocument/formatting", json!({ "textDocument": { "uri": URI }, "options": { "tabSize": 4, "insertSpaces": true } }));
    assert_eq!(f["result"][0]["newText"], t);

    // Rename the part `upright` to `knuckle`: every use and the definition.
    let r = ed.request(
        "textDocument/rename",
        json!({ "textDocument": { "uri": URI }, "position": pos(&messy, "upright.L8", 0, 2), "newName": "knuckle" }),
    );
    let edits = r["result"]["changes"][URI].as_array().unwrap();
    assert_eq!(edits.len(), expected.len());
    insta::assert_json_snapshot!("mcpherson_rename", edits);
    // A rename onto an existing part is refused.
    let r = ed.request(
        "textDocument/rename",
        json!({ "textDocument": { "uri": URI }, "position": pos(&messy, "upright.L8", 0, 2), "newName": "chassis" }),
    );
    assert_eq!(r["error"]["message"], "a part `chassis` exists already");
    ed.finish();
}

#[test]
fn bad_input_gets_an_error_and_the_server_stays_up() {
    let mut ed = Editor::start();
    // Garbage before anything: a header-less line, then a framed non-JSON body.
    ed.raw(b"hello, is this the language server?\r\n\r\n");
    let e = ed.recv();
    assert_eq!(e["error"]["code"], -32700);
    ed.raw(b"Content-Length: 7\r\n\r\n{{{{{{{");
    let e = ed.recv();
    assert_eq!(e["error"]["code"], -32700);
    assert_eq!(e["id"], Value::Null);
    ed.initialize();
    // A request about a file that was never opened.
    let h = ed.request(
        "textDocument/hover",
        at("file:///nowhere.axle", json!({ "line": 0, "character": 0 })),
    );
    assert_eq!(h["error"]["code"], -32602);
    // An unknown method.
    let u = ed.request("axle/teleport", json!({}));
    assert_eq!(u["error"]["code"], -32601);
    // A body that is not UTF-8 (a Latin-1 `é` in a comment): opened, with a
    // replacement character, and checked.
    let latin1 = b"model m\n// caf\xe9\nground g {\n    marker o at (0, 0, 0) mm\n}\n";
    let mut body = br#"{"jsonrpc":"2.0","method":"textDocument/didOpen","params":{"textDocument":{"uri":"file:///latin1.axle","languageId":"axle","version":1,"text":""#.to_vec();
    body.extend(latin1.iter().flat_map(|&b| match b {
        b'\n' => b"\\n".to_vec(),
        b => vec![b],
    }));
    body.extend(br#""}}}"#);
    let mut framed = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
    framed.extend(body);
    ed.raw(&framed);
    let d = ed.diagnostics();
    assert_eq!(d["uri"], "file:///latin1.axle");
    assert_eq!(d["diagnostics"], json!([]));
    let s = ed.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": "file:///latin1.axle" } }),
    );
    assert_eq!(s["result"][1]["name"], "g");
    // A 10 MB file: not checked as typed, said so; the server still answers.
    let big = format!(
        "model m\n{}",
        "// a generated comment line of some length, repeated\n".repeat(200_000)
    );
    assert!(big.len() > 10_000_000);
    let d = ed.open("file:///big.axle", &big);
    let msg = d["diagnostics"][0]["message"].as_str().unwrap();
    assert!(msg.contains("run `axle check`"), "{msg}");
    let h = ed.request(
        "textDocument/hover",
        at("file:///big.axle", json!({ "line": 0, "character": 7 })),
    );
    assert_eq!(h["result"], Value::Null);
    // Positions past the end of the file and of a line are clamped, not a crash.
    let opened = ed.open(URI, MCPHERSON);
    assert_eq!(opened["diagnostics"], json!([]));
    let h = ed.request(
        "textDocument/hover",
        at(URI, json!({ "line": 100000, "character": 100000 })),
    );
    assert!(h.get("result").is_some());
    ed.finish();
}

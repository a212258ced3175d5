//! Messages over stdio with `Content-Length` framing. lsp-server's own reader
//! stops the server at the first malformed message; this one reports it
//! (a parse error to the editor) and reads on, so garbage never ends a session.

use lsp_server::Message;
use std::io::{BufRead, Read, Write};

/// A message body larger than this is skipped, not parsed.
const MAX_BODY: usize = 256 << 20;

/// What the reader got from the editor.
pub enum Incoming {
    Message(Message),
    /// Not a message: why, for a JSON-RPC parse error.
    Garbage(String),
}

/// Reads framed messages until end of input. Invalid UTF-8 in a body is
/// replaced (U+FFFD) rather than refused: a file in another encoding still
/// opens, with replacement characters where its bytes were not UTF-8.
pub fn read(r: &mut impl BufRead) -> Option<Incoming> {
    let mut length: Option<usize> = None;
    let mut garbage = false;
    loop {
        let mut line = Vec::new();
        match r.read_until(b'\n', &mut line) {
            Ok(0) | Err(_) => return None,
            Ok(_) => {}
        }
        let line = String::from_utf8_lossy(&line);
        let line = line.trim_end_matches(['\r', '\n']);
        if line.is_empty() {
            match length {
                Some(n) => return Some(body(r, n)),
                None if garbage => {
                    return Some(Incoming::Garbage(
                        "a header without `Content-Length`".into(),
                    ));
                }
                None => continue,
            }
        }
        match line.split_once(':') {
            Some((k, v)) if k.eq_ignore_ascii_case("content-length") => {
                length = v.trim().parse().ok();
                garbage |= length.is_none();
            }
            Some((k, _)) if k.eq_ignore_ascii_case("content-type") => {}
            _ => garbage = true,
        }
    }
}

fn body(r: &mut impl BufRead, n: usize) -> Incoming {
    if n > MAX_BODY {
        let skipped = std::io::copy(&mut r.take(n as u64), &mut std::io::sink());
        return Incoming::Garbage(format!(
            "a message of {n} bytes (at most {MAX_BODY} are read){}",
            if skipped.is_err() {
                "; input ended"
            } else {
                ""
            }
        ));
    }
    let mut buf = vec![0u8; n];
    if r.read_exact(&mut buf).is_err() {
        return Incoming::Garbage("the input ended inside a message".into());
    }
    match serde_json::from_slice::<Message>(&buf) {
        Ok(m) => Incoming::Message(m),
        Err(_) => match serde_json::from_str::<Message>(&String::from_utf8_lossy(&buf)) {
            Ok(m) => Incoming::Message(m),
            Err(e) => Incoming::Garbage(format!("not a JSON-RPC message: {e}")),
        },
    }
}

/// Writes a message; a closed stdout (the editor went away) is reported to the caller.
pub fn write(w: &mut impl Write, m: &Message) -> std::io::Result<()> {
    m.write(w)
}

/// A JSON-RPC parse error (its id is `null`: the request could not be read).
pub fn write_parse_error(w: &mut impl Write, why: &str) -> std::io::Result<()> {
    let v = serde_json::json!({
        "jsonrpc": "2.0",
        "id": null,
        "error": { "code": -32700, "message": format!("axle lsp: {why}") },
    });
    let text = v.to_string();
    write!(w, "Content-Length: {}\r\n\r\n{text}", text.len())?;
    w.flush()
}

//! Latency of `axle lsp` from a change to its diagnostics on the McPherson
//! (target: median at most 20 ms on the 2-core machine; docs/editors.md has the
//! figure). The change goes through the server as an editor's notification
//! does; the mobility analysis runs on save, so it is measured separately.

use axle::lsp::Server;
use lsp_server::{Message, Notification};
use serde_json::json;

fn main() {
    divan::main();
}

const MCPHERSON: &str = include_str!("../examples/mcpherson.axle");

fn notification(method: &str, text: &str) -> Message {
    let params = match method {
        "textDocument/didChange" => json!({
            "textDocument": { "uri": "file:///bench/mcpherson.axle", "version": 2 },
            "contentChanges": [{ "text": text }],
        }),
        _ => json!({
            "textDocument": { "uri": "file:///bench/mcpherson.axle" },
            "text": text,
        }),
    };
    Message::Notification(Notification::new(method.into(), params))
}

/// A keystroke: the whole text (full sync), parse, check, diagnostics.
#[divan::bench]
fn change_to_diagnostics(b: divan::Bencher) {
    let mut server = Server::default();
    let edited = MCPHERSON.replace("k 30 N/mm", "k 31 N/mm");
    b.bench_local(|| {
        server.handle(divan::black_box(notification(
            "textDocument/didChange",
            &edited,
        )))
    });
}

/// A save: the same plus the mobility analysis.
#[divan::bench]
fn save_to_diagnostics(b: divan::Bencher) {
    let mut server = Server::default();
    b.bench_local(|| {
        server.handle(divan::black_box(notification(
            "textDocument/didSave",
            MCPHERSON,
        )))
    });
}

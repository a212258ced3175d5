// Starts `axle lsp` for .axle files. The command is the setting `axle.server.path`
// (default: `axle` on the PATH); the server speaks LSP over stdio.
const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const command = vscode.workspace.getConfiguration("axle").get("server.path") || "axle";
  const server = { command, args: ["lsp"], transport: TransportKind.stdio };
  client = new LanguageClient(
    "axle",
    "axle language server",
    { run: server, debug: server },
    { documentSelector: [{ scheme: "file", language: "axle" }] }
  );
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };

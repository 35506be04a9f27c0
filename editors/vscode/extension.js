// Starts `stampc lsp` (the stamp language server, over stdio) for .stamp files.
// The command comes from the setting `stamp.server.command` (default: stampc lsp).
"use strict";
const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const [command, ...args] = vscode.workspace.getConfiguration("stamp").get("server.command");
  const serverOptions = { command, args, transport: TransportKind.stdio };
  const clientOptions = {
    documentSelector: [{ scheme: "file", language: "stamp" }],
    synchronize: { fileEvents: vscode.workspace.createFileSystemWatcher("**/*.stamp") },
  };
  client = new LanguageClient("stamp", "stamp language server", serverOptions, clientOptions);
  context.subscriptions.push({ dispose: () => client && client.stop() });
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };

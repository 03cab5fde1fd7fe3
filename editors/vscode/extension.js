// The raytrace extension: starts `raytrace lsp` (the language server
// built into raytrace) for .rt files. Plain JavaScript, no build step;
// `npm install` fetches vscode-languageclient.
const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

function activate(context) {
  const command = vscode.workspace.getConfiguration('raytrace').get('path') || 'raytrace';
  const serverOptions = { command, args: ['lsp'] };
  const clientOptions = {
    documentSelector: [{ scheme: 'file', language: 'rt' }],
    // Re-check open scenes when an included file changes on disk.
    synchronize: { fileEvents: vscode.workspace.createFileSystemWatcher('**/*.rt') },
  };
  client = new LanguageClient('raytrace', 'raytrace', serverOptions, clientOptions);
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };

// VS Code client for `osplint lsp`: starts the server over stdio for OSP
// program files and forwards changes of osplint.toml and of subprogram files.
'use strict';
const vscode = require('vscode');
const { LanguageClient, TransportKind } = require('vscode-languageclient/node');

let client;

async function activate(context) {
  const command = vscode.workspace.getConfiguration('osplint').get('path') || 'osplint';
  const serverOptions = {
    run: { command, args: ['lsp'], transport: TransportKind.stdio },
    debug: { command, args: ['lsp'], transport: TransportKind.stdio },
  };
  const watcher = vscode.workspace.createFileSystemWatcher('**/{osplint.toml,*.SSB,*.SUB,*.LIB,*.MSB,*.ssb,*.sub,*.lib,*.msb}');
  context.subscriptions.push(watcher);
  const clientOptions = {
    documentSelector: [
      { scheme: 'file', language: 'osp' },
      { scheme: 'untitled', language: 'osp' },
    ],
    synchronize: { fileEvents: watcher },
  };
  client = new LanguageClient('osplint', 'osplint', serverOptions, clientOptions);
  await client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };

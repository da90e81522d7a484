// The AsmetaL extension: starts `PYTHON -m asmcheck lsp` and shows its asmcheck: documents
// (the read-only built-in libraries, counterexamples and simulations).
import * as vscode from "vscode";
import {
  LanguageClient,
  LanguageClientOptions,
  ServerOptions,
  TransportKind,
} from "vscode-languageclient/node";

let client: LanguageClient | undefined;

const SCHEME = "asmcheck";

function settings(): Record<string, unknown> {
  const c = vscode.workspace.getConfiguration("asmetal");
  return {
    importPath: c.get<string[]>("importPath", []),
    intRange: c.get<string>("intRange", "") || null,
    monitored: c.get<string[]>("monitored", []),
    exploreTimeLimit: c.get<number>("exploreTimeLimit", 30),
  };
}

function python(): string {
  const configured = vscode.workspace.getConfiguration("asmetal").get<string>("python", "");
  if (configured) {
    return configured;
  }
  return process.platform === "win32" ? "python" : "python3";
}

class AsmcheckDocuments implements vscode.TextDocumentContentProvider {
  readonly changed = new vscode.EventEmitter<vscode.Uri>();
  readonly onDidChange = this.changed.event;

  async provideTextDocumentContent(uri: vscode.Uri): Promise<string> {
    if (!client) {
      return "";
    }
    const res = await client.sendRequest<{ text: string | null }>("asmcheck/textDocumentContent", {
      uri: uri.toString(true),
    });
    return res && res.text !== null ? res.text : `asmcheck has no document ${uri.toString(true)}`;
  }
}

async function start(context: vscode.ExtensionContext): Promise<void> {
  const command = python();
  const serverOptions: ServerOptions = {
    run: { command, args: ["-m", "asmcheck", "lsp"], transport: TransportKind.stdio },
    debug: { command, args: ["-m", "asmcheck", "lsp"], transport: TransportKind.stdio },
  };
  const clientOptions: LanguageClientOptions = {
    documentSelector: [
      { scheme: "file", language: "asmetal" },
      { scheme: SCHEME, language: "asmetal" },
    ],
    initializationOptions: { asmetal: settings() },
    outputChannelName: "asmcheck",
  };
  client = new LanguageClient("asmetal", "asmcheck language server", serverOptions, clientOptions);
  try {
    await client.start();
  } catch (err) {
    vscode.window.showErrorMessage(
      `Could not start '${command} -m asmcheck lsp' (${err}). Install it with ` +
        `pip install 'asmcheck[lsp]' or set asmetal.python to the interpreter that has it.`
    );
  }
}

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  const docs = new AsmcheckDocuments();
  context.subscriptions.push(vscode.workspace.registerTextDocumentContentProvider(SCHEME, docs));
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration(async (e) => {
      if (!client) {
        return;
      }
      if (e.affectsConfiguration("asmetal.python")) {
        await client.stop();
        await start(context);
      } else if (e.affectsConfiguration("asmetal")) {
        await client.sendNotification("workspace/didChangeConfiguration", { settings: { asmetal: settings() } });
      }
    })
  );
  context.subscriptions.push(
    vscode.commands.registerCommand("asmetal.restartServer", async () => {
      if (client) {
        await client.stop();
      }
      await start(context);
    })
  );
  await start(context);
}

export async function deactivate(): Promise<void> {
  if (client) {
    await client.stop();
  }
}

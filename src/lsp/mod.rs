//! `raytrace lsp`: a Language Server over stdio for `.rt` files.
//!
//! ```text
//!  editor ──didOpen/didChange──▶ main loop ──job──▶ checker thread: parse + evaluate + build
//!         ◀──publishDiagnostics───────────────────── (never render), per file
//!         ──hover/completion/definition/documentSymbol──▶ main loop (text + last analysis)
//! ```
//!
//! Diagnostics carry the command line's messages and spans
//! ([`check`]); a newer version of a document cancels the check of an older
//! one, and checks are debounced so a burst of keystrokes costs one check.
//! The protocol's framing is the `lsp-server` crate's (rust-analyzer's).

mod analysis;
mod check;
mod complete;
mod context;
mod docs;
mod hover;
pub mod positions;
mod symbols;
pub mod uri;

use crate::lang::incremental::ParseCache;
use analysis::Analysis;
use lsp_server::{Connection, ExtractError, Message, Notification, Request, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, DidSaveTextDocument,
    Notification as _, PublishDiagnostics,
};
use lsp_types::request::{Completion, DocumentSymbolRequest, GotoDefinition, HoverRequest};
use lsp_types::{
    CompletionOptions, CompletionResponse, Diagnostic, DocumentSymbolResponse,
    GotoDefinitionResponse, Hover, HoverContents, HoverProviderCapability, MarkupContent,
    MarkupKind, OneOf, Position, PublishDiagnosticsParams, ServerCapabilities,
    TextDocumentSyncCapability, TextDocumentSyncKind, Uri,
};
use positions::LineIndex;
use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How long the checker waits after a change for the next one (editors
/// send one per keystroke): short against the ~200 ms an edit should take
/// to show its mistakes.
const DEBOUNCE: Duration = Duration::from_millis(25);

/// Runs the server on stdin/stdout until the client says `exit`.
pub fn main() -> ExitCode {
    let (connection, io_threads) = Connection::stdio();
    let result = serve(connection);
    // The reader thread ends when the client closes stdin.
    let joined = io_threads.join().map_err(Into::into);
    match (result, joined) {
        (Ok(()), Ok(())) => ExitCode::SUCCESS,
        (Err(e), _) | (Ok(()), Err(e)) => {
            eprintln!("raytrace lsp: {e}");
            ExitCode::FAILURE
        }
    }
}

fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        completion_provider: Some(CompletionOptions::default()),
        definition_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        ..ServerCapabilities::default()
    }
}

/// An open document.
struct Doc {
    text: String,
    version: i32,
    lines: LineIndex,
    /// Set when a newer version supersedes the check of this one.
    cancel: Arc<AtomicBool>,
}

/// What the checker thread is asked to do.
enum Job {
    Check {
        uri: Uri,
        version: i32,
        text: String,
        cancel: Arc<AtomicBool>,
    },
    Close(Uri),
}

/// Maps are keyed by the URI's text (`Uri` has interior mutability).
type Analyses = Arc<Mutex<HashMap<String, Arc<Analysis>>>>;

fn serve(connection: Connection) -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    let caps = serde_json::to_value(capabilities())?;
    connection.initialize(caps)?;
    let analyses: Analyses = Arc::default();
    let (jobs, queue) = mpsc::channel::<Job>();
    let checker = {
        let sender = connection.sender.clone();
        let analyses = analyses.clone();
        std::thread::Builder::new()
            .name("rt-check".into())
            // Parsing and evaluation recurse: the render's stack size.
            .stack_size(64 << 20)
            .spawn(move || {
                checker(
                    queue,
                    move |m| {
                        let _ = sender.send(m);
                    },
                    analyses,
                )
            })?
    };
    let mut docs: HashMap<String, Doc> = HashMap::new();
    for msg in &connection.receiver {
        match msg {
            Message::Request(req) => {
                if connection.handle_shutdown(&req)? {
                    break;
                }
                let resp = respond(req, &docs, &analyses);
                connection.sender.send(Message::Response(resp))?;
            }
            Message::Notification(n) => notified(n, &mut docs, &jobs),
            Message::Response(_) => {}
        }
    }
    drop(jobs);
    let _ = checker.join();
    Ok(())
}

fn notified(n: Notification, docs: &mut HashMap<String, Doc>, jobs: &mpsc::Sender<Job>) {
    let check = |docs: &mut HashMap<String, Doc>, uri: Uri, version: i32, text: String| {
        if let Some(old) = docs.get(uri.as_str()) {
            old.cancel.store(true, Ordering::Relaxed);
        }
        let cancel = Arc::new(AtomicBool::new(false));
        let _ = jobs.send(Job::Check {
            uri: uri.clone(),
            version,
            text: text.clone(),
            cancel: cancel.clone(),
        });
        docs.insert(
            uri.as_str().to_string(),
            Doc {
                lines: LineIndex::new(&text),
                text,
                version,
                cancel,
            },
        );
    };
    match n.method.as_str() {
        DidOpenTextDocument::METHOD => {
            if let Ok(p) =
                n.extract::<lsp_types::DidOpenTextDocumentParams>(DidOpenTextDocument::METHOD)
            {
                let d = p.text_document;
                check(docs, d.uri, d.version, d.text);
            }
        }
        DidChangeTextDocument::METHOD => {
            if let Ok(p) =
                n.extract::<lsp_types::DidChangeTextDocumentParams>(DidChangeTextDocument::METHOD)
                && let Some(change) = p.content_changes.into_iter().last()
            {
                // Full sync: each change is the whole text.
                check(
                    docs,
                    p.text_document.uri,
                    p.text_document.version,
                    change.text,
                );
            }
        }
        DidSaveTextDocument::METHOD => {
            // An included file saved changes what its includers see.
            let open: Vec<(String, i32, String)> = docs
                .iter()
                .map(|(u, d)| (u.clone(), d.version, d.text.clone()))
                .collect();
            for (u, v, t) in open {
                let Ok(u) = u.parse::<Uri>() else { continue };
                check(docs, u, v, t);
            }
        }
        DidCloseTextDocument::METHOD => {
            if let Ok(p) =
                n.extract::<lsp_types::DidCloseTextDocumentParams>(DidCloseTextDocument::METHOD)
            {
                if let Some(d) = docs.remove(p.text_document.uri.as_str()) {
                    d.cancel.store(true, Ordering::Relaxed);
                }
                let _ = jobs.send(Job::Close(p.text_document.uri));
            }
        }
        _ => {}
    }
}

fn respond(req: Request, docs: &HashMap<String, Doc>, analyses: &Analyses) -> Response {
    let id = req.id.clone();
    let at = |uri: &Uri, p: Position| -> Option<(&Doc, usize, Option<Arc<Analysis>>)> {
        let d = docs.get(uri.as_str())?;
        let a = analyses.lock().ok()?.get(uri.as_str()).cloned();
        Some((d, d.lines.offset(&d.text, p), a))
    };
    let result = match req.method.as_str() {
        "textDocument/hover" => extract::<HoverRequest>(req).map(|p| {
            let p = p.text_document_position_params;
            let h = at(&p.text_document.uri, p.position).and_then(|(d, off, a)| {
                let (text, s, e) = hover::hover(&d.text, off, a.as_deref())?;
                Some(Hover {
                    contents: HoverContents::Markup(MarkupContent {
                        kind: MarkupKind::Markdown,
                        value: text,
                    }),
                    range: Some(d.lines.range(&d.text, s, e)),
                })
            });
            serde_json::to_value(h)
        }),
        "textDocument/completion" => extract::<Completion>(req).map(|p| {
            let p = p.text_document_position;
            let items = at(&p.text_document.uri, p.position)
                .map(|(d, off, a)| complete::complete(&d.text, off, a.as_deref()))
                .unwrap_or_default();
            serde_json::to_value(CompletionResponse::Array(items))
        }),
        "textDocument/definition" => extract::<GotoDefinition>(req).map(|p| {
            let p = p.text_document_position_params;
            let l = at(&p.text_document.uri, p.position)
                .and_then(|(d, off, a)| symbols::definition(&d.text, off, a.as_deref()?));
            serde_json::to_value(l.map(GotoDefinitionResponse::Scalar))
        }),
        "textDocument/documentSymbol" => extract::<DocumentSymbolRequest>(req).map(|p| {
            let a = analyses
                .lock()
                .ok()
                .and_then(|m| m.get(p.text_document.uri.as_str()).cloned());
            let syms = a.map(|a| DocumentSymbolResponse::Nested(symbols::outline(&a)));
            serde_json::to_value(syms)
        }),
        _ => {
            return Response::new_err(
                id,
                lsp_server::ErrorCode::MethodNotFound as i32,
                format!("raytrace lsp does not answer `{}`", req.method),
            );
        }
    };
    match result {
        Ok(Ok(v)) => Response::new_ok(id, v),
        Ok(Err(e)) => Response::new_err(
            id,
            lsp_server::ErrorCode::InternalError as i32,
            e.to_string(),
        ),
        Err(e) => Response::new_err(id, lsp_server::ErrorCode::InvalidParams as i32, e),
    }
}

fn extract<R: lsp_types::request::Request>(req: Request) -> Result<R::Params, String> {
    req.extract::<R::Params>(R::METHOD)
        .map(|(_, p)| p)
        .map_err(|e| match e {
            ExtractError::MethodMismatch(r) => format!("unexpected method {}", r.method),
            ExtractError::JsonError { method, error } => {
                format!("bad parameters for {method}: {error}")
            }
        })
}

/// The checker thread: checks each document's latest text, publishes its
/// diagnostics (and its includes'), and keeps its analysis for requests.
fn checker(queue: mpsc::Receiver<Job>, sender: impl Fn(Message), analyses: Analyses) {
    // What each open document's last check said of each file.
    let mut reports: HashMap<String, BTreeMap<PathBuf, Vec<Diagnostic>>> = HashMap::new();
    // Each open document's parses, so that a keystroke re-parses only
    // the part of the text it changed.
    let mut caches: HashMap<String, ParseCache> = HashMap::new();
    while let Ok(first) = queue.recv() {
        std::thread::sleep(DEBOUNCE);
        // The latest job per document; earlier ones are superseded.
        let mut batch: Vec<Job> = vec![first];
        batch.extend(queue.try_iter());
        let mut latest: Vec<Job> = Vec::new();
        for job in batch {
            let uri = match &job {
                Job::Check { uri, .. } | Job::Close(uri) => uri.clone(),
            };
            latest.retain(|j| !matches!(j, Job::Check { uri: u, .. } | Job::Close(u) if *u == uri));
            latest.push(job);
        }
        for job in latest {
            match job {
                Job::Close(uri) => {
                    if let Ok(mut m) = analyses.lock() {
                        m.remove(uri.as_str());
                    }
                    caches.remove(uri.as_str());
                    let old = reports.remove(uri.as_str()).unwrap_or_default();
                    publish(&sender, &reports, old.keys(), None);
                }
                Job::Check {
                    uri,
                    version,
                    text,
                    cancel,
                } => {
                    if cancel.load(Ordering::Relaxed) {
                        continue;
                    }
                    let Some(path) =
                        uri::to_path(&uri).or_else(|| Some(PathBuf::from("untitled.rt")))
                    else {
                        continue;
                    };
                    let cpu = thread_cpu_seconds();
                    let cache = caches.entry(uri.as_str().to_string()).or_default();
                    let report = check::check_with(&path, &text, Some(cancel.clone()), Some(cache));
                    let cpu = thread_cpu_seconds() - cpu;
                    if cancel.load(Ordering::Relaxed) {
                        continue;
                    }
                    // A line per check on stderr, which editors keep as the server's log.
                    let [p, b, a] = report.times.map(|t| t * 1000.0);
                    eprintln!(
                        "raytrace lsp: checked {} (version {version}) in {:.0} ms ({:.0} ms of CPU): parse {p:.0}, evaluate and build {b:.0}, analyse {a:.0}",
                        path.display(),
                        p + b + a,
                        cpu * 1000.0
                    );
                    if let Some(a) = report.analysis
                        && let Ok(mut m) = analyses.lock()
                    {
                        m.insert(uri.as_str().to_string(), a);
                    }
                    let own = uri::to_path(&uri);
                    let mut touched: Vec<PathBuf> = report.diagnostics.keys().cloned().collect();
                    if let Some(old) = reports.insert(uri.as_str().to_string(), report.diagnostics)
                    {
                        touched.extend(old.into_keys());
                    }
                    touched.sort();
                    touched.dedup();
                    publish(
                        &sender,
                        &reports,
                        touched.iter(),
                        own.as_ref().map(|p| (p, version, &uri)),
                    );
                }
            }
        }
    }
}

/// Publishes the diagnostics of each path: what every open document's
/// last check says of it (a file included by two open scenes shows the
/// mistakes either finds, once).
fn publish<'a>(
    sender: &impl Fn(Message),
    reports: &HashMap<String, BTreeMap<PathBuf, Vec<Diagnostic>>>,
    paths: impl Iterator<Item = &'a PathBuf>,
    own: Option<(&PathBuf, i32, &Uri)>,
) {
    for path in paths {
        let mut all: Vec<Diagnostic> = Vec::new();
        for r in reports.values() {
            for d in r.get(path).into_iter().flatten() {
                if !all
                    .iter()
                    .any(|o| o.range == d.range && o.message == d.message)
                {
                    all.push(d.clone());
                }
            }
        }
        let (uri, version) = match own {
            Some((p, v, u)) if p == path => (u.clone(), Some(v)),
            _ => match uri::from_path(path) {
                Some(u) => (u, None),
                None => continue,
            },
        };
        let params = PublishDiagnosticsParams {
            uri,
            diagnostics: all,
            version,
        };
        let note = lsp_server::Notification::new(PublishDiagnostics::METHOD.to_string(), params);
        sender(Message::Notification(note));
    }
}

/// CPU time this thread has used: on a busy machine, what a check costs
/// apart from waiting for a core.
fn thread_cpu_seconds() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec to the pointer given.
    let ok = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0;
    if ok {
        t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
    } else {
        0.0
    }
}

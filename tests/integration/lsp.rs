//! `raytrace lsp` driven as an editor drives it: a child process spoken to
//! in JSON-RPC with `Content-Length` framing over its stdin and stdout.

use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Long enough for a loaded machine; a healthy answer takes milliseconds.
const PATIENCE: Duration = Duration::from_secs(30);

struct Client {
    child: Child,
    stdin: ChildStdin,
    incoming: mpsc::Receiver<Value>,
    /// Notifications that arrived while waiting for something else.
    pending: Vec<Value>,
    next_id: i64,
}

impl Client {
    fn start(root: &Path) -> Client {
        let mut child = Command::new(env!("CARGO_BIN_EXE_raytrace"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("raytrace lsp starts");
        let stdin = child.stdin.take().unwrap();
        let stdout = child.stdout.take().unwrap();
        let (tx, incoming) = mpsc::channel();
        std::thread::spawn(move || {
            let mut r = BufReader::new(stdout);
            loop {
                let mut length = None;
                loop {
                    let mut line = String::new();
                    if r.read_line(&mut line).unwrap_or(0) == 0 {
                        return;
                    }
                    let line = line.trim_end();
                    if line.is_empty() {
                        break;
                    }
                    if let Some(n) = line.strip_prefix("Content-Length: ") {
                        length = n.parse::<usize>().ok();
                    }
                }
                let mut body = vec![0; length.expect("a Content-Length header")];
                if r.read_exact(&mut body).is_err() {
                    return;
                }
                let v: Value = serde_json::from_slice(&body).expect("the body is JSON");
                if tx.send(v).is_err() {
                    return;
                }
            }
        });
        let mut c = Client {
            child,
            stdin,
            incoming,
            pending: Vec::new(),
            next_id: 1,
        };
        let root_uri = uri(root);
        let init = c.request(
            "initialize",
            json!({ "processId": null, "rootUri": root_uri, "capabilities": {} }),
        );
        assert!(
            init["capabilities"]["hoverProvider"]
                .as_bool()
                .unwrap_or(false),
            "{init}"
        );
        c.notify("initialized", json!({}));
        c
    }

    fn send(&mut self, v: Value) {
        let body = v.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
        self.stdin.flush().unwrap();
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({ "jsonrpc": "2.0", "method": method, "params": params }));
    }

    fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }));
        let deadline = Instant::now() + PATIENCE;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let v = self
                .incoming
                .recv_timeout(left)
                .unwrap_or_else(|_| panic!("no answer to {method}"));
            if v["id"] == json!(id) {
                assert!(v.get("error").is_none(), "{method} failed: {v}");
                return v["result"].clone();
            }
            self.pending.push(v);
        }
    }

    /// The next diagnostics published for `uri` that satisfy `ok`.
    fn diagnostics(&mut self, uri: &str, ok: impl Fn(&[Value]) -> bool) -> Vec<Value> {
        let deadline = Instant::now() + PATIENCE;
        let matches = |v: &Value| {
            v["method"] == "textDocument/publishDiagnostics" && v["params"]["uri"] == uri
        };
        loop {
            if let Some(k) = self.pending.iter().position(matches) {
                let v = self.pending.remove(k);
                let d = v["params"]["diagnostics"].as_array().unwrap().clone();
                if ok(&d) {
                    return d;
                }
                continue;
            }
            let left = deadline.saturating_duration_since(Instant::now());
            match self.incoming.recv_timeout(left) {
                Ok(v) => self.pending.push(v),
                Err(_) => panic!(
                    "no fitting diagnostics for {uri}; pending: {:?}",
                    self.pending
                ),
            }
        }
    }

    fn open(&mut self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": "rt", "version": 1, "text": text } }),
        );
    }

    fn change(&mut self, uri: &str, version: i64, text: &str) {
        self.notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": uri, "version": version }, "contentChanges": [{ "text": text }] }),
        );
    }

    fn at(&mut self, method: &str, uri: &str, line: u32, character: u32) -> Value {
        self.request(
            method,
            json!({ "textDocument": { "uri": uri }, "position": { "line": line, "character": character } }),
        )
    }

    /// shutdown, exit, and the process ends cleanly.
    fn finish(mut self) {
        let r = self.request("shutdown", Value::Null);
        assert!(r.is_null());
        self.notify("exit", Value::Null);
        drop(self.stdin);
        let deadline = Instant::now() + PATIENCE;
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                assert!(status.success(), "raytrace lsp exited with {status}");
                return;
            }
            assert!(Instant::now() < deadline, "raytrace lsp did not exit");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

fn uri(p: &Path) -> String {
    raytrace::lsp::uri::from_path(p)
        .unwrap()
        .as_str()
        .to_string()
}

fn range(d: &Value) -> (u64, u64, u64, u64) {
    let r = &d["range"];
    let n = |v: &Value| v.as_u64().unwrap();
    (
        n(&r["start"]["line"]),
        n(&r["start"]["character"]),
        n(&r["end"]["line"]),
        n(&r["end"]["character"]),
    )
}

// In the first line, `/* é𝄞 */` before the mistake: `radus` starts at
// byte 22, character 18, and UTF-16 unit 19 (𝄞 is two units), which is
// what the protocol counts.
const TWO_MISTAKES: &str = "sphere { /* é𝄞 */ radus 1 }\nbox { materail { colour red } }\n";

#[test]
fn two_mistakes_are_both_published_with_their_ranges_and_a_fix_removes_one() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("two.rt");
    let u = uri(&scene);
    let mut c = Client::start(dir.path());
    c.open(&u, TWO_MISTAKES);
    let d = c.diagnostics(&u, |d| !d.is_empty());
    assert_eq!(d.len(), 2, "{d:?}");
    assert_eq!(range(&d[0]), (0, 19, 0, 24));
    let m = d[0]["message"].as_str().unwrap();
    assert!(
        m.starts_with("unknown parameter `radus` in `sphere`"),
        "{m}"
    );
    assert!(m.contains("did you mean `radius`?"), "{m}");
    assert_eq!(range(&d[1]), (1, 6, 1, 14));
    assert!(d[1]["message"].as_str().unwrap().contains("`materail`"));
    assert_eq!(d[0]["severity"], 1);

    // The CLI reports the same two, at the same places.
    std::fs::write(&scene, TWO_MISTAKES).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_raytrace"))
        .arg(&scene)
        .arg("--check")
        .env("NO_COLOR", "1")
        .output()
        .unwrap();
    let cli = String::from_utf8_lossy(&out.stderr);
    assert!(
        cli.contains("unknown parameter `radus` in `sphere`") && cli.contains("two.rt:1:19"),
        "{cli}"
    );
    assert!(cli.contains("two.rt:2:7"), "{cli}");

    let fixed_one = TWO_MISTAKES.replace("radus", "radius");
    c.change(&u, 2, &fixed_one);
    let d = c.diagnostics(&u, |d| d.len() != 2);
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(range(&d[0]), (1, 6, 1, 14));
    c.change(&u, 3, &fixed_one.replace("materail", "material"));
    let d = c.diagnostics(&u, |d| d.len() != 1);
    assert!(d.is_empty(), "{d:?}");
    c.finish();
}

#[test]
fn a_syntax_error_and_an_unclosed_block_are_published() {
    let dir = tempfile::tempdir().unwrap();
    let u = uri(&dir.path().join("syntax.rt"));
    let mut c = Client::start(dir.path());
    c.open(
        &u,
        "sphere { radius 1 }\nbox {\n  min <0, 0, 0>\nplane { }\n",
    );
    let d = c.diagnostics(&u, |d| !d.is_empty());
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(range(&d[0]), (1, 4, 1, 5));
    let m = d[0]["message"].as_str().unwrap();
    assert!(m.contains("the block of `box` is never closed"), "{m}");
    assert!(m.contains("before `plane` on line 4"), "{m}");
    c.finish();
}

#[test]
fn mistakes_in_an_included_file_are_published_for_that_file() {
    let dir = tempfile::tempdir().unwrap();
    let inc = dir.path().join("parts.rt");
    std::fs::write(
        &inc,
        "// parts\nmaterial steel { colour #b0b0c0  reflekt 0.3 }\n",
    )
    .unwrap();
    let scene = dir.path().join("scene.rt");
    let su = uri(&scene);
    let iu = uri(&inc);
    let mut c = Client::start(dir.path());
    c.open(&su, "include \"parts.rt\"\nsphere { material steel }\n");
    let d = c.diagnostics(&iu, |d| !d.is_empty());
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(range(&d[0]), (1, 33, 1, 40));
    assert!(
        d[0]["message"]
            .as_str()
            .unwrap()
            .contains("did you mean `reflect`?")
    );
    let related = &d[0]["relatedInformation"][0];
    assert_eq!(related["location"]["uri"], su.as_str());
    assert_eq!(related["message"], "included from here");
    // And the scene shows where its include went wrong.
    let d = c.diagnostics(&su, |d| !d.is_empty());
    assert_eq!(range(&d[0]), (0, 8, 0, 18));
    assert!(d[0]["message"].as_str().unwrap().contains("`"), "{d:?}");
    c.finish();
}

#[test]
fn hover_completion_and_definition_answer() {
    let dir = tempfile::tempdir().unwrap();
    let u = uri(&dir.path().join("h.rt"));
    let text = "let R = 2 * 1.5\nmaterial gold2 { colour gold }\nsphere { radius R  material gold2 }\nbox {  }\n";
    let mut c = Client::start(dir.path());
    c.open(&u, text);
    let d = c.diagnostics(&u, |_| true);
    assert!(d.is_empty(), "{d:?}");

    // The use of R on line 3: its definition and value.
    let h = c.at("textDocument/hover", &u, 2, 16);
    let v = h["contents"]["value"].as_str().unwrap();
    assert!(
        v.contains("let R = 2 * 1.5") && v.contains("= 3 (a number)"),
        "{v}"
    );
    assert_eq!(h["range"]["start"]["character"], 16);
    // A parameter: what it expects.
    let h = c.at("textDocument/hover", &u, 2, 11);
    let v = h["contents"]["value"].as_str().unwrap();
    assert!(v.starts_with("**radius** (in `sphere`): a number"), "{v}");
    // A statement: the language reference's text.
    let h = c.at("textDocument/hover", &u, 3, 1);
    assert!(
        h["contents"]["value"]
            .as_str()
            .unwrap()
            .contains("`min <a>`, `max <b>`")
    );

    // Inside `box { }`: box's parameters, not a sphere's.
    let items = c.at("textDocument/completion", &u, 3, 6);
    let labels: Vec<&str> = items
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["label"].as_str().unwrap())
        .collect();
    assert!(
        labels.contains(&"min") && labels.contains(&"front") && labels.contains(&"translate"),
        "{labels:?}"
    );
    assert!(!labels.contains(&"radius"), "{labels:?}");
    assert!(labels.contains(&"R"), "names in scope: {labels:?}");

    // gold2 in the sphere → its declaration on line 2.
    let l = c.at("textDocument/definition", &u, 2, 30);
    assert_eq!(l["uri"], u.as_str());
    assert_eq!(l["range"]["start"], json!({ "line": 1, "character": 9 }));

    let syms = c.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": u } }),
    );
    let names: Vec<&str> = syms
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["R", "material gold2", "sphere", "box"]);
    c.finish();
}

/// A scene of `n` one-line objects, the `k`-th at line `k`.
fn many_objects(n: usize) -> Vec<String> {
    (0..n)
        .map(|k| {
            format!(
                "sphere {{ centre <{}, 0, {}>  radius 0.4 }}",
                k % 100,
                k / 100
            )
        })
        .collect()
}

/// Edits in a large scene re-parse only what changed (the server keeps
/// the parses of the rest); the ranges must still be the full parse's:
/// a mistake that lines inserted above it move down, a syntax error, and
/// a fix.
#[test]
fn edits_in_a_large_scene_give_the_right_ranges() {
    let dir = tempfile::tempdir().unwrap();
    let u = uri(&dir.path().join("large.rt"));
    let mut c = Client::start(dir.path());
    let mut lines = many_objects(20_000);
    c.open(&u, &(lines.join("\n") + "\n"));
    let d = c.diagnostics(&u, |_| true);
    assert!(d.is_empty(), "{d:?}");

    // A misspelt parameter on line 12,000 (0-based 11,999).
    lines[11_999] = "sphere { radus 1 }".into();
    c.change(&u, 2, &(lines.join("\n") + "\n"));
    let d = c.diagnostics(&u, |d| !d.is_empty());
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(range(&d[0]), (11_999, 9, 11_999, 14));

    // Three lines inserted near the top, one of them a block over lines:
    // the mistake moves down three lines.
    lines.splice(
        10..10,
        ["box {".to_string(), "  min <0, 0, 0>".into(), "}".into()],
    );
    c.change(&u, 3, &(lines.join("\n") + "\n"));
    let d = c.diagnostics(&u, |d| d.len() == 1 && range(&d[0]).0 != 11_999);
    assert_eq!(range(&d[0]), (12_002, 9, 12_002, 14));

    // A `]` for a `}` on line 5,001: only the bracket errors are
    // reported (the stray `]`, and the `{` it left open), not the mistake.
    lines[5_000] = "sphere { radius 1 ]".into();
    c.change(&u, 4, &(lines.join("\n") + "\n"));
    let d = c.diagnostics(&u, |d| d.iter().all(|d| range(d).0 != 12_002));
    assert_eq!(d.len(), 2, "{d:?}");
    assert_eq!(range(&d[0]), (5_000, 7, 5_000, 8), "{d:?}");
    assert_eq!(range(&d[1]), (5_000, 18, 5_000, 19), "{d:?}");

    // A `let` without its name on line 8,001: the whole-file parse's
    // syntax error.
    lines[5_000] = "sphere { radius 1 }".into();
    lines[8_000] = "let = 1".into();
    c.change(&u, 5, &(lines.join("\n") + "\n"));
    let d = c.diagnostics(&u, |d| d.len() == 1 && range(&d[0]).0 != 5_000);
    assert_eq!(range(&d[0]), (8_000, 4, 8_000, 5), "{d:?}");
    assert!(
        d[0]["message"]
            .as_str()
            .unwrap()
            .contains("expected a name"),
        "{d:?}"
    );

    // Both fixed.
    lines[8_000] = "sphere { radius 1 }".into();
    lines[12_002] = "sphere { radius 1 }".into();
    c.change(&u, 6, &(lines.join("\n") + "\n"));
    let d = c.diagnostics(&u, |d| d.is_empty());
    assert!(d.is_empty());
    c.finish();
}

#[test]
fn a_runaway_loop_is_stopped_by_the_editor_s_budget() {
    let dir = tempfile::tempdir().unwrap();
    let u = uri(&dir.path().join("loop.rt"));
    let mut c = Client::start(dir.path());
    let start = Instant::now();
    c.open(&u, "for i in 0..1000 { for j in 0..1000 { for k in 0..1000 { let a = i } } }\nsphere { radus 1 }\n");
    let d = c.diagnostics(&u, |d| !d.is_empty());
    let took = start.elapsed();
    assert!(
        d.iter()
            .any(|d| d["severity"] == 3
                && d["message"].as_str().unwrap().contains("stopped checking")),
        "{d:?}"
    );
    // A billion steps would take minutes; the budget is a fraction of a second
    // (generous bound for a loaded test machine).
    assert!(took < Duration::from_secs(20), "{took:?}");
    c.finish();
}

/// The VS Code grammar highlights every word of the language: a word
/// added to the language and forgotten there fails here.
#[test]
fn the_editor_grammar_knows_every_word_of_the_language() {
    let root = crate::support::project_root().join("editors/vscode");
    let read = |p: &str| -> Value {
        serde_json::from_str(&std::fs::read_to_string(root.join(p)).unwrap())
            .unwrap_or_else(|e| panic!("{p} is not JSON: {e}"))
    };
    let package = read("package.json");
    let grammar_path = package["contributes"]["grammars"][0]["path"]
        .as_str()
        .unwrap();
    let grammar = read(grammar_path);
    let text = grammar.to_string();
    let mut words: Vec<&str> = raytrace::lang::parser::STATEMENT_KEYWORDS.to_vec();
    words.extend(raytrace::scene::pattern::NAMES);
    words.extend(raytrace::eval::expr::FUNCTIONS.iter().map(|(f, _)| *f));
    words.extend([
        "translate",
        "rotate",
        "scale",
        "shear",
        "mirror",
        "matrix",
        "pi",
        "clock",
        "frame",
    ]);
    let missing: Vec<&str> = words
        .into_iter()
        .filter(|w| {
            !text.contains(&format!("|{w}|"))
                && !text.contains(&format!("({w}|"))
                && !text.contains(&format!("|{w})"))
                && !text.contains(&format!("\\\\b{w}\\\\b"))
        })
        .collect();
    assert!(missing.is_empty(), "not in {grammar_path}: {missing:?}");
    let config = read("language-configuration.json");
    assert_eq!(config["comments"]["lineComment"], "//");
    assert_eq!(config["comments"]["blockComment"], json!(["/*", "*/"]));
    assert_eq!(package["activationEvents"][0], "onLanguage:rt");
}

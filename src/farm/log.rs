//! `--log json`: one JSON object a line on stderr for each frame or tile
//! that finished, was skipped, or failed, for a farm's log collector:
//!
//! ```text
//! {"event":"finished","output":"out_0003.png","frame":3,"clock":0.5,"region":[0,0,48,32],"picture":[48,32],"seconds":0.41,"render_seconds":0.38,"rays":9216,"peak_rss_bytes":14680064}
//! {"event":"skipped","output":"out_0004.png","frame":4,"reason":"exists"}
//! {"event":"failed","frame":5,"exit":1,"message":"..."}
//! ```
//!
//! Each line goes to stderr in one write, so lines of processes sharing a
//! log do not interleave mid-line.

use crate::cli::{Args, LogFormat};
use crate::render::{Region, RenderStats};
use std::io::Write;
use std::path::Path;

/// A JSON string literal.
fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A JSON number: finite as Rust prints it (which JSON reads), else null.
fn number(x: f64) -> String {
    if x.is_finite() {
        format!("{x:?}")
    } else {
        "null".into()
    }
}

/// The most memory this process has held, in bytes (getrusage's
/// `ru_maxrss`: kibibytes on Linux, bytes on macOS).
pub fn peak_rss_bytes() -> Option<u64> {
    let mut usage = std::mem::MaybeUninit::<libc::rusage>::zeroed();
    // SAFETY: getrusage fills the struct it is given; RUSAGE_SELF is valid.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_SELF, usage.as_mut_ptr()) };
    if rc != 0 {
        return None;
    }
    // SAFETY: zero-initialised and filled by a successful call.
    let max = unsafe { usage.assume_init() }.ru_maxrss.max(0) as u64;
    Some(if cfg!(target_os = "macos") {
        max
    } else {
        max * 1024
    })
}

fn emit(args: &Args, fields: &[(&str, String)]) {
    if args.log != Some(LogFormat::Json) {
        return;
    }
    let body: Vec<String> = fields
        .iter()
        .map(|(k, v)| format!("{}:{v}", string(k)))
        .collect();
    let line = format!("{{{}}}\n", body.join(","));
    let _ = std::io::stderr().write_all(line.as_bytes());
}

fn frame_fields(args: &Args) -> Vec<(&'static str, String)> {
    vec![
        ("frame", args.frame.unwrap_or(0).to_string()),
        ("clock", number(args.clock)),
    ]
}

/// A picture (or region of one) was written to `path`.
pub fn finished(
    args: &Args,
    path: &Path,
    region: Region,
    picture: (u32, u32),
    stats: &RenderStats,
    seconds: f64,
) {
    let mut f = vec![
        ("event", string("finished")),
        ("output", string(&path.to_string_lossy())),
    ];
    f.extend(frame_fields(args));
    f.extend([
        (
            "region",
            format!(
                "[{},{},{},{}]",
                region.x, region.y, region.width, region.height
            ),
        ),
        ("picture", format!("[{},{}]", picture.0, picture.1)),
        ("seconds", number(seconds)),
        ("render_seconds", number(stats.seconds)),
        ("rays", stats.rays.total().to_string()),
        (
            "peak_rss_bytes",
            peak_rss_bytes().map_or("null".into(), |b| b.to_string()),
        ),
    ]);
    emit(args, &f);
}

/// `--skip-existing` found `path` already there.
pub fn skipped(args: &Args, path: &Path) {
    let mut f = vec![
        ("event", string("skipped")),
        ("output", string(&path.to_string_lossy())),
    ];
    f.extend(frame_fields(args));
    f.push(("reason", string("exists")));
    emit(args, &f);
}

/// The run stopped with `exit` and this message.
pub fn failed(args: &Args, exit: i32, message: &str) {
    let mut f = vec![("event", string("failed"))];
    f.extend(frame_fields(args));
    f.extend([("exit", exit.to_string()), ("message", string(message))]);
    emit(args, &f);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_and_numbers_are_json() {
        assert_eq!(string("a\"b\\c\nd\u{1}"), r#""a\"b\\c\nd\u0001""#);
        assert_eq!(number(0.5), "0.5");
        assert_eq!(number(1.0), "1.0");
        assert_eq!(number(f64::NAN), "null");
    }

    #[test]
    fn peak_memory_is_measured() {
        // This test process holds at least a megabyte.
        assert!(peak_rss_bytes().unwrap() > 1 << 20);
    }
}

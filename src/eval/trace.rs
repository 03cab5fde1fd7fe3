//! Where generated items came from, for messages: "in iteration i = 7 of
//! the loop at scene.rt:9:1", "in `pillar` called from scene.rt:14:5 with
//! h = 1.7".

use super::*;

/// Where generated items came from: loop iterations and calls, innermost
/// first, put into words only when a message needs them.
#[derive(Debug, PartialEq)]
pub struct Trace {
    pub(super) frame: Frame,
    pub(super) parent: Option<Arc<Trace>>,
}

#[derive(Debug, PartialEq)]
pub(super) enum Frame {
    Loop {
        /// Shared by every iteration of the loop.
        var: Arc<str>,
        value: Value,
        at: Span,
    },
    Call {
        name: String,
        at: Span,
        args: Vec<(String, Value)>,
    },
}

/// One run of a loop: what its iterations share.
#[derive(Debug, PartialEq)]
pub struct LoopSite {
    pub(super) var: Arc<str>,
    pub(super) at: Span,
    pub(super) parent: Option<Arc<Trace>>,
}

/// The trace generated items carry. A loop iteration is its loop's site
/// and its value, with no frame of its own: a loop of 100,000 objects
/// then allocates one site, not 100,000 frames (made into a [`Trace`]
/// only when something inside needs it as a parent: a nested loop or
/// call).
#[derive(Clone, Debug, PartialEq)]
pub enum TraceRef {
    Shared(Arc<Trace>),
    Iteration(Arc<LoopSite>, Value),
}

impl TraceRef {
    /// The same trace as a shared frame (allocated for an iteration).
    pub(super) fn shared(&self) -> Arc<Trace> {
        match self {
            TraceRef::Shared(t) => t.clone(),
            TraceRef::Iteration(site, value) => Arc::new(Trace {
                frame: Frame::Loop {
                    var: site.var.clone(),
                    value: value.clone(),
                    at: site.at,
                },
                parent: site.parent.clone(),
            }),
        }
    }

    /// The trace around this one.
    pub(super) fn parent(&self) -> Option<Arc<Trace>> {
        match self {
            TraceRef::Shared(t) => t.parent.clone(),
            TraceRef::Iteration(site, _) => site.parent.clone(),
        }
    }

    /// As [`Trace::lines`].
    pub fn lines(&self, sources: &crate::lang::source::Sources) -> Vec<String> {
        match self {
            TraceRef::Shared(t) => t.lines(sources),
            TraceRef::Iteration(site, value) => {
                let mut out = vec![loop_line(&site.var, value, site.at, sources)];
                if let Some(p) = &site.parent {
                    out.extend(p.lines(sources));
                }
                out
            }
        }
    }
}

fn loop_line(var: &str, value: &Value, at: Span, sources: &crate::lang::source::Sources) -> String {
    format!(
        "in iteration {var} = {} of the loop at {}",
        value.show(),
        sources.location(at)
    )
}

impl Trace {
    /// "in iteration i = 7 of the loop at scene.rt:9:1", "in `pillar`
    /// called from scene.rt:14:5 with h = 1.7", innermost first.
    pub fn lines(&self, sources: &crate::lang::source::Sources) -> Vec<String> {
        let mut out = Vec::new();
        let mut t = Some(self);
        while let Some(trace) = t {
            out.push(match &trace.frame {
                Frame::Loop { var, value, at } => loop_line(var, value, *at, sources),
                Frame::Call { name, at, args } => {
                    let mut line = format!("in `{name}` called from {}", sources.location(*at));
                    if !args.is_empty() {
                        let shown: Vec<String> = args
                            .iter()
                            .map(|(n, v)| format!("{n} = {}", v.show()))
                            .collect();
                        line.push_str(" with ");
                        line.push_str(&shown.join(", "));
                    }
                    line
                }
            });
            t = trace.parent.as_deref();
        }
        out
    }
}

/// The lines of a trace (innermost first) as shown under a message: deep
/// recursion keeps its innermost three and outermost two calls.
pub fn trail(lines: &[String]) -> String {
    if lines.len() <= 6 {
        return lines.join("\n");
    }
    let n = lines.len();
    let mut out: Vec<String> = lines[..3].to_vec();
    out.push(format!("… {} more …", n - 5));
    out.extend_from_slice(&lines[n - 2..]);
    out.join("\n")
}

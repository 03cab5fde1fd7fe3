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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lang::ast::FileId;

    /// A program whose text gives the locations below: line 3 starts at
    /// byte 11, line 5's fifth column is byte 34.
    const TEXT: &str = "let a = 1\n\nfor i in 0..9 { }\n\n    pillar(1.7)\n";

    fn sources() -> (crate::lang::source::Sources, FileId) {
        let p = crate::lang::load_text(std::path::Path::new("scene.rt"), TEXT.into())
            .unwrap_or_else(|_| panic!("{TEXT} does not parse"));
        (p.sources, p.root)
    }

    fn call(root: FileId, args: Vec<(String, Value)>) -> Arc<Trace> {
        Arc::new(Trace {
            frame: Frame::Call {
                name: "pillar".into(),
                at: Span::new(root, 34, 45),
                args,
            },
            parent: None,
        })
    }

    /// An iteration inside a call, innermost first, in the words of the
    /// module's doc: the loop's variable and value and where the loop
    /// starts, then the call with its arguments. As an iteration, as the
    /// shared frame made of it, and through `Trace::lines`, the same.
    #[test]
    fn an_iteration_in_a_call_says_which_in_words() {
        let (sources, root) = sources();
        let outer = call(
            root,
            vec![
                ("h".into(), Value::Number(1.7)),
                ("r".into(), Value::Number(0.3)),
            ],
        );
        let site = Arc::new(LoopSite {
            var: Arc::from("i"),
            at: Span::new(root, 11, 28),
            parent: Some(outer.clone()),
        });
        let it = TraceRef::Iteration(site, Value::Number(7.0));
        let want = [
            "in iteration i = 7 of the loop at scene.rt:3:1",
            "in `pillar` called from scene.rt:5:5 with h = 1.7, r = 0.3",
        ];
        assert_eq!(it.lines(&sources), want);
        let shared = it.shared();
        assert_eq!(shared.lines(&sources), want);
        assert_eq!(TraceRef::Shared(shared.clone()).lines(&sources), want);
        assert_eq!(
            shared.frame,
            Frame::Loop {
                var: Arc::from("i"),
                value: Value::Number(7.0),
                at: Span::new(root, 11, 28),
            }
        );
        // Both kinds know the trace around them: the call, which has none.
        assert_eq!(it.parent(), Some(outer.clone()));
        assert_eq!(TraceRef::Shared(shared).parent(), Some(outer.clone()));
        assert_eq!(TraceRef::Shared(outer).parent(), None);
    }

    /// A call without arguments has no "with".
    #[test]
    fn a_call_without_arguments_says_no_with() {
        let (sources, root) = sources();
        assert_eq!(
            call(root, Vec::new()).lines(&sources),
            ["in `pillar` called from scene.rt:5:5"]
        );
    }

    /// Up to six lines are shown whole; past that the innermost three and
    /// the outermost two, with the count of those left out between.
    #[test]
    fn a_long_trail_keeps_its_ends() {
        let lines = |n: usize| (1..=n).map(|k| format!("line {k}")).collect::<Vec<_>>();
        assert_eq!(trail(&[]), "");
        assert_eq!(trail(&lines(1)), "line 1");
        assert_eq!(
            trail(&lines(6)),
            "line 1\nline 2\nline 3\nline 4\nline 5\nline 6"
        );
        assert_eq!(
            trail(&lines(7)),
            "line 1\nline 2\nline 3\n… 2 more …\nline 6\nline 7"
        );
        assert_eq!(
            trail(&lines(12)),
            "line 1\nline 2\nline 3\n… 7 more …\nline 11\nline 12"
        );
    }
}

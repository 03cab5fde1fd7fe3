//! The evaluator's entry points: its options and limits, whole-program and
//! item-by-item evaluation (the language server also wants the top-level
//! values), and the value of a `-D NAME=VALUE`.

use super::*;

/// Caps on the work a scene program may ask for.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Iterations of one loop.
    pub iterations: u64,
    /// Objects produced in all.
    pub objects: u64,
    /// Nested function calls.
    pub depth: usize,
    /// Evaluation steps (expressions and items) in all.
    pub steps: u64,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            iterations: 1_000_000,
            objects: 10_000_000,
            depth: 100,
            steps: 200_000_000,
        }
    }
}

/// What comes from outside the scene file.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// `-D NAME=VALUE`: replaces the value of the top-level `let NAME`.
    pub defines: Vec<(String, Value)>,
    /// `clock` (0..1 over an animation; 0 for a still).
    pub clock: f64,
    /// `frame` (0 for a still).
    pub frame: f64,
    pub limits: Limits,
    /// Set from another thread to stop the evaluation early, quietly (an
    /// editor's newer text makes this check useless).
    pub cancel: Option<Arc<std::sync::atomic::AtomicBool>>,
    /// `--accel`: replaces the scene's `render { accel }`.
    pub accel: Option<crate::accel::Accel>,
}

/// Evaluation steps after which a top-level loop hands what it made to
/// the sink: small enough that a part's items stay in the cache and few
/// exist at once, large enough that a part is not one tiny item.
const PART_STEPS: u64 = 4096;
/// Items after which a top-level loop hands over what it made, whatever
/// the steps.
const PART_ITEMS: usize = 256;

/// The evaluated program.
pub struct Evaluated {
    pub items: Vec<Item>,
    pub errors: Vec<Error>,
    /// Every name bound anywhere, for the builder's suggestions.
    pub known: Vec<String>,
}

/// Evaluates the program's items. `transfer` decodes `#rrggbb` and
/// named colours.
pub fn evaluate(program: &Program, transfer: Transfer, options: &Options) -> Evaluated {
    let mut items = Vec::new();
    let mut known = Vec::new();
    let errors = evaluate_in_parts(program, transfer, options, |part, names| {
        items.extend(part);
        known = names.to_vec();
    });
    Evaluated {
        items,
        errors,
        known,
    }
}

/// As [`evaluate`], handing the items over in parts, each a run of whole
/// statements, as soon as they are made: a loop's hundred thousand objects
/// can be built and dropped before the next statement is evaluated. `sink`
/// also gets the names bound so far and the error list.
pub fn evaluate_in_parts(
    program: &Program,
    transfer: Transfer,
    options: &Options,
    sink: impl FnMut(Vec<Item>, &[String]),
) -> Vec<Error> {
    evaluate_in_parts_bound(program, transfer, options, sink).0
}

/// A name bound at the top level of a program, with its value at the end
/// of the evaluation (`None` when its definition failed); for an editor's
/// hover.
#[derive(Clone, Debug)]
pub struct TopLevel {
    pub name: String,
    pub span: Span,
    pub value: Option<Value>,
}

/// Where [`evaluate_into`] hands its parts. A closure `|items, known| …`
/// is one.
pub trait Sink {
    /// A part, with the names bound so far.
    fn part(&mut self, items: Vec<Item>, known: &[String]);

    /// A sink that gets its parts back once they are used (the builder on
    /// its own thread) can free them a little at a time: the evaluator
    /// calls this after every loop iteration, at any depth. Freeing one
    /// used iteration there gives the allocator back blocks of the very
    /// sizes the next iteration asks for, from its per-thread cache; a
    /// part freed at once (hundreds of iterations) overflows that cache
    /// into the slower shared bins.
    fn recycler(&mut self) -> Option<Box<dyn FnMut()>> {
        None
    }
}

impl<F: FnMut(Vec<Item>, &[String])> Sink for F {
    fn part(&mut self, items: Vec<Item>, known: &[String]) {
        self(items, known)
    }
}

/// As [`evaluate_in_parts`], also giving the top-level `let`s and their
/// values (functions are not values and are left out).
pub fn evaluate_in_parts_bound(
    program: &Program,
    transfer: Transfer,
    options: &Options,
    sink: impl FnMut(Vec<Item>, &[String]),
) -> (Vec<Error>, Vec<TopLevel>) {
    evaluate_into(program, transfer, options, sink)
}

/// As [`evaluate_in_parts_bound`], into any [`Sink`].
pub fn evaluate_into<S: Sink>(
    program: &Program,
    transfer: Transfer,
    options: &Options,
    mut sink: S,
) -> (Vec<Error>, Vec<TopLevel>) {
    let ex = Expander::new(program, transfer, options);
    *ex.recycle.borrow_mut() = sink.recycler();
    let root = Scope::root();
    root.bind(
        "clock",
        Binding::Value(Some(Value::Number(options.clock))),
        None,
    );
    root.bind(
        "frame",
        Binding::Value(Some(Value::Number(options.frame))),
        None,
    );
    let mut errors = Vec::new();
    // Statements never straddle a `let`, `fn`, `for` or `if`: those are
    // where a part may end.
    let boundary = |i: &Item| {
        matches!(
            i,
            Item::Let { .. }
                | Item::LetItems { .. }
                | Item::Fn(_)
                | Item::For { .. }
                | Item::If { .. }
        )
    };
    let items = &program.items;
    let mut start = 0;
    while start < items.len() {
        let mut end = start + 1;
        if !boundary(&items[start]) {
            while end < items.len() && !boundary(&items[end]) {
                end += 1;
            }
        }
        if let Item::For {
            var,
            source,
            body,
            span,
        } = &items[start]
        {
            // A top-level loop hands its objects over every few thousand
            // evaluation steps: counting iterations alone would hold a
            // whole nested loop's objects per iteration (an outer loop of
            // 400 around an inner one of 250 kept 64,000 spheres' items
            // alive at once), and steps grow with what was made.
            let mut pending = Vec::new();
            let mut flushed_at = ex.steps.get();
            let mut emit = |it: Item| {
                pending.push(it);
                let steps = ex.steps.get();
                if pending.len() >= PART_ITEMS || steps - flushed_at >= PART_STEPS {
                    flushed_at = steps;
                    // The next part starts at full size rather than
                    // growing (and copying) from nothing.
                    let part = std::mem::replace(&mut pending, Vec::with_capacity(PART_ITEMS));
                    sink.part(part, &ex.known.borrow());
                }
            };
            if ex.step(items[start].span(), &mut errors) {
                ex.for_loop(var, source, body, *span, &root, &mut emit, &mut errors);
            }
            if !pending.is_empty() {
                sink.part(pending, &ex.known.borrow());
            }
            start = end;
            continue;
        }
        let mut out = Vec::new();
        ex.expand(&items[start..end], &root, true, &mut out, &mut errors);
        if !out.is_empty() {
            sink.part(out, &ex.known.borrow());
        }
        start = end;
    }
    let used = ex.used_defines.borrow();
    for (name, _) in &options.defines {
        if !used.contains(name) {
            let lets: Vec<String> = program
                .items
                .iter()
                .filter_map(|i| match i {
                    Item::Let { name, .. } => Some(name.node.clone()),
                    _ => None,
                })
                .collect();
            let help = did_you_mean(name, lets.iter().map(String::as_str))
                .unwrap_or_else(|| "`-D` replaces the value of a top-level `let`".into());
            errors.push(
                Error::new(
                    Span::new(program.root, 0, 0),
                    format!("`-D {name}`: the scene has no top-level `let {name}`"),
                )
                .label("nothing to replace")
                .help(help),
            );
        }
    }
    let bound = root
        .vars
        .borrow()
        .iter()
        .filter_map(|(name, b, span)| match (b, span) {
            (Binding::Value(v), Some(span)) => Some(TopLevel {
                name: name.to_string(),
                span: *span,
                value: v.clone(),
            }),
            _ => None,
        })
        .collect();
    (errors, bound)
}

/// Parses and evaluates the value of `-D NAME=VALUE` (a number, vector,
/// colour or list with no names but built-ins).
pub fn define_value(text: &str) -> Result<Value, String> {
    use crate::lang::ast::FileId;
    let src = format!("let v = {text}");
    let bad = || format!("`{text}` is not a value (write e.g. `2`, `<1, 2, 3>` or `rgb(1, 0, 0)`)");
    let items = crate::lang::parser::parse(&src, FileId(0)).map_err(|_| bad())?;
    let [Item::Let { value, .. }] = items.as_slice() else {
        return Err(bad());
    };
    let env = expr::Env::new(Transfer::Srgb);
    let mut errors = Vec::new();
    env.eval(value, &mut errors)
        .ok_or_else(|| match errors.first() {
            Some(e) => format!("`{text}`: {}", e.message),
            None => bad(),
        })
}

#[cfg(test)]
#[path = "entry_tests.rs"]
mod tests;

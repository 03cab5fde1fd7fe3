//! Stage 2, EVALUATE: the parser's items → items the builder can read
//! without knowing the language: every `let`, `fn`, `for` and `if` is
//! gone, bound names carry their values ([`ExprKind::Bound`]), closed
//! expressions are worked out ([`ExprKind::Value`]), loops are unrolled and
//! calls expanded in place. Spans are kept, so later errors still point at
//! the characters; items made by a loop iteration or a call are wrapped in
//! [`Item::Traced`] so the builder can say which iteration or call.
//!
//! ```text
//! let spoke = cylinder { radius 0.05  height 2 }     // a value made of items
//! fn pillar(h, r = 0.3) { cylinder { radius r  height h } }
//! fn bell(t) = exp(-t * t)
//! for i in 0..12 { spoke { rotate z i * 30 } }       // a placement, shared
//! if frame % 2 == 0 { pillar(1.5, r: 0.2) { translate <1, 0, 0> } }
//! ```
//!
//! Runaway programs stop at [`Limits`], each named in its message.

mod budget;
mod builtins;
mod calls;
mod entry;
mod fast;
pub use entry::{
    Evaluated, Limits, Options, Sink, TopLevel, define_value, evaluate, evaluate_in_parts,
    evaluate_in_parts_bound, evaluate_into,
};
pub mod colours;
pub mod expr;
mod loops;
mod scope;
use scope::{Binding, Scope};
mod trace;
use trace::Frame;
pub use trace::{LoopSite, Trace, TraceRef, trail};

use crate::lang::Program;
use crate::lang::ast::{Block, Expr, ExprKind, FnBody, FnDef, ForSource, Item, Span, Spanned};
use crate::lang::diagnostics::{Error, did_you_mean};
use crate::scene::Transfer;
use expr::{Fragment, Names, Value};
use std::cell::{Cell, RefCell};
use std::rc::Rc;
use std::sync::Arc;

// ---- the expander ----

struct Expander<'p> {
    program: &'p Program,
    transfer: Transfer,
    options: &'p Options,
    steps: Cell<u64>,
    objects: Cell<u64>,
    depth: Cell<usize>,
    /// Set once a limit is hit: everything after is skipped.
    stopped: Cell<bool>,
    /// The loop iteration or call being evaluated (innermost), if any.
    context: RefCell<Option<TraceRef>>,
    known: RefCell<Vec<String>>,
    used_defines: RefCell<Vec<String>>,
    /// Called after every loop iteration, at any depth (see
    /// [`Sink::recycler`]).
    recycle: RefCell<Option<Box<dyn FnMut()>>>,
}

/// Names as seen from one scope.
struct At<'a, 'p> {
    ex: &'a Expander<'p>,
    scope: &'a Rc<Scope>,
    /// Set for a trial evaluation ([`Expander::closed_value`]): marked
    /// instead of reporting an unknown name, and where the trial gives up.
    trial: Option<&'a Cell<bool>>,
}

impl At<'_, '_> {
    /// In a trial, marks it given up and says so.
    fn abandon(&self) -> bool {
        self.trial.inspect(|t| t.set(true)).is_some()
    }

    /// The number `name` stands for, when it is bound to one or is `pi`
    /// (what [`expr::eval`] would give it): the fast path's lookup.
    fn number(&self, name: &str) -> Option<f64> {
        match self.scope.with(name, |b| match b {
            Binding::Value(Some(Value::Number(x))) => Some(*x),
            _ => None,
        }) {
            Some(x) => x,
            None => (name == "pi").then_some(std::f64::consts::PI),
        }
    }
}

impl Names for At<'_, '_> {
    fn transfer(&self) -> Transfer {
        self.ex.transfer
    }

    fn lookup(&self, name: &str) -> Option<Option<Value>> {
        // The value alone is copied out, not the binding.
        self.scope
            .with(name, |b| match b {
                // A number (a loop's variable) without Value's clone.
                Binding::Value(Some(Value::Number(x))) => Some(Some(Value::Number(*x))),
                Binding::Value(v) => Some(v.clone()),
                Binding::Function(..) => None,
            })
            .flatten()
    }

    fn binds(&self, name: &str) -> bool {
        self.scope
            .with(name, |b| matches!(b, Binding::Value(_)))
            .unwrap_or(false)
    }

    fn call(&self, call: &Expr, errors: &mut Vec<Error>) -> Option<Option<Value>> {
        let ExprKind::Call { name, named, .. } = &call.kind else {
            return None;
        };
        // A trial stops before a user function (whose arguments are read
        // there) and before a call with named arguments (a built-in reads
        // none of them): whether such a call is closed is for `is_closed`.
        if self.trial.is_some() {
            if !named.is_empty() || self.scope.with(&name.node, |_| ()).is_some() {
                self.abandon();
                return Some(None);
            }
            return None;
        }
        match self.scope.get(&name.node) {
            Some(Binding::Function(def, home)) => {
                Some(self.ex.call_value(&def, &home, call, self.scope, errors))
            }
            Some(Binding::Value(v)) => {
                let what = v.map_or("a value".to_string(), |v| v.kind());
                errors.push(
                    Error::new(
                        name.span,
                        format!("`{}` is {what}, not a function", name.node),
                    )
                    .label("cannot be called"),
                );
                Some(None)
            }
            None => None,
        }
    }

    fn unknown(&self, n: &str, span: Span, errors: &mut Vec<Error>) {
        if self.abandon() {
            // Not closed: the name is left for the builder.
            return;
        }
        let mut err = Error::new(span, format!("unknown name `{n}`")).label("not defined");
        let later = self.ex.program.items.iter().find_map(|i| match i {
            Item::Let { name, .. } | Item::LetItems { name, .. } if name.node == n => {
                Some(name.span)
            }
            _ => None,
        });
        if let Some(def) = later {
            err = err
                .help(format!(
                    "`{n}` is defined later; a constant can only be used after its `let`"
                ))
                .note(def, "defined here");
        } else {
            let names = self.scope.names();
            let all = names
                .iter()
                .map(String::as_str)
                .chain(["pi"])
                .chain(colours::COLOURS.iter().map(|(c, _)| *c));
            err = err.maybe_help(did_you_mean(n, all));
        }
        errors.push(err);
    }

    fn step(&self, span: Span, errors: &mut Vec<Error>) -> bool {
        self.ex.step(span, errors)
    }

    fn give_up(&self) -> bool {
        self.abandon()
    }

    fn functions(&self) -> Vec<String> {
        self.scope
            .names()
            .into_iter()
            .filter(|n| matches!(self.scope.get(n), Some(Binding::Function(..))))
            .collect()
    }
}

impl<'p> Expander<'p> {
    /// An expander with nothing counted yet.
    fn new(program: &'p Program, transfer: Transfer, options: &'p Options) -> Self {
        Expander {
            program,
            transfer,
            options,
            steps: Cell::new(0),
            objects: Cell::new(0),
            depth: Cell::new(0),
            stopped: Cell::new(false),
            context: RefCell::new(None),
            known: RefCell::new(Vec::new()),
            used_defines: RefCell::new(Vec::new()),
            recycle: RefCell::new(None),
        }
    }

    /// A loop iteration has handed over its items.
    fn iterated(&self) {
        if let Some(f) = self.recycle.borrow_mut().as_mut() {
            f();
        }
    }

    fn at<'a>(&'a self, scope: &'a Rc<Scope>) -> At<'a, 'p> {
        At {
            ex: self,
            scope,
            trial: None,
        }
    }

    /// Adds the loop iterations and calls the error is inside.
    fn traced(&self, mut e: Error) -> Error {
        let Some(t) = self.context.borrow().clone() else {
            return e;
        };
        let lines = t.lines(&self.program.sources);
        if e.help
            .as_deref()
            .is_some_and(|h| h.contains(lines[0].as_str()))
        {
            return e;
        }
        let trail = trail(&lines);
        e.help = Some(match e.help {
            Some(h) => format!("{h}\n{trail}"),
            None => trail,
        });
        e
    }

    /// Enters a loop iteration or call (for messages); returns the trace
    /// that items made inside carry.
    fn push(&self, frame: Frame) -> Arc<Trace> {
        let t = Arc::new(Trace {
            frame,
            parent: self.current(),
        });
        *self.context.borrow_mut() = Some(TraceRef::Shared(t.clone()));
        t
    }

    /// The trace being evaluated in, as a shared frame (a loop iteration's
    /// is made now, and kept for whatever else nests in it).
    fn current(&self) -> Option<Arc<Trace>> {
        let mut ctx = self.context.borrow_mut();
        let t = ctx.as_ref()?.shared();
        *ctx = Some(TraceRef::Shared(t.clone()));
        Some(t)
    }

    /// Starts a loop: the site its iterations share.
    fn loop_site(&self, var: Arc<str>, at: Span) -> Arc<LoopSite> {
        Arc::new(LoopSite {
            var,
            at,
            parent: self.current(),
        })
    }

    /// Enters an iteration of the loop at `site`; returns the trace that
    /// items made inside carry.
    fn push_iteration(&self, site: &Arc<LoopSite>, value: Value) -> TraceRef {
        let t = TraceRef::Iteration(site.clone(), value);
        *self.context.borrow_mut() = Some(t.clone());
        t
    }

    fn pop(&self) {
        let mut ctx = self.context.borrow_mut();
        *ctx = ctx
            .as_ref()
            .and_then(TraceRef::parent)
            .map(TraceRef::Shared);
    }

    fn remember(&self, name: &str) {
        let mut k = self.known.borrow_mut();
        if !k.iter().any(|n| n == name) {
            k.push(name.to_string());
        }
    }

    /// Checks a new name for the current scope; false (reported) when it
    /// may not be bound.
    fn may_bind(&self, name: &Spanned<String>, scope: &Rc<Scope>, errors: &mut Vec<Error>) -> bool {
        if expr::is_reserved(&name.node) {
            errors.push(
                Error::new(name.span, format!("`{}` is a built-in name", name.node))
                    .label("cannot be redefined")
                    .help("choose another name for the constant"),
            );
            return false;
        }
        if let Some(first) = scope.here(&name.node) {
            let mut e = Error::new(name.span, format!("`{}` is already defined", name.node))
                .label("defined again here")
                .help("a constant can only be defined once");
            if let Some(f) = first {
                e = e.note(f, "first defined here");
            }
            errors.push(e);
            return false;
        }
        self.remember(&name.node);
        true
    }

    /// Expands `items` in `scope`, appending to `out`.
    fn expand(
        &self,
        items: &[Item],
        scope: &Rc<Scope>,
        top: bool,
        out: &mut Vec<Item>,
        errors: &mut Vec<Error>,
    ) {
        let mut i = 0;
        while i < items.len() {
            if self.stopped.get() {
                return;
            }
            let item = &items[i];
            i += 1;
            if !self.step_item(item, errors) {
                return;
            }
            match item {
                Item::Let { name, value, .. } => {
                    if !self.may_bind(name, scope, errors) {
                        continue;
                    }
                    let define = top
                        .then(|| self.options.defines.iter().find(|(n, _)| *n == name.node))
                        .flatten();
                    let v = match define {
                        Some((n, v)) => {
                            self.used_defines.borrow_mut().push(n.clone());
                            Some(v.clone())
                        }
                        None => self.value(value, scope, errors),
                    };
                    scope.bind(name.node.as_str(), Binding::Value(v), Some(name.span));
                }
                Item::LetItems {
                    name, items: body, ..
                } => {
                    if !self.may_bind(name, scope, errors) {
                        continue;
                    }
                    let mut made = Vec::new();
                    let before = errors.len();
                    self.expand(body, &scope.child(), false, &mut made, errors);
                    let v = (errors.len() == before).then(|| {
                        Value::Items(Arc::new(Fragment {
                            items: made,
                            span: name.span,
                        }))
                    });
                    scope.bind(name.node.as_str(), Binding::Value(v), Some(name.span));
                }
                Item::Fn(def) => {
                    if !self.may_bind(&def.name, scope, errors) {
                        continue;
                    }
                    for p in &def.params {
                        self.remember(&p.name.node);
                    }
                    scope.bind(
                        def.name.node.as_str(),
                        Binding::Function(def.clone(), scope.clone()),
                        Some(def.name.span),
                    );
                }
                Item::For {
                    var,
                    source,
                    body,
                    span,
                } => self.for_loop(
                    var,
                    source,
                    body,
                    *span,
                    scope,
                    &mut |it| out.push(it),
                    errors,
                ),
                Item::If {
                    cond,
                    then,
                    otherwise,
                    ..
                } => {
                    let mut branch = Some(item);
                    let mut chosen: Option<&Block> = None;
                    let _ = (cond, then, otherwise);
                    while let Some(Item::If {
                        cond,
                        then,
                        otherwise,
                        ..
                    }) = branch
                    {
                        match expr::condition(&self.at(scope), cond, errors) {
                            Some(true) => {
                                chosen = Some(then);
                                break;
                            }
                            Some(false) => match otherwise.as_deref() {
                                Some(Item::Block(b)) => {
                                    chosen = Some(b);
                                    break;
                                }
                                other => branch = other,
                            },
                            None => break,
                        }
                    }
                    if let Some(b) = chosen {
                        self.expand(&b.items, &scope.child(), false, out, errors);
                    }
                }
                Item::Block(b) => {
                    let mut inner = Vec::with_capacity(b.items.len());
                    self.expand(&b.items, &block_scope(scope, b), false, &mut inner, errors);
                    out.push(Item::Block(Block {
                        items: inner,
                        span: b.span,
                    }));
                }
                Item::Str {
                    text,
                    span,
                    content,
                    ..
                } => {
                    let implicit =
                        i >= 2 && items[i - 2].as_name().is_some_and(|n| n.node == "implicit");
                    out.push(Item::Str {
                        text: text.clone(),
                        span: *span,
                        content: *content,
                        constants: implicit.then(|| Arc::new(scope.numbers())),
                    });
                }
                Item::List(l) => {
                    let node = l
                        .node
                        .iter()
                        .map(|e| self.resolve(e, scope, errors))
                        .collect();
                    out.push(Item::List(Spanned::new(node, l.span)));
                }
                Item::Value(e) => {
                    let next_block = match items.get(i) {
                        Some(Item::Block(b)) => Some(b),
                        _ => None,
                    };
                    match self.value_item(e, next_block, scope, out, errors) {
                        Placed::UsedBlock => i += 1,
                        Placed::Done => {}
                    }
                }
                Item::Include { .. } | Item::Traced { .. } => out.push(item.clone()),
            }
        }
    }

    /// A name or expression among items: a placement of an object value or
    /// a call of an object function (taking the block after it), or a value.
    fn value_item(
        &self,
        e: &Expr,
        next_block: Option<&Block>,
        scope: &Rc<Scope>,
        out: &mut Vec<Item>,
        errors: &mut Vec<Error>,
    ) -> Placed {
        match &e.kind {
            ExprKind::Name(n) => match scope.get(n) {
                Some(Binding::Value(Some(Value::Items(frag))))
                    if next_block.is_some()
                        || !after_name(out)
                        || !crate::scene::is_object(frag.head()) =>
                {
                    if !self.count_object(e.span, errors) {
                        return Placed::Done;
                    }
                    if crate::scene::is_object(frag.head()) {
                        // Built once by the builder, shared by every
                        // placement: the value, then the placement's block
                        // (empty when none is written).
                        let mut placement = Vec::new();
                        let span = match next_block {
                            Some(b) => {
                                self.expand(
                                    &b.items,
                                    &block_scope(scope, b),
                                    false,
                                    &mut placement,
                                    errors,
                                );
                                b.span
                            }
                            None => e.span,
                        };
                        out.push(Item::Value(Expr {
                            kind: ExprKind::Bound(n.clone(), Some(Value::Items(frag.clone()))),
                            span: e.span,
                        }));
                        out.push(Item::Block(Block {
                            items: placement,
                            span,
                        }));
                        return if next_block.is_some() {
                            Placed::UsedBlock
                        } else {
                            Placed::Done
                        };
                    }
                    return self.place(
                        e.span,
                        &frag.items,
                        !frag.is_material() && crate::scene::is_object(frag.head()),
                        next_block,
                        scope,
                        out,
                        errors,
                        &frag,
                    );
                }
                Some(Binding::Value(v)) => {
                    out.push(Item::Value(Expr {
                        kind: ExprKind::Bound(n.clone(), v),
                        span: e.span,
                    }));
                    return Placed::Done;
                }
                Some(Binding::Function(def, _)) => {
                    errors.push(
                        self.traced(
                            Error::new(e.span, format!("`{n}` is a function"))
                                .label("not called")
                                .help(format!(
                                    "call it with its arguments: `{n}({})`",
                                    def.params
                                        .iter()
                                        .map(|p| p.name.node.as_str())
                                        .collect::<Vec<_>>()
                                        .join(", ")
                                )),
                        ),
                    );
                    return Placed::Done;
                }
                None => {
                    if crate::scene::is_object(n) && !self.count_object(e.span, errors) {
                        return Placed::Done;
                    }
                    // A keyword of the builder's (`sphere`, `radius`): as
                    // written, without looking it up a second time.
                    out.push(Item::Value(e.clone()));
                    return Placed::Done;
                }
            },
            ExprKind::Call { name, .. } => {
                if let Some(Binding::Function(def, home)) = scope.get(&name.node)
                    && let FnBody::Items(_) = def.body
                {
                    if !self.count_object(e.span, errors) {
                        return Placed::Done;
                    }
                    let made = self.call_items(&def, &home, e, scope, errors);
                    let Some(made) = made else {
                        // Reported; the block after the call goes with it.
                        return if next_block.is_some() {
                            Placed::UsedBlock
                        } else {
                            Placed::Done
                        };
                    };
                    let frag = Fragment {
                        items: made,
                        span: e.span,
                    };
                    return self.place(
                        e.span,
                        &frag.items,
                        true,
                        next_block,
                        scope,
                        out,
                        errors,
                        &frag,
                    );
                }
            }
            _ => {}
        }
        let value = self.resolve(e, scope, errors);
        if matches!(&value.kind, ExprKind::Bound(n, None) if n.is_empty()) && !after_name(out) {
            // A statement-level value that failed (reported): drop it, and
            // the block of a failed call with it, rather than have the
            // builder report "expected a statement" as well.
            let call = matches!(e.kind, ExprKind::Call { .. });
            return if call && next_block.is_some() {
                Placed::UsedBlock
            } else {
                Placed::Done
            };
        }
        out.push(Item::Value(value));
        Placed::Done
    }

    /// Puts an object value (or a call's objects) where it is used; with a
    /// block after it, inside a `group` that takes the block's transforms
    /// and material.
    #[allow(clippy::too_many_arguments)]
    fn place(
        &self,
        at: Span,
        items: &[Item],
        object: bool,
        next_block: Option<&Block>,
        scope: &Rc<Scope>,
        out: &mut Vec<Item>,
        errors: &mut Vec<Error>,
        frag: &Fragment,
    ) -> Placed {
        if let Some(b) = next_block.filter(|_| object) {
            let mut inner = items.to_vec();
            self.expand(&b.items, &block_scope(scope, b), false, &mut inner, errors);
            out.push(Item::Value(Expr {
                kind: ExprKind::Name("group".into()),
                span: at,
            }));
            out.push(Item::Block(Block {
                items: inner,
                span: b.span,
            }));
            return Placed::UsedBlock;
        }
        if frag.is_material() && items.len() == 2 {
            // `material m` where `let m = material { … }`: the block.
            out.push(items[1].clone());
        } else {
            out.extend(items.iter().cloned());
        }
        Placed::Done
    }

    /// Evaluates an expression that must give a value now (`let`, a loop's
    /// range, an argument).
    fn value(&self, e: &Expr, scope: &Rc<Scope>, errors: &mut Vec<Error>) -> Option<Value> {
        let before = errors.len();
        let v = expr::eval(&self.at(scope), e, errors);
        for err in &mut errors[before..] {
            *err = self.traced(err.clone());
        }
        v
    }

    /// `e` worked out, as [`Expander::value`] would, when it is closed
    /// ([`expr::is_closed`]) — found by evaluating it, not by a walk first
    /// (a loop's `centre <…>` and `rgb(…)`, each of 100,000 spheres, were
    /// walked twice). `None`, with the steps, errors and stop it caused
    /// undone, when it names something unbound, reaches a part a trial
    /// cannot judge (a user function, named arguments, `and`/`or`) or
    /// stops at a limit; then
    /// the caller asks `is_closed`. A closed expression's evaluation sees
    /// every name `is_closed` looks at, so the two agree.
    fn closed_value(
        &self,
        e: &Expr,
        scope: &Rc<Scope>,
        errors: &mut Vec<Error>,
    ) -> Option<ExprKind> {
        let open = Cell::new(false);
        let at = At {
            ex: self,
            scope,
            trial: Some(&open),
        };
        let (steps, stopped, before) = (self.steps.get(), self.stopped.get(), errors.len());
        let v = expr::eval(&at, e, errors);
        // A trial that ran out of steps (or was cancelled) did not see all
        // of `e`: it is undone too, and the limit met again as before.
        if open.get() || (self.stopped.get() && !stopped) {
            self.steps.set(steps);
            self.stopped.set(stopped);
            errors.truncate(before);
            return None;
        }
        for err in &mut errors[before..] {
            *err = self.traced(err.clone());
        }
        Some(match v {
            Some(v) => ExprKind::Value(v),
            None => ExprKind::Bound("".into(), None),
        })
    }

    /// An expression among items: worked out when everything it names is
    /// known here, otherwise its bound names are filled in and the rest is
    /// left to the builder (which knows its keywords and materials).
    fn resolve(&self, e: &Expr, scope: &Rc<Scope>, errors: &mut Vec<Error>) -> Expr {
        let at = self.at(scope);
        // Literals and bare names need no working out (a bare name may be a
        // keyword of the builder's); test that first, it is the common case.
        let simple = matches!(
            e.kind,
            ExprKind::Number(_) | ExprKind::Hex(_) | ExprKind::Name(_)
        );
        if !simple && let Some(v) = fast::value(&at, e) {
            return Expr {
                kind: ExprKind::Value(v),
                span: e.span,
            };
        }
        if !simple && let Some(kind) = self.closed_value(e, scope, errors) {
            return Expr { kind, span: e.span };
        }
        if !simple && expr::is_closed(&at, e) {
            let v = self.value(e, scope, errors);
            return Expr {
                kind: match v {
                    Some(v) => ExprKind::Value(v),
                    None => ExprKind::Bound("".into(), None),
                },
                span: e.span,
            };
        }
        let kind = match &e.kind {
            ExprKind::Name(n) => match scope.get(n) {
                Some(Binding::Value(v)) => ExprKind::Bound(n.clone(), v),
                _ => e.kind.clone(),
            },
            ExprKind::Vector(v) => {
                ExprKind::Vector(v.iter().map(|p| self.resolve(p, scope, errors)).collect())
            }
            ExprKind::List(v) => {
                ExprKind::List(v.iter().map(|p| self.resolve(p, scope, errors)).collect())
            }
            ExprKind::Call { name, args, named } => ExprKind::Call {
                name: name.clone(),
                args: args
                    .iter()
                    .map(|p| self.resolve(p, scope, errors))
                    .collect(),
                named: named
                    .iter()
                    .map(|(n, p)| (n.clone(), self.resolve(p, scope, errors)))
                    .collect(),
            },
            ExprKind::Neg(x) => ExprKind::Neg(Box::new(self.resolve(x, scope, errors))),
            ExprKind::Not(x) => ExprKind::Not(Box::new(self.resolve(x, scope, errors))),
            ExprKind::Binary { op, lhs, rhs } => ExprKind::Binary {
                op: *op,
                lhs: Box::new(self.resolve(lhs, scope, errors)),
                rhs: Box::new(self.resolve(rhs, scope, errors)),
            },
            ExprKind::Index { base, index } => ExprKind::Index {
                base: Box::new(self.resolve(base, scope, errors)),
                index: Box::new(self.resolve(index, scope, errors)),
            },
            k => k.clone(),
        };
        Expr { kind, span: e.span }
    }
}

/// The scope for a block's items: a child of `scope` when the block binds
/// names of its own (`let`, `fn`), otherwise `scope` itself. A block that
/// binds nothing sees exactly the same names either way, and an object's
/// block (two per sphere in a 100,000-sphere loop) then costs no scope.
fn block_scope(scope: &Rc<Scope>, b: &Block) -> Rc<Scope> {
    let binds = b
        .items
        .iter()
        .any(|i| matches!(i, Item::Let { .. } | Item::LetItems { .. } | Item::Fn(_)));
    if binds { scope.child() } else { scope.clone() }
}

/// Whether the last item made is a name or string, so that what follows is
/// its value (`radius b`) rather than a statement of its own.
fn after_name(out: &[Item]) -> bool {
    matches!(out.last(), Some(i) if i.as_name().is_some() || matches!(i, Item::Str { .. }))
}

enum Placed {
    /// The block after the name was taken (a placement).
    UsedBlock,
    Done,
}

#[cfg(test)]
mod tests;

//! `for NAME in A..B` / `A..=B` / `step` / lists: each iteration expanded
//! in a scope of its own, under the step and object budgets, traced so
//! that an error inside says which iteration.

use super::*;

impl Expander<'_> {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn for_loop(
        &self,
        var: &Spanned<String>,
        source: &ForSource,
        body: &Block,
        span: Span,
        scope: &Rc<Scope>,
        out: &mut dyn FnMut(Item),
        errors: &mut Vec<Error>,
    ) {
        if expr::is_reserved(&var.node) && !matches!(var.node.as_str(), "x" | "y" | "z") {
            errors.push(
                self.traced(
                    Error::new(var.span, format!("`{}` is a built-in name", var.node))
                        .label("cannot be a loop variable")
                        .help("choose another name"),
                ),
            );
            return;
        }
        self.remember(&var.node);
        let limit = self.options.limits.iterations;
        let too_many = |n: f64, at: Span| {
            Error::new(
                at,
                format!("this loop would run {n} times; the limit is {limit}"),
            )
            .label("too many iterations")
            .help("raise the limit with `--max-iterations N` if this is meant")
        };
        let values: Vec<Value> = match source {
            ForSource::Range {
                from,
                to,
                inclusive,
                step,
            } => {
                let num = |e: &Expr, errors: &mut Vec<Error>| match self.value(e, scope, errors)? {
                    Value::Number(v) => Some(v),
                    other => {
                        errors.push(
                            self.traced(
                                Error::new(
                                    e.span,
                                    format!("a range needs numbers, found {}", other.kind()),
                                )
                                .label(format!("this is {}", other.kind())),
                            ),
                        );
                        None
                    }
                };
                let a = num(from, errors);
                let b = num(to, errors);
                let s = match step {
                    Some(s) => num(s, errors),
                    None => Some(1.0),
                };
                let (Some(a), Some(b), Some(s)) = (a, b, s) else {
                    return;
                };
                if s == 0.0 {
                    let at = step.as_ref().map_or(span, |e| e.span);
                    errors.push(self.traced(
                        Error::new(at, "a loop's step cannot be 0").label("step 0 never ends"),
                    ));
                    return;
                }
                // Counted in whole steps, each value a + k·s, so a long
                // loop does not drift.
                let span_len = (b - a) / s;
                let n = if span_len < 0.0 {
                    0.0
                } else {
                    let whole = span_len.floor();
                    if *inclusive || whole < span_len {
                        whole + 1.0
                    } else {
                        whole
                    }
                };
                if n > limit as f64 {
                    errors.push(self.traced(too_many(n, from.span.to(to.span))));
                    return;
                }
                (0..n as u64)
                    .map(|k| Value::Number(a + k as f64 * s))
                    .collect()
            }
            ForSource::Each(e) => match self.value(e, scope, errors) {
                Some(Value::List(l)) => {
                    if l.len() as u64 > limit {
                        errors.push(self.traced(too_many(l.len() as f64, e.span)));
                        return;
                    }
                    l.as_ref().clone()
                }
                Some(other) => {
                    errors.push(
                        self.traced(
                            Error::new(e.span, format!("cannot loop over {}", other.kind()))
                                .label(format!("this is {}", other.kind()))
                                .help("loop over a range `0..n` or a list `[a, b, c]`"),
                        ),
                    );
                    return;
                }
                None => return,
            },
        };
        // One copy of the name for every iteration's scope and trace.
        let name: Arc<str> = Arc::from(var.node.as_str());
        let site = self.loop_site(name.clone(), span);
        let mut inner = scope.child();
        for v in values {
            if self.stopped.get() {
                return;
            }
            // The last iteration's scope is emptied and used again when
            // nothing kept it (a `fn` declared in the body keeps it): the
            // same as a new one, without two allocations an iteration.
            if Rc::strong_count(&inner) == 1 && Rc::weak_count(&inner) == 0 {
                inner.vars.borrow_mut().clear();
            } else {
                inner = scope.child();
            }
            let trace = self.push_iteration(&site, v.clone());
            inner.bind(name.clone(), Binding::Value(Some(v)), Some(var.span));
            let before = errors.len();
            let mut made = Vec::with_capacity(body.items.len());
            self.expand(&body.items, &inner, false, &mut made, errors);
            self.pop();
            if !made.is_empty() {
                out(Item::Traced { trace, items: made });
            }
            self.iterated();
            if errors.len() > before {
                // One report for a mistake, not one per iteration.
                return;
            }
        }
    }
}

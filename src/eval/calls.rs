//! Calls of `fn`s: arguments bound to parameters (positional, named,
//! defaulted), the recursion depth limit, and the two kinds of body: an
//! expression (a value) and items (objects placed where called).

use super::*;

impl Expander<'_> {
    /// Binds a call's arguments to the function's parameters in a new
    /// scope inside the function's own; `None` when they do not fit
    /// (reported).
    pub(super) fn bind_args(
        &self,
        def: &FnDef,
        home: &Rc<Scope>,
        call: &Expr,
        caller: &Rc<Scope>,
        errors: &mut Vec<Error>,
    ) -> Option<(Rc<Scope>, Frame)> {
        let ExprKind::Call { name, args, named } = &call.kind else {
            return None;
        };
        let before = errors.len();
        let mut given: Vec<Option<Value>> = vec![None; def.params.len()];
        let mut ok = true;
        if args.len() > def.params.len() {
            errors.push(
                self.traced(
                    Error::new(
                        args[def.params.len()].span,
                        format!(
                            "`{}` takes {} argument{}, not {}",
                            name.node,
                            def.params.len(),
                            if def.params.len() == 1 { "" } else { "s" },
                            args.len()
                        ),
                    )
                    .label("one too many")
                    .note(def.name.span, "declared here"),
                ),
            );
            return None;
        }
        for (k, a) in args.iter().enumerate() {
            match self.value(a, caller, errors) {
                Some(v) => given[k] = Some(v),
                None => ok = false,
            }
        }
        for (n, a) in named {
            let Some(k) = def.params.iter().position(|p| p.name.node == n.node) else {
                let names = def.params.iter().map(|p| p.name.node.as_str());
                errors.push(
                    self.traced(
                        Error::new(
                            n.span,
                            format!("`{}` has no parameter `{}`", name.node, n.node),
                        )
                        .label("unknown parameter")
                        .help(did_you_mean(&n.node, names).unwrap_or_else(|| {
                            format!(
                                "its parameters are {}",
                                def.params
                                    .iter()
                                    .map(|p| format!("`{}`", p.name.node))
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            )
                        }))
                        .note(def.name.span, "declared here"),
                    ),
                );
                ok = false;
                continue;
            };
            if given[k].is_some() || k < args.len() {
                errors.push(
                    self.traced(
                        Error::new(n.span, format!("`{}` is given twice", n.node))
                            .label("given again")
                            .help("give each parameter once, by position or by name"),
                    ),
                );
                ok = false;
                continue;
            }
            match self.value(a, caller, errors) {
                Some(v) => given[k] = Some(v),
                None => ok = false,
            }
        }
        if !ok || errors.len() > before {
            return None;
        }
        let scope = home.child();
        let mut shown = Vec::new();
        for (p, v) in def.params.iter().zip(given) {
            let v = match (v, &p.default) {
                (Some(v), _) => v,
                (None, Some(d)) => self.value(d, &scope, errors)?,
                (None, None) => {
                    errors.push(
                        self.traced(
                            Error::new(
                                call.span,
                                format!("`{}` needs `{}`", name.node, p.name.node),
                            )
                            .label(format!("no `{}` given", p.name.node))
                            .note(p.name.span, "declared here without a default"),
                        ),
                    );
                    return None;
                }
            };
            shown.push((p.name.node.clone(), v.clone()));
            scope.bind(
                p.name.node.as_str(),
                Binding::Value(Some(v)),
                Some(p.name.span),
            );
        }
        Some((
            scope,
            Frame::Call {
                name: name.node.clone(),
                at: call.span,
                args: shown,
            },
        ))
    }

    pub(super) fn enter(&self, call: &Expr, errors: &mut Vec<Error>) -> bool {
        let d = self.depth.get() + 1;
        if d > self.options.limits.depth {
            self.stop(
                errors,
                Error::new(
                    call.span,
                    format!(
                        "function calls nest more than {} deep",
                        self.options.limits.depth
                    ),
                )
                .label("one call too deep")
                .help("a recursive function needs a case that stops it; raise the limit with `--max-recursion N` if this is meant"),
            );
            return false;
        }
        self.depth.set(d);
        true
    }

    /// A call of a function of numbers (`fn bell(t) = …`).
    pub(super) fn call_value(
        &self,
        def: &FnDef,
        home: &Rc<Scope>,
        call: &Expr,
        caller: &Rc<Scope>,
        errors: &mut Vec<Error>,
    ) -> Option<Value> {
        let FnBody::Expr(body) = &def.body else {
            errors.push(
                self.traced(
                    Error::new(
                        call.span,
                        format!("`{}` makes objects, not a value", def.name.node),
                    )
                    .label("used as a value")
                    .help("place it among objects: `name(…) { translate … }`")
                    .note(def.name.span, "declared here"),
                ),
            );
            return None;
        };
        let (scope, line) = self.bind_args(def, home, call, caller, errors)?;
        if !self.enter(call, errors) {
            return None;
        }
        self.push(line);
        let v = self.value(body, &scope, errors);
        self.pop();
        self.depth.set(self.depth.get() - 1);
        v
    }

    /// A call of a function of objects: its items, wrapped to say which call.
    pub(super) fn call_items(
        &self,
        def: &FnDef,
        home: &Rc<Scope>,
        call: &Expr,
        caller: &Rc<Scope>,
        errors: &mut Vec<Error>,
    ) -> Option<Vec<Item>> {
        let FnBody::Items(body) = &def.body else {
            return None;
        };
        let (scope, line) = self.bind_args(def, home, call, caller, errors)?;
        if !self.enter(call, errors) {
            return None;
        }
        let trace = self.push(line);
        let mut made = Vec::new();
        self.expand(&body.items, &scope, false, &mut made, errors);
        self.pop();
        self.depth.set(self.depth.get() - 1);
        Some(vec![Item::Traced {
            trace: TraceRef::Shared(trace),
            items: made,
        }])
    }
}

//! Names in blocks: each block (file, loop iteration, call) binds its own,
//! lookups go outwards, and a function keeps the scope it was declared in.

use super::*;

#[derive(Clone)]
pub(super) enum Binding {
    /// `None` when its definition failed (already reported).
    Value(Option<Value>),
    /// A function and the scope it was declared in.
    Function(Arc<FnDef>, Rc<Scope>),
}

/// A name, what it is bound to and where (none for built-ins).
pub(super) type Bound = (Arc<str>, Binding, Option<Span>);

/// One block's names; lookups go outwards. A block binds few names, so a
/// list searched from the end is cheaper than a hash map (a loop makes one
/// scope per iteration).
pub(super) struct Scope {
    /// Names are shared strings: a loop binds its variable once per
    /// iteration, and a shared name costs no allocation each time.
    pub(super) vars: RefCell<Vec<Bound>>,
    pub(super) parent: Option<Rc<Scope>>,
}

impl Scope {
    pub(super) fn root() -> Rc<Scope> {
        Rc::new(Scope {
            vars: RefCell::new(Vec::new()),
            parent: None,
        })
    }

    pub(super) fn child(self: &Rc<Scope>) -> Rc<Scope> {
        Rc::new(Scope {
            vars: RefCell::new(Vec::new()),
            parent: Some(self.clone()),
        })
    }

    pub(super) fn bind(&self, name: impl Into<Arc<str>>, b: Binding, span: Option<Span>) {
        self.vars.borrow_mut().push((name.into(), b, span));
    }

    pub(super) fn get(&self, name: &str) -> Option<Binding> {
        self.with(name, Binding::clone)
    }

    /// `f` of the innermost binding of `name`, if there is one: what a
    /// caller wants to know of it without copying it out.
    pub(super) fn with<R>(&self, name: &str, f: impl FnOnce(&Binding) -> R) -> Option<R> {
        let mut s = Some(self);
        while let Some(scope) = s {
            if let Some((_, b, _)) = scope
                .vars
                .borrow()
                .iter()
                .rev()
                .find(|(n, ..)| **n == *name)
            {
                return Some(f(b));
            }
            s = scope.parent.as_deref();
        }
        None
    }

    /// Where `name` was bound in this very scope, if it was.
    pub(super) fn here(&self, name: &str) -> Option<Option<Span>> {
        self.vars
            .borrow()
            .iter()
            .find(|(n, ..)| **n == *name)
            .map(|(.., s)| *s)
    }

    /// Every name visible here (for suggestions).
    pub(super) fn names(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .vars
            .borrow()
            .iter()
            .map(|(n, ..)| n.to_string())
            .collect();
        if let Some(p) = &self.parent {
            v.extend(p.names());
        }
        v
    }

    /// The numbers visible here, for `implicit` equations (not `x`, `y`,
    /// `z`: those are the equation's variables).
    pub(super) fn numbers(&self) -> Vec<(String, f64)> {
        let mut out: Vec<(String, f64)> = Vec::new();
        let mut s = Some(self);
        while let Some(scope) = s {
            for (k, b, _) in scope.vars.borrow().iter() {
                if let Binding::Value(Some(Value::Number(v))) = b
                    && !matches!(&**k, "x" | "y" | "z")
                    && !out.iter().any(|(n, _)| **n == **k)
                {
                    out.push((k.to_string(), *v));
                }
            }
            s = scope.parent.as_deref();
        }
        out
    }
}

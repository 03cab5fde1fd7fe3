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
    /// Two bits of every name bound so far in any scope of this tree
    /// ([`filter_bits`]): a name whose bits are not all set is bound
    /// nowhere, and its lookup ends without walking the scopes. Most
    /// names looked up are the builder's keywords (`sphere`, `centre`,
    /// `rgb`, ten of them for each sphere a loop makes), which nothing
    /// binds. Shared by the whole tree, so it only ever gains bits.
    seen: Rc<Cell<u64>>,
}

/// Two of 64 bits for a name, from its length and its first and last
/// bytes (a cheap hash: a false "maybe bound" only costs the walk).
#[inline(always)]
fn filter_bits(name: &str) -> u64 {
    let b = name.as_bytes();
    let (first, last) = match (b.first(), b.last()) {
        (Some(&f), Some(&l)) => (f as u32, l as u32),
        _ => (0, 0),
    };
    let h = (b.len() as u32)
        .wrapping_mul(0x9e37_79b9)
        .wrapping_add(first.wrapping_mul(0x85eb_ca6b))
        .wrapping_add(last.wrapping_mul(0xc2b2_ae35));
    (1u64 << (h >> 26)) | (1u64 << ((h >> 20) & 63))
}

impl Scope {
    pub(super) fn root() -> Rc<Scope> {
        Rc::new(Scope {
            vars: RefCell::new(Vec::new()),
            parent: None,
            seen: Rc::new(Cell::new(0)),
        })
    }

    pub(super) fn child(self: &Rc<Scope>) -> Rc<Scope> {
        Rc::new(Scope {
            vars: RefCell::new(Vec::new()),
            parent: Some(self.clone()),
            seen: self.seen.clone(),
        })
    }

    pub(super) fn bind(&self, name: impl Into<Arc<str>>, b: Binding, span: Option<Span>) {
        let name = name.into();
        self.seen.set(self.seen.get() | filter_bits(&name));
        self.vars.borrow_mut().push((name, b, span));
    }

    #[inline]
    pub(super) fn get(&self, name: &str) -> Option<Binding> {
        if !self.may_bind(name) {
            return None;
        }
        self.with(name, Binding::clone)
    }

    /// False when `name` is bound in no scope of this tree (the filter):
    /// a keyword's lookup then ends here, inlined where it is asked.
    #[inline(always)]
    pub(super) fn may_bind(&self, name: &str) -> bool {
        let bits = filter_bits(name);
        self.seen.get() & bits == bits
    }

    /// `f` of the innermost binding of `name`, if there is one: what a
    /// caller wants to know of it without copying it out.
    pub(super) fn with<R>(&self, name: &str, f: impl FnOnce(&Binding) -> R) -> Option<R> {
        if !self.may_bind(name) {
            return None;
        }
        let mut s = Some(self);
        while let Some(scope) = s {
            if let Some((_, b, _)) = scope
                .vars
                .borrow()
                .iter()
                .rev()
                .find(|(n, ..)| crate::lang::ast::same_name(n, name))
            {
                return Some(f(b));
            }
            s = scope.parent.as_deref();
        }
        None
    }

    /// Where `name` was bound in this very scope, if it was.
    pub(super) fn here(&self, name: &str) -> Option<Option<Span>> {
        if !self.may_bind(name) {
            return None;
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn number(s: &Scope, name: &str) -> Option<f64> {
        match s.get(name)? {
            Binding::Value(Some(Value::Number(x))) => Some(x),
            _ => None,
        }
    }

    #[test]
    fn lookups_find_every_binding_the_filter_has_seen_from_any_scope() {
        let root = Scope::root();
        let child = root.child();
        let grandchild = child.child();
        // Bound after the children were made, in the outer scope: the
        // children share the filter, so they still find it.
        root.bind("late", Binding::Value(Some(Value::Number(1.0))), None);
        child.bind("i", Binding::Value(Some(Value::Number(2.0))), None);
        assert_eq!(number(&grandchild, "late"), Some(1.0));
        assert_eq!(number(&grandchild, "i"), Some(2.0));
        assert_eq!(number(&root, "i"), None, "not seen from outside");
        // Names the filter may confuse with bound ones (same length and
        // ends) are still told apart by the walk.
        assert_eq!(number(&grandchild, "lxte"), None);
        assert_eq!(number(&grandchild, "j"), None);
        assert!(grandchild.here("i").is_none() && child.here("i").is_some());
        // Many names: every one still found (the filter only ever gains bits).
        let names: Vec<String> = (0..200).map(|k| format!("n{k}")).collect();
        for (k, n) in names.iter().enumerate() {
            grandchild.bind(
                n.as_str(),
                Binding::Value(Some(Value::Number(k as f64))),
                None,
            );
        }
        for (k, n) in names.iter().enumerate() {
            assert_eq!(number(&grandchild, n), Some(k as f64));
        }
        assert_eq!(number(&grandchild, "sphere"), None);
    }

    fn span(start: usize) -> Option<Span> {
        Some(Span {
            file: crate::lang::ast::FileId(0),
            start,
            end: start + 1,
        })
    }

    #[test]
    fn the_innermost_and_latest_binding_wins_and_lists_see_outwards() {
        let _watchdog = crate::watchdog::start();
        let num = |v: f64| Binding::Value(Some(Value::Number(v)));
        let root = Scope::root();
        root.bind("a", num(1.0), span(1));
        root.bind("b", num(2.0), span(2));
        root.bind("x", num(9.0), span(3));
        root.bind("c", Binding::Value(Some(Value::Bool(true))), span(4));
        root.bind("d", Binding::Value(None), span(5));
        let child = root.child();
        child.bind("a", num(10.0), span(6));
        child.bind("e", num(3.0), span(7));
        child.bind("y", num(8.0), span(9));
        assert_eq!(number(&child, "a"), Some(10.0), "the inner `a`");
        assert_eq!(number(&root, "a"), Some(1.0), "the outer one is kept");
        assert_eq!(number(&child, "b"), Some(2.0), "found outwards");
        assert_eq!(number(&child, "e"), Some(3.0));
        assert_eq!(child.with("e", |_| 7), Some(7));
        assert_eq!(child.with("nowhere", |_| 7), None);
        // `here`: only this scope, and where the name was first bound.
        assert_eq!(child.here("a"), Some(span(6)));
        assert_eq!(child.here("e"), Some(span(7)));
        assert_eq!(child.here("x"), None, "bound outside");
        assert_eq!(child.here("b"), None);
        assert_eq!(root.here("b"), Some(span(2)));
        assert_eq!(root.here("e"), None);
        // Every visible name, this scope's first.
        assert_eq!(child.names(), ["a", "e", "y", "a", "b", "x", "c", "d"]);
        assert_eq!(root.names(), ["a", "b", "x", "c", "d"]);
        // The numbers, innermost first and each name once, without the
        // equations' variables or what is not a number.
        assert_eq!(
            child.numbers(),
            [
                ("a".to_string(), 10.0),
                ("e".to_string(), 3.0),
                ("b".to_string(), 2.0)
            ]
        );
        // The evaluator binds a name once per scope (`is already
        // defined`); the scope itself still answers with the later one.
        let other = root.child();
        other.bind("f", num(3.0), None);
        other.bind("f", num(4.0), None);
        assert_eq!(number(&other, "f"), Some(4.0));
    }
}

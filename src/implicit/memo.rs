//! Equations already compiled in this process, so that twenty objects with
//! the same degree-40 equation expand it once (issue 17: they took 19.7×
//! as long to load as one). An equation is known by its text and the
//! values of the constants it names; only successes are kept, and the
//! cache is bounded.

use super::Equation;
use super::parse::{Expr, Node, Parsed};
use std::collections::HashMap;
use std::sync::Mutex;

/// The most equations kept; past it the cache starts again (a scene with
/// more distinct equations compiles each as before).
const CAPACITY: usize = 256;

/// The text and each name it uses with its value's bits (or none, for x,
/// y, z and unknown names, which then fail to compile and are not kept).
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub struct Key {
    text: String,
    constants: Vec<(String, Option<u64>)>,
}

static CACHE: Mutex<Option<HashMap<Key, Equation>>> = Mutex::new(None);

impl Key {
    pub fn new(text: &str, parsed: &Parsed, constant: &dyn Fn(&str) -> Option<f64>) -> Key {
        let mut names = Vec::new();
        // An explicit stack: the tree's depth is bounded, but this needs
        // no recursion to stay safe.
        let mut stack: Vec<&Expr> = [Some(&parsed.lhs), parsed.rhs.as_ref()]
            .into_iter()
            .flatten()
            .collect();
        while let Some(e) = stack.pop() {
            match &e.node {
                Node::Num(_) => {}
                Node::Name(n) => names.push(n.clone()),
                Node::Neg(a) => stack.push(a),
                Node::Sum(v) | Node::Product(v) => stack.extend(v.iter().map(|(_, a)| a)),
                Node::Pow(a, b) | Node::Root(a, b) => stack.extend([&**a, &**b]),
            }
        }
        names.sort();
        names.dedup();
        let constants = names
            .into_iter()
            .map(|n| {
                let v = constant(&n).map(f64::to_bits);
                (n, v)
            })
            .collect();
        Key {
            text: text.to_owned(),
            constants,
        }
    }
}

pub fn get(key: &Key) -> Option<Equation> {
    let cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    cache.as_ref()?.get(key).cloned()
}

pub fn put(key: Key, eq: &Equation) {
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    let map = cache.get_or_insert_with(HashMap::new);
    if map.len() >= CAPACITY {
        map.clear();
    }
    map.insert(key, eq.clone());
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(text: &str, r: f64) -> Key {
        let parsed = super::super::parse::parse(text).unwrap();
        Key::new(text, &parsed, &|n| (n == "R").then_some(r))
    }

    #[test]
    fn an_equation_is_compiled_once_per_text_and_constants() {
        // A text no other test uses, so parallel tests cannot fill it.
        let text = "x^2 + y^2 + z^2 - R^2 + 0.000123";
        let consts = |r: f64| move |n: &str| (n == "R").then_some(r);
        assert!(get(&key(text, 2.0)).is_none());
        let a = Equation::compile(text, &consts(2.0)).unwrap();
        let cached = get(&key(text, 2.0)).expect("kept after the first compile");
        assert_eq!(cached.terms, a.terms);
        // Another value of R is another equation.
        assert!(get(&key(text, 3.0)).is_none());
        let b = Equation::compile(text, &consts(3.0)).unwrap();
        assert_ne!(b.terms, a.terms);
        // Failures are not kept: an unknown name fails each time.
        let bad = "x^2 + Q + 0.000123";
        assert!(Equation::compile(bad, &consts(2.0)).is_err());
        let parsed = super::super::parse::parse(bad).unwrap();
        assert!(get(&Key::new(bad, &parsed, &consts(2.0))).is_none());
    }
}

//! Equation text → a small expression tree with byte spans (no meaning yet:
//! names are not resolved, exponents not checked). The grammar is
//! `grammar/equation.pest`; this is the only place that walks its pairs.

use super::EquationError;
use crate::lang::grammar::{RtParser, Rule};
use pest::Parser;
use pest::iterators::Pair;
use std::ops::Range;

/// Parentheses nested deeper than this are refused before pest sees them:
/// both pest and the tree walkers recurse, and a stack overflow would abort
/// the process instead of reporting an error.
pub const MAX_NESTING: usize = 64;

/// How deep the expression tree may be. Parentheses are capped above, but
/// `^` and `_` chain without them (`(x)_1_1_1…`), and every later stage
/// (expansion, and the branch test that runs in the render workers' small
/// stacks) walks the tree recursively: the bound is checked here, at load,
/// so nothing after this can recurse deeper.
pub const MAX_TREE_DEPTH: usize = 256;

#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub node: Node,
    pub span: Range<usize>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    Num(f64),
    /// `x`, `y`, `z` or a constant's name.
    Name(String),
    Neg(Box<Expr>),
    /// Terms with their signs (`true` = subtracted).
    Sum(Vec<(bool, Expr)>),
    /// Factors with their operation (`true` = divided by).
    Product(Vec<(bool, Expr)>),
    Pow(Box<Expr>, Box<Expr>),
    Root(Box<Expr>, Box<Expr>),
}

/// The parsed equation: `lhs` or `lhs = rhs`.
#[derive(Clone, Debug)]
pub struct Parsed {
    pub lhs: Expr,
    pub rhs: Option<Expr>,
}

pub fn parse(text: &str) -> Result<Parsed, Vec<EquationError>> {
    check_nesting(text)?;
    let mut pairs = RtParser::parse(Rule::equation, text).map_err(|e| vec![pest_error(e)])?;
    let eq = pairs.next().expect("the entry rule yields one pair");
    check_chains(eq.clone())?;
    let mut sides = Vec::new();
    let mut errors = Vec::new();
    for p in eq.into_inner() {
        if p.as_rule() == Rule::eq_side {
            let span = p.as_span().start()..p.as_span().end();
            match p.into_inner().next() {
                Some(sum) => sides.push(Some(sum_expr(sum))),
                None => {
                    errors.push(EquationError {
                        span,
                        message: "empty equation".into(),
                        help: Some(
                            "write an expression in x, y and z, e.g. \"x^2 + y^2 + z^2 - 1\""
                                .into(),
                        ),
                    });
                    sides.push(None);
                }
            }
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    for side in sides.iter().flatten() {
        check_depth(side)?;
    }
    let mut sides = sides.into_iter().flatten();
    let lhs = sides.next().expect("the grammar always has a left side");
    Ok(Parsed {
        lhs,
        rhs: sides.next(),
    })
}

/// Checks the parentheses before pest sees them: nesting is capped (pest
/// and the tree walkers recurse), and an unmatched one is reported as
/// such, where it is, rather than as whatever pest expected next.
fn check_nesting(text: &str) -> Result<(), Vec<EquationError>> {
    let one = |span: Range<usize>, message: String, help: &str| {
        Err(vec![EquationError {
            span,
            message,
            help: Some(help.into()),
        }])
    };
    let mut open = Vec::new();
    for (i, c) in text.char_indices() {
        match c {
            '(' => {
                open.push(i);
                if open.len() > MAX_NESTING {
                    return one(
                        i..i + 1,
                        format!("parentheses nested more than {MAX_NESTING} deep"),
                        "write the equation with fewer nested parentheses",
                    );
                }
            }
            ')' if open.pop().is_none() => {
                return one(
                    i..i + 1,
                    "this `)` closes nothing".into(),
                    "remove it, or add the `(` it should close",
                );
            }
            _ => {}
        }
    }
    match open.pop() {
        Some(i) => one(
            i..i + 1,
            "this `(` is never closed: a `)` is missing".into(),
            "add the `)` where the parenthesised part ends",
        ),
        None => Ok(()),
    }
}

/// Refuses a run of more than [`MAX_NESTING`] `^`/`_` on one base before the
/// tree is built (building one recurses once per operator when a unary
/// minus is pushed down to the base). pest's `flatten` walks the pairs
/// without recursion.
fn check_chains(eq: Pair<Rule>) -> Result<(), Vec<EquationError>> {
    for p in eq.into_inner().flatten() {
        if p.as_rule() == Rule::eq_power
            && let Some(op) = p.into_inner().nth(MAX_NESTING + 1)
        {
            let s = op.as_span();
            return Err(vec![EquationError {
                span: s.start()..s.end(),
                message: format!("more than {MAX_NESTING} `^` or `_` in a row"),
                help: Some("write the power or root once, with its combined index".into()),
            }]);
        }
    }
    Ok(())
}

/// The tree's depth, measured with an explicit stack (no recursion), must
/// stay within [`MAX_TREE_DEPTH`].
fn check_depth(root: &Expr) -> Result<(), Vec<EquationError>> {
    let mut stack = vec![(root, 1usize)];
    while let Some((e, d)) = stack.pop() {
        if d > MAX_TREE_DEPTH {
            return Err(vec![EquationError {
                span: e.span.clone(),
                message: format!("this equation nests more than {MAX_TREE_DEPTH} operations deep"),
                help: Some("split it into fewer nested powers, roots and parentheses".into()),
            }]);
        }
        match &e.node {
            Node::Num(_) | Node::Name(_) => {}
            Node::Neg(a) => stack.push((a, d + 1)),
            Node::Sum(v) | Node::Product(v) => stack.extend(v.iter().map(|(_, a)| (a, d + 1))),
            Node::Pow(a, b) | Node::Root(a, b) => {
                stack.push((a, d + 1));
                stack.push((b, d + 1));
            }
        }
    }
    Ok(())
}

fn pest_error(e: pest::error::Error<Rule>) -> EquationError {
    let e = e.renamed_rules(|r| {
        match r {
            Rule::eq_addop => "`+` or `-`",
            Rule::eq_mulop => "`*` or `/`",
            Rule::eq_equals => "`=`",
            Rule::eq_neg => "`-`",
            Rule::eq_pow => "`^`",
            Rule::eq_root => "`_`",
            Rule::eq_postfix => "`^` or `_`",
            Rule::eq_sum | Rule::eq_term | Rule::eq_side => "an expression",
            Rule::eq_number => "a number",
            Rule::eq_name => "a name",
            Rule::eq_paren | Rule::eq_atom | Rule::eq_power | Rule::eq_factor => {
                "a number, a name or `(`"
            }
            Rule::eq_index => "an integer",
            Rule::EOI => "the end of the equation",
            // Every rule is named above; a new one reads as a value.
            _ => "a value",
        }
        .to_string()
    });
    let span = match e.location {
        pest::error::InputLocation::Pos(p) => p..p,
        pest::error::InputLocation::Span((a, b)) => a..b,
    };
    EquationError {
        span,
        message: e.variant.message().into_owned(),
        help: None,
    }
}

/// The pair's span without the whitespace pest may leave at its end.
fn span_of(p: &Pair<Rule>) -> Range<usize> {
    let start = p.as_span().start();
    start..start + p.as_str().trim_end().len()
}

fn sum_expr(p: Pair<Rule>) -> Expr {
    let span = span_of(&p);
    let mut terms = Vec::new();
    let mut minus = false;
    for q in p.into_inner() {
        match q.as_rule() {
            Rule::eq_addop => minus = q.as_str() == "-",
            _ => {
                terms.push((minus, term_expr(q)));
                minus = false;
            }
        }
    }
    if terms.len() == 1 && !terms[0].0 {
        return terms.pop().expect("one term").1;
    }
    Expr {
        node: Node::Sum(terms),
        span,
    }
}

fn term_expr(p: Pair<Rule>) -> Expr {
    let span = span_of(&p);
    let mut factors = Vec::new();
    let mut divide = false;
    for q in p.into_inner() {
        match q.as_rule() {
            Rule::eq_mulop => divide = q.as_str() == "/",
            Rule::eq_factor => {
                factors.push((divide, factor_expr(q)));
                divide = false;
            }
            _ => factors.push((false, power_expr(q))),
        }
    }
    if factors.len() == 1 {
        return factors.pop().expect("one factor").1;
    }
    Expr {
        node: Node::Product(factors),
        span,
    }
}

fn factor_expr(p: Pair<Rule>) -> Expr {
    let span = span_of(&p);
    let mut negs = 0;
    let mut inner = None;
    for q in p.into_inner() {
        match q.as_rule() {
            Rule::eq_neg => negs += 1,
            _ => inner = Some(power_expr(q)),
        }
    }
    let inner = inner.expect("a factor has a power");
    negate(inner, negs, span)
}

/// Unary minus applies to the atom before any `^` or `_` (`-x^2` is
/// `(-x)^2`), so negations are pushed down onto the power's base.
fn negate(e: Expr, negs: usize, span: Range<usize>) -> Expr {
    if negs.is_multiple_of(2) {
        return Expr { node: e.node, span };
    }
    match e.node {
        Node::Pow(b, i) => {
            let bs = span.start..b.span.end;
            Expr {
                node: Node::Pow(Box::new(negate(*b, 1, bs)), i),
                span,
            }
        }
        Node::Root(b, i) => {
            let bs = span.start..b.span.end;
            Expr {
                node: Node::Root(Box::new(negate(*b, 1, bs)), i),
                span,
            }
        }
        node => Expr {
            node: Node::Neg(Box::new(Expr { node, span: e.span })),
            span,
        },
    }
}

fn power_expr(p: Pair<Rule>) -> Expr {
    let mut it = p.into_inner();
    let mut e = atom_expr(it.next().expect("a power has an atom"));
    for post in it {
        let span = e.span.start..span_of(&post).end;
        let op = post.into_inner().next().expect("a postfix has an operator");
        let is_root = op.as_rule() == Rule::eq_root;
        let index = index_expr(op.into_inner().next().expect("an operator has an index"));
        e = Expr {
            node: if is_root {
                Node::Root(Box::new(e), Box::new(index))
            } else {
                Node::Pow(Box::new(e), Box::new(index))
            },
            span,
        };
    }
    e
}

fn index_expr(p: Pair<Rule>) -> Expr {
    let span = span_of(&p);
    let mut neg = false;
    let mut inner = None;
    for q in p.into_inner() {
        match q.as_rule() {
            Rule::eq_neg => neg = true,
            _ => inner = Some(atom_expr(q)),
        }
    }
    let inner = inner.expect("an index has a value");
    if neg {
        Expr {
            node: Node::Neg(Box::new(inner)),
            span,
        }
    } else {
        inner
    }
}

fn atom_expr(p: Pair<Rule>) -> Expr {
    let p = if p.as_rule() == Rule::eq_atom {
        p.into_inner().next().expect("an atom has content")
    } else {
        p
    };
    let span = span_of(&p);
    match p.as_rule() {
        Rule::eq_number => Expr {
            // The grammar only admits digits with one optional point, which
            // always parses (very long ones round or become infinite, which
            // the compiler reports).
            node: Node::Num(p.as_str().parse().unwrap_or(f64::INFINITY)),
            span,
        },
        Rule::eq_name => Expr {
            node: Node::Name(p.as_str().to_string()),
            span,
        },
        Rule::eq_paren => {
            let inner = sum_expr(p.into_inner().next().expect("parentheses hold a sum"));
            Expr {
                node: inner.node,
                span,
            }
        }
        r => unreachable!("atom rule {r:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn show(e: &Expr) -> String {
        match &e.node {
            Node::Num(v) => format!("{v}"),
            Node::Name(n) => n.clone(),
            Node::Neg(a) => format!("(-{})", show(a)),
            Node::Sum(ts) => {
                let s: Vec<_> = ts
                    .iter()
                    .map(|(m, t)| format!("{}{}", if *m { "-" } else { "+" }, show(t)))
                    .collect();
                format!("[{}]", s.join(" "))
            }
            Node::Product(fs) => {
                let s: Vec<_> = fs
                    .iter()
                    .map(|(d, t)| format!("{}{}", if *d { "/" } else { "*" }, show(t)))
                    .collect();
                format!("{{{}}}", s.join(" "))
            }
            Node::Pow(a, b) => format!("{}^{}", show(a), show(b)),
            Node::Root(a, b) => format!("{}_{}", show(a), show(b)),
        }
    }

    fn p(s: &str) -> String {
        show(&parse(s).unwrap().lhs)
    }

    #[test]
    fn unary_minus_binds_tightest() {
        assert_eq!(p("-x^2"), "(-x)^2");
        assert_eq!(p("- -x"), "x");
        assert_eq!(p("2 -x"), "[+2 -x]");
        assert_eq!(p("2*-x^2"), "{*2 *(-x)^2}");
    }

    #[test]
    fn juxtaposition() {
        assert_eq!(p("2x^2"), "{*2 *x^2}");
        assert_eq!(p("x^2z^2"), "{*x^2 *z^2}");
        assert_eq!(p("6x y z"), "{*6 *x *y *z}");
        assert_eq!(p("(x-2)^2(x+2)^2"), "{*[+x -2]^2 *[+x +2]^2}");
        assert_eq!(p("4R^2(x^2+y^2)"), "{*4 *R^2 *[+x^2 +y^2]}");
        assert_eq!(p("xy"), "xy");
        assert_eq!(p("x/2/y"), "{*x /2 /y}");
    }

    #[test]
    fn roots_and_rhs() {
        assert_eq!(p("(x^2 + y^2)_2"), "[+x^2 +y^2]_2");
        let e = parse("x^2 = 1").unwrap();
        assert_eq!(show(&e.rhs.unwrap()), "1");
    }

    #[test]
    fn spans_are_bytes_in_the_text() {
        let e = parse("1 + foo").unwrap().lhs;
        let Node::Sum(ts) = e.node else { panic!() };
        assert_eq!(ts[1].1.span, 4..7);
    }

    #[test]
    fn errors() {
        assert_eq!(parse("").unwrap_err()[0].message, "empty equation");
        assert_eq!(parse("  = x").unwrap_err()[0].message, "empty equation");
        let e = parse("x + * 2").unwrap_err();
        assert_eq!(e[0].span.start, 4);
        assert!(parse(&"(".repeat(100_000)).is_err());
    }

    /// Issue 17: an unmatched `(` gave a message naming the internal rule
    /// `eq_postfix` and did not say the `)` was missing.
    #[test]
    fn unmatched_parentheses_say_so() {
        let e = parse("x^2 + (y^2 - 1").unwrap_err();
        assert!(e[0].message.contains("`)` is missing"), "{}", e[0].message);
        assert_eq!(e[0].span, 6..7);
        let e = parse("x + 1) * 2").unwrap_err();
        assert!(e[0].message.contains("closes nothing"), "{}", e[0].message);
        assert_eq!(e[0].span, 5..6);
        // No error message anywhere names a grammar rule.
        for bad in [
            "x +", "(x", "x^", "x_", "2 3 ^", "x = = y", "x @ y", "^", ")(",
        ] {
            for e in parse(bad).unwrap_err() {
                assert!(!e.message.contains("eq_"), "{bad}: {}", e.message);
            }
        }
    }

    /// Issue 17: 18,000 chained roots passed `--check` and then overflowed
    /// a render worker's stack. Long chains are refused at parse time, and
    /// any tree deeper than the bound is refused before it is expanded.
    #[test]
    fn chained_roots_and_powers_are_refused_not_a_crash() {
        for op in ["_1", "^1"] {
            let text = format!("(x){}", op.repeat(18_000));
            let e = parse(&text).unwrap_err();
            assert!(e[0].message.contains("in a row"), "{}", e[0].message);
            assert_eq!(e[0].span.start, 3 + 2 * MAX_NESTING);
            let neg = format!("-x{}", op.repeat(18_000));
            assert!(parse(&neg).is_err());
        }
        // The limit itself is accepted.
        assert!(parse(&format!("(x){}", "^1".repeat(MAX_NESTING))).is_ok());
        // Parentheses within the nesting cap, each holding a chain within
        // the chain cap, still add up past the tree bound.
        let mut deep = "x".to_string();
        for _ in 0..40 {
            deep = format!("({deep}){}", "^1".repeat(10));
        }
        let e = parse(&deep).unwrap_err();
        assert!(e[0].message.contains("nests more than"), "{}", e[0].message);
    }
}

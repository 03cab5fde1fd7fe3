//! Text → items. Three steps: a bracket pass (so that an unclosed `{` is
//! reported where it was opened, and nesting is capped before the
//! recursive-descent parser could overflow the stack), pest, then pest's
//! pairs → [`ast`](super::ast) with precedence climbing for expressions.
//! pest's errors are reworded here: no rule name reaches the user.

use super::ast::*;
use super::diagnostics::Error;
use super::grammar::{RtParser, Rule};
use pest::Parser;
use pest::iterators::Pair;
use pest::pratt_parser::{Assoc, Op, PrattParser};
use std::sync::LazyLock;

mod brackets;
mod errors;

pub use brackets::check_brackets;
pub use errors::describe_rule;
use errors::syntax_error;

/// How deeply brackets of any kind may nest. Far beyond any real scene, and
/// low enough that parsing and evaluation stay within a small thread stack.
pub const MAX_NESTING: usize = 64;

/// How deep one expression tree may be (chains of `^` and unary minus
/// recurse, and so does a long sum once it is a tree).
pub const MAX_EXPR_DEPTH: usize = 256;

/// The object kinds, written once: the list [`OBJECTS`] and the `match`
/// of [`is_object`] are made from it.
macro_rules! objects {
    ($($name:literal),+ $(,)?) => {
        /// The objects' keywords (the builder's kinds of object).
        pub const OBJECTS: &[&str] = &[$($name),+];

        /// Whether `name` is one of [`OBJECTS`]. A `match` rather than a
        /// search of the list: the evaluator asks it of every bare name it
        /// passes on (a loop-built sphere asks five times), and the
        /// compiler's dispatch on length and bytes takes a tenth of the
        /// list's string compares.
        pub fn is_object(name: &str) -> bool {
            matches!(name, $($name)|+)
        }
    };
}

objects![
    "sphere",
    "plane",
    "box",
    "cylinder",
    "cone",
    "disc",
    "triangle",
    "rectangle",
    "torus",
    "implicit",
    "mesh",
    "group",
    "union",
    "intersection",
    "difference",
];

/// The statement keywords other than the objects'.
const STATEMENTS: &[&str] = &[
    "camera",
    "render",
    "ambient",
    "light",
    "environment",
    "material",
    "let",
    "include",
    "for",
    "if",
    "fn",
];

/// Statement keywords: for the "did you mean to close … before …" hint,
/// and the builder's suggestions for an unknown statement ([`STATEMENTS`]
/// and then [`OBJECTS`]).
pub const STATEMENT_KEYWORDS: &[&str] =
    &concat::<{ STATEMENTS.len() + OBJECTS.len() }>(STATEMENTS, OBJECTS);

/// `a` and then `b`, at compile time (`N` their lengths' sum).
const fn concat<const N: usize>(a: &[&'static str], b: &[&'static str]) -> [&'static str; N] {
    let mut out = [""; N];
    let mut i = 0;
    while i < N {
        out[i] = if i < a.len() { a[i] } else { b[i - a.len()] };
        i += 1;
    }
    out
}

static PRATT: LazyLock<PrattParser<Rule>> = LazyLock::new(|| {
    // Later lines bind tighter: unary minus sits between `*` and `^`, so
    // `-2^2` is −4 and `2^-1` works.
    PrattParser::new()
        .op(Op::infix(Rule::add, Assoc::Left) | Op::infix(Rule::sub, Assoc::Left))
        .op(Op::infix(Rule::mul, Assoc::Left)
            | Op::infix(Rule::div, Assoc::Left)
            | Op::infix(Rule::rem, Assoc::Left))
        .op(Op::prefix(Rule::neg))
        .op(Op::infix(Rule::pow, Assoc::Right))
        .op(Op::postfix(Rule::index))
});

/// Conditions: `or` below `and` below `not` below the comparisons, each
/// side of which is an arithmetic expression (parsed with [`PRATT`]).
static CPRATT: LazyLock<PrattParser<Rule>> = LazyLock::new(|| {
    PrattParser::new()
        .op(Op::infix(Rule::or_op, Assoc::Left))
        .op(Op::infix(Rule::and_op, Assoc::Left))
        .op(Op::prefix(Rule::not_op))
        .op(Op::infix(Rule::eq, Assoc::Left)
            | Op::infix(Rule::ne, Assoc::Left)
            | Op::infix(Rule::lt, Assoc::Left)
            | Op::infix(Rule::le, Assoc::Left)
            | Op::infix(Rule::gt, Assoc::Left)
            | Op::infix(Rule::ge, Assoc::Left))
});

/// Parses one file's text into its items (includes not yet resolved).
pub fn parse(text: &str, file: FileId) -> Result<Vec<Item>, Vec<Error>> {
    let errors = check_brackets(text, file);
    if !errors.is_empty() {
        return Err(errors);
    }
    // One top-level item at a time: pest keeps every token of a parse in
    // memory, which for a whole file of 100k objects is hundreds of MB.
    let mut items = Vec::new();
    let mut errors = Vec::new();
    let mut pos = 0;
    loop {
        match step(text, pos, file) {
            Step::End => break,
            Step::Syntax(e) => {
                errors.push(e);
                break;
            }
            Step::Item(i, end) => {
                match i {
                    Ok(i) => items.push(i),
                    Err(e) => errors.push(e),
                }
                pos = end;
            }
        }
    }
    if errors.is_empty() {
        Ok(items)
    } else {
        Err(errors)
    }
}

/// What the parser finds at one place of a file's top level.
pub(super) enum Step {
    /// Only blank space and comments are left.
    End,
    /// A top-level item (or the mistake that turning it into an item
    /// found), and the byte offset in the file where it ends.
    Item(Result<Item, Error>, usize),
    /// The text does not parse here; the file's parse stops.
    Syntax(Error),
}

/// The top-level item of `text` that follows `pos` (after blank space and
/// comments). A file's parse is these steps from 0, each from where the
/// last ended, so a caller may run them from any item's start.
pub(super) fn step(text: &str, pos: usize, file: FileId) -> Step {
    let Some(rest) = text.get(pos..) else {
        return Step::End;
    };
    let at = Loc { file, offset: pos };
    let mut pairs = match RtParser::parse(Rule::next_item, rest) {
        Ok(p) => p,
        Err(first) => {
            // Tracking the tokens pest tried slows every parse; only a
            // failed one needs them, for "expected `,` or `>`".
            pest::set_error_detail(true);
            let detailed = RtParser::parse(Rule::next_item, rest).err();
            pest::set_error_detail(false);
            return Step::Syntax(syntax_error(detailed.unwrap_or(first), rest, at));
        }
    };
    let Some(p) = pairs.next().and_then(|top| top.into_inner().next()) else {
        return Step::End;
    };
    if p.as_rule() == Rule::EOI {
        return Step::End;
    }
    let end = p.as_span().end();
    Step::Item(item(p, at), pos + end.max(1))
}

/// Where a piece of text being parsed sits: its file, and the byte offset
/// of the parsed slice in it (top-level items are parsed one at a time).
#[derive(Clone, Copy, Debug)]
struct Loc {
    file: FileId,
    offset: usize,
}

impl Loc {
    fn span(&self, start: usize, end: usize) -> Span {
        Span::new(self.file, self.offset + start, self.offset + end)
    }
}

fn span_of(p: &Pair<Rule>, at: Loc) -> Span {
    let s = p.as_span();
    at.span(s.start(), s.end())
}

fn item(p: Pair<Rule>, at: Loc) -> Result<Item, Error> {
    let span = span_of(&p, at);
    Ok(match p.as_rule() {
        Rule::let_stmt => {
            let mut inner = p.into_inner();
            let _kw = inner.next();
            let name = inner.next().expect("grammar: let has a name");
            let value = inner.next().expect("grammar: let has a value");
            let name = Spanned::new(name.as_str().to_string(), span_of(&name, at));
            if value.as_rule() == Rule::fragment {
                let mut items = Vec::new();
                for c in value.into_inner() {
                    items.push(match c.as_rule() {
                        Rule::ident => Item::Value(Expr {
                            kind: ExprKind::Name(c.as_str().into()),
                            span: span_of(&c, at),
                        }),
                        _ => item(c, at)?,
                    });
                }
                Item::LetItems { name, items, span }
            } else {
                Item::Let {
                    name,
                    value: Box::new(expr(value, at)?),
                    span,
                }
            }
        }
        Rule::for_stmt => {
            let mut inner = p.into_inner();
            let _kw = inner.next();
            let var = inner.next().expect("grammar: for has a name");
            let _in = inner.next();
            let src = inner.next().expect("grammar: for has a source");
            let body = inner.next().expect("grammar: for has a body");
            let source = if src.as_rule() == Rule::range {
                let mut r = src.into_inner();
                let from = expr(r.next().expect("grammar: range start"), at)?;
                let inclusive = r.next().is_some_and(|o| o.as_rule() == Rule::range_incl);
                let to = expr(r.next().expect("grammar: range end"), at)?;
                let _step = r.next();
                let step = match r.next() {
                    Some(e) => Some(expr(e, at)?),
                    None => None,
                };
                ForSource::Range {
                    from,
                    to,
                    inclusive,
                    step,
                }
            } else {
                ForSource::Each(expr(src, at)?)
            };
            Item::For {
                var: Spanned::new(var.as_str().to_string(), span_of(&var, at)),
                source: Box::new(source),
                body: block(body, at)?,
                span,
            }
        }
        Rule::if_stmt => {
            let mut inner = p.into_inner();
            let _kw = inner.next();
            let cond = expr(inner.next().expect("grammar: if has a condition"), at)?;
            let then = block(inner.next().expect("grammar: if has a block"), at)?;
            let _else = inner.next();
            let otherwise = match inner.next() {
                Some(e) => Some(Box::new(item(e, at)?)),
                None => None,
            };
            Item::If {
                cond: Box::new(cond),
                then,
                otherwise,
                span,
            }
        }
        Rule::fn_stmt => {
            let mut inner = p.into_inner();
            let _kw = inner.next();
            let name = inner.next().expect("grammar: fn has a name");
            let name = Spanned::new(name.as_str().to_string(), span_of(&name, at));
            let mut params = Vec::new();
            let mut body = None;
            for c in inner {
                match c.as_rule() {
                    Rule::fn_param => {
                        let mut q = c.into_inner();
                        let n = q.next().expect("grammar: a parameter has a name");
                        let default = match q.next() {
                            Some(d) => Some(expr(d, at)?),
                            None => None,
                        };
                        params.push(FnParam {
                            name: Spanned::new(n.as_str().to_string(), span_of(&n, at)),
                            default,
                        });
                    }
                    Rule::fn_expr => {
                        let e = c.into_inner().next().expect("grammar: `=` has a value");
                        body = Some(FnBody::Expr(expr(e, at)?));
                    }
                    _ => body = Some(FnBody::Items(block(c, at)?)),
                }
            }
            Item::Fn(std::sync::Arc::new(FnDef {
                name,
                params,
                body: body.expect("grammar: fn has a body"),
                span,
            }))
        }
        Rule::include_stmt => {
            let s = p
                .into_inner()
                .nth(1)
                .expect("grammar: include has a string");
            let Item::Str {
                text,
                span: sspan,
                content,
                ..
            } = string(s, at)
            else {
                unreachable!()
            };
            Item::Include {
                text,
                span,
                content,
                string: sspan,
            }
        }
        Rule::block => Item::Block(block(p, at)?),
        Rule::list => {
            let mut v = Vec::new();
            for c in p.into_inner() {
                v.push(expr(c, at)?);
            }
            Item::List(Spanned::new(v, span))
        }
        Rule::string => string(p, at),
        Rule::expr => Item::Value(expr(p, at)?),
        r => unreachable!("grammar: unexpected item rule {r:?}"),
    })
}

fn block(p: Pair<Rule>, at: Loc) -> Result<Block, Error> {
    let span = span_of(&p, at);
    let mut items = Vec::new();
    for c in p.into_inner() {
        items.push(item(c, at)?);
    }
    Ok(Block { items, span })
}

fn string(p: Pair<Rule>, at: Loc) -> Item {
    let span = span_of(&p, at);
    let inner = p.into_inner().next().expect("grammar: string has content");
    Item::Str {
        text: inner.as_str().to_string(),
        span,
        content: span_of(&inner, at),
        constants: None,
    }
}

type Built = Result<(Expr, usize), Error>;

fn expr(p: Pair<Rule>, at: Loc) -> Result<Expr, Error> {
    expr_depth(p, at).map(|(e, _)| e)
}

fn expr_depth(p: Pair<Rule>, at: Loc) -> Built {
    if p.as_rule() == Rule::cexpr {
        return cexpr_depth(p, at);
    }
    // Each operator adds a level to the tree (a flat `1+1+…` is a chain as
    // long as the sum): cap the count before the Pratt parser runs, at the
    // operator that breaks it, so a 10 MB one-line sum costs one scan.
    let mut operators = p.clone().into_inner().filter(|c| {
        matches!(
            c.as_rule(),
            Rule::neg
                | Rule::add
                | Rule::sub
                | Rule::mul
                | Rule::div
                | Rule::pow
                | Rule::rem
                | Rule::index
        )
    });
    if let Some(op) = operators.nth(MAX_EXPR_DEPTH) {
        return Err(Error::new(
            span_of(&op, at),
            format!("this expression has more than {MAX_EXPR_DEPTH} operators"),
        )
        .label(format!("operator {}", MAX_EXPR_DEPTH + 1))
        .help("split it into parts with `let`"));
    }
    PRATT
        .map_primary(|p| primary(p, at))
        .map_prefix(|op, rhs| unary(ExprKind::Neg, span_of(&op, at), rhs?))
        .map_infix(|lhs, op, rhs| binary(bin_op(op.as_rule()), lhs?, rhs?))
        .map_postfix(|base, op| {
            let (base, db) = base?;
            let whole = span_of(&op, at);
            let inner = op
                .into_inner()
                .next()
                .expect("grammar: index holds a value");
            let (index, di) = expr_depth(inner, at)?;
            let span = base.span.to(whole);
            node(
                Expr {
                    kind: ExprKind::Index {
                        base: Box::new(base),
                        index: Box::new(index),
                    },
                    span,
                },
                db.max(di),
            )
        })
        .parse(p.into_inner())
}

fn cexpr_depth(p: Pair<Rule>, at: Loc) -> Built {
    CPRATT
        .map_primary(|p| expr_depth(p, at))
        .map_prefix(|op, rhs| unary(ExprKind::Not, span_of(&op, at), rhs?))
        .map_infix(|lhs, op, rhs| binary(bin_op(op.as_rule()), lhs?, rhs?))
        .parse(p.into_inner())
}

/// The operator a grammar rule stands for, in both precedence tables
/// (arithmetic and conditions).
fn bin_op(rule: Rule) -> BinOp {
    match rule {
        Rule::add => BinOp::Add,
        Rule::sub => BinOp::Sub,
        Rule::mul => BinOp::Mul,
        Rule::div => BinOp::Div,
        Rule::pow => BinOp::Pow,
        Rule::rem => BinOp::Rem,
        Rule::or_op => BinOp::Or,
        Rule::and_op => BinOp::And,
        Rule::eq => BinOp::Eq,
        Rule::ne => BinOp::Ne,
        Rule::lt => BinOp::Lt,
        Rule::le => BinOp::Le,
        Rule::gt => BinOp::Gt,
        Rule::ge => BinOp::Ge,
        r => unreachable!("grammar: unexpected operator {r:?}"),
    }
}

fn binary(op: BinOp, (lhs, dl): (Expr, usize), (rhs, dr): (Expr, usize)) -> Built {
    let span = lhs.span.to(rhs.span);
    node(
        Expr {
            kind: ExprKind::Binary {
                op,
                lhs: Box::new(lhs),
                rhs: Box::new(rhs),
            },
            span,
        },
        dl.max(dr),
    )
}

/// A prefix operator (`-x`, `not c`) spanning from the operator to its
/// operand's end.
fn unary(kind: fn(Box<Expr>) -> ExprKind, op: Span, (rhs, d): (Expr, usize)) -> Built {
    let span = op.to(rhs.span);
    node(
        Expr {
            kind: kind(Box::new(rhs)),
            span,
        },
        d,
    )
}

fn node(e: Expr, child_depth: usize) -> Built {
    if child_depth + 1 > MAX_EXPR_DEPTH {
        return Err(too_deep(e.span));
    }
    Ok((e, child_depth + 1))
}

fn too_deep(span: Span) -> Error {
    Error::new(span, "this expression is nested too deeply")
        .label("too deep")
        .help(format!(
            "an expression may nest at most {MAX_EXPR_DEPTH} operators deep; split it with `let`"
        ))
}

fn primary(p: Pair<Rule>, at: Loc) -> Built {
    let span = span_of(&p, at);
    match p.as_rule() {
        Rule::number => {
            let mut inner = p.into_inner();
            let body = inner.next().expect("grammar: number has a body");
            if let Some(tail) = inner.next() {
                let dot = tail.as_span().start();
                return Err(Error::new(
                    at.span(dot, dot + 1),
                    format!("`{}` is not a number", p_str(&body, &tail)),
                )
                .label("a second decimal point")
                .help("a number has at most one `.`; separate values with `,` or spaces"));
            }
            let v: f64 = body
                .as_str()
                .parse()
                .map_err(|_| Error::new(span, "this is not a number").label("not a number"))?;
            Ok((
                Expr {
                    kind: ExprKind::Number(v),
                    span,
                },
                1,
            ))
        }
        Rule::hex => {
            let digits = &p.as_str()[1..];
            let ok = digits.len() == 6 && digits.chars().all(|c| c.is_ascii_hexdigit());
            if !ok {
                return Err(
                    Error::new(span, format!("`{}` is not a colour", p.as_str()))
                        .label("expected `#` and six hex digits")
                        .help("write colours as `#rrggbb`, e.g. `#ff8000`"),
                );
            }
            let byte = |i: usize| u8::from_str_radix(&digits[i..i + 2], 16).unwrap_or(0);
            Ok((
                Expr {
                    kind: ExprKind::Hex([byte(0), byte(2), byte(4)]),
                    span,
                },
                1,
            ))
        }
        Rule::ident => Ok((
            Expr {
                kind: ExprKind::Name(p.as_str().into()),
                span,
            },
            1,
        )),
        Rule::paren => {
            let inner = p.into_inner().next().expect("grammar: paren holds an expr");
            let (mut e, d) = expr_depth(inner, at)?;
            // The parentheses belong to the value's extent in messages.
            e.span = span;
            Ok((e, d))
        }
        Rule::vector => {
            let mut v = Vec::new();
            let mut depth = 0;
            for c in p.into_inner() {
                let (e, d) = expr_depth(c, at)?;
                depth = depth.max(d);
                v.push(e);
            }
            node(
                Expr {
                    kind: ExprKind::Vector(v),
                    span,
                },
                depth,
            )
        }
        Rule::call => {
            let mut inner = p.into_inner();
            let callee = inner.next().expect("grammar: call has a name");
            let name = Spanned::new(callee.as_str().to_string(), span_of(&callee, at));
            let mut args = Vec::new();
            let mut named = Vec::new();
            let mut depth = 0;
            for c in inner {
                let mut parts = c.into_inner();
                let first = parts.next().expect("grammar: an argument has a value");
                let (label, value) = if first.as_rule() == Rule::arg_name {
                    let n = Spanned::new(first.as_str().to_string(), span_of(&first, at));
                    (Some(n), parts.next().expect("grammar: `name:` has a value"))
                } else {
                    (None, first)
                };
                let (e, d) = expr_depth(value, at)?;
                depth = depth.max(d);
                match label {
                    Some(n) => named.push((n, e)),
                    None if !named.is_empty() => {
                        return Err(Error::new(
                            e.span,
                            "a positional argument cannot follow a named one",
                        )
                        .label("positional")
                        .help("put the positional arguments first: `f(1, 2, r: 0.5)`"));
                    }
                    None => args.push(e),
                }
            }
            node(
                Expr {
                    kind: ExprKind::Call { name, args, named },
                    span,
                },
                depth,
            )
        }
        Rule::list => {
            let mut v = Vec::new();
            let mut depth = 0;
            for c in p.into_inner() {
                let (e, d) = expr_depth(c, at)?;
                depth = depth.max(d);
                v.push(e);
            }
            node(
                Expr {
                    kind: ExprKind::List(v),
                    span,
                },
                depth,
            )
        }
        Rule::expr | Rule::cexpr => expr_depth(p, at),
        r => unreachable!("grammar: unexpected primary {r:?}"),
    }
}

fn p_str(body: &Pair<Rule>, tail: &Pair<Rule>) -> String {
    format!("{}{}", body.as_str(), tail.as_str())
}

#[cfg(test)]
#[path = "parser_tests.rs"]
mod tests;

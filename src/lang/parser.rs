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

/// How deeply brackets of any kind may nest. Far beyond any real scene, and
/// low enough that parsing and evaluation stay within a small thread stack.
pub const MAX_NESTING: usize = 64;

/// How deep one expression tree may be (chains of `^` and unary minus
/// recurse, and so does a long sum once it is a tree).
pub const MAX_EXPR_DEPTH: usize = 256;

/// Statement keywords: for the "did you mean to close … before …" hint,
/// and the builder's suggestions for an unknown statement.
pub const STATEMENT_KEYWORDS: &[&str] = &[
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
    while pos <= text.len() {
        let rest = &text[pos..];
        let at = Loc { file, offset: pos };
        let mut pairs = match RtParser::parse(Rule::next_item, rest) {
            Ok(p) => p,
            Err(first) => {
                // Tracking the tokens pest tried slows every parse; only a
                // failed one needs them, for "expected `,` or `>`".
                pest::set_error_detail(true);
                let detailed = RtParser::parse(Rule::next_item, rest).err();
                pest::set_error_detail(false);
                errors.push(syntax_error(detailed.unwrap_or(first), rest, at));
                break;
            }
        };
        let Some(p) = pairs.next().and_then(|top| top.into_inner().next()) else {
            break;
        };
        if p.as_rule() == Rule::EOI {
            break;
        }
        let end = p.as_span().end();
        match item(p, at) {
            Ok(i) => items.push(i),
            Err(e) => errors.push(e),
        }
        pos += end.max(1);
    }
    if errors.is_empty() {
        Ok(items)
    } else {
        Err(errors)
    }
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
                            kind: ExprKind::Name(c.as_str().to_string()),
                            span: span_of(&c, at),
                        }),
                        _ => item(c, at)?,
                    });
                }
                Item::LetItems { name, items, span }
            } else {
                Item::Let {
                    name,
                    value: expr(value, at)?,
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
                cond,
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
                kind: ExprKind::Name(p.as_str().to_string()),
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

// ---- pest errors in our words ----

/// What a grammar rule is called in a message.
pub fn describe_rule(r: Rule) -> Option<&'static str> {
    Some(match r {
        Rule::expr
        | Rule::number
        | Rule::num_body
        | Rule::hex
        | Rule::vector
        | Rule::paren
        | Rule::call
        | Rule::callee
        | Rule::cexpr
        | Rule::arg
        | Rule::neg => "a value",
        Rule::ident => "a name",
        Rule::block => "a block `{ … }`",
        Rule::list => "a list `[ … ]`",
        Rule::string | Rule::string_inner => "a string",
        Rule::let_stmt | Rule::kw_let => "`let`",
        Rule::include_stmt | Rule::kw_include => "`include`",
        Rule::kw_in => "`in`",
        Rule::range | Rule::range_excl | Rule::range_incl => "a range `a..b`",
        Rule::fn_param => "a parameter name",
        Rule::EOI => "end of file",
        Rule::exponent => "an exponent",
        // Operators could always continue a value: naming them is noise.
        _ => return None,
    })
}

fn syntax_error(e: pest::error::Error<Rule>, text: &str, at: Loc) -> Error {
    use pest::error::{ErrorVariant, InputLocation};
    let pos = match e.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((a, _)) => a,
    };
    let mut expected: Vec<String> = Vec::new();
    let mut push = |s: String| {
        if !expected.contains(&s) {
            expected.push(s);
        }
    };
    if let ErrorVariant::ParsingError { positives, .. } = &e.variant {
        // Where any item could start, say so once rather than list every
        // kind of item.
        let item_start = [Rule::block, Rule::expr]
            .iter()
            .all(|r| positives.contains(r));
        if item_start {
            for d in ["a name", "a value", "a block"] {
                push(d.into());
            }
        }
        for r in positives {
            let item_rule = matches!(
                r,
                Rule::let_stmt
                    | Rule::kw_let
                    | Rule::kw_include
                    | Rule::include_stmt
                    | Rule::block
                    | Rule::list
                    | Rule::string
                    | Rule::expr
                    | Rule::for_stmt
                    | Rule::if_stmt
                    | Rule::fn_stmt
                    | Rule::kw_for
                    | Rule::kw_if
                    | Rule::kw_fn
            );
            if item_start && item_rule {
                continue;
            }
            if let Some(d) = describe_rule(*r) {
                push(d.into());
            }
        }
    }
    if let Some(attempts) = e.parse_attempts()
        && attempts.max_position == pos
    {
        for t in attempts.expected_tokens() {
            let token = t.to_string();
            if matches!(token.as_str(), "}" | ")" | "]" | ">" | "," | "=") {
                push(format!("`{token}`"));
            }
        }
    }
    if let ErrorVariant::CustomError { message } = &e.variant {
        push(message.clone());
    }
    if expected.iter().any(|e| e == "a value") {
        // A list is a value too.
        expected.retain(|e| e != "a list `[ … ]`");
    }
    if expected.iter().any(|e| e == "a value") && !expected.iter().any(|e| e == "a block") {
        expected.retain(|e| e != "a name");
    }
    let (found, len) = found_at(text, pos);
    let list = match expected.len() {
        // pest named nothing: say what may start a statement.
        0 => "a statement (a name, a value or a block)".to_string(),
        1 => expected[0].clone(),
        n => format!("{} or {}", expected[..n - 1].join(", "), expected[n - 1]),
    };
    let err = Error::new(
        at.span(pos, pos + len),
        format!("expected {list}, found {found}"),
    )
    .label(format!("expected {list}"));
    match found.as_str() {
        "`,`" => err.help(
            "values in a block are separated by spaces; commas go only inside `< >`, `( )` and `[ ]`",
        ),
        "`;`" => err.help("statements need no `;`"),
        "`:`" => err.help("a parameter's value follows its name after a space: `radius 1`, not `radius: 1`"),
        _ => err,
    }
}

/// A few words on what is at `pos`, and how many bytes it covers.
fn found_at(text: &str, pos: usize) -> (String, usize) {
    let rest = &text[super::source::floor_char_boundary(text, pos)..];
    let Some(c) = rest.chars().next() else {
        return ("the end of the file".into(), 0);
    };
    if c.is_ascii_alphabetic() || c == '_' {
        let n = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        return (format!("`{}`", &rest[..n]), n);
    }
    if c.is_ascii_digit() {
        let n = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '.'))
            .unwrap_or(rest.len());
        return (format!("`{}`", &rest[..n]), n);
    }
    (format!("`{c}`"), c.len_utf8())
}

// ---- the bracket pass ----

struct Open {
    ch: char,
    at: usize,
}

fn closer(open: char) -> char {
    match open {
        '{' => '}',
        '(' => ')',
        '[' => ']',
        _ => '>',
    }
}

/// Matches brackets, skipping comments and strings, so that a block that is
/// never closed is reported at its `{` with the statement it belongs to,
/// rather than at the end of the file.
pub fn check_brackets(text: &str, file: FileId) -> Vec<Error> {
    let b = text.as_bytes();
    let mut errors = Vec::new();
    let mut stack: Vec<Open> = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        match c {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => match text[i + 2..].find("*/") {
                Some(n) => {
                    i += 2 + n + 2;
                    continue;
                }
                None => {
                    errors.push(
                        Error::new(Span::new(file, i, i + 2), "this comment is never closed")
                            .label("comment starts here")
                            .help("end a block comment with `*/`"),
                    );
                    return errors;
                }
            },
            b'"' => {
                let end = text[i + 1..].find(['"', '\n']).map(|n| i + 1 + n);
                match end {
                    Some(e) if b[e] == b'"' => {
                        i = e + 1;
                        continue;
                    }
                    _ => {
                        let e = end.unwrap_or(b.len());
                        errors.push(
                            Error::new(Span::new(file, i, e), "this string is not closed")
                                .label("no closing `\"` on this line")
                                .help("strings end on the line they start"),
                        );
                        i = e;
                        continue;
                    }
                }
            }
            // `<=` and `>=` compare; a `<` or `>` may be a comparison too,
            // so a `>` closes only a `<` on top, and an unmatched `<` is
            // dropped when a block opens or a bracket around it closes
            // (a vector holds neither).
            b'<' | b'>' if b.get(i + 1) == Some(&b'=') => {
                i += 2;
                continue;
            }
            b'>' if stack.last().is_some_and(|o| o.ch == '<') => {
                stack.pop();
            }
            b'>' => {}
            b'{' | b'(' | b'[' | b'<' => {
                if c == b'{' {
                    while stack.last().is_some_and(|o| o.ch == '<') {
                        stack.pop();
                    }
                }
                stack.push(Open {
                    ch: c as char,
                    at: i,
                });
                if stack.len() > MAX_NESTING {
                    errors.push(
                        Error::new(Span::new(file, i, i + 1), "brackets nest too deeply")
                            .label(format!("more than {MAX_NESTING} levels deep here"))
                            .help(format!(
                                "blocks, vectors, lists and parentheses may nest at most {MAX_NESTING} deep"
                            )),
                    );
                    return errors;
                }
            }
            b'}' | b')' | b']' => {
                let c = c as char;
                match stack.iter().rposition(|o| closer(o.ch) == c) {
                    Some(k) => {
                        // Anything opened after the match and not closed.
                        for o in stack.drain(k + 1..).rev().filter(|o| o.ch != '<') {
                            errors.push(
                                Error::new(
                                    Span::new(file, o.at, o.at + 1),
                                    format!("`{}` is never closed", o.ch),
                                )
                                .label(format!("this `{}` needs a `{}`", o.ch, closer(o.ch)))
                                .note(
                                    Span::new(file, i, i + 1),
                                    format!("expected `{}` before this", closer(o.ch)),
                                ),
                            );
                        }
                        stack.pop();
                    }
                    None => errors.push(
                        Error::new(
                            Span::new(file, i, i + 1),
                            format!("unexpected `{c}`: nothing here is open"),
                        )
                        .label("nothing to close"),
                    ),
                }
            }
            _ => {}
        }
        i += 1;
    }
    for o in stack {
        if o.ch == '<' && looks_like_comparison(b, o.at) {
            continue;
        }
        errors.push(unclosed_at_eof(text, file, &o));
    }
    errors
}

/// Whether the `<` at `at` reads as "less than" rather than a vector: a
/// value before it and a space after (`x < 1`, not `= <1, 2, 3`).
fn looks_like_comparison(b: &[u8], at: usize) -> bool {
    let before = b[..at].iter().rev().find(|c| !c.is_ascii_whitespace());
    let value_before =
        before.is_some_and(|c| c.is_ascii_alphanumeric() || matches!(c, b')' | b']' | b'_' | b'.'));
    let space_after = b.get(at + 1).is_some_and(|c| c.is_ascii_whitespace());
    value_before && space_after
}

fn unclosed_at_eof(text: &str, file: FileId, o: &Open) -> Error {
    // The last character of the file, so the label shows.
    let end = text.trim_end().len();
    let end = if end == 0 {
        0
    } else {
        super::source::floor_char_boundary(text, end - 1)
    };
    let end_span = Span::new(file, end, text.trim_end().len());
    if o.ch != '{' {
        return Error::new(
            Span::new(file, o.at, o.at + 1),
            format!("`{}` is never closed", o.ch),
        )
        .label(format!("this `{}` needs a `{}`", o.ch, closer(o.ch)))
        .note(end_span, "the file ends here");
    }
    let owner = block_owner(text, o.at);
    let what = owner
        .as_deref()
        .map_or("this block".to_string(), |w| format!("the block of `{w}`"));
    let mut err = Error::new(
        Span::new(file, o.at, o.at + 1),
        format!("{what} is never closed"),
    )
    .label(format!("{what} opens here"))
    .note(end_span, "the file ends before its `}`");
    if let Some((line, col_span, word)) = next_statement(text, o.at) {
        let name = owner.as_deref().unwrap_or("the block");
        err = err
            .help(format!(
                "did you mean to close `{name}` before `{word}` on line {line}?"
            ))
            .note(
                Span::new(file, col_span.0, col_span.1),
                format!("`{word}` starts a new statement"),
            );
    } else {
        err = err.help("add a `}` where the block should end");
    }
    err
}

/// The words before a `{` on its line: `sphere`, `material gold`,
/// `mesh "x.ply"`.
fn block_owner(text: &str, brace: usize) -> Option<String> {
    let line_start = text[..brace].rfind('\n').map_or(0, |n| n + 1);
    let before = text[line_start..brace].trim();
    let before = before.rsplit(['{', '}']).next().unwrap_or("").trim();
    let words: Vec<&str> = before.split_whitespace().collect();
    match words.as_slice() {
        [] => None,
        [.., a, b] if STATEMENT_KEYWORDS.contains(a) => Some(format!("{a} {b}")),
        [.., b] => Some((*b).to_string()),
    }
}

fn indent(line: &str) -> usize {
    line.len() - line.trim_start().len()
}

/// The first later line, indented no deeper than the line of the `{`,
/// that starts with a statement keyword: (line number, span of the word,
/// the word).
fn next_statement(text: &str, brace: usize) -> Option<(usize, (usize, usize), String)> {
    let line_start = text[..brace].rfind('\n').map_or(0, |n| n + 1);
    let own_indent = indent(&text[line_start..]);
    let after = text[brace..].find('\n')? + brace + 1;
    let mut offset = after;
    let first_line = text[..after].matches('\n').count() + 1;
    for (line_no, line) in (first_line..).zip(text[after..].split('\n')) {
        let word: String = line
            .trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        if indent(line) <= own_indent && STATEMENT_KEYWORDS.contains(&word.as_str()) {
            let s = offset + indent(line);
            return Some((line_no, (s, s + word.len()), word));
        }
        offset += line.len() + 1;
    }
    None
}

#[cfg(test)]
#[path = "parser_tests.rs"]
mod tests;

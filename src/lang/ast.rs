//! The syntax tree: what the user typed, with a [`Span`] on every piece, and
//! no meaning yet. A file is a flat sequence of [`Item`]s; statements are
//! only recognised by the builder (`scene::build`), which reads items
//! against a schema. Nothing here depends on pest.

use std::fmt;

/// Which loaded file a span is in (an index into [`super::Sources`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FileId(pub u32);

/// A byte range in one file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Span {
    pub file: FileId,
    pub start: usize,
    pub end: usize,
}

impl Span {
    pub fn new(file: FileId, start: usize, end: usize) -> Span {
        Span { file, start, end }
    }

    /// The smallest span covering both (same file assumed; otherwise `self`).
    pub fn to(self, other: Span) -> Span {
        if self.file != other.file {
            return self;
        }
        Span::new(
            self.file,
            self.start.min(other.start),
            self.end.max(other.end),
        )
    }

    pub fn len(&self) -> usize {
        self.end - self.start
    }

    pub fn is_empty(&self) -> bool {
        self.end == self.start
    }
}

/// A value with the place it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Spanned<T> {
    pub node: T,
    pub span: Span,
}

impl<T> Spanned<T> {
    pub fn new(node: T, span: Span) -> Self {
        Spanned { node, span }
    }
}

/// One element of a file or a block.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// `let NAME = expr`; the expression boxed, as `if`'s condition, so
    /// that an item is 128 bytes rather than 200: an evaluated loop makes
    /// and moves hundreds of thousands of items, and none is a `let`.
    Let {
        name: Spanned<String>,
        value: Box<Expr>,
        span: Span,
    },
    /// A name, number, vector, colour or any expression.
    Value(Expr),
    /// `"text"`; `span` covers the quotes, `content` only the text.
    /// `constants` are the numbers in scope where it was written (set by
    /// the evaluator, for the names in `implicit` equations).
    Str {
        text: String,
        span: Span,
        content: Span,
        constants: Option<std::sync::Arc<Vec<(String, f64)>>>,
    },
    /// `include "path"` before the loader splices the file in; `string`
    /// covers the quoted path, `content` its text.
    Include {
        text: String,
        span: Span,
        string: Span,
        content: Span,
    },
    /// `[a, b, …]`
    List(Spanned<Vec<Expr>>),
    /// `{ item* }`
    Block(Block),
    /// `let NAME = sphere { … }`: a value written as items (an object, a
    /// material, a pattern).
    LetItems {
        name: Spanned<String>,
        items: Vec<Item>,
        span: Span,
    },
    /// `for NAME in SOURCE { … }`
    For {
        var: Spanned<String>,
        source: Box<ForSource>,
        body: Block,
        span: Span,
    },
    /// `if COND { … } else …`; `otherwise` is a block or another `If`.
    If {
        cond: Box<Expr>,
        then: Block,
        otherwise: Option<Box<Item>>,
        span: Span,
    },
    /// `fn NAME(…) …`
    Fn(std::sync::Arc<FnDef>),
    /// Items made by a loop iteration or a function call (put here by the
    /// evaluator, never by the parser): `trace` says where they came
    /// from, innermost first, for messages about them.
    Traced {
        trace: crate::eval::TraceRef,
        items: Vec<Item>,
    },
}

/// What a `for` runs over (boxed in [`Item::For`]).
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum ForSource {
    /// `A..B`, `A..=B`, optionally `step S`.
    Range {
        from: Expr,
        to: Expr,
        inclusive: bool,
        step: Option<Expr>,
    },
    /// A list (or anything else, which is a kind error).
    Each(Expr),
}

/// A function declaration.
#[derive(Debug, PartialEq)]
pub struct FnDef {
    pub name: Spanned<String>,
    pub params: Vec<FnParam>,
    pub body: FnBody,
    pub span: Span,
}

#[derive(Debug, PartialEq)]
pub struct FnParam {
    pub name: Spanned<String>,
    pub default: Option<Expr>,
}

#[derive(Debug, PartialEq)]
pub enum FnBody {
    /// `= expression`
    Expr(Expr),
    /// `{ objects }`
    Items(Block),
}

impl Item {
    pub fn span(&self) -> Span {
        match self {
            Item::Let { span, .. } => *span,
            Item::Value(e) => e.span,
            Item::Str { span, .. } => *span,
            Item::Include { span, .. } => *span,
            Item::List(l) => l.span,
            Item::Block(b) => b.span,
            Item::LetItems { span, .. } | Item::For { span, .. } | Item::If { span, .. } => *span,
            Item::Fn(f) => f.span,
            Item::Traced { items, .. } => match (items.first(), items.last()) {
                (Some(a), Some(b)) => a.span().to(b.span()),
                _ => Span::new(FileId(0), 0, 0),
            },
        }
    }

    /// The name if this item is a bare name (`sphere`, `radius`, `x`),
    /// bound to a value or not.
    pub fn as_name(&self) -> Option<Spanned<&str>> {
        match self {
            Item::Value(Expr {
                kind: ExprKind::Name(n) | ExprKind::Bound(n, _),
                span,
            }) if !n.is_empty() => Some(Spanned::new(&**n, *span)),
            _ => None,
        }
    }

    /// Whether this is a name bound by `let`, a loop or a parameter (a
    /// value, never a parameter or keyword of the builder's).
    pub fn is_bound_name(&self) -> bool {
        matches!(
            self,
            Item::Value(Expr {
                kind: ExprKind::Bound(..),
                ..
            })
        )
    }

    /// A few words for "found …" in messages.
    pub fn describe(&self) -> String {
        match self {
            Item::Let { .. } => "a `let`".into(),
            Item::Value(e) => e.describe(),
            Item::Str { .. } => "a string".into(),
            Item::Include { .. } => "an `include`".into(),
            Item::List(_) => "a list `[…]`".into(),
            Item::Block(_) => "a block `{…}`".into(),
            Item::LetItems { .. } => "a `let`".into(),
            Item::For { .. } => "a `for` loop".into(),
            Item::If { .. } => "an `if`".into(),
            Item::Fn(_) => "a function declaration".into(),
            Item::Traced { .. } => "generated items".into(),
        }
    }
}

/// `{ item* }`; `open` is the span of the `{` (for "never closed" notes).
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Rem,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    And,
    Or,
}

impl fmt::Display for BinOp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Pow => "^",
            BinOp::Rem => "%",
            BinOp::Eq => "==",
            BinOp::Ne => "!=",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            BinOp::Ge => ">=",
            BinOp::And => "and",
            BinOp::Or => "or",
        })
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

/// A name in an expression. The evaluator copies every keyword it passes
/// on (`sphere`, `radius`, … once per loop iteration), so a name is held
/// inline (up to 23 bytes, longer ones shared): copying a shared string
/// counts up and down on one cache line that the builder's thread reads
/// the same words from, and on a machine whose cores are far apart that
/// line travelled between them for every keyword of every iteration.
pub type Name = smol_str::SmolStr;

/// `a == b` for names and keywords, the first byte looked at before the
/// rest: most names a lookup passes differ in length or first letter
/// (`i` against `j`, `radius` against `centre`), and `==` on two strings
/// of one length is a call to `memcmp`. The evaluator's scopes and the
/// builder's parameter lists are searched by name this way.
#[inline(always)]
pub fn same_name(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.as_bytes().first() == b.as_bytes().first() && a == b
}

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Number(f64),
    Name(Name),
    /// `#rrggbb`, already checked to be six hex digits.
    Hex([u8; 3]),
    /// `<a, b, …>` with any number of components.
    Vector(Vec<Expr>),
    Call {
        name: Spanned<String>,
        args: Vec<Expr>,
        /// `name: value` arguments, after the positional ones.
        named: Vec<(Spanned<String>, Expr)>,
    },
    Neg(Box<Expr>),
    /// `not a`
    Not(Box<Expr>),
    /// `[a, b, …]` as a value.
    List(Vec<Expr>),
    /// `xs[i]`
    Index {
        base: Box<Expr>,
        index: Box<Expr>,
    },
    /// A value the evaluator has already worked out (a bound name,
    /// substituted where it was used; never made by the parser).
    Value(crate::eval::expr::Value),
    /// A bound name the evaluator replaced by its value: still a name
    /// for the builder's reading of parameters (`rotate x 90`).
    /// `None` when its definition failed (already reported).
    Bound(Name, Option<crate::eval::expr::Value>),
    Binary {
        op: BinOp,
        lhs: Box<Expr>,
        rhs: Box<Expr>,
    },
}

impl Expr {
    pub fn describe(&self) -> String {
        match &self.kind {
            ExprKind::Number(_) => "a number".into(),
            ExprKind::Name(n) => format!("`{n}`"),
            ExprKind::Hex(_) => "a colour".into(),
            ExprKind::Vector(v) => format!("a {}-vector", v.len()),
            ExprKind::Call { name, .. } => format!("`{}(…)`", name.node),
            ExprKind::Neg(_) | ExprKind::Binary { .. } | ExprKind::Not(_) => "an expression".into(),
            ExprKind::List(_) => "a list".into(),
            ExprKind::Index { .. } => "an indexed value".into(),
            ExprKind::Value(v) | ExprKind::Bound(_, Some(v)) => v.kind(),
            ExprKind::Bound(n, None) => format!("`{n}`"),
        }
    }

    /// Splits `offset -2` (which the grammar reads as the subtraction
    /// `offset - 2`) into the leading name and the rest, `-2`. Only a `-`
    /// right after the leading name can be split; the rest keeps its
    /// precedence because unary minus and subtraction group the same way
    /// (`a -2*3` → `-(2*3)`, `a -1 + 2` → `(-1) + 2`).
    pub fn split_leading_name(&self) -> Option<(Spanned<String>, Expr)> {
        match &self.kind {
            ExprKind::Binary { op, lhs, rhs } => {
                if let (BinOp::Sub, ExprKind::Name(n)) = (op, &lhs.kind) {
                    let rest = Expr {
                        span: Span::new(self.span.file, lhs.span.end, rhs.span.end),
                        kind: ExprKind::Neg(rhs.clone()),
                    };
                    // Start the rest at the minus sign rather than after the name.
                    let rest = Expr {
                        span: Span::new(
                            rest.span.file,
                            rhs.span.start.saturating_sub(1).max(lhs.span.end),
                            rest.span.end,
                        ),
                        ..rest
                    };
                    return Some((Spanned::new(n.to_string(), lhs.span), rest));
                }
                let (name, rest) = lhs.split_leading_name()?;
                Some((
                    name,
                    Expr {
                        span: rest.span.to(rhs.span),
                        kind: ExprKind::Binary {
                            op: *op,
                            lhs: Box::new(rest),
                            rhs: rhs.clone(),
                        },
                    },
                ))
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sp(a: usize, b: usize) -> Span {
        Span::new(FileId(0), a, b)
    }
    fn num(v: f64, a: usize, b: usize) -> Expr {
        Expr {
            kind: ExprKind::Number(v),
            span: sp(a, b),
        }
    }

    #[test]
    fn split_keeps_the_rest_of_the_expression() {
        // "offset -1 + 2"
        let sub = Expr {
            kind: ExprKind::Binary {
                op: BinOp::Sub,
                lhs: Box::new(Expr {
                    kind: ExprKind::Name("offset".into()),
                    span: sp(0, 6),
                }),
                rhs: Box::new(num(1.0, 8, 9)),
            },
            span: sp(0, 9),
        };
        let add = Expr {
            kind: ExprKind::Binary {
                op: BinOp::Add,
                lhs: Box::new(sub),
                rhs: Box::new(num(2.0, 12, 13)),
            },
            span: sp(0, 13),
        };
        let (name, rest) = add.split_leading_name().unwrap();
        assert_eq!(name.node, "offset");
        assert_eq!(rest.span, sp(7, 13));
        match rest.kind {
            ExprKind::Binary {
                op: BinOp::Add,
                lhs,
                ..
            } => assert!(matches!(lhs.kind, ExprKind::Neg(_))),
            k => panic!("{k:?}"),
        }
    }

    #[test]
    fn same_name_is_string_equality() {
        let names = [
            "", "i", "j", "ii", "radius", "radial", "centre", "Centre", "rgb", "rgc",
        ];
        for a in names {
            for b in names {
                // Copies, so that equal names are never the same pointer.
                let (x, y) = (String::from(a), String::from(b));
                assert_eq!(same_name(&x, &y), a == b, "{a} {b}");
            }
        }
    }
}

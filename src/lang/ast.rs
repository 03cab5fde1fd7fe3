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
    /// `let NAME = expr`
    Let {
        name: Spanned<String>,
        value: Expr,
        span: Span,
    },
    /// A name, number, vector, colour or any expression.
    Value(Expr),
    /// `"text"`; `span` covers the quotes, `content` only the text.
    Str {
        text: String,
        span: Span,
        content: Span,
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
        }
    }

    /// The name if this item is a bare name (`sphere`, `radius`, `x`).
    pub fn as_name(&self) -> Option<Spanned<&str>> {
        match self {
            Item::Value(Expr {
                kind: ExprKind::Name(n),
                span,
            }) => Some(Spanned::new(n.as_str(), *span)),
            _ => None,
        }
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
}

impl fmt::Display for BinOp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Pow => "^",
        })
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Number(f64),
    Name(String),
    /// `#rrggbb`, already checked to be six hex digits.
    Hex([u8; 3]),
    /// `<a, b, …>` with any number of components.
    Vector(Vec<Expr>),
    Call {
        name: Spanned<String>,
        args: Vec<Expr>,
    },
    Neg(Box<Expr>),
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
            ExprKind::Neg(_) | ExprKind::Binary { .. } => "an expression".into(),
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
                    return Some((Spanned::new(n.clone(), lhs.span), rest));
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
}

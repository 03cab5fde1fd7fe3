//! Transforms: `translate`, `rotate` (about an axis or by a vector),
//! `scale`, `mirror` and `matrix`, read from a block's transform list and
//! composed in the order written. Objects (objects.rs) and placed patterns
//! (patterns.rs) both take their placement from here.

use super::Builder;
use super::params::Param;
use crate::geometry::{DVec3, Transform};
use crate::lang::ast::{Item, Span};
use crate::lang::diagnostics::{Error, did_you_mean};

fn axis_index(name: &str) -> Option<usize> {
    match name {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    }
}

impl Builder<'_> {
    /// Composes transforms in the order written. Mistakes are reported and
    /// the faulty step skipped (the build fails anyway).
    pub(super) fn transform(&mut self, list: Vec<Param>) -> Transform {
        let mut xf = Transform::IDENTITY;
        for q in list {
            if let Some(t) = self.one_transform(&q) {
                xf = xf.then(&t);
            }
        }
        xf
    }

    fn axis(&mut self, item: &Item) -> Option<usize> {
        match item.as_name() {
            Some(n) => match axis_index(n.node) {
                Some(a) => Some(a),
                None => {
                    self.err(
                        Error::new(n.span, format!("`{}` is not an axis", n.node))
                            .label("expected `x`, `y`, `z` (or a vector for `rotate`)")
                            .maybe_help(did_you_mean(n.node, ["x", "y", "z"])),
                    );
                    None
                }
            },
            None => {
                self.err(
                    Error::new(
                        item.span(),
                        format!("expected an axis, found {}", item.describe()),
                    )
                    .label("expected `x`, `y` or `z`"),
                );
                None
            }
        }
    }

    fn singular(&mut self, at: Span, what: &str) {
        self.err(
            Error::new(at, format!("this {what} is singular"))
                .label("flattens the object")
                .help(
                    "a transform must be invertible: no zero scale factors or degenerate matrices",
                ),
        );
    }

    fn one_transform(&mut self, q: &Param) -> Option<Transform> {
        let v = &q.values;
        match q.name.node {
            "translate" => self.vec3(&v[0]).map(|(d, _)| Transform::translate(d)),
            "rotate" => {
                // `x`, `y` and `z` are axes here even where a loop or a
                // parameter has that name; any other bound name is a vector.
                let bare = v[0]
                    .as_name()
                    .filter(|n| !v[0].is_bound_name() || axis_index(n.node).is_some());
                let axis = match bare {
                    Some(_) => self.axis(&v[0]).map(|a| DVec3::AXES[a]),
                    None => match self.vec3(&v[0]) {
                        Some((a, _)) if a.length() > 0.0 => Some(a),
                        Some((_, s)) => {
                            self.err(
                                Error::new(s, "a rotation axis cannot be zero")
                                    .label("zero vector"),
                            );
                            None
                        }
                        None => None,
                    },
                };
                let angle = self.number(&v[1]).map(|a| a.0);
                Transform::rotate(axis?, angle?)
            }
            "scale" => {
                let (s, at) = match self.value(&v[0], "a number or a 3-vector")? {
                    (super::Value::Number(s), at) => (DVec3::splat(s), at),
                    (super::Value::Vector(s), at) if s.len() == 3 => {
                        (DVec3::new(s[0], s[1], s[2]), at)
                    }
                    (other, at) => {
                        self.wrong_kind(at, "a number or a 3-vector", &other, None);
                        return None;
                    }
                };
                let t = Transform::scale(s);
                if t.is_none() {
                    self.singular(at, "scale");
                }
                t
            }
            "shear" => {
                let pair = match v[0].as_name() {
                    Some(n) => {
                        let b = n.node.as_bytes();
                        let ok = b.len() == 2 && b[0] != b[1];
                        let ix = |c: u8| axis_index(std::str::from_utf8(&[c]).unwrap_or(""));
                        match (
                            ok,
                            b.first().and_then(|c| ix(*c)),
                            b.get(1).and_then(|c| ix(*c)),
                        ) {
                            (true, Some(from), Some(to)) => Some((from, to)),
                            _ => {
                                self.err(
                                    Error::new(n.span, format!("`{}` is not a shear", n.node))
                                        .label("expected xy, xz, yx, yz, zx or zy")
                                        .help("`shear AB d` moves coordinate B by d times coordinate A")
                                        .maybe_help(did_you_mean(n.node, ["xy", "xz", "yx", "yz", "zx", "zy"])),
                                );
                                None
                            }
                        }
                    }
                    None => {
                        self.err(
                            Error::new(
                                v[0].span(),
                                format!("expected a shear such as `xy`, found {}", v[0].describe()),
                            )
                            .label("expected xy, xz, yx, yz, zx or zy"),
                        );
                        None
                    }
                };
                let d = self.number(&v[1]).map(|d| d.0);
                let (from, to) = pair?;
                Some(Transform::shear(from, to, d?))
            }
            "mirror" => self.axis(&v[0]).map(Transform::mirror),
            "matrix" => {
                let Item::List(list) = &*v[0] else {
                    self.err(
                        Error::new(
                            v[0].span(),
                            format!("expected a list of 12 numbers, found {}", v[0].describe()),
                        )
                        .label("expected `[a, b, c, d,  e, f, g, h,  i, j, k, l]`"),
                    );
                    return None;
                };
                if list.node.len() != 12 {
                    let n = list.node.len();
                    self.err(
                        Error::new(list.span, format!("`matrix` needs 12 numbers, found {n}"))
                            .label(format!("{n} number{}", if n == 1 { "" } else { "s" }))
                            .help("write the top three rows of the 4×4 matrix: `[a, b, c, d,  e, f, g, h,  i, j, k, l]`"),
                    );
                    return None;
                }
                let mut rows = [0.0; 12];
                let mut ok = true;
                for (k, e) in list.node.iter().enumerate() {
                    match self.number(&Item::Value(e.clone())) {
                        Some((x, _)) => rows[k] = x,
                        None => ok = false,
                    }
                }
                if !ok {
                    return None;
                }
                let t = Transform::from_rows(rows);
                if t.is_none() {
                    self.singular(list.span, "matrix");
                }
                t
            }
            other => unreachable!("not a transform: {other}"),
        }
    }
}

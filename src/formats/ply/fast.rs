//! A fast reader for the bulk data of well-formed files. The crate reads
//! the header (it stays the reader of record); its grammar costs a few
//! hundred instructions per number, so the element data of a file this
//! module can read plainly is read here. Anything unusual (a token that is
//! not a plain number, a count that does not fit, data left over) makes it
//! give up, and the crate's reader then reads the file and reports.
//!
//! ASCII data has one record a line, so its lines are cut into runs (at
//! line ends found with memchr), none across two elements, and the runs
//! are read in parallel: a run must hold exactly its lines' records.

use super::{Raw, Run, is_index_list};
use ply_rs_bw::ply::{Encoding, Header, PropertyType, ScalarType};
use rayon::prelude::*;

/// Where a property's values go.
#[derive(Clone, Copy)]
enum Sink {
    Skip,
    Vertex(usize),
    Indices,
}

/// An element's properties, each with where its values go.
struct Plan {
    props: Vec<(PropertyType, Sink)>,
    is_vertex: bool,
    is_face: bool,
}

impl Plan {
    fn new(name: &str, def: &ply_rs_bw::ply::ElementDef) -> Option<Plan> {
        let is_vertex = name == "vertex";
        let is_face = name == "face";
        let props: Vec<(PropertyType, Sink)> = def
            .properties
            .iter()
            .map(|(pname, p)| {
                let sink = if is_vertex {
                    slot(pname).map_or(Sink::Skip, Sink::Vertex)
                } else if is_face && is_index_list(pname) {
                    Sink::Indices
                } else {
                    Sink::Skip
                };
                (p.data_type.clone(), sink)
            })
            .collect();
        if is_face {
            // Exactly one index list, of integers: else the crate decides.
            let lists: Vec<_> = props
                .iter()
                .filter(|(_, s)| matches!(s, Sink::Indices))
                .collect();
            match lists.as_slice() {
                [(PropertyType::List(_, t), _)] if !is_float(t) => {}
                _ => return None,
            }
        }
        Some(Plan {
            props,
            is_vertex,
            is_face,
        })
    }
}

impl Run {
    fn with_capacity(plan: &Plan, count: usize) -> Run {
        let n = count.min(1 << 26);
        let mut run = Run::default();
        if plan.is_vertex {
            run.values.reserve(n);
            run.set.reserve(n);
        }
        if plan.is_face {
            run.ends.reserve(n);
            run.indices.reserve(3 * n);
        }
        run
    }
}

/// Reads `count` records of the element `plan` from `src` into `run`.
fn records(src: &mut Source, plan: &Plan, count: usize, run: &mut Run) -> Option<()> {
    for _ in 0..count {
        src.begin_record()?;
        let mut values = [0f64; 8];
        let mut set = 0u8;
        for (ty, sink) in &plan.props {
            match ty {
                PropertyType::Scalar(t) => {
                    let v = src.scalar(t)?;
                    if let Sink::Vertex(k) = sink {
                        values[*k] = v;
                        set |= 1 << *k;
                    }
                }
                PropertyType::List(count_type, t) => {
                    let count = src.count(count_type)?;
                    for _ in 0..count {
                        let v = src.scalar(t)?;
                        if let Sink::Indices = sink {
                            run.indices.push(v as i64);
                        }
                    }
                }
            }
        }
        src.end_record()?;
        if plan.is_vertex {
            run.values.push(values);
            run.set.push(set);
        }
        if plan.is_face {
            run.ends.push(run.indices.len());
        }
    }
    Some(())
}

/// The most lines an ASCII run holds: a big file's runs are read in
/// parallel (several per thread, for balance); a small file is one run
/// per element.
pub(super) const RUN_LINES: usize = 8192;

/// The payload, an ASCII file's cut into runs of at most `run_lines`
/// lines; `None` where the crate must read it.
pub(super) fn payload(bytes: &[u8], header: &Header, run_lines: usize) -> Option<Raw> {
    let plans = header
        .elements
        .iter()
        .map(|(name, def)| Plan::new(name, def).map(|p| (p, def.count)))
        .collect::<Option<Vec<_>>>()?;
    let mut raw = Raw::default();
    if header.encoding != Encoding::Ascii {
        let mut src = Source::Binary(bytes, 0, header.encoding == Encoding::BinaryBigEndian);
        for (plan, count) in &plans {
            let mut run = Run::with_capacity(plan, *count);
            records(&mut src, plan, *count, &mut run)?;
            raw.runs.push(run);
        }
        return src.at_end().then_some(raw);
    }
    // ASCII has one record a line: the lines are cut into runs, each
    // within one element, read in parallel and kept in order. A run holds
    // exactly its lines' records or the file is not plain.
    let spans = ascii_runs(bytes, &plans, run_lines)?;
    raw.runs = spans
        .par_iter()
        .map(|&(element, from, to, count)| {
            let plan = &plans[element].0;
            let mut run = Run::with_capacity(plan, count);
            let mut src = Source::Ascii(&bytes[from..to], 0);
            records(&mut src, plan, count, &mut run)?;
            matches!(src, Source::Ascii(b, p) if p == b.len()).then_some(run)
        })
        .collect::<Option<Vec<Run>>>()?;
    let end = spans.last().map_or(0, |r| r.2);
    Source::Ascii(&bytes[end..], 0).at_end().then_some(raw)
}

/// The ASCII payload's lines cut into runs of at most `run_lines`, none
/// across two elements: (element, first byte, byte past its last line
/// end, lines). `None` when there are fewer line ends than records.
fn ascii_runs(
    bytes: &[u8],
    plans: &[(Plan, usize)],
    run_lines: usize,
) -> Option<Vec<(usize, usize, usize, usize)>> {
    let mut runs = Vec::new();
    let mut line_ends = memchr::memchr_iter(b'\n', bytes);
    let mut at = 0;
    for (element, &(_, count)) in plans.iter().enumerate() {
        let mut left = count;
        while left > 0 {
            let n = left.min(run_lines.max(1));
            // The n-th line end from here.
            let end = line_ends.nth(n - 1)? + 1;
            runs.push((element, at, end, n));
            at = end;
            left -= n;
        }
    }
    Some(runs)
}

/// Whether a whole file's data goes through here (for the tests).
#[cfg(test)]
pub(super) fn payload_is_fast(bytes: &[u8], run_lines: usize) -> bool {
    use ply_rs_bw::parser::{Parser, Reader};
    let mut reader = Reader::new(bytes);
    let Ok(header) = Parser::<super::Elem>::new().read_header(&mut reader) else {
        return false;
    };
    payload(reader.get_ref(), &header, run_lines).is_some()
}

/// The slot of a vertex property in `Raw::values` (see `Elem::scalar`).
fn slot(name: &str) -> Option<usize> {
    Some(match name {
        "x" => 0,
        "y" => 1,
        "z" => 2,
        "nx" => 3,
        "ny" => 4,
        "nz" => 5,
        "u" | "s" | "texture_u" | "texture_s" => 6,
        "v" | "t" | "texture_v" | "texture_t" => 7,
        _ => return None,
    })
}

fn is_float(t: &ScalarType) -> bool {
    matches!(t, ScalarType::Float | ScalarType::Double)
}

/// A token read by the crate's number grammar,
/// `[+-]? d+ (. d+)? ([eE] [+-]? d+)?`, in one pass that also gathers
/// its digits: a token the grammar refuses must reach the crate, to be
/// refused there.
#[derive(Clone, Copy)]
pub(super) struct Num<'a> {
    text: &'a [u8],
    neg: bool,
    /// Only `-`? digits, at most 18 of them: `mant` is the integer.
    int_ok: bool,
    /// No `+`, no exponent, at most 19 digits: the value is
    /// `mant · 10^exp10`.
    dec_ok: bool,
    mant: u64,
    exp10: i32,
}

/// Scans the token starting at `i`, which must end at a blank, a line
/// end or the end of the text; returns it and the position after it.
#[inline(always)]
pub(super) fn scan(b: &[u8], mut i: usize) -> Option<(Num<'_>, usize)> {
    let start = i;
    let (mut neg, mut plus) = (false, false);
    match b.get(i) {
        Some(b'-') => (neg, i) = (true, i + 1),
        Some(b'+') => (plus, i) = (true, i + 1),
        _ => {}
    }
    // Digits go into `mant` unchecked: with at most 19 of them it is
    // exact, and a longer number goes to the standard parser.
    let digits = |i: &mut usize, mant: &mut u64| {
        let start = *i;
        while let Some(&c) = b.get(*i) {
            let d = c.wrapping_sub(b'0');
            if d > 9 {
                break;
            }
            *mant = mant.wrapping_mul(10).wrapping_add(d as u64);
            *i += 1;
        }
        *i - start
    };
    let mut mant = 0u64;
    let int_digits = digits(&mut i, &mut mant);
    if int_digits == 0 {
        return None;
    }
    let dot = b.get(i) == Some(&b'.');
    let mut frac_digits = 0;
    if dot {
        i += 1;
        frac_digits = digits(&mut i, &mut mant);
        if frac_digits == 0 {
            return None;
        }
    }
    let exp = matches!(b.get(i), Some(b'e' | b'E'));
    if exp {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        let exp_start = i;
        while b.get(i).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
        if i == exp_start {
            return None;
        }
    }
    if !matches!(b.get(i), None | Some(b' ' | b'\t' | b'\n')) {
        return None;
    }
    let num = Num {
        text: &b[start..i],
        neg,
        int_ok: !plus && !dot && !exp && int_digits <= 18,
        dec_ok: !plus && !exp && int_digits + frac_digits <= 19,
        mant,
        exp10: -(frac_digits as i32),
    };
    Some((num, i))
}

/// Powers of ten that are exact in `f64` (up to 1e10 also in `f32`).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

impl Num<'_> {
    #[inline]
    fn int(&self) -> Option<i64> {
        let v = self.mant as i64;
        self.int_ok.then_some(if self.neg { -v } else { v })
    }

    /// Clinger's fast path: when the digits and the power of ten are
    /// both exact in the type, one multiplication or division rounds
    /// correctly, giving the standard parser's value. Other numbers go
    /// to that parser.
    #[inline]
    fn float32(&self) -> Option<f32> {
        let (m, e) = (self.mant, self.exp10);
        if self.dec_ok && m < (1 << 24) && (-10..=10).contains(&e) {
            let p = POW10[e.unsigned_abs() as usize] as f32;
            let v = if e < 0 { m as f32 / p } else { m as f32 * p };
            return Some(if self.neg { -v } else { v });
        }
        std::str::from_utf8(self.text).ok()?.parse().ok()
    }

    #[inline]
    fn float64(&self) -> Option<f64> {
        let (m, e) = (self.mant, self.exp10);
        if self.dec_ok && m < (1 << 53) && (-22..=22).contains(&e) {
            let p = POW10[e.unsigned_abs() as usize];
            let v = if e < 0 { m as f64 / p } else { m as f64 * p };
            return Some(if self.neg { -v } else { v });
        }
        std::str::from_utf8(self.text).ok()?.parse().ok()
    }
}

/// A whole string as a number (for the tests): by the fast path when
/// the grammar takes it, else by the standard parser.
#[cfg(test)]
fn whole(s: &[u8]) -> Option<Num<'_>> {
    scan(s, 0)
        .filter(|&(_, end)| end == s.len())
        .map(|(n, _)| n)
}

#[cfg(test)]
pub(super) fn float32(s: &[u8]) -> Option<f32> {
    match whole(s) {
        Some(n) => n.float32(),
        None => std::str::from_utf8(s).ok()?.parse().ok(),
    }
}

#[cfg(test)]
pub(super) fn float64(s: &[u8]) -> Option<f64> {
    match whole(s) {
        Some(n) => n.float64(),
        None => std::str::from_utf8(s).ok()?.parse().ok(),
    }
}

enum Source<'a> {
    /// The text and the position in it.
    Ascii(&'a [u8], usize),
    /// The bytes, the position, big-endian.
    Binary(&'a [u8], usize, bool),
}

impl Source<'_> {
    /// ASCII: one record per line, nothing before it but blanks.
    fn begin_record(&mut self) -> Option<()> {
        match self {
            Source::Ascii(b, p) => {
                while *p < b.len() && (b[*p] == b' ' || b[*p] == b'\t') {
                    *p += 1;
                }
                (*p < b.len()).then_some(())
            }
            Source::Binary(..) => Some(()),
        }
    }

    /// ASCII: the rest of the line must be blank, then a line end.
    fn end_record(&mut self) -> Option<()> {
        match self {
            Source::Ascii(b, p) => {
                while *p < b.len() && (b[*p] == b' ' || b[*p] == b'\t') {
                    *p += 1;
                }
                if *p < b.len() && b[*p] == b'\n' {
                    *p += 1;
                    Some(())
                } else {
                    None
                }
            }
            Source::Binary(..) => Some(()),
        }
    }

    fn at_end(&self) -> bool {
        match self {
            Source::Ascii(b, p) => b[*p..].iter().all(|c| c.is_ascii_whitespace()),
            Source::Binary(b, p, _) => *p == b.len(),
        }
    }

    /// The next token of a line, a number by the crate's grammar.
    #[inline(always)]
    fn token<'b>(b: &'b [u8], p: &mut usize) -> Option<Num<'b>> {
        let mut i = *p;
        while i < b.len() && (b[i] == b' ' || b[i] == b'\t') {
            i += 1;
        }
        let (num, end) = scan(b, i)?;
        *p = end;
        Some(num)
    }

    fn bytes<const N: usize>(&mut self) -> Option<[u8; N]> {
        let Source::Binary(b, p, big) = self else {
            return None;
        };
        let mut a: [u8; N] = b.get(*p..*p + N)?.try_into().ok()?;
        *p += N;
        if *big {
            a.reverse();
        }
        Some(a)
    }

    /// A scalar of type `t`, widened to `f64` as the crate's setters do.
    #[inline(always)]
    fn scalar(&mut self, t: &ScalarType) -> Option<f64> {
        if let Source::Ascii(b, p) = self {
            let s = Self::token(b, p)?;
            return Some(match t {
                ScalarType::Char => i8::try_from(s.int()?).ok()?.into(),
                ScalarType::UChar => u8::try_from(s.int()?).ok()?.into(),
                ScalarType::Short => i16::try_from(s.int()?).ok()?.into(),
                ScalarType::UShort => u16::try_from(s.int()?).ok()?.into(),
                ScalarType::Int => i32::try_from(s.int()?).ok()?.into(),
                ScalarType::UInt => u32::try_from(s.int()?).ok()?.into(),
                ScalarType::Float => s.float32()?.into(),
                ScalarType::Double => s.float64()?,
            });
        }
        Some(match t {
            ScalarType::Char => i8::from_le_bytes(self.bytes()?).into(),
            ScalarType::UChar => u8::from_le_bytes(self.bytes()?).into(),
            ScalarType::Short => i16::from_le_bytes(self.bytes()?).into(),
            ScalarType::UShort => u16::from_le_bytes(self.bytes()?).into(),
            ScalarType::Int => i32::from_le_bytes(self.bytes()?).into(),
            ScalarType::UInt => u32::from_le_bytes(self.bytes()?).into(),
            ScalarType::Float => f32::from_le_bytes(self.bytes()?).into(),
            ScalarType::Double => f64::from_le_bytes(self.bytes()?),
        })
    }

    /// A list's length.
    fn count(&mut self, t: &ScalarType) -> Option<usize> {
        if let Source::Ascii(b, p) = self {
            return usize::try_from(Self::token(b, p)?.int()?).ok();
        }
        if is_float(t) {
            return None;
        }
        let v = self.scalar(t)?;
        (v >= 0.0).then_some(v as usize)
    }
}

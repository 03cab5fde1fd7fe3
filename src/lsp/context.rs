//! Where the cursor is, read from the text as typed (which is often not a
//! scene yet: `sphere { ra` has an unclosed block): the word under it, and
//! the blocks around it (`material gold { colour checker { | } }` is in a
//! `checker` inside a `material`). A small tokenizer that skips comments
//! and strings as the parser does, and never fails.

/// A token of the text.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tok<'a> {
    Word(&'a str),
    /// A number, a colour `#…`, or any other piece of a value.
    Value,
    /// A string, quotes included.
    Str,
    Punct(u8),
}

/// Tokens with their byte ranges.
pub fn tokens(text: &str) -> Vec<(Tok<'_>, usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let start = i;
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if c == b'/' && b.get(i + 1) == Some(&b'*') {
            i = text[i + 2..].find("*/").map_or(b.len(), |n| i + 2 + n + 2);
        } else if c == b'"' {
            i = text[i + 1..]
                .find(['"', '\n'])
                .map_or(b.len(), |n| i + 1 + n + 1);
            out.push((Tok::Str, start, i.min(b.len())));
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push((Tok::Word(&text[start..i]), start, i));
        } else if c.is_ascii_digit()
            || c == b'#'
            || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_alphanumeric() || (b[i] == b'.' && b.get(i + 1) != Some(&b'.')))
            {
                i += 1;
            }
            out.push((Tok::Value, start, i));
        } else {
            // One byte of punctuation; other characters (UTF-8) are skipped whole.
            let n = text[i..].chars().next().map_or(1, char::len_utf8);
            if n == 1 {
                out.push((Tok::Punct(c), start, i + 1));
            }
            i += n;
        }
    }
    out
}

/// The name under (or just before) byte `at`: its range and text.
pub fn word_at(text: &str, at: usize) -> Option<(usize, usize, &str)> {
    let b = text.as_bytes();
    let is = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let at = at.min(b.len());
    let mut s = at;
    while s > 0 && is(b[s - 1]) {
        s -= 1;
    }
    let mut e = at;
    while e < b.len() && is(b[e]) {
        e += 1;
    }
    let w = &text[s..e];
    (s < e && (b[s].is_ascii_alphabetic() || b[s] == b'_')).then_some((s, e, w))
}

/// A block around the cursor: what it belongs to.
#[derive(Clone, Debug, PartialEq)]
pub struct Open {
    /// `sphere`, `material`, `checker`, a user's name (`wheel`, `pillar`),
    /// or `for`, `if`, `fn`, `let` for the language's own blocks; empty
    /// for a bare `{`.
    pub owner: String,
    /// Where the `{` is.
    pub at: usize,
}

/// The blocks open at byte `at`, outermost first.
pub fn blocks_at(toks: &[(Tok<'_>, usize, usize)], at: usize) -> Vec<Open> {
    let mut stack: Vec<Open> = Vec::new();
    for (k, &(t, s, _)) in toks.iter().enumerate() {
        if s >= at {
            break;
        }
        match t {
            Tok::Punct(b'{') => stack.push(Open {
                owner: owner(toks, k),
                at: s,
            }),
            Tok::Punct(b'}') => {
                stack.pop();
            }
            _ => {}
        }
    }
    stack
}

/// What the `{` at token `k` belongs to.
fn owner(toks: &[(Tok<'_>, usize, usize)], k: usize) -> String {
    // The statement starts after the previous `{` or `}`.
    let start = toks[..k]
        .iter()
        .rposition(|(t, ..)| matches!(t, Tok::Punct(b'{' | b'}')))
        .map_or(0, |p| p + 1);
    let stmt = &toks[start..k];
    let word = |t: &Tok<'_>| match t {
        Tok::Word(w) => Some(w.to_string()),
        _ => None,
    };
    if let Some(first) = stmt.first().and_then(|t| word(&t.0))
        && matches!(first.as_str(), "for" | "if" | "else" | "fn")
    {
        return if first == "else" { "if".into() } else { first };
    }
    let mut j = stmt.len();
    // `mesh "x.ply" {`, `implicit "…" {`: the word before the string.
    if j > 0 && stmt[j - 1].0 == Tok::Str {
        j -= 1;
    }
    // `pillar(1, r: 2) {`: the name before the matching `(`.
    if j > 0 && stmt[j - 1].0 == Tok::Punct(b')') {
        let mut depth = 0;
        while j > 0 {
            j -= 1;
            match stmt[j].0 {
                Tok::Punct(b')') => depth += 1,
                Tok::Punct(b'(') => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                _ => {}
            }
        }
    }
    let Some(w) = j.checked_sub(1).and_then(|i| word(&stmt[i].0)) else {
        return String::new();
    };
    // `material gold {` declares a material.
    if j >= 2 && stmt[j - 2].0 == Tok::Word("material") && w != "material" {
        return "material".into();
    }
    w
}

/// The block whose parameters apply at the cursor, and the one around it
/// (`(refract, material)`): loops and conditions are see-through.
pub fn innermost(blocks: &[Open]) -> (Option<&str>, Option<&str>) {
    let mut real = blocks
        .iter()
        .rev()
        .filter(|b| !matches!(b.owner.as_str(), "for" | "if"))
        .map(|b| b.owner.as_str());
    (real.next(), real.next())
}

/// The word before the cursor's word (skipping nothing else): `material`
/// in `material go|`.
pub fn previous_word<'a>(toks: &[(Tok<'a>, usize, usize)], at: usize) -> Option<&'a str> {
    let before: Vec<&(Tok<'a>, usize, usize)> =
        toks.iter().take_while(|(_, s, _)| *s < at).collect();
    // The token holding the cursor (being typed) is not "before" it.
    let mut k = before.len();
    if let Some((Tok::Word(_), _, e)) = before.last()
        && *e >= at
    {
        k -= 1;
    }
    match before.get(k.checked_sub(1)?)?.0 {
        Tok::Word(w) => Some(w),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn owners(text: &str) -> Vec<String> {
        let at = text.find('|').unwrap();
        let text = text.replace('|', "");
        blocks_at(&tokens(&text), at)
            .into_iter()
            .map(|o| o.owner)
            .collect()
    }

    #[test]
    fn blocks_are_named_by_their_statement() {
        assert_eq!(owners("sphere { ra|"), ["sphere"]);
        assert_eq!(
            owners("material gold { refract { | } }"),
            ["material", "refract"]
        );
        assert_eq!(
            owners("material m { colour checker { a white | } }"),
            ["material", "checker"]
        );
        assert_eq!(owners("mesh \"a{.ply\" { |"), ["mesh"]);
        assert_eq!(
            owners("let w = union { for i in 0..3 { | } }"),
            ["union", "for"]
        );
        assert_eq!(owners("pillar(1, r: f(2)) { |"), ["pillar"]);
        assert_eq!(owners("sphere { } // { \n box { |"), ["box"]);
        assert_eq!(owners("if a < b { } else { |"), ["if"]);
    }

    #[test]
    fn loops_are_see_through() {
        let b = blocks_at(&tokens("union { for i in 0..3 { if i > 1 { "), 40);
        assert_eq!(innermost(&b), (Some("union"), None));
    }

    #[test]
    fn words_and_previous_words() {
        let t = "sphere { material go }";
        let at = t.find("go").unwrap() + 2;
        assert_eq!(word_at(t, at).unwrap().2, "go");
        assert_eq!(previous_word(&tokens(t), at), Some("material"));
        assert_eq!(word_at("  1.5 ", 3), None);
    }
}

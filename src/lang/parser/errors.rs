//! pest's errors in our words: what a rule is called in a message, and a
//! syntax error turned into "expected …, found …" at the right character,
//! with no internal rule name reaching the user.

use super::*;

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

pub(super) fn syntax_error(e: pest::error::Error<Rule>, text: &str, at: Loc) -> Error {
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
pub(super) fn found_at(text: &str, pos: usize) -> (String, usize) {
    let rest = &text[crate::lang::source::floor_char_boundary(text, pos)..];
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

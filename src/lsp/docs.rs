//! Hover text, read from docs/language.md (compiled in with `include_str!`):
//! the language reference is the one place a keyword, function or
//! parameter is described, and what an editor shows is that text. The code
//! here only knows *where* in the reference each word is described (a
//! heading, a table row, a bullet); a test checks that every keyword,
//! statement, object, pattern and function of the language is found there,
//! so a reference that loses one fails the build's tests.
//!
//! What a parameter expects ("a 3-vector") comes from the builder's
//! schemas (`scene::block_parameters`), the same words its "expected …"
//! messages use.

const REFERENCE: &str = include_str!("../../docs/language.md");

/// The text under a heading (the heading line itself excluded), up to the
/// next heading of the same or a higher level.
fn section(heading: &str) -> Option<&'static str> {
    let level = heading.chars().take_while(|&c| c == '#').count();
    let mut offset = 0;
    let mut start = None;
    for line in REFERENCE.split_inclusive('\n') {
        let l = line.trim_end();
        if let Some(s) = start {
            let hashes = l.chars().take_while(|&c| c == '#').count();
            if hashes > 0 && hashes <= level && l[hashes..].starts_with(' ') {
                return Some(&REFERENCE[s..offset]);
            }
        } else if l == heading {
            start = Some(offset + line.len());
        }
        offset += line.len();
    }
    start.map(|s| &REFERENCE[s..])
}

/// The section's opening: its first example (when it starts with one) and
/// its first paragraph.
fn opening(text: &str) -> String {
    let mut out = Vec::new();
    let mut lines = text.lines().skip_while(|l| l.trim().is_empty()).peekable();
    if lines.peek().is_some_and(|l| l.starts_with("```")) {
        let mut code = vec![lines.next().unwrap_or_default()];
        for l in lines.by_ref() {
            code.push(l);
            if l.starts_with("```") {
                break;
            }
        }
        out.push(code.join("\n"));
    }
    let para: Vec<&str> = lines
        .skip_while(|l| l.trim().is_empty())
        .take_while(|l| !l.trim().is_empty() && !l.starts_with("```"))
        .collect();
    if !para.is_empty() {
        out.push(para.join("\n"));
    }
    out.join("\n\n")
}

/// The words a table cell names in backticks: "`sqrt sin cos`" names
/// `sqrt`, `sin` and `cos`; "`rad(deg)`" names `rad`; "`adaptive { … }`"
/// names `adaptive`.
fn cell_names(cell: &str) -> Vec<&str> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .flat_map(|code| {
            let head = code.split(['(', '{', '"']).next().unwrap_or("");
            head.split([' ', ',']).filter(|w| !w.is_empty())
        })
        .collect()
}

/// The row of a table in `text` whose first cell names `word`, as
/// "`first cell`: column: value; …" with the table's own column names.
fn table_row(text: &str, word: &str) -> Option<String> {
    // Tables may be indented (inside a bullet).
    let lines: Vec<&str> = text.lines().map(str::trim_start).collect();
    for (k, l) in lines.iter().enumerate() {
        if !l.starts_with('|') || l.starts_with("| ---") {
            continue;
        }
        let cells = cells(l);
        if cells.first().is_none_or(|c| !cell_names(c).contains(&word)) {
            continue;
        }
        // The header is the first row of this table.
        let top = lines[..k]
            .iter()
            .rposition(|l| !l.starts_with('|'))
            .map_or(0, |p| p + 1);
        if top == k {
            continue; // the header row itself
        }
        let header = cells_of(lines[top]);
        let mut out = format!("**{}**", cells[0]);
        for (h, c) in header.iter().zip(&cells).skip(1) {
            if !c.is_empty() {
                out.push_str(&format!("\n\n*{h}*: {c}"));
            }
        }
        return Some(out);
    }
    None
}

fn cells(line: &str) -> Vec<String> {
    cells_of(line)
}

fn cells_of(line: &str) -> Vec<String> {
    // `\|` inside a cell is an escaped bar.
    let l = line.trim().trim_start_matches('|').trim_end_matches('|');
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut chars = l.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                cur.push('|');
                chars.next();
            }
            '|' => out.push(std::mem::take(&mut cur).trim().to_string()),
            c => cur.push(c),
        }
    }
    out.push(cur.trim().to_string());
    out
}

/// The bullet (`- …` up to the next bullet or blank line) in `text` that
/// starts with `start`.
fn bullet(text: &str, start: &str) -> Option<String> {
    let mut out: Option<Vec<&str>> = None;
    for l in text.lines() {
        match &mut out {
            None if l.starts_with(&format!("- {start}")) => out = Some(vec![&l[2..]]),
            None => {}
            Some(v) => {
                if l.starts_with("- ") || l.trim().is_empty() || !l.starts_with("  ") {
                    break;
                }
                v.push(l.trim());
            }
        }
    }
    out.map(|v| v.join("\n"))
}

/// Lines of the section's examples that start with `word` (the transforms).
fn example_lines(text: &str, word: &str) -> Option<String> {
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| l.split_whitespace().next() == Some(word))
        .collect();
    (!lines.is_empty()).then(|| format!("```\n{}\n```", lines.join("\n")))
}

/// Where the reference describes a word of the language (a keyword,
/// statement, object, pattern, transform, built-in function or constant).
pub fn word(w: &str) -> Option<String> {
    let s = |h: &str| section(h);
    let objects = || s("## Objects").and_then(|t| table_row(t, w));
    let found = match w {
        "camera" => s("### `camera`").map(opening),
        "render" => s("### `render`").map(opening),
        "ambient" | "light" | "environment" => {
            let t = s("### `ambient` and `light`")?;
            let para = match w {
                "ambient" => t.split("\n\n").find(|p| p.starts_with("`ambient`")),
                "environment" => t.split("\n\n").find(|p| p.starts_with("`environment`")),
                _ => t.split("\n\n").find(|p| p.starts_with("Point, parallel")),
            };
            Some(format!("{}\n\n{}", opening(t), para.unwrap_or("")))
        }
        "material" => s("### `material`").map(opening),
        "include" => s("### `include`").map(opening),
        "let" => s("## Values and expressions").and_then(|t| bullet(t, "`let NAME")),
        "for" | "in" | "step" => {
            s("## Reuse, loops and functions").and_then(|t| bullet(t, "**Loops.**"))
        }
        "if" | "else" => {
            s("## Reuse, loops and functions").and_then(|t| bullet(t, "**Conditions.**"))
        }
        "fn" => s("## Reuse, loops and functions").and_then(|t| bullet(t, "**Functions.**")),
        "and" | "or" | "not" => {
            s("## Values and expressions").and_then(|t| bullet(t, "Comparisons"))
        }
        "pi" | "clock" | "frame" => s("## Values and expressions")
            .and_then(|t| bullet(t, "Built-in constants"))
            .map(|b| {
                b.split("Functions:")
                    .next()
                    .unwrap_or(&b)
                    .trim()
                    .to_string()
            }),
        "implicit" => Some(format!(
            "{}\n\n{}",
            objects()?,
            opening(s("## Implicit surfaces")?)
        )),
        "mesh" => Some(format!("{}\n\n{}", objects()?, opening(s("## Meshes")?))),
        "union" | "intersection" | "difference" => {
            Some(format!("{}\n\n{}", objects()?, opening(s("## CSG")?)))
        }
        _ if crate::scene::is_transform(w) => {
            let t = s("## Transforms")?;
            let para = opening(t);
            let para = para.rsplit("\n\n").next().unwrap_or("");
            Some(format!("{}\n\n{para}", example_lines(t, w)?))
        }
        "bumps" | "ripples" | "waves" => {
            s("## Patterns").and_then(|t| table_row(t.split("**Normal patterns**").nth(1)?, w))
        }
        _ if crate::scene::is_object(w) => objects(),
        _ if crate::scene::pattern::NAMES.contains(&w) => {
            s("## Patterns").and_then(|t| table_row(t, w))
        }
        _ if crate::eval::expr::FUNCTIONS.iter().any(|(f, _)| *f == w) => {
            s("## Values and expressions").and_then(|t| table_row(t, w))
        }
        _ => None,
    };
    found.filter(|t| !t.trim().is_empty())
}

/// What the reference says of parameter `param` of block `block` (a row of
/// the block's table, where it has one).
pub fn parameter(block: &str, param: &str) -> Option<String> {
    let heading = match block {
        "render" | "adaptive" => "### `render`",
        "material" | "refract" => "### `material`",
        "camera" => "### `camera`",
        "light" | "ambient" | "environment" | "occlusion" => "### `ambient` and `light`",
        b if crate::scene::pattern::NAMES.contains(&b) => "## Patterns",
        b if crate::scene::is_object(b) => "## Objects",
        _ => return None,
    };
    let t = section(heading)?;
    if crate::scene::is_object(block) {
        // The objects' table has a row per object: show that row.
        return match param {
            _ if param == "material" || crate::scene::is_transform(param) => word(param),
            _ => table_row(t, block),
        };
    }
    table_row(t, param)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every word of the language has its text in the reference.
    #[test]
    fn every_word_of_the_language_is_in_the_reference() {
        let mut words: Vec<&str> = crate::lang::parser::STATEMENT_KEYWORDS.to_vec();
        words.extend([
            "in", "else", "step", "and", "or", "not", "pi", "clock", "frame",
        ]);
        words.extend(crate::scene::pattern::NAMES);
        words.extend(["bumps", "ripples", "waves"]);
        words.extend(["translate", "rotate", "scale", "shear", "mirror", "matrix"]);
        words.extend(crate::eval::expr::FUNCTIONS.iter().map(|(f, _)| *f));
        let missing: Vec<&str> = words.into_iter().filter(|w| word(w).is_none()).collect();
        assert!(
            missing.is_empty(),
            "not described in docs/language.md: {missing:?}"
        );
    }

    #[test]
    fn texts_are_the_reference_s_own() {
        let sqrt = word("sqrt").unwrap();
        assert!(sqrt.contains("trigonometry in radians"), "{sqrt}");
        let sphere = word("sphere").unwrap();
        assert!(sphere.contains("`centre <c>`"), "{sphere}");
        let camera = word("camera").unwrap();
        assert!(camera.contains("field of view"), "{camera}");
        let fr = word("for").unwrap();
        assert!(fr.starts_with("**Loops.**"), "{fr}");
        assert!(word("colour").is_none());
    }

    #[test]
    fn parameters_come_from_their_block_s_table() {
        let md = parameter("render", "max_depth").unwrap();
        assert!(md.contains("reflection bounces"), "{md}");
        let d = parameter("material", "diffuse").unwrap();
        assert!(d.contains("Lambert"), "{d}");
        let t = parameter("gradient", "turbulence").unwrap();
        assert!(t.contains("displaced"), "{t}");
        assert!(parameter("camera", "fov").is_none(), "camera has no table");
    }

    #[test]
    fn cells_name_their_words() {
        assert_eq!(cell_names("`sqrt sin cos`"), ["sqrt", "sin", "cos"]);
        assert_eq!(cell_names("`rad(deg)`, `deg(rad)`"), ["rad", "deg"]);
        assert_eq!(cell_names("`adaptive { threshold T }`"), ["adaptive"]);
        assert_eq!(cell_names("`implicit \"EQUATION\"`"), ["implicit"]);
        assert_eq!(
            cell_names("`union`, `intersection`"),
            ["union", "intersection"]
        );
    }
}
